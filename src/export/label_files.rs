//! [`LabelFiles`]: the files of a label map's pass (`tmc extract --labels`,
//! the Python package's `extract_labels_to`): one file per label (`{label}`
//! in the output's name), or one PLY or `.tmesh` with a per-face label,
//! assembled after the pass ([`write_labelled`]) from one `.tmesh` per
//! label in a temporary directory beside it.
//!
//! The pass only notes each label's totals; the files are finished after
//! it, several at once ([`LabelFiles::finish`]), or, once told where each
//! label's mesh ends ([`LabelFiles::finish_early`]), each `.tmesh` as soon
//! as the pass is past its label (`early_finish.rs`); all of them are kept
//! or none.

use super::early_finish::{Finished, Finisher, Job};
use super::set_aside::SetAside;
use super::{create_sink, write_labelled};
use crate::fan_out::fan_out;
use crate::files::{fill_placeholder, has_placeholder, withdraw};
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Totals};
use crate::meshfile::TmeshWriter;
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// The outputs of `labels` for the output name `template`: with `{label}`
/// in it, one per label, `{label}` replaced by the label's integer value;
/// without, `template` itself, which must then be a `.ply` or `.tmesh` (a
/// per-face label) and every label must fit its `uint32`.
pub fn label_outputs(template: &Path, labels: &[i64]) -> Result<Vec<PathBuf>> {
    if has_placeholder(template, "{label}") {
        return Ok(labels
            .iter()
            .map(|l| fill_placeholder(template, "{label}", &l.to_string()))
            .collect());
    }
    if template
        .extension()
        .is_none_or(|e| e != "ply" && e != "tmesh")
    {
        return Err(Error::Invalid(format!(
            "{}: the output of a label map must contain {{label}} (one file per label) or be one .ply or .tmesh (a per-face label)",
            template.display()
        )));
    }
    if let Some(l) = labels.iter().find(|&&l| u32::try_from(l).is_err()) {
        return Err(Error::Invalid(format!(
            "label {l} does not fit the uint32 per-face label of one file; write one file per label with {{label}}"
        )));
    }
    Ok(vec![template.to_path_buf()])
}

/// Refuses, before the volume is read, an output name that no label's
/// file could take: a form [`label_outputs`] refuses (also for the labels
/// `listed`, when a list was asked for: one file's uint32 cannot hold
/// label -5), an unknown format, or (unless `{label}` is in its
/// directory) a directory that is missing or takes no file. The labels
/// of `all` are known only after a reading of the whole volume, and
/// these were found only after it.
pub fn check_label_template(template: &Path, listed: &[i64]) -> Result<()> {
    label_outputs(template, listed)?;
    match template
        .parent()
        .is_some_and(|p| has_placeholder(p, "{label}"))
    {
        true => super::Format::from_path(template).map(drop),
        false => super::check_output_path(template),
    }
}

/// Files a label pass keeps open per label for the output name
/// `template`: one for a `.tmesh` or `.stl` file per label and for one
/// file of every label (a `.tmesh` per label in a temporary directory);
/// three for a `.ply`, `.obj` or `.off` per label (the file and the two
/// spools of its vertices and faces, see `spooled.rs`).
pub fn open_files_per_label(template: &Path) -> usize {
    let spooled = template
        .extension()
        .is_some_and(|e| e == "ply" || e == "obj" || e == "off");
    match has_placeholder(template, "{label}") && spooled {
        true => 3,
        false => 1,
    }
}

/// Refuses, before the pass, label files that would overwrite one of the
/// input's files (`inputs`: the path given and the data files it names)
/// or that cannot be written (each directory tried once).
pub fn check_label_outputs(outputs: &[PathBuf], inputs: &[&Path]) -> Result<()> {
    for output in outputs {
        for input in inputs {
            crate::files::check_distinct(input, output)?;
        }
    }
    super::check_output_paths(outputs.iter().map(PathBuf::as_path))
}

/// A label's file sink: one that may be finished on another thread (the
/// `.tmesh` and part writers), or one that may not.
pub enum LabelSink {
    /// A sink that may be finished on another thread.
    Send(Box<dyn MeshSink + Send>),
    /// A sink finished on the calling thread.
    Local(Box<dyn MeshSink>),
}

impl LabelSink {
    /// The sink of the label file `target`, one of `labels` files: a
    /// `.tmesh` writer with its share of 64 MiB of output buffer (4 KiB
    /// to 64 KiB: a larger buffer only touched more fresh pages, a fault
    /// each, as the pass wrote the same bytes), else [`create_sink`]'s.
    pub fn create(target: &Path, labels: usize) -> Result<LabelSink> {
        Ok(match target.extension().is_some_and(|e| e == "tmesh") {
            true => LabelSink::Send(Box::new(TmeshWriter::create_buffered(
                target,
                label_buffer(labels),
            )?)),
            false => LabelSink::Local(create_sink(target)?),
        })
    }

    fn sink(&mut self) -> &mut dyn MeshSink {
        match self {
            LabelSink::Send(sink) => &mut **sink,
            LabelSink::Local(sink) => &mut **sink,
        }
    }
}

/// The bytes each label's `.tmesh` writer gathers before it writes them:
/// 64 MiB shared by all labels, between 4 KiB and 64 KiB each, so that
/// hundreds of labels do not hold hundreds of MiB of output, nor
/// thousands of labels (an instance segmentation's cells) a GiB of
/// buffers. Up to 1 MiB each (a single extraction's buffer), most label
/// files were held whole until the end, and every buffer's pages were
/// faulted in afresh: 64 KiB was faster (docs/performance-labels.md).
fn label_buffer(labels: usize) -> usize {
    ((64 << 20) / labels.max(1)).clamp(4 << 10, 64 << 10)
}

/// A label's sink in the pass: its file's, whose `finish` only notes the
/// totals ([`LabelFiles::finish`] finishes the file), unless the file was
/// handed to the finishing threads when the pass was past its label.
pub struct LabelFile {
    /// `None` once handed to the finishing threads.
    inner: Option<LabelSink>,
    /// What the pass's `finish` was given.
    totals: Option<Totals>,
    /// Where the label's mesh ends, and where to hand the file then.
    early: Option<Early>,
}

/// A label file that is finished as soon as its last chunk is in.
struct Early {
    /// The label's index, which the finishing threads report.
    index: usize,
    /// The last plane whose chunk may hold part of the mesh.
    last_plane: u64,
    /// The totals of the chunks given so far.
    seen: Totals,
    to: crossbeam::channel::Sender<Job>,
    /// The path the file is put at.
    target: PathBuf,
}

impl LabelFile {
    /// The sink still here, or, once the file was handed over, nothing,
    /// where `chunk` must then be empty.
    fn take_chunk(&mut self, chunk: &Chunk) -> Result<Option<&mut dyn MeshSink>> {
        if self.inner.is_none() && !(chunk.vertices.is_empty() && chunk.triangles.is_empty()) {
            return Err(past_the_end());
        }
        if let Some(early) = &mut self.early {
            early.seen.vertices += chunk.vertices.len() as u64;
            early.seen.triangles += chunk.triangles.len() as u64;
            early.seen.chunks += 1;
        }
        Ok(self.inner.as_mut().map(LabelSink::sink))
    }

    /// Hands the file over once `chunk` was its label's last.
    fn after_chunk(&mut self, chunk: &Chunk) -> Result<()> {
        let Some(early) = &self.early else {
            return Ok(());
        };
        if chunk.plane < early.last_plane || self.inner.is_none() {
            return Ok(());
        }
        if let Some(LabelSink::Send(sink)) = self.inner.take() {
            let job = Job {
                index: early.index,
                sink,
                totals: early.seen,
                target: early.target.clone(),
            };
            early
                .to
                .send(job)
                .map_err(|_| Error::Invalid("the label files' finishing threads stopped".into()))?;
        }
        Ok(())
    }
}

/// A label's mesh went on past the plane where its samples end: the pass
/// and [`crate::stream::last_label_chunks`] disagree.
fn past_the_end() -> Error {
    Error::Invalid("a label's mesh went on past its last plane (a bug: please report it)".into())
}

impl MeshSink for LabelFile {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        match &mut self.inner {
            Some(sink) => sink.sink().begin(info),
            None => Err(crate::mesh::used_after_finish()),
        }
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        if let Some(sink) = self.take_chunk(chunk)? {
            sink.chunk(base, chunk)?;
        }
        self.after_chunk(chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        if let Some(sink) = self.take_chunk(chunk)? {
            sink.chunk_cancellable(base, chunk, cancel)?;
        }
        self.after_chunk(chunk)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        // A file handed over was finished with the totals of its chunks:
        // the pass must count the same mesh.
        if let (None, Some(early)) = (&self.inner, &self.early) {
            if (early.seen.vertices, early.seen.triangles) != (totals.vertices, totals.triangles) {
                return Err(past_the_end());
            }
        }
        self.totals = Some(*totals);
        Ok(())
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        match &self.inner {
            Some(LabelSink::Send(sink)) => sink.encoder(),
            Some(LabelSink::Local(sink)) => sink.encoder(),
            None => None,
        }
    }
}

/// The files of a label pass (see the module documentation). Dropped
/// unfinished, it leaves nothing behind.
pub struct LabelFiles {
    /// The one file of every label; `None` with a file per label.
    one: Option<(PathBuf, tempfile::TempDir)>,
    labels: Vec<i64>,
    /// Where each label's sink writes: its output, or its `.tmesh` in the
    /// temporary directory.
    targets: Vec<PathBuf>,
    files: Vec<LabelFile>,
    /// The threads finishing files during the pass
    /// ([`LabelFiles::finish_early`]).
    finisher: Option<Finisher>,
}

impl LabelFiles {
    /// The sinks of `labels` for the output name `template` (see
    /// [`label_outputs`], which gives `outputs`), each made by
    /// `open(target, label)` (for example [`LabelSink::create`]) for the
    /// label's output; for one file of every label, each label's sink is a
    /// `.tmesh` in a temporary directory beside it, not synced to disk (it
    /// is read into the one file and removed).
    pub fn create(
        template: &Path,
        labels: &[i64],
        outputs: &[PathBuf],
        mut open: impl FnMut(&Path, i64) -> Result<LabelSink>,
    ) -> Result<LabelFiles> {
        let one = match (has_placeholder(template, "{label}"), outputs) {
            (true, _) if outputs.len() == labels.len() => None,
            (false, [path]) => {
                let dir = path
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
                let spool = tempfile::Builder::new()
                    .prefix(".tmc-labels-")
                    .tempdir_in(dir)
                    .map_err(|e| Error::io(dir, e))?;
                Some((path.clone(), spool))
            }
            _ => {
                return Err(Error::Invalid(format!(
                    "{}: {} outputs for {} labels",
                    template.display(),
                    outputs.len(),
                    labels.len()
                )))
            }
        };
        let targets: Vec<PathBuf> = match &one {
            Some((_, dir)) => labels
                .iter()
                .map(|l| dir.path().join(format!("{l}.tmesh")))
                .collect(),
            None => outputs.to_vec(),
        };
        let mut files = Vec::with_capacity(labels.len());
        for (target, &label) in targets.iter().zip(labels) {
            let inner = match one {
                // Read into the one file, then removed with the directory.
                Some(_) => LabelSink::Send(Box::new(TmeshWriter::create_scratch(
                    target,
                    label_buffer(labels.len()),
                )?)),
                None => open(target, label)?,
            };
            files.push(LabelFile {
                inner: Some(inner),
                totals: None,
                early: None,
            });
        }
        Ok(LabelFiles {
            one,
            labels: labels.to_vec(),
            targets,
            files,
            finisher: None,
        })
    }

    /// Finishes each label's `.tmesh` file (those of [`LabelSink::create`],
    /// not part files, nor the one file of every label) on threads of its
    /// own as soon as the pass has handed it the chunk of the plane
    /// `last_planes[i]` gives for it (from
    /// [`crate::stream::last_label_chunks`]; `None`: at the end), while the
    /// pass goes on. A chunk with a triangle or vertex after that plane is
    /// an error, and so is a pass whose totals are not those of the chunks
    /// the file was finished with. The files are settled as before: all
    /// kept by [`LabelFiles::finish`], or none.
    pub fn finish_early(&mut self, last_planes: &[Option<u64>]) {
        if self.one.is_some() || self.finisher.is_some() {
            return;
        }
        let early: Vec<usize> = (0..self.files.len())
            .filter(|&i| last_planes.get(i).copied().flatten().is_some())
            .filter(|&i| matches!(self.files[i].inner, Some(LabelSink::Send(_))))
            .collect();
        if early.is_empty() {
            return;
        }
        let finisher = Finisher::start(early.len().min(EARLY_FINISHING_THREADS));
        for i in early {
            self.files[i].early = Some(Early {
                index: i,
                last_plane: last_planes[i].expect("filtered"),
                seen: Totals::default(),
                to: finisher.sender(),
                target: self.targets[i].clone(),
            });
        }
        self.finisher = Some(finisher);
    }

    /// The results of the files finished during the pass, by label index,
    /// once the finishing threads are done.
    /// They are settled by the caller (kept or removed), so they no longer
    /// count as kept in place by a run that may fail.
    fn finished_early(&mut self) -> Vec<(usize, Finished)> {
        // The threads end once every file's sender is gone.
        for file in &mut self.files {
            file.early = None;
        }
        let results = self.finisher.take().map(Finisher::join).unwrap_or_default();
        let placed = results.iter().filter(|(_, r)| r.is_ok()).count();
        crate::files::fatal_cleanup::note_kept_in_place(-(placed as isize));
        results
    }

    /// Each label's sink, in the order of the labels.
    pub fn sinks(&mut self) -> &mut [LabelFile] {
        &mut self.files
    }

    /// Finishes every label's file (the pass has given each its totals) on
    /// up to [`FINISHING_THREADS`] threads, then, for one file, assembles
    /// it. A failure, or `cancel`, removes the files already put in place,
    /// so that none is left behind; the error is the first label's in
    /// order, an interruption stays [`Error::Interrupted`].
    pub fn finish(mut self, cancel: Option<&AtomicBool>) -> Result<()> {
        let early = self.finished_early();
        let mut results = finish_all(&mut self.files, &self.targets, cancel)?;
        for (i, result) in early {
            results[i] = result;
        }
        all_or_none(&self.targets, results)?;
        if let Some((path, dir)) = self.one.take() {
            let parts: Vec<(u32, &Path)> = self
                .labels
                .iter()
                .zip(&self.targets)
                .map(|(&l, t)| (l as u32, t.as_path()))
                .collect();
            let never = AtomicBool::new(false);
            write_labelled(&path, &parts, cancel.unwrap_or(&never))?;
            dir.close().map_err(|e| Error::io(&path, e))?;
        }
        Ok(())
    }
}

/// The most threads that finish label files at once.
pub const FINISHING_THREADS: usize = 16;

/// The most threads that finish label files during the pass
/// ([`LabelFiles::finish_early`]): the labels end one after another, so
/// fewer are waiting at a time than at the end.
const EARLY_FINISHING_THREADS: usize = 8;

impl Drop for LabelFiles {
    /// A pass that failed, or whose files were never finished, leaves none
    /// of the files finished during it behind: each is removed, or the
    /// file it replaced put back.
    fn drop(&mut self) {
        for (i, result) in self.finished_early() {
            match result {
                Ok(Some(aside)) => {
                    let _ = aside.restore();
                }
                Ok(None) => {
                    let _ = std::fs::remove_file(&self.targets[i]);
                }
                Err(_) => {}
            }
        }
    }
}

/// Finishes the file of every label (the pass has given each its totals):
/// those that may go to another thread on up to [`FINISHING_THREADS`]
/// threads, the others in turn. Finishing a file is mostly waiting for the
/// disk (the last bytes written, the file synced, renamed into place), and
/// one file after another, hundreds of them took longer than the pass.
/// Each file is finished or removed as in the pass, the file at its path
/// (`targets`, in the same order) set aside first; the result of each, in
/// the order of `files` (see [`all_or_none`]).
fn finish_all(
    files: &mut [LabelFile],
    targets: &[PathBuf],
    cancel: Option<&AtomicBool>,
) -> Result<Vec<Finished>> {
    let never = AtomicBool::new(false);
    let cancel = cancel.unwrap_or(&never);
    let mut results: Vec<Finished> = Vec::with_capacity(files.len());
    let mut moving = Vec::new();
    for (i, file) in files.iter_mut().enumerate() {
        let totals = file
            .totals
            .ok_or_else(|| Error::Invalid("a label's mesh was not finished".into()))?;
        // A file finished during the pass: its result comes from there.
        results.push(Err(Error::Invalid(
            "a label's file was not finished".into(),
        )));
        match &mut file.inner {
            Some(LabelSink::Send(sink)) => moving.push((i, sink, totals)),
            Some(LabelSink::Local(sink)) => {
                results[i] = SetAside::before_replacing(&targets[i])
                    .and_then(|aside| sink.finish_cancellable(&totals, cancel).map(|()| aside))
            }
            None => {}
        }
    }
    let threads = moving.len().min(FINISHING_THREADS);
    let finished = fan_out(moving, threads, |_, (i, sink, totals)| {
        let result = SetAside::before_replacing(&targets[i])
            .and_then(|aside| sink.finish_cancellable(&totals, cancel).map(|()| aside));
        (i, result)
    });
    for (i, result) in finished {
        results[i] = result;
    }
    Ok(results)
}

/// Settles the files finished at `targets` (`results`, in the same order):
/// when one failed, those put in place are taken back, so that a failed
/// run leaves none of its label files behind, whichever threads finished
/// which before the failure: each is removed, or, where it replaced a file
/// of an earlier run, that file is put back (a file it did not replace is
/// left alone). When all succeeded, the files replaced go. The error is
/// the first label's in order; an interruption stays one (exit 130).
fn all_or_none(targets: &[PathBuf], results: Vec<Finished>) -> Result<()> {
    let mut placed = Vec::new();
    let mut first_error = None;
    for (target, result) in targets.iter().zip(results) {
        match result {
            Ok(aside) => placed.push((target.as_path(), aside)),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    let Some(e) = first_error else {
        // The replaced files go: freeing their blocks is waiting for the
        // disk too, so on several threads.
        let asides: Vec<SetAside> = placed.into_iter().filter_map(|(_, a)| a).collect();
        let threads = asides.len().min(FINISHING_THREADS);
        fan_out(asides, threads, |_, aside| drop(aside));
        return Ok(());
    };
    let mut new = Vec::new();
    for (target, aside) in placed {
        match aside {
            // An earlier run's file is back; nothing of this run is left.
            Some(aside) => {
                let _ = aside.restore();
            }
            None => new.push(target),
        }
    }
    match e {
        Error::Interrupted => {
            for path in new {
                let _ = std::fs::remove_file(path);
            }
            Err(Error::Interrupted)
        }
        e => Err(withdraw(new, e)),
    }
}

#[cfg(test)]
mod tests {
    use super::{all_or_none, LabelFiles, LabelSink, SetAside};
    use crate::mesh::{Chunk, MeshInfo, MeshSink, Totals};
    use crate::params::{Inside, Method};
    use crate::{Error, Grid};
    use std::path::{Path, PathBuf};

    /// The tests that finish files during the pass, one at a time: they
    /// look at the process's count of files kept in place.
    static EARLY: std::sync::Mutex<()> = std::sync::Mutex::new(());

    fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
        EARLY.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Two labels' `.tmesh` files in `dir`, the first finished once the
    /// pass has given it plane 1's chunk, the second at the end.
    fn two_files(dir: &Path) -> (LabelFiles, Vec<PathBuf>) {
        let template = dir.join("{label}.tmesh");
        let outputs: Vec<PathBuf> = [1, 2]
            .iter()
            .map(|l| dir.join(format!("{l}.tmesh")))
            .collect();
        let mut files = LabelFiles::create(&template, &[1, 2], &outputs, |target, _| {
            LabelSink::create(target, 2)
        })
        .unwrap();
        files.finish_early(&[Some(1), None]);
        let info = MeshInfo {
            grid: Grid::unit([4, 4, 4]),
            iso: 0.5,
            method: Method::Tmc,
            inside: Inside::High,
            close: false,
            normals: false,
            labels: false,
        };
        for file in files.sinks() {
            file.begin(&info).unwrap();
        }
        (files, outputs)
    }

    /// The chunk of `plane`, with one triangle or none.
    fn chunk(plane: u64, full: bool) -> Chunk {
        let mut chunk = Chunk {
            plane,
            ..Chunk::default()
        };
        if full {
            chunk.vertices = vec![[0.0, 0.0, plane as f32], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            chunk.triangles = vec![[0, 1, 2]];
        }
        chunk
    }

    /// Waits (up to 10 s) for `path` to appear.
    fn appears(path: &Path) -> bool {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while std::time::Instant::now() < deadline {
            if path.exists() {
                return true;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        false
    }

    #[test]
    fn a_label_past_its_last_plane_is_finished_during_the_pass() {
        let _one = one_at_a_time();
        let dir = tempfile::tempdir().unwrap();
        let (mut files, outputs) = two_files(dir.path());
        let sinks = files.sinks();
        sinks[0].chunk(0, &chunk(0, true)).unwrap();
        sinks[1].chunk(0, &chunk(0, true)).unwrap();
        assert!(!outputs[0].exists(), "not before its last plane");
        sinks[0].chunk(3, &chunk(1, true)).unwrap();
        assert!(appears(&outputs[0]), "finished once its last plane is in");
        for plane in 2..4 {
            sinks[0].chunk(6, &chunk(plane, false)).unwrap();
            sinks[1].chunk(3, &chunk(plane, false)).unwrap();
        }
        let totals = |v, t| Totals {
            vertices: v,
            triangles: t,
            chunks: 4,
        };
        sinks[0].finish(&totals(6, 2)).unwrap();
        sinks[1].finish(&totals(3, 1)).unwrap();
        assert!(!outputs[1].exists());
        files.finish(None).unwrap();
        assert!(!crate::files::fatal_cleanup::kept_in_place());
        let read = |p: &Path| {
            let r = crate::meshfile::TmeshReader::open(p).unwrap();
            (r.vertices(), r.triangles())
        };
        assert_eq!(read(&outputs[0]), (6, 2));
        assert_eq!(read(&outputs[1]), (3, 1));
    }

    #[test]
    fn a_pass_that_fails_after_takes_the_early_file_with_it() {
        let _one = one_at_a_time();
        let dir = tempfile::tempdir().unwrap();
        let (mut files, outputs) = two_files(dir.path());
        files.sinks()[0].chunk(0, &chunk(1, true)).unwrap();
        assert!(appears(&outputs[0]));
        // A fatal signal's handler now says the file was left in place.
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while !crate::files::fatal_cleanup::kept_in_place() {
            assert!(std::time::Instant::now() < deadline, "not counted as kept");
            std::thread::yield_now();
        }
        // The pass fails: the files are dropped unfinished.
        drop(files);
        assert!(!outputs[0].exists() && !outputs[1].exists());
        assert!(!crate::files::fatal_cleanup::kept_in_place());
    }

    #[test]
    fn a_mesh_going_on_past_its_last_plane_is_an_error() {
        let _one = one_at_a_time();
        let dir = tempfile::tempdir().unwrap();
        let (mut files, outputs) = two_files(dir.path());
        let sinks = files.sinks();
        sinks[0].chunk(0, &chunk(1, true)).unwrap();
        let err = sinks[0].chunk(3, &chunk(2, true)).unwrap_err();
        assert!(err.to_string().contains("past its last plane"), "{err}");
        // Totals other than those the file was finished with, likewise.
        let totals = Totals {
            vertices: 6,
            triangles: 2,
            chunks: 2,
        };
        let err = sinks[0].finish(&totals).unwrap_err();
        assert!(err.to_string().contains("past its last plane"), "{err}");
        drop(files);
        assert!(!outputs[0].exists());
    }

    /// Three label files: the first and last put in place, the middle one
    /// failed, with an older file at its path.
    fn three(dir: &std::path::Path) -> Vec<PathBuf> {
        let targets: Vec<PathBuf> = (1..=3).map(|l| dir.join(format!("{l}.ply"))).collect();
        for t in &targets {
            std::fs::write(t, b"mesh").unwrap();
        }
        targets
    }

    #[test]
    fn a_failed_label_takes_the_files_put_in_place_with_it() {
        let dir = tempfile::tempdir().unwrap();
        let targets = three(dir.path());
        let results = vec![Ok(None), Err(Error::Invalid("disk full".into())), Ok(None)];
        let err = all_or_none(&targets, results).unwrap_err().to_string();
        assert!(err.starts_with("disk full; removed the output"), "{err}");
        assert!(!targets[0].exists() && !targets[2].exists());
        assert!(targets[1].exists(), "a file this run did not write is kept");
    }

    #[test]
    fn an_interruption_removes_them_and_stays_an_interruption() {
        let dir = tempfile::tempdir().unwrap();
        let targets = three(dir.path());
        let results = vec![
            Err(Error::Interrupted),
            Ok(None),
            Err(Error::Invalid("later".into())),
        ];
        assert!(matches!(
            all_or_none(&targets, results),
            Err(Error::Interrupted)
        ));
        assert!(targets[0].exists() && !targets[1].exists() && targets[2].exists());
    }

    #[test]
    fn when_all_are_finished_all_stay() {
        let dir = tempfile::tempdir().unwrap();
        let targets = three(dir.path());
        all_or_none(&targets, vec![Ok(None), Ok(None), Ok(None)]).unwrap();
        assert!(targets.iter().all(|t| t.exists()));
    }

    /// The files of an earlier run into the same directory, replaced by
    /// this run's: put back when a label fails, let go when all succeed;
    /// no second name is left either way.
    #[test]
    fn a_failed_run_puts_back_the_files_it_replaced() {
        for fail in [true, false] {
            let dir = tempfile::tempdir().unwrap();
            let targets = three(dir.path());
            let mut results = Vec::new();
            for t in &targets {
                let aside = SetAside::before_replacing(t).unwrap();
                assert!(aside.is_some());
                let new = dir.path().join("new");
                std::fs::write(&new, b"this run").unwrap();
                std::fs::rename(&new, t).unwrap();
                results.push(Ok(aside));
            }
            if fail {
                results[1] = Err(Error::Invalid("disk full".into()));
            }
            assert_eq!(all_or_none(&targets, results).is_err(), fail);
            let want: &[u8] = if fail { b"mesh" } else { b"this run" };
            for t in [&targets[0], &targets[2]] {
                assert_eq!(std::fs::read(t).unwrap(), want, "fail {fail}");
            }
            assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
        }
    }

    /// A file finished during the pass over an earlier run's file: the
    /// pass fails, and the earlier file is back.
    #[test]
    fn a_pass_that_fails_puts_back_the_file_an_early_one_replaced() {
        let _one = one_at_a_time();
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("1.tmesh"), b"earlier").unwrap();
        let (mut files, outputs) = two_files(dir.path());
        files.sinks()[0].chunk(0, &chunk(1, true)).unwrap();
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while std::fs::read(&outputs[0]).unwrap() == b"earlier" {
            assert!(std::time::Instant::now() < deadline, "not finished early");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        drop(files);
        assert_eq!(std::fs::read(&outputs[0]).unwrap(), b"earlier");
        assert!(!outputs[1].exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
