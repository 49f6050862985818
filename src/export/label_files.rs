//! [`LabelFiles`]: the files of a label map's pass (`tmc extract --labels`,
//! the Python package's `extract_labels_to`): one file per label (`{label}`
//! in the output's name), or one PLY or `.tmesh` with a per-face label,
//! assembled after the pass ([`write_labelled`]) from one `.tmesh` per
//! label in a temporary directory beside it.
//!
//! The pass only notes each label's totals; the files are finished after
//! it, several at once ([`LabelFiles::finish`]), and all of them are put in
//! place or none.

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
    /// `.tmesh` writer with its share of 64 MiB of output buffer (64 KiB
    /// to 1 MiB), else [`create_sink`]'s.
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
/// 64 MiB shared by all labels, between 4 KiB and 1 MiB (a single
/// extraction's buffer) each, so that hundreds of labels do not hold
/// hundreds of MiB of output (each label's file is mostly smaller than
/// 1 MiB, so it was held whole until the end), nor thousands of labels
/// (an instance segmentation's cells) a GiB of buffers.
fn label_buffer(labels: usize) -> usize {
    ((64 << 20) / labels.max(1)).clamp(4 << 10, 1 << 20)
}

/// A label's sink in the pass: its file's, whose `finish` only notes the
/// totals ([`LabelFiles::finish`] finishes the file).
pub struct LabelFile {
    inner: LabelSink,
    /// What the pass's `finish` was given.
    totals: Option<Totals>,
}

impl MeshSink for LabelFile {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.inner.sink().begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.inner.sink().chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.inner.sink().chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.totals = Some(*totals);
        Ok(())
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        match &self.inner {
            LabelSink::Send(sink) => sink.encoder(),
            LabelSink::Local(sink) => sink.encoder(),
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
                inner,
                totals: None,
            });
        }
        Ok(LabelFiles {
            one,
            labels: labels.to_vec(),
            targets,
            files,
        })
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
        let results = finish_all(&mut self.files, cancel)?;
        all_or_none(&self.targets, results)?;
        if let Some((path, dir)) = self.one {
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

/// Finishes the file of every label (the pass has given each its totals):
/// those that may go to another thread on up to [`FINISHING_THREADS`]
/// threads, the others in turn. Finishing a file is mostly waiting for the
/// disk (the last bytes written, the file synced, renamed into place), and
/// one file after another, hundreds of them took longer than the pass.
/// Each file is finished or removed as in the pass; the result of each, in
/// the order of `files` (see [`all_or_none`]).
fn finish_all(files: &mut [LabelFile], cancel: Option<&AtomicBool>) -> Result<Vec<Result<()>>> {
    let never = AtomicBool::new(false);
    let cancel = cancel.unwrap_or(&never);
    let mut results: Vec<Result<()>> = Vec::with_capacity(files.len());
    let mut moving = Vec::new();
    for (i, file) in files.iter_mut().enumerate() {
        let totals = file
            .totals
            .ok_or_else(|| Error::Invalid("a label's mesh was not finished".into()))?;
        results.push(Ok(()));
        match &mut file.inner {
            LabelSink::Send(sink) => moving.push((i, sink, totals)),
            LabelSink::Local(sink) => results[i] = sink.finish_cancellable(&totals, cancel),
        }
    }
    let threads = moving.len().min(FINISHING_THREADS);
    let finished = fan_out(moving, threads, |_, (i, sink, totals)| {
        (i, sink.finish_cancellable(&totals, cancel))
    });
    for (i, result) in finished {
        results[i] = result;
    }
    Ok(results)
}

/// Settles the files finished at `targets` (`results`, in the same order):
/// when one failed, those put in place are removed again, so that a failed
/// run leaves none of its label files behind, whichever threads finished
/// which before the failure (a file it did not put in place, one that was
/// there before, is left alone). The error is the first label's in order;
/// an interruption stays one (exit 130).
fn all_or_none(targets: &[PathBuf], results: Vec<Result<()>>) -> Result<()> {
    let mut placed = Vec::new();
    let mut first_error = None;
    for (target, result) in targets.iter().zip(results) {
        match result {
            Ok(()) => placed.push(target.as_path()),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    match first_error {
        None => Ok(()),
        Some(Error::Interrupted) => {
            for path in placed {
                let _ = std::fs::remove_file(path);
            }
            Err(Error::Interrupted)
        }
        Some(e) => Err(withdraw(placed, e)),
    }
}

#[cfg(test)]
mod tests {
    use super::all_or_none;
    use crate::Error;
    use std::path::PathBuf;

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
        let results = vec![Ok(()), Err(Error::Invalid("disk full".into())), Ok(())];
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
            Ok(()),
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
        all_or_none(&targets, vec![Ok(()), Ok(()), Ok(())]).unwrap();
        assert!(targets.iter().all(|t| t.exists()));
    }
}
