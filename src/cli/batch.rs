//! `tmc extract` in batch: several inputs (or a manifest) and several
//! isovalues per input, one pass over each input, one JSON-lines report line
//! per input.

use super::extract_args::ExtractArgs;
use super::manifest::{self, Item};
use super::monitor::Monitor;
use super::output::{one_line, to_stdout, withdraw};
use super::{memory, report};
use serde::Serialize;
use std::cell::Cell;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;
use tmc::files::check_distinct;
use tmc::stream::check_grid;
use tmc::stream::RunSummary;
use tmc::{Chunk, ChunkEncoder, Error, MeshInfo, MeshSink, Result, Stats, Totals};

/// Inputs of the batch whose outputs were written before a signal stopped
/// it: they are kept, and the interrupted line says so.
pub(crate) static FINISHED_BEFORE_INTERRUPT: AtomicUsize = AtomicUsize::new(0);

/// One report line.
#[derive(Serialize)]
struct Line<'a> {
    input: String,
    outputs: Vec<String>,
    isos: &'a [f64],
    status: &'static str,
    error: Option<String>,
    triangles: Vec<u64>,
    vertices: Vec<u64>,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    line: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    series: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    segment: Option<u32>,
}

/// Runs a batch; fails with the item's own error when it holds one input,
/// else with a summary naming the failed inputs.
pub(crate) fn run(args: &ExtractArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    if let Some(part) = args.part {
        return Err(Error::Invalid(format!(
            "--part {}/{} runs one extraction, not a batch: it takes one input, one isovalue and no batch option (--report, --manifest); use --json for the run's statistics",
            part.index, part.count
        )));
    }
    let items = match (&args.batch.manifest, &args.output) {
        (Some(path), _) => {
            // A manifest can be a FIFO (`--manifest <(...)`): its read may
            // wait for a writer.
            let path = path.clone();
            super::signals::interruptible(cancel, move || manifest::read(&path))?
        }
        (None, Some(template)) => manifest::from_args(&args.input, &args.iso, template)?,
        (None, None) => return Err(Error::Invalid("no output given (-o)".into())),
    };
    if let Some(template) = &args.preview {
        if items.len() > 1 && !template.to_string_lossy().contains("{stem}") {
            return Err(Error::Invalid(format!(
                "{}: with several inputs the preview must contain {{stem}} (e.g. --preview 'out/{{stem}}_{{iso}}.png')",
                template.display()
            )));
        }
        check_unique_pictures(template, &items)?;
    }
    if let Some(path) = &args.batch.report {
        let pictures = (items.iter())
            .flat_map(|i| pictures(args, i))
            .collect::<Vec<_>>();
        check_report_path(path, args.batch.manifest.as_deref(), &items, &pictures)?;
    }
    let mut report = match &args.batch.report {
        Some(path) => {
            // A report can be a FIFO read by another program: its open
            // waits for that reader.
            let owned = path.clone();
            let file = super::signals::interruptible(cancel, move || {
                File::options()
                    .create(true)
                    .append(true)
                    .open(&owned)
                    .map_err(|e| tmc::files::output_error(&owned, e))
            })?;
            Some((file, path))
        }
        None => None,
    };
    let mut failed = Vec::new();
    let mut attempted = 0;
    let mut first_error = None;
    for item in &items {
        attempted += 1;
        let started = Instant::now();
        let result = run_item(args, item, cancel);
        let line = report_line(item, &result, started.elapsed().as_secs_f64());
        // The item's meshes (and pictures) are committed; if its report
        // line cannot be written, the run fails and takes them back.
        let drawn = pictures(args, item);
        let withdraw = |e| match result {
            Ok(_) => withdraw(item.outputs.iter().chain(&drawn).map(PathBuf::as_path), e),
            Err(_) => e,
        };
        if let Some((file, path)) = &mut report {
            file.write_all(line.as_bytes())
                .and_then(|()| file.flush())
                .map_err(|e| withdraw(Error::io(path.as_path(), e)))?;
        }
        if args.json {
            to_stdout(|out| out.write_all(line.as_bytes())).map_err(withdraw)?;
        }
        match result {
            Ok(_) => {}
            Err(Error::Interrupted) => {
                let finished = attempted - 1 - failed.len();
                FINISHED_BEFORE_INTERRUPT.store(finished, Ordering::SeqCst);
                return Err(Error::Interrupted);
            }
            Err(e) => {
                if items.len() > 1 {
                    // Most messages name the input already.
                    let input = item.input.display().to_string();
                    let message = e.to_string();
                    let message = if message.contains(&input) {
                        message
                    } else {
                        format!("{input}: {message}")
                    };
                    say!("tmc: error: {}", one_line(&message));
                }
                failed.push(item.input.display().to_string());
                first_error.get_or_insert(e);
                if !args.batch.keep_going {
                    break;
                }
            }
        }
    }
    match first_error {
        None => Ok(()),
        Some(e) if items.len() == 1 => Err(e),
        Some(_) => {
            let skipped = items.len() - attempted;
            Err(Error::Invalid(format!(
                "{} of {} inputs failed: {}{}",
                failed.len(),
                items.len(),
                failed.join(", "),
                if skipped > 0 {
                    format!("; stopped there, {skipped} not run (--keep-going runs them)")
                } else {
                    String::new()
                }
            )))
        }
    }
}

/// Fails when two items of the batch would draw the same picture (two
/// manifest lines of one input, or inputs of one name in two folders,
/// with `--preview 'out/{stem}.png'`): the second replaced the first
/// without a word, where two meshes of one name are refused.
fn check_unique_pictures(template: &Path, items: &[Item]) -> Result<()> {
    let mut seen = std::collections::HashSet::new();
    for item in items {
        for picture in manifest::outputs(template, &item.input, &item.isos) {
            if !seen.insert(manifest::file_key(&picture)) {
                return Err(Error::Invalid(format!(
                    "{}: two previews of the batch have this name; use {{stem}} and {{iso}} in the preview's name",
                    picture.display()
                )));
            }
        }
    }
    Ok(())
}

/// Refuses a report path that is the manifest, an input, an output or a
/// preview picture (`pictures`) of the batch: the report is appended to
/// while they are read or replaced (a picture replaced the report's lines).
fn check_report_path(
    report: &Path,
    manifest: Option<&Path>,
    items: &[Item],
    pictures: &[PathBuf],
) -> Result<()> {
    let inputs = items.iter().map(|item| (&item.input, "an input"));
    let outputs = items
        .iter()
        .flat_map(|item| item.outputs.iter().map(|o| (o, "an output")));
    let manifest = manifest.map(|m| (m, "the manifest"));
    let clashes = manifest
        .into_iter()
        .chain(inputs.map(|(p, what)| (p.as_path(), what)))
        .chain(outputs.map(|(p, what)| (p.as_path(), what)))
        .chain(pictures.iter().map(|p| (p.as_path(), "a preview")))
        .find(|(path, _)| same_path(report, path));
    match clashes {
        Some((path, what)) => Err(Error::Invalid(format!(
            "{}: the report is {what} of the batch ({}); choose another --report path",
            report.display(),
            path.display()
        ))),
        None => Ok(()),
    }
}

/// Whether `a` and `b` name the same file: the same absolute path, or (when
/// both exist) the same file through links.
fn same_path(a: &Path, b: &Path) -> bool {
    if let (Ok(x), Ok(y)) = (std::path::absolute(a), std::path::absolute(b)) {
        if x == y {
            return true;
        }
    }
    check_distinct(a, b).is_err()
}

/// The report line of `item` (with its newline).
fn report_line(item: &Item, result: &Result<Vec<Stats>>, seconds: f64) -> String {
    let (status, error, stats) = match result {
        Ok(stats) => ("ok", None, &stats[..]),
        Err(e) => ("failed", Some(one_line(&e.to_string())), &[][..]),
    };
    let line = Line {
        input: item.input.display().to_string(),
        outputs: item
            .outputs
            .iter()
            .map(|o| o.display().to_string())
            .collect(),
        isos: &item.isos,
        status,
        error,
        triangles: stats.iter().map(|s| s.triangles).collect(),
        vertices: stats.iter().map(|s| s.vertices).collect(),
        seconds,
        line: item.line,
        series: item.series.as_deref(),
        segment: item.segment,
    };
    let mut text = serde_json::to_string(&line).expect("a report line serialises");
    text.push('\n');
    text
}

/// The pictures `--preview` draws of `item`, one per output; none without
/// `--preview`.
fn pictures(args: &ExtractArgs, item: &Item) -> Vec<PathBuf> {
    (args.preview.iter())
        .flat_map(|t| manifest::outputs(t, &item.input, &item.isos))
        .collect()
}

/// Extracts every isovalue of `item` in one pass; returns the statistics
/// of each output.
fn run_item(args: &ExtractArgs, item: &Item, cancel: Option<&AtomicBool>) -> Result<Vec<Stats>> {
    let started = Instant::now();
    for output in &item.outputs {
        args.check_normals_output(output)?;
        check_distinct(&item.input, output)?;
    }
    let mut raw = args.raw.clone();
    if item.series.is_some() {
        raw.series = item.series.clone();
    }
    if item.segment.is_some() {
        raw.segment = item.segment;
    }
    let source = super::raw_input::open_input(&item.input, &raw, cancel, args.quiet)?;
    for (data, output) in source
        .data_files()
        .iter()
        .flat_map(|d| item.outputs.iter().map(move |o| (d, o)))
    {
        check_distinct(data, output)?;
    }
    let grid = *source.grid();
    check_grid(&item.input, &grid, args.close)?;
    for output in &item.outputs {
        tmc::export::check_output_path(output)?;
    }
    let pictures = pictures(args, item);
    let meshes: Vec<&Path> = item.outputs.iter().map(PathBuf::as_path).collect();
    for picture in &pictures {
        tmc::preview::check_picture(picture, Some(&item.input), &meshes)?;
    }
    let params: Vec<_> = item.isos.iter().map(|&iso| args.params(iso)).collect();
    let mut monitor = Monitor::new(&grid, args, &item.input);
    let on_progress = |p: &tmc::Progress| monitor.slab_done(p);
    let options = args.pipeline_options(&on_progress, cancel);
    let no_surface = |iso: f64| {
        format!(
            "no surface at isovalue {}: every sample of {} is on the same side of it (the isovalue is outside the data range)",
            tmc::params::number_text(iso),
            item.input.display()
        )
    };
    let mut files = item
        .outputs
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let sink = tmc::export::create_sink(o)?;
            Ok(match pictures.get(i) {
                Some(picture) => {
                    let title = tmc::preview::title_of(&item.input);
                    let threads = args.threads.unwrap_or(0);
                    tmc::preview::WithPreview::wrap(sink, o, picture, title, threads)
                }
                None => sink,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let triangles = vec![Cell::new(0); item.isos.len()];
    let messages: Vec<String> = item
        .isos
        .iter()
        .map(|&iso| format!("{}; nothing written (--require-surface)", no_surface(iso)))
        .collect();
    let mut guards: Vec<RequireAll> = files
        .iter_mut()
        .enumerate()
        .map(|(index, sink)| RequireAll {
            inner: sink.as_mut(),
            index,
            triangles: &triangles,
            messages: &messages,
        })
        .collect();
    let mut sinks: Vec<&mut dyn MeshSink> = if args.require_surface {
        guards.iter_mut().map(|g| g as &mut dyn MeshSink).collect()
    } else {
        guards.iter_mut().map(|g| &mut *g.inner).collect()
    };
    let stats = tmc::extract_many_to(source.as_ref(), &params, &options, &mut sinks)?;
    let peak_anon = monitor.finish();
    for ((s, output), p) in stats.iter().zip(&item.outputs).zip(&params) {
        if s.triangles == 0 && !args.quiet {
            say!(
                "tmc: note: {}; wrote an empty mesh to {}",
                no_surface(p.iso),
                output.display()
            );
        }
        if args.stats {
            let resources = report::Resources {
                slab_depth: args.slab_depth.map(usize::from),
                bytes_read: report::bytes_read(s, &grid, source.sample_bytes(), p.close),
                bytes_written: std::fs::metadata(output).ok().map(|m| m.len()),
                peak_rss_anon_bytes: peak_anon,
                vm_hwm_bytes: memory::peak_resident(),
                wall_seconds: started.elapsed().as_secs_f64(),
            };
            let run = report::Run {
                input: &item.input,
                output,
                summary: RunSummary::new(p, &grid, s),
                resources: &resources,
            };
            let mut err = std::io::stderr().lock();
            report::write_table(&mut err, &run).map_err(|e| Error::io("standard error", e))?;
        }
    }
    Ok(stats)
}

/// `--require-surface` over several isovalues: no output is finished unless
/// every isovalue has a surface. [`tmc::extract_many_to`] hands every sink
/// all its chunks before it finishes the first, so the counts are complete
/// when `finish` looks at them.
struct RequireAll<'a> {
    /// The sink that writes this isovalue's output.
    inner: &'a mut dyn MeshSink,
    /// Which isovalue this is.
    index: usize,
    /// Triangles seen so far, per isovalue.
    triangles: &'a [Cell<u64>],
    /// The error message per isovalue, for an empty mesh.
    messages: &'a [String],
}

impl RequireAll<'_> {
    /// Fails when some isovalue has no triangle.
    fn check(&self) -> Result<()> {
        match self.triangles.iter().position(|t| t.get() == 0) {
            Some(empty) => Err(Error::Invalid(self.messages[empty].clone())),
            None => Ok(()),
        }
    }

    /// Adds the triangles of `chunk` to this isovalue's count.
    fn count(&self, chunk: &Chunk) {
        let seen = &self.triangles[self.index];
        seen.set(seen.get() + chunk.triangles.len() as u64);
    }
}

impl MeshSink for RequireAll<'_> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.inner.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.count(chunk);
        self.inner.chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.count(chunk);
        self.inner.chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.check()?;
        self.inner.finish(totals)
    }

    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.check()?;
        self.inner.finish_cancellable(totals, cancel)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.inner.encoder()
    }
}
