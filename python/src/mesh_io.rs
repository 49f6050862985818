//! Meshes read from and written to files, checked, and volumes described:
//! the library's readers, writers, checker and `tmc info`.

use crate::errors::OrPyErr;
use crate::extract::Select;
use crate::interrupt;
use crate::output::{mesh_arrays, rows_from};
use crate::record::{write_tmesh, Record};
use pyo3::prelude::*;
use std::path::PathBuf;
use tmc::volume::zarr::ZarrSelect;

/// Reads a `.tmesh`, PLY, OBJ or OFF mesh: `(vertices, triangles,
/// normals, labels)` in tmc's layout (float64, uint32, float32 or `None`,
/// uint32 or `None`).
#[pyfunction]
pub(crate) fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let mesh = py.detach(|| tmc::check::read_mesh(&path)).or_py()?;
    let ((v, t, normals), labels) = mesh_arrays(py, mesh)?;
    (v, t, normals, labels)
        .into_pyobject(py)
        .map(|t| t.into_any())
}

/// A mesh from `(N, 3)` float64 vertices and `(M, 3)` uint32 triangles.
fn mesh_from(vertices: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>) -> PyResult<tmc::Mesh> {
    let vertices: Vec<[f64; 3]> = rows_from(vertices, "vertices")?;
    Ok(tmc::Mesh {
        vertices: vertices.iter().map(|v| v.map(|c| c as f32)).collect(),
        triangles: rows_from(triangles, "triangles")?,
        ..tmc::Mesh::default()
    })
}

/// Draws a mesh into the PNG `path` as `tmc preview` draws a PLY of it:
/// four shaded views framed by its vertices' box, captioned `title` and
/// the closed/genus verdict, by `threads` workers (0: one per core); the
/// file appears whole or not at all.
#[pyfunction]
pub(crate) fn preview_mesh(
    py: Python<'_>,
    path: PathBuf,
    vertices: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    title: String,
    threads: usize,
) -> PyResult<()> {
    let mesh = mesh_from(vertices, triangles)?;
    crate::extract::refuse_placeholders(&path, &[]).or_py()?;
    interrupt::run(py, |cancel| {
        tmc::preview::check_png_path(&path)?;
        tmc::preview::draw_mesh(mesh, &path, title, threads, cancel)
    })
}

/// Writes a mesh to `path` in the format its extension names (`.ply`,
/// `.obj`, `.off`, `.stl`, and `.tmesh` given the `record` of the
/// extraction that made the mesh), with its `normals` ((N, 3) float32, one
/// per vertex) where the format holds them and its `labels` ((M,) uint32,
/// one per triangle) into PLY; the file appears whole or not at all.
#[pyfunction]
#[pyo3(signature = (path, vertices, triangles, record = None, normals = None, labels = None))]
pub(crate) fn write_mesh(
    py: Python<'_>,
    path: PathBuf,
    vertices: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
    record: Option<PyRef<'_, Record>>,
    normals: Option<&Bound<'_, PyAny>>,
    labels: Option<Vec<u32>>,
) -> PyResult<()> {
    let mut mesh = mesh_from(vertices, triangles)?;
    if let Some(normals) = normals {
        let normals = rows_from::<f32>(normals, "normals")?;
        if normals.len() != mesh.vertices.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} normals for {} vertices",
                normals.len(),
                mesh.vertices.len()
            )));
        }
        mesh.normals = Some(normals);
    }
    if let Some(labels) = labels {
        if labels.len() != mesh.triangles.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} labels for {} triangles",
                labels.len(),
                mesh.triangles.len()
            )));
        }
        mesh.labels = Some(labels);
    }
    let tmesh = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("tmesh"));
    match record {
        Some(record) if tmesh => {
            let record: &Record = &record;
            py.detach(|| write_tmesh(&path, &mesh, record))
        }
        _ => py.detach(|| tmc::export::write_mesh(&path, &mesh)).or_py(),
    }
}

/// The report of `tmc check --json` for a mesh, as JSON text.
#[pyfunction]
pub(crate) fn check_mesh(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    triangles: &Bound<'_, PyAny>,
) -> PyResult<String> {
    let mesh = mesh_from(vertices, triangles)?;
    let report = py.detach(|| tmc::check::check_mesh(&mesh));
    serde_json::to_string(&report)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
}

/// What `tmc info --json` prints for the volume at `path` (what `select`
/// chooses of it: a DICOM series or segment, a Zarr array, level or entry,
/// an HDF5 dataset), as JSON text; for a DICOM directory of several series
/// and neither a series nor a segment chosen, their listing (`input`,
/// `format`, `series`), as `tmc info --json` prints it.
#[pyfunction]
#[pyo3(signature = (path, bins = 1024, plane_step = 0, select = None))]
pub(crate) fn info(
    py: Python<'_>,
    path: PathBuf,
    bins: usize,
    plane_step: usize,
    select: Option<Select>,
) -> PyResult<String> {
    interrupt::run(py, |cancel| {
        tmc::files::check_input_kind(&path)?;
        if !select.as_ref().is_some_and(Select::names_dicom_part) {
            if let Some(listed) = tmc::volume::dicom_series_to_choose(&path)? {
                let value = serde_json::json!({
                    "input": path.display().to_string(),
                    "format": "DICOM",
                    "series": listed,
                });
                return Ok(value.to_string());
            }
        }
        let select = select.map(ZarrSelect::from).unwrap_or_default();
        let source = tmc::volume::open_selected(&path, None, &select, cancel)?;
        let info = tmc::volume::volume_info(&path, None, source.as_ref(), bins, plane_step)?;
        serde_json::to_string(&info).map_err(|e| tmc::Error::Invalid(e.to_string()))
    })
}
