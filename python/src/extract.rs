//! The extraction calls: into numpy arrays (`extract`) or streamed into a
//! file of any output format (`extract_to`), from an array or a path.

use crate::array::{self, MappedAt};
use crate::interrupt::{self, Watch};
use crate::output::{arrays, rows};
use crate::record::{Record, Recorder};
use crate::skimage::SkimageArrays;
use crate::sliced::{self, PySlices, SlicedArray};
use crate::values;
use numpy::PyUntypedArray;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::{Mutex, PoisonError};
use tmc::volume::zarr::ZarrSelect;
use tmc::{ExtractParams, Inside, Method, PipelineOptions, SampleSource};

/// The volume argument: an array (with its grid), a lazy array read a
/// slice of planes at a time (`sliced.rs`), or a path to open, with what
/// to read of it (a DICOM series or segment), and for the store of a
/// `zarr.Array` or `h5py.Dataset` the array's grid (`[spacing, origin]`),
/// which replaces the file's (see [`Select`]).
pub(crate) enum Input<'a> {
    Array(Box<tmc::volume::StridedVolume<'a>>),
    Sliced(Box<tmc::volume::LayeredVolume<PySlices>>),
    Path(PathBuf, ZarrSelect, Option<[[f64; 3]; 2]>),
}

impl<'a> Input<'a> {
    pub(crate) fn new(
        input: &'a Bound<'_, PyAny>,
        spacing: [f64; 3],
        origin: [f64; 3],
        mapped: MappedAt,
        select: Select,
    ) -> PyResult<Self> {
        let array_grid = (select.6 == Some(true)).then_some([spacing, origin]);
        let select = ZarrSelect::from(select);
        if let Ok(sliced) = input.cast::<SlicedArray>() {
            let volume = sliced::volume(sliced, spacing, origin)?;
            return Ok(Input::Sliced(Box::new(volume)));
        }
        match input.cast::<PyUntypedArray>() {
            Ok(_) if select != ZarrSelect::default() => Err(PyValueError::new_err(
                "series, segment, at, array, level and dataset choose what to read of a path (a DICOM series, a Zarr array or HDF5 dataset and its entry), not of an array",
            )),
            Ok(array) => Ok(Input::Array(Box::new(array::volume(
                array, spacing, origin, mapped,
            )?))),
            Err(_) => Ok(Input::Path(input.extract::<PathBuf>()?, select, array_grid)),
        }
    }

    /// Opens the volume (a path is opened by the CLI's readers) and runs
    /// `work` on it, all with the GIL released and Ctrl-C watched. The
    /// reader's notes that the CLI prints on stderr (a NIfTI's zero
    /// `pixdim` read as 1, ...) are raised as Python `UserWarning`s once
    /// the GIL is back, whether `work` succeeded or not.
    pub(crate) fn run<T: Send>(
        &self,
        py: Python<'_>,
        progress: Option<&Bound<'_, PyAny>>,
        work: impl FnOnce(&dyn SampleSource, Option<&Path>, &Watch) -> tmc::Result<T> + Send,
    ) -> PyResult<T> {
        let notes = Mutex::new(Vec::new());
        let result = interrupt::run_watched(py, progress, |watch| match self {
            Input::Array(volume) => work(volume.as_ref(), None, watch),
            Input::Sliced(volume) => work(volume.as_ref(), None, watch),
            Input::Path(path, select, array_grid) => {
                tmc::files::check_input_kind(path)?;
                let mut source = tmc::volume::open_selected(path, None, select, &watch.cancel)?;
                if let Some([spacing, origin]) = *array_grid {
                    // The caller passed an array object: its grid is the
                    // call's, as for a numpy array, and not the file's (the
                    // notes that the file's was replaced are not for them).
                    source = tmc::volume::regrid(source, Some(spacing), Some(origin))?.0;
                }
                *notes.lock().unwrap_or_else(PoisonError::into_inner) = source.notes().warnings;
                work(source.as_ref(), Some(path), watch)
            }
        });
        // An exception the lazy array raised is raised as it is, not as
        // the library's line about it.
        let result = match (result, self) {
            (Err(e), Input::Sliced(volume)) => Err(volume.reader().take_raised().unwrap_or(e)),
            (result, _) => result,
        };
        let user_warning = py.get_type::<PyUserWarning>();
        for note in notes.into_inner().unwrap_or_else(PoisonError::into_inner) {
            let message = CString::new(note.replace('\0', "\\0"))
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            // Level 2: the line of the user's code that called the
            // package's Python function, which called this one.
            PyErr::warn(py, &user_warning, &message, 2)?;
        }
        result
    }
}

/// What to read of a path, as the package's `_select` passes it: the
/// DICOM series (number or UID), the Segmentation segment, the entry of a
/// Zarr array's or HDF5 dataset's axes before z, y, x (`--at`), the Zarr
/// array inside its store (`--array`), the OME-Zarr level (`--level`) and
/// the HDF5 dataset (`--dataset`), each `None` when not given; and
/// `Some(true)` when the path is the store of a `zarr.Array` or
/// `h5py.Dataset` the caller passed, streamed on the call's grid (spacing
/// and origin) as a numpy array would be.
#[derive(FromPyObject)]
pub(crate) struct Select(
    Option<String>,
    Option<u32>,
    Option<Vec<(String, u64)>>,
    Option<String>,
    Option<usize>,
    Option<String>,
    Option<bool>,
);

impl Select {
    /// Nothing chosen: what a numpy array takes.
    pub(crate) fn none() -> Select {
        Select(None, None, None, None, None, None, None)
    }

    /// Whether a DICOM series or segment was chosen (`info` lists a DICOM
    /// directory's series when neither was).
    pub(crate) fn names_dicom_part(&self) -> bool {
        self.0.is_some() || self.1.is_some()
    }
}

impl From<Select> for ZarrSelect {
    fn from(Select(series, segment, at, array, level, dataset, _): Select) -> Self {
        ZarrSelect {
            array,
            level,
            dataset,
            series,
            segment,
            at: at.unwrap_or_default(),
        }
    }
}

/// The extraction parameters from the package's names.
pub(crate) fn params(
    iso: f64,
    method: &str,
    inside: &str,
    close: bool,
    threads: usize,
    normals: bool,
) -> PyResult<ExtractParams> {
    let method = match method {
        "tmc" => Method::Tmc,
        "mc" => Method::Mc,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown method '{other}' (expected 'tmc' or 'mc')"
            )))
        }
    };
    let inside = match inside {
        "high" => Inside::High,
        "low" => Inside::Low,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown inside '{other}' (expected 'high' or 'low')"
            )))
        }
    };
    Ok(ExtractParams {
        iso,
        method,
        inside,
        close,
        threads,
        normals,
    })
}

/// The checks the CLI makes before it extracts (a grid with cells, unless
/// closed, inside the range of f32 coordinates; an output that is neither
/// the input nor a file the input reads), then the pipeline options of a
/// run that `watch` stops and hears the progress of.
pub(crate) fn preflight<'a>(
    source: &dyn SampleSource,
    input: Option<&Path>,
    params: &ExtractParams,
    output: Option<&Path>,
    watch: &'a Watch,
) -> tmc::Result<PipelineOptions<'a>> {
    let name = input.unwrap_or(Path::new("array"));
    tmc::stream::check_grid(name, source.grid(), params.close)?;
    if let Some(output) = output {
        for data in input.into_iter().chain(source.data_files()) {
            tmc::files::check_distinct(data, output)?;
        }
        tmc::export::check_output_path(output)?;
    }
    Ok(PipelineOptions {
        cancel: Some(&watch.cancel),
        progress: Some(watch.progress()),
        ..Default::default()
    })
}

/// The run as `tmc extract --json` reports it, in its key order: the
/// paths (null for an array or an in-memory mesh) and the library's
/// summary; the CLI's memory and byte counts describe its process and are
/// left out.
#[derive(serde::Serialize)]
struct Report {
    input: Option<String>,
    output: Option<String>,
    #[serde(flatten)]
    summary: tmc::stream::RunSummary,
}

/// [`Report`] as JSON text.
pub(crate) fn report(
    input: Option<&Path>,
    output: Option<&Path>,
    source: &dyn SampleSource,
    params: &ExtractParams,
    stats: &tmc::Stats,
) -> tmc::Result<String> {
    let path = |p: Option<&Path>| p.map(|p| p.display().to_string());
    let report = Report {
        input: path(input),
        output: path(output),
        summary: tmc::stream::RunSummary::new(params, source.grid(), stats),
    };
    serde_json::to_string(&report).map_err(|e| tmc::Error::Invalid(e.to_string()))
}

/// One extraction collected in memory: the vertices (f64), the triangles,
/// the normals (empty without `params.normals`), the report JSON and the
/// record a `.tmesh` needs.
pub(crate) type Collected = (
    Vec<[f64; 3]>,
    Vec<[u32; 3]>,
    Vec<[f32; 3]>,
    String,
    Option<Record>,
);

/// Extracts the isosurface of `input` (a 3-D numpy array indexed
/// `[z][y][x]`, or a path) into memory, with tmc's conventions. Returns
/// `(vertices, triangles, normals or None, report JSON, record)`, the
/// record being what `Mesh.write` needs for a `.tmesh` file (see
/// `record.rs`). The vertices are widened to f64 as the chunks come (on
/// the writing thread, while the workers triangulate).
#[pyfunction]
#[pyo3(signature = (input, iso, spacing, origin, mapped, method, inside, close, threads, normals, select, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn extract<'py>(
    py: Python<'py>,
    input: &Bound<'py, PyAny>,
    iso: f64,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
    method: &str,
    inside: &str,
    close: bool,
    threads: usize,
    normals: bool,
    select: Select,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let params = params(iso, method, inside, close, threads, normals)?;
    let input = Input::new(input, spacing, origin, mapped, select)?;
    let (vertices, triangles, n, report, record): Collected =
        input.run(py, progress, |source, path, watch| {
            let options = preflight(source, path, &params, None, watch)?;
            let mut recorder = Recorder::<[f64; 3]>::default();
            let stats = tmc::extract_to(source, &params, &options, &mut recorder)?;
            let report = report(path, None, source, &params, &stats)?;
            let record = recorder.record();
            let (vertices, triangles, normals) = recorder.collector.into_parts();
            Ok((vertices, triangles, normals, report, record))
        })?;
    let (v, t, n) = arrays(py, vertices, triangles, normals.then_some(n))?;
    (v, t, n, report, record)
        .into_pyobject(py)
        .map(|t| t.into_any())
}

/// `skimage.measure.marching_cubes` of the 3-D numpy array `input`
/// (indexed `[z][y][x]`, samples `spacing` apart in `[x, y, z]`, first
/// sample at the origin): `(verts, faces, normals, values)` in scikit-image's
/// layout and types, written by the extraction's sink as the chunks come
/// (see `skimage.rs`); the normals point toward lower values whatever
/// `inside`.
#[pyfunction]
#[pyo3(signature = (input, iso, spacing, mapped, method, inside, threads))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn marching_cubes<'py>(
    py: Python<'py>,
    input: &Bound<'py, PyAny>,
    iso: f64,
    spacing: [f64; 3],
    mapped: MappedAt,
    method: &str,
    inside: &str,
    threads: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let params = params(iso, method, inside, false, threads, true)?;
    let Input::Array(volume) = Input::new(input, spacing, [0.0; 3], mapped, Select::none())? else {
        return Err(PyValueError::new_err(
            "marching_cubes takes a numpy array, not a path",
        ));
    };
    let flip = params.inside == Inside::Low;
    let volume = volume.as_ref();
    let arrays = interrupt::run_watched(py, None, |watch| {
        // The per-vertex values are read from the array by the workers,
        // chunk by chunk, beside the extraction (not by the sink on the
        // one writing thread, which would then bound the speed-up).
        let values =
            |vertices: &[[f32; 3]], out: &mut Vec<f32>| values::push_maxima(volume, vertices, out);
        let options = PipelineOptions {
            vertex_values: Some(&values),
            ..preflight(volume, None, &params, None, watch)?
        };
        let mut sink = SkimageArrays::new(flip);
        tmc::extract_to(volume, &params, &options, &mut sink)?;
        Ok(sink)
    })?;
    let SkimageArrays {
        verts,
        faces,
        normals,
        values,
        ..
    } = arrays;
    (
        rows(py, verts)?,
        rows(py, faces)?,
        rows(py, normals)?,
        numpy::PyArray1::from_vec(py, values),
    )
        .into_pyobject(py)
        .map(|t| t.into_any())
}

/// Streams the isosurface of `input` (array or path) into the file
/// `output`, whose extension chooses the format, without holding the mesh;
/// the file appears whole or not at all; with `normals`, the vertex
/// normals go into it too (formats that carry them), as `tmc extract
/// --normals` writes them; with `preview`, its picture into that PNG, as
/// `tmc extract --preview` draws it (titled with the input file's name, or
/// the output's for an array; the mesh is taken back if the picture
/// fails). Returns the report JSON.
#[pyfunction]
#[pyo3(signature = (input, output, iso, spacing, origin, mapped, method, inside, close, threads, normals, select, preview = None, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn extract_to(
    py: Python<'_>,
    input: &Bound<'_, PyAny>,
    output: PathBuf,
    iso: f64,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
    method: &str,
    inside: &str,
    close: bool,
    threads: usize,
    normals: bool,
    select: Select,
    preview: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    // The name's form first: no placeholder is filled in ('{stem}' and
    // '{iso}', which the CLI's -o fills in, would stay in the name).
    for name in std::iter::once(&output).chain(&preview) {
        refuse_placeholders(name, &[]).map_err(crate::errors::to_py)?;
    }
    tmc::export::check_normals_output(&output, normals).map_err(crate::errors::to_py)?;
    let params = params(iso, method, inside, close, threads, normals)?;
    let input = Input::new(input, spacing, origin, mapped, select)?;
    input.run(py, progress, |source, path, watch| {
        let options = preflight(source, path, &params, Some(&output), watch)?;
        if let Some(picture) = &preview {
            tmc::preview::check_picture(picture, path, &[output.as_path()])?;
            for data in source.data_files() {
                tmc::files::check_distinct(data, picture)?;
            }
        }
        let mut sink = tmc::export::create_sink(&output)?;
        if let Some(picture) = &preview {
            let title = tmc::preview::title_of(path.unwrap_or(&output));
            sink = tmc::preview::WithPreview::wrap(sink, &output, picture, title, threads);
        }
        let stats = tmc::extract_to(source, &params, &options, sink.as_mut())?;
        report(path, Some(&output), source, &params, &stats)
    })
}

/// Fails when the output name `output` holds a `{NAME}` placeholder that
/// is none of `known`, the ones the call fills in: it would stay in the
/// file's name.
pub(crate) fn refuse_placeholders(output: &Path, known: &[&str]) -> tmc::Result<()> {
    match tmc::files::unknown_placeholder(output, known) {
        None => Ok(()),
        Some(p) => Err(tmc::Error::Invalid(format!(
            "{}: unknown placeholder {p} in output; it may use {}",
            output.display(),
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        ))),
    }
}

/// The worker threads `threads` means (0: one per core), as reported.
#[pyfunction]
pub(crate) fn worker_threads(threads: usize) -> usize {
    tmc::stream::threads::worker_threads(threads)
}

/// The shape `[nz, ny, nx]` in which tmc's readers open the Zarr array or
/// HDF5 dataset that `select` names in the store at `path`, or `None` when
/// they do not open it (a codec or filter they do not read, a store that
/// is not there): the package then streams a `zarr.Array` or
/// `h5py.Dataset` from its store only when this agrees with the object's
/// shape, and reads it through numpy otherwise. Opening reads metadata
/// only.
#[pyfunction]
pub(crate) fn stored_shape(py: Python<'_>, path: PathBuf, select: Select) -> Option<[usize; 3]> {
    let select = ZarrSelect::from(select);
    py.detach(|| {
        let never = AtomicBool::new(false);
        let source = tmc::volume::open_selected(&path, None, &select, &never).ok()?;
        let [nx, ny, nz] = source.grid().dims;
        Some([nz, ny, nx])
    })
}
