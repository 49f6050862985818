//! `tmc extract --labels`: the boundary surface of each label of a
//! segmentation in one pass ([`tmc::stream::extract_labels_to`]), one file
//! per label (`{label}` in `-o`) or one PLY or `.tmesh` with a per-face
//! label; with `--part I/N`, one part file per label.
//!
//! The values are counted first ([`tmc::volume::scan_labels_on`]: one
//! reading of the volume, plane by plane on `--threads` threads, which also
//! refuses a sample that is not a whole number); `all` is every value
//! present but the background. The label files are finished after the
//! pass, several at once ([`finish_all`]).

use super::extract_args::{ExtractArgs, InsideArg};
use super::monitor::Monitor;
use super::output::{to_stdout, withdraw};
use serde::Serialize;
use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::check::{Scratch, StreamCheck, Verdict};
use tmc::fan_out::fan_out;
use tmc::files::check_distinct;
use tmc::stream::check_grid;
use tmc::{Chunk, ChunkEncoder, Error, MeshInfo, MeshSink, Result, Totals};

/// One label's figures for `--stats` and `--json`.
#[derive(Serialize)]
struct LabelReport {
    label: i64,
    output: String,
    triangles: u64,
    vertices: u64,
    /// Samples of the label; `voxel_volume` is their count times the
    /// volume of a voxel.
    samples: u64,
    voxel_volume: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    components: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    genus: Option<i64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    closed: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    area: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    enclosed_volume: Option<f64>,
}

/// The `--json` object of a label run.
#[derive(Serialize)]
struct LabelRun<'a> {
    input: String,
    close: bool,
    method: &'static str,
    background: i64,
    labels: &'a [LabelReport],
    scan_seconds: f64,
    pass_seconds: f64,
    seconds: f64,
}

/// Refuses a DICOM Segmentation whose segments overlap: its label map
/// gives a shared sample to one segment only, so the meshes would not be
/// the segments'.
fn refuse_overlaps(input: &Path, pairs: &[[u32; 2]]) -> Result<()> {
    if pairs.is_empty() {
        return Ok(());
    }
    let pairs: Vec<String> = pairs.iter().map(|[a, b]| format!("{a} and {b}")).collect();
    Err(Error::Invalid(format!(
        "{}: segments {} overlap, and a label map holds one segment per sample; extract each with --segment N --iso 0.5",
        input.display(),
        pairs.join(", ")
    )))
}

/// Runs `tmc extract --labels`.
pub(crate) fn run(args: &ExtractArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    let started = Instant::now();
    let (input, template) = match (&args.input[..], &args.output) {
        ([input], Some(output)) if !args.batch.given() => (input, output),
        _ => {
            return Err(Error::Invalid(
                "--labels takes one input and -o (no batch options)".into(),
            ))
        }
    };
    let spec = args.labels.as_deref().unwrap_or("all");
    let background = args.background.unwrap_or(0);
    let text = template.to_string_lossy();
    let per_label = text.contains("{label}");
    let one_file = template
        .extension()
        .is_some_and(|e| e == "ply" || e == "tmesh");
    if !per_label && !one_file {
        return Err(Error::Invalid(format!(
            "{}: with --labels, -o must contain {{label}} (one file per label) or be one .ply or .tmesh (a per-face label)",
            template.display()
        )));
    }
    if args.part.is_some() && (!per_label || template.extension().is_none_or(|e| e != "tmesh")) {
        return Err(Error::Invalid(format!(
            "{}: --labels with --part writes one part file per label for 'tmc merge': -o must contain {{label}} and end in .tmesh",
            template.display()
        )));
    }
    if args.part.is_some() && (args.stats || args.json) {
        return Err(Error::Invalid(
            "--labels with --part writes part files: --stats and --json need the merged meshes"
                .into(),
        ));
    }
    if args.inside == InsideArg::Low {
        return Err(Error::Invalid(
            "--inside low does not apply to --labels: a label's surface always faces out of the label's samples".into(),
        ));
    }
    args.check_normals_output(template)?;
    let source = super::raw_input::open_input(input, &args.raw, cancel, args.quiet)?;
    let grid = *source.grid();
    check_grid(input, &grid, args.close)?;
    refuse_overlaps(input, &source.notes().overlapping_segments)?;
    let scan_start = Instant::now();
    let counts = tmc::volume::scan_labels_on(source.as_ref(), cancel, args.threads.unwrap_or(0))
        .map_err(|e| name_input(input, e))?;
    let scan_seconds = scan_start.elapsed().as_secs_f64();
    let labels = match spec {
        "all" => counts.labels_except(background),
        list => parse_list(list)?,
    };
    if labels.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: no label but the background {background}",
            input.display()
        )));
    }
    let outputs: Vec<PathBuf> = if per_label {
        let text = text.replace("{stem}", &super::manifest::stem(input));
        labels
            .iter()
            .map(|l| PathBuf::from(text.replace("{label}", &l.to_string())))
            .collect()
    } else {
        if let Some(l) = labels.iter().find(|&&l| u32::try_from(l).is_err()) {
            return Err(Error::Invalid(format!(
                "label {l} does not fit the uint32 per-face label of one file; write one file per label with {{label}}"
            )));
        }
        vec![template.clone()]
    };
    for output in &outputs {
        check_distinct(input, output)?;
        for data in source.data_files() {
            check_distinct(data, output)?;
        }
    }
    // One file created and removed per directory, not per label.
    tmc::export::check_output_paths(outputs.iter().map(PathBuf::as_path))?;
    // One file: each label goes to a .tmesh in a temporary directory beside
    // the output, assembled into the one file at the end.
    let spool = match per_label {
        true => None,
        false => {
            let dir = template
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            let spool = tempfile::Builder::new()
                .prefix(".tmc-labels-")
                .tempdir_in(dir)
                .map_err(|e| Error::io(dir, e))?;
            Some(spool)
        }
    };
    let targets: Vec<PathBuf> = match &spool {
        Some(dir) => labels
            .iter()
            .map(|l| dir.path().join(format!("{l}.tmesh")))
            .collect(),
        None => outputs.clone(),
    };
    let measure = args.stats || args.json;
    // With --part, one part file per label, recording its label.
    let record = match args.part {
        Some(spec) => {
            let reading = args.raw.options().map(|r| format!("{r:?}"));
            let source = source.as_ref();
            Some(tmc::part::PartRecord::new(
                spec, input, source, args.close, reading,
            )?)
        }
        None => None,
    };
    let mut sinks = Vec::with_capacity(labels.len());
    // One working space for every label's check: the pass writes one
    // label's chunk at a time.
    let scratch = Rc::new(RefCell::new(Scratch::default()));
    for (target, &label) in targets.iter().zip(&labels) {
        let inner = match &record {
            Some(record) => {
                let record = tmc::part::PartRecord {
                    label: Some(label),
                    ..record.clone()
                };
                Inner::Send(Box::new(tmc::part::PartWriter::create(target, record)?))
            }
            None if target.extension().is_some_and(|e| e == "tmesh") => Inner::Send(Box::new(
                tmc::meshfile::TmeshWriter::create_buffered(target, label_buffer(labels.len()))?,
            )),
            None => Inner::Local(tmc::export::create_sink(target)?),
        };
        sinks.push(Measured {
            inner,
            measure: measure.then(|| Measure::new(Rc::clone(&scratch))),
            totals: None,
        });
    }
    let mut dyn_sinks: Vec<&mut dyn MeshSink> =
        sinks.iter_mut().map(|s| s as &mut dyn MeshSink).collect();
    let params = args.params(0.5);
    let mut monitor = Monitor::new(&grid, args, input);
    let on_progress = |p: &tmc::Progress| monitor.slab_done(p);
    let options = args.pipeline_options(&on_progress, cancel);
    let pass_start = Instant::now();
    let part = args.part.map(|p| (p.index, p.count));
    let stats = tmc::stream::extract_labels_to(
        source.as_ref(),
        &labels,
        &params,
        &options,
        part,
        &mut dyn_sinks,
    )?;
    drop(dyn_sinks);
    let finished = finish_all(&mut sinks, cancel)?;
    all_or_none(&targets, finished)?;
    monitor.finish();
    if let Some(dir) = spool {
        let parts: Vec<(u32, &Path)> = labels
            .iter()
            .zip(&targets)
            .map(|(&l, t)| (l as u32, t.as_path()))
            .collect();
        let never = AtomicBool::new(false);
        tmc::export::write_labelled(template, &parts, cancel.unwrap_or(&never))?;
        dir.close().map_err(|e| Error::io(template, e))?;
    }
    let pass_seconds = pass_start.elapsed().as_secs_f64();
    if !measure {
        return Ok(());
    }
    let voxel = voxel_volume(&grid);
    let reports: Vec<LabelReport> = labels
        .iter()
        .zip(&mut sinks)
        .zip(&stats)
        .enumerate()
        .map(|(i, ((&label, sink), stats))| {
            let output = outputs[if per_label { i } else { 0 }].display().to_string();
            let measured = sink.measure.take().map(Measure::finish).transpose()?;
            let checked = measured
                .as_ref()
                .and_then(|(v, sums)| Some((v.checked()?, sums)));
            let samples = counts.samples(label);
            Ok(LabelReport {
                label,
                output,
                triangles: stats.triangles,
                vertices: stats.vertices,
                samples,
                voxel_volume: samples as f64 * voxel,
                components: checked.map(|(c, _)| c.components as usize),
                genus: checked.and_then(|(c, _)| c.genus),
                closed: checked.map(|(c, _)| c.closed_manifold),
                area: checked.map(|(_, s)| s.area),
                enclosed_volume: checked.map(|(_, s)| s.volume),
            })
        })
        .collect::<Result<_>>()?;
    let written: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    if args.stats {
        write_table(&reports)
            .map_err(|e| withdraw(written.iter().copied(), Error::io("standard error", e)))?;
    }
    if args.json {
        let run = LabelRun {
            input: input.display().to_string(),
            close: args.close,
            method: params.method.name(),
            background,
            labels: &reports,
            scan_seconds,
            pass_seconds,
            seconds: started.elapsed().as_secs_f64(),
        };
        to_stdout(|out| {
            serde_json::to_writer(&mut *out, &run).map_err(std::io::Error::other)?;
            writeln!(out)
        })
        .map_err(|e| withdraw(written.iter().copied(), e))?;
    }
    Ok(())
}

/// The bytes each label's `.tmesh` writer gathers before it writes them:
/// 64 MiB shared by all labels, between 64 KiB and 1 MiB (a single
/// extraction's buffer) each, so that hundreds of labels do not hold
/// hundreds of MiB of output (each label's file is mostly smaller than
/// 1 MiB, so it was held whole until the end).
fn label_buffer(labels: usize) -> usize {
    ((64 << 20) / labels.max(1)).clamp(64 << 10, 1 << 20)
}

/// Prefixes the input's name unless the message has it.
fn name_input(input: &Path, e: Error) -> Error {
    match e {
        Error::Invalid(m) => Error::Invalid(format!("{}: {m}", input.display())),
        other => other,
    }
}

/// `L1,L2,...`: integers, each once.
fn parse_list(list: &str) -> Result<Vec<i64>> {
    let mut labels = Vec::new();
    for item in list.split(',') {
        let l: i64 = item.trim().parse().map_err(|_| {
            Error::Invalid(format!(
                "--labels: '{item}' is not an integer (give 'all' or L1,L2,...)"
            ))
        })?;
        if labels.contains(&l) {
            return Err(Error::Invalid(format!("--labels: {l} is given twice")));
        }
        labels.push(l);
    }
    Ok(labels)
}

/// The volume of one voxel: |det| of the index-to-world map's matrix.
fn voxel_volume(grid: &tmc::Grid) -> f64 {
    let m: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| grid.direction[i][j] * grid.spacing[j]));
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    det.abs()
}

/// Surface area and enclosed volume (divergence theorem, outward
/// triangles: positive for a closed surface), summed in `f64` triangle by
/// triangle in the order of the file, so that the sums do not depend on
/// the threads, the slab depth or the parts.
#[derive(Debug, Default, Clone, Copy)]
struct Sums {
    area: f64,
    volume: f64,
}

impl Sums {
    /// Adds `triangles`, whose corners index `vertices`.
    fn add(&mut self, vertices: &[[f32; 3]], triangles: &[[u32; 3]]) {
        for t in triangles {
            let corner = |k: u32| vertices.get(k as usize).map(|p| p.map(f64::from));
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                continue;
            };
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            self.area += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0;
            // a . (b x c) / 6
            let bc = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            self.volume += (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]) / 6.0;
        }
    }
}

/// The `--stats` table on stderr.
fn write_table(reports: &[LabelReport]) -> std::io::Result<()> {
    let mut err = std::io::stderr().lock();
    let opt = |v: Option<String>| v.unwrap_or_else(|| "-".into());
    writeln!(
        err,
        "{:>8} {:>10} {:>6} {:>6} {:>7} {:>14} {:>14} {:>14}",
        "label", "triangles", "comps", "genus", "closed", "area", "volume", "voxels*voxel"
    )?;
    for r in reports {
        writeln!(
            err,
            "{:>8} {:>10} {:>6} {:>6} {:>7} {:>14} {:>14} {:>14.3}",
            r.label,
            r.triangles,
            opt(r.components.map(|c| c.to_string())),
            opt(r.genus.map(|g| g.to_string())),
            opt(r.closed.map(|c| if c { "yes" } else { "no" }.to_string())),
            opt(r.area.map(|a| format!("{a:.3}"))),
            opt(r.enclosed_volume.map(|v| format!("{v:.3}"))),
            r.voxel_volume,
        )?;
    }
    Ok(())
}

/// A label's sink: its file's, and the figures for `--stats`. The pass's
/// `finish` only notes the totals: the files are finished after the pass,
/// all labels at once ([`finish_all`]).
struct Measured {
    inner: Inner,
    measure: Option<Measure>,
    /// What the pass's `finish` was given.
    totals: Option<Totals>,
}

/// A label's figures for `--stats`, counted while its chunks stream: a
/// [`StreamCheck::full`] (components, genus, closed: the figures `tmc
/// check` gives the label's file) and the [`Sums`], over a window of two
/// chunks. Each chunk waits for the next one's vertices, which its
/// triangles end in; a label absent from the planes being written holds
/// nothing but counters.
struct Measure {
    check: StreamCheck,
    /// The working space of every label's check.
    scratch: Rc<RefCell<Scratch>>,
    sums: Sums,
    pending: Option<Pending>,
}

/// The last chunk's vertices (with room for the next one's first) and
/// triangles, and how many of the next chunk's vertices they use.
struct Pending {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    next: u32,
}

impl Measure {
    fn new(scratch: Rc<RefCell<Scratch>>) -> Self {
        Measure {
            check: StreamCheck::full(),
            scratch,
            sums: Sums::default(),
            pending: None,
        }
    }

    /// Counts the pending chunk with the first vertices of `after` (none
    /// after the last).
    fn flush(&mut self, after: &[[f32; 3]]) -> Result<()> {
        let Some(Pending {
            mut vertices,
            triangles,
            next,
        }) = self.pending.take()
        else {
            return Ok(());
        };
        let Some(first) = after.get(..next as usize) else {
            return Err(Error::Invalid(
                "a label's triangle refers to a vertex past the next chunk's".into(),
            ));
        };
        let own = vertices.len() as u32;
        vertices.extend_from_slice(first);
        self.sums.add(&vertices, &triangles);
        let mut scratch = self.scratch.borrow_mut();
        self.check.chunk(&mut scratch, own, next, &triangles);
        Ok(())
    }

    /// Takes `chunk` in, counting the one before.
    fn chunk(&mut self, chunk: &Chunk) -> Result<()> {
        self.flush(&chunk.vertices)?;
        let Ok(own) = u32::try_from(chunk.vertices.len()) else {
            return Err(Error::Invalid("a label's chunk is too large".into()));
        };
        let top = chunk
            .triangles
            .iter()
            .map(|t| t[0].max(t[1]).max(t[2]))
            .max();
        let next = top.map_or(0, |i| i.saturating_add(1).saturating_sub(own));
        let mut vertices = Vec::with_capacity(own as usize + next as usize);
        vertices.extend_from_slice(&chunk.vertices);
        self.pending = Some(Pending {
            vertices,
            triangles: chunk.triangles.clone(),
            next,
        });
        Ok(())
    }

    /// The verdict and the sums once the last chunk is in.
    fn finish(mut self) -> Result<(Verdict, Sums)> {
        self.flush(&[])?;
        Ok((self.check.finish(), self.sums))
    }
}

/// A label's file sink: one that may be finished on another thread (the
/// `.tmesh` and part writers), or one that may not.
enum Inner {
    Send(Box<dyn MeshSink + Send>),
    Local(Box<dyn MeshSink>),
}

impl Inner {
    fn sink(&mut self) -> &mut dyn MeshSink {
        match self {
            Inner::Send(sink) => &mut **sink,
            Inner::Local(sink) => &mut **sink,
        }
    }
}

impl MeshSink for Measured {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.inner.sink().begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        if let Some(m) = &mut self.measure {
            m.chunk(chunk)?;
        }
        self.inner.sink().chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        if let Some(m) = &mut self.measure {
            m.chunk(chunk)?;
        }
        self.inner.sink().chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.totals = Some(*totals);
        Ok(())
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        match &self.inner {
            Inner::Send(sink) => sink.encoder(),
            Inner::Local(sink) => sink.encoder(),
        }
    }
}

/// The most threads that finish label files at once.
const FINISHING_THREADS: usize = 16;

/// Finishes the file of every label (the pass has given each its totals):
/// those that may go to another thread on up to [`FINISHING_THREADS`]
/// threads, the others in turn. Finishing a file is mostly waiting for the
/// disk (the last bytes written, the file synced, renamed into place), and
/// one file after another, hundreds of them took longer than the pass.
/// Each file is finished or removed as in the pass; the result of each, in
/// the order of `sinks` (see [`all_or_none`]).
fn finish_all(sinks: &mut [Measured], cancel: Option<&AtomicBool>) -> Result<Vec<Result<()>>> {
    let never = AtomicBool::new(false);
    let cancel = cancel.unwrap_or(&never);
    let mut results: Vec<Result<()>> = Vec::with_capacity(sinks.len());
    let mut moving = Vec::new();
    for (i, measured) in sinks.iter_mut().enumerate() {
        let totals = measured
            .totals
            .ok_or_else(|| Error::Invalid("a label's mesh was not finished".into()))?;
        results.push(Ok(()));
        match &mut measured.inner {
            Inner::Send(sink) => moving.push((i, sink, totals)),
            Inner::Local(sink) => results[i] = sink.finish_cancellable(&totals, cancel),
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
    use std::path::PathBuf;
    use tmc::Error;

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
