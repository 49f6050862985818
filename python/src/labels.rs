//! Label maps: every label's surface in one pass over the volume
//! ([`tmc::stream::extract_labels_to`]), into numpy arrays
//! (`extract_labels`) or streamed into files as `tmc extract --labels`
//! writes them (`extract_labels_to`, with the library's
//! [`tmc::export::LabelFiles`], and the figures of its `--json` counted by
//! [`tmc::check::Measured`]).

use crate::array::MappedAt;
use crate::extract::{params, preflight, report, Collected, Input, Select};
use crate::output::arrays;
use crate::record::Recorder;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::check::{measure_reports, Measured};
use tmc::export::{LabelFiles, LabelSink};
use tmc::preview::LabelPicture;
use tmc::stream::label_report::label_reports;
use tmc::stream::LabelRun;
use tmc::volume::{LabelCounts, MapRuns};
use tmc::{ExtractParams, MeshSink, SampleSource};

/// The labels of `source` to extract (`labels`, or every value present
/// but `background`), with the counts of its values and the runs the scan
/// kept for the pass (the package sets no memory budget); a sample that
/// is not a whole number is an error naming its position.
fn choose(
    source: &dyn SampleSource,
    path: Option<&Path>,
    labels: Option<&[i64]>,
    background: i64,
    params: &ExtractParams,
    cancel: &AtomicBool,
) -> tmc::Result<(Vec<i64>, LabelCounts, MapRuns)> {
    let name = path.unwrap_or(Path::new("array"));
    let (counts, runs) =
        tmc::volume::scan_label_map(name, source, Some(cancel), params.threads, None)?;
    let chosen = counts.select(labels, background, name)?;
    Ok((chosen, counts, runs))
}

/// The parameters of every label's indicator: isovalue 0.5, inside high,
/// the method of TMC.
fn label_params(close: bool, threads: usize, normals: bool) -> PyResult<ExtractParams> {
    params(0.5, "tmc", "high", close, threads, normals)
}

/// One label's mesh as `extract` returns it: the label, then `extract`'s
/// tuple.
type LabelMesh<'py> = (i64, Bound<'py, PyAny>);

/// Extracts the surface of each label of `input` (a 3-D array indexed
/// `[z][y][x]`, or a path) in one pass into memory. `labels` is the list
/// to extract, `None` for every value present but `background`. Returns a
/// list of `(label, (vertices, triangles, normals or None, report JSON,
/// record))`, each tuple what `extract` gives for that label's 0/1
/// indicator at 0.5.
#[pyfunction]
#[pyo3(signature = (input, labels, background, spacing, origin, mapped, close, threads, normals, select, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn extract_labels<'py>(
    py: Python<'py>,
    input: &Bound<'py, PyAny>,
    labels: Option<Vec<i64>>,
    background: i64,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
    close: bool,
    threads: usize,
    normals: bool,
    select: Select,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Vec<LabelMesh<'py>>> {
    let params = label_params(close, threads, normals)?;
    let input = Input::new(input, spacing, origin, mapped, select)?;
    let collected: Vec<(i64, Collected)> = input.run(py, progress, |source, path, watch| {
        let options = preflight(source, path, &params, None, watch)?;
        let (labels, _, runs) = choose(
            source,
            path,
            labels.as_deref(),
            background,
            &params,
            &watch.cancel,
        )?;
        // One collector per label: the meshes asked for, nothing more.
        let mut recorders: Vec<Recorder<[f64; 3]>> =
            labels.iter().map(|_| Recorder::default()).collect();
        let mut sinks: Vec<&mut dyn MeshSink> = recorders
            .iter_mut()
            .map(|r| r as &mut dyn MeshSink)
            .collect();
        let stats = tmc::stream::extract_labels_with_runs_to(
            source, &runs, &labels, &params, &options, None, &mut sinks,
        )?;
        drop(sinks);
        let mut out = Vec::with_capacity(labels.len());
        for ((label, recorder), stats) in labels.into_iter().zip(recorders).zip(&stats) {
            let report = report(path, None, source, &params, stats)?;
            let record = recorder.record();
            let (vertices, triangles, normals) = recorder.collector.into_parts();
            out.push((label, (vertices, triangles, normals, report, record)));
        }
        Ok(out)
    })?;
    let mut meshes = Vec::with_capacity(collected.len());
    for (label, (vertices, triangles, n, report, record)) in collected {
        let (v, t, n) = arrays(py, vertices, triangles, normals.then_some(n))?;
        let mesh = (v, t, n, report, record).into_pyobject(py)?.into_any();
        meshes.push((label, mesh));
    }
    Ok(meshes)
}

/// Streams the surface of each label of `input` (array or path) into the
/// files `output` names, in one pass, as `tmc extract --labels` writes
/// them: `{label}` in `output` for a file per label, else one `.ply` or
/// `.tmesh` with a per-face label. Every file appears whole or none does.
/// Returns the report JSON (`tmc extract --labels --json`'s object); with
/// `stats`, each label's components, genus, closed, area and enclosed
/// volume counted while its chunks stream ([`tmc::check::Measured`], as
/// the CLI counts them), else without them.
#[pyfunction]
#[pyo3(signature = (input, output, labels, background, spacing, origin, mapped, close, threads, normals, select, stats = false, preview = None, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn extract_labels_to(
    py: Python<'_>,
    input: &Bound<'_, PyAny>,
    output: PathBuf,
    labels: Option<Vec<i64>>,
    background: i64,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
    close: bool,
    threads: usize,
    normals: bool,
    select: Select,
    stats: bool,
    preview: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let params = label_params(close, threads, normals)?;
    let input = Input::new(input, spacing, origin, mapped, select)?;
    input.run(py, progress, |source, path, watch| {
        let cancel = &watch.cancel;
        let started = Instant::now();
        // The name's form first, before the volume is read; `{label}` is
        // the one placeholder filled in ('{stem}' would stay in the name).
        crate::extract::refuse_placeholders(&output, &["{label}"])?;
        if let Some(picture) = &preview {
            crate::extract::refuse_placeholders(picture, &[])?;
        }
        tmc::export::check_normals_output(&output, normals)?;
        tmc::export::check_label_template(&output, labels.as_deref().unwrap_or_default())?;
        let options = preflight(source, path, &params, None, watch)?;
        let (labels, counts, runs) =
            choose(source, path, labels.as_deref(), background, &params, cancel)?;
        let scan_seconds = started.elapsed().as_secs_f64();
        let outputs = tmc::export::label_outputs(&output, &labels)?;
        let inputs: Vec<&Path> = path.into_iter().chain(source.data_files()).collect();
        tmc::export::check_label_outputs(&outputs, &inputs)?;
        if let Some(picture) = &preview {
            let outputs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
            tmc::preview::check_picture(picture, path, &outputs)?;
        }
        let picture = preview.as_ref().map(|picture| {
            let title = tmc::preview::title_of(path.unwrap_or(&output));
            LabelPicture::new(picture, title, params.threads, &labels)
        });
        // Every label's file stays open until all are committed.
        tmc::files::raise_open_file_limit();
        tmc::files::check_open_files(labels.len(), tmc::export::open_files_per_label(&output))?;
        let pass_start = Instant::now();
        let mut files = LabelFiles::create(&output, &labels, &outputs, |target, _| {
            LabelSink::create(target, labels.len())
        })?;
        files.finish_early(&tmc::stream::last_label_chunks(
            &counts,
            &labels,
            params.close,
        ));
        let mut measured = Measured::all(
            files.sinks().iter_mut().map(|f| f as &mut dyn MeshSink),
            stats,
        );
        let mut paired = Vec::new();
        let mut sinks = LabelPicture::sinks(picture.as_ref(), &mut measured, &mut paired);
        let label_stats = tmc::stream::extract_labels_with_runs_to(
            source, &runs, &labels, &params, &options, None, &mut sinks,
        )?;
        drop(sinks);
        let grid = source.grid();
        let mut reports = label_reports(&labels, &outputs, &label_stats, &counts, grid);
        // Each label's last chunk counted before any file is put in place.
        measure_reports(measured, &mut reports)?;
        // The picture before the files are settled, as the CLI does.
        if let Some(picture) = &picture {
            picture.finish()?;
        }
        files
            .finish(Some(cancel))
            .map_err(|e| tmc::files::withdraw(preview.as_deref(), e))?;
        let pass_seconds = pass_start.elapsed().as_secs_f64();
        let run = LabelRun {
            input: path.unwrap_or(Path::new("array")).display().to_string(),
            close: params.close,
            method: params.method.name(),
            background,
            labels: &reports,
            scan_seconds,
            pass_seconds,
            seconds: started.elapsed().as_secs_f64(),
        };
        serde_json::to_string(&run).map_err(|e| {
            tmc::files::withdraw(
                outputs.iter().map(PathBuf::as_path),
                tmc::Error::Invalid(e.to_string()),
            )
        })
    })
}
