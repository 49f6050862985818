//! Meshes handed to Python as numpy arrays, moved rather than copied where
//! the element type stays the same.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tmc::Mesh;

/// `(N, 3)` numpy array owning `rows` (no copy).
fn rows<'py, T: numpy::Element>(py: Python<'py>, rows: Vec<[T; 3]>) -> PyResult<Bound<'py, PyAny>> {
    let n = rows.len();
    let flat = PyArray1::from_vec(py, rows.into_flattened());
    Ok(flat.reshape([n, 3])?.into_any())
}

/// The arrays of a mesh, in one of the two conventions of the package.
pub(crate) enum Layout {
    /// tmc's: vertices `[x, y, z]` as float64, triangles as uint32.
    Tmc,
    /// scikit-image's: vertices in array index order `[z, y, x]` as
    /// float32, triangles as int32. Triangles keep their order: reversing
    /// the axes mirrors space, so triangles that were counter-clockwise
    /// seen from outside become clockwise, which is scikit-image's winding.
    Index,
}

/// Vertices, triangles and (if computed) normals as numpy arrays.
type MeshArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
);

/// Vertex positions as collected: `f32` as the pipeline makes them (what
/// the normals and values are computed from), or already `f64` (collected
/// so while the extraction ran, for tmc's layout).
pub(crate) enum Positions {
    /// As the pipeline made them.
    Narrow(Vec<[f32; 3]>),
    /// Widened as they came.
    Wide(Vec<[f64; 3]>),
}

/// Vertices, triangles and normals of `mesh` as numpy arrays.
pub(crate) fn mesh_arrays<'py>(
    py: Python<'py>,
    mesh: Mesh,
    normals: Option<Vec<[f32; 3]>>,
    layout: Layout,
) -> PyResult<MeshArrays<'py>> {
    let Mesh {
        vertices,
        triangles,
        ..
    } = mesh;
    arrays(py, Positions::Narrow(vertices), triangles, normals, layout)
}

/// [`mesh_arrays`] of vertices as collected ([`Positions`]); the index
/// layout needs them narrow.
pub(crate) fn arrays<'py>(
    py: Python<'py>,
    positions: Positions,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    layout: Layout,
) -> PyResult<MeshArrays<'py>> {
    let normals_rows = |py, n: Option<Vec<[f32; 3]>>| n.map(|n| rows(py, n)).transpose();
    let mut vertices = match (positions, layout) {
        (Positions::Wide(wide), Layout::Tmc) => {
            return Ok((
                rows(py, wide)?,
                rows(py, triangles)?,
                normals_rows(py, normals)?,
            ));
        }
        (Positions::Narrow(narrow), Layout::Tmc) => {
            let wide: Vec<[f64; 3]> = narrow.iter().map(|v| v.map(f64::from)).collect();
            drop(narrow);
            return Ok((
                rows(py, wide)?,
                rows(py, triangles)?,
                normals_rows(py, normals)?,
            ));
        }
        (Positions::Narrow(narrow), Layout::Index) => narrow,
        (Positions::Wide(_), Layout::Index) => {
            return Err(PyValueError::new_err(
                "internal: scikit-image's layout is made from f32 positions",
            ))
        }
    };
    if vertices.len() > i32::MAX as usize {
        return Err(PyValueError::new_err(format!(
            "{} vertices do not fit scikit-image's int32 faces; use tmc.extract",
            vertices.len()
        )));
    }
    vertices.iter_mut().for_each(|v| v.reverse());
    let mut normals = normals;
    if let Some(n) = normals.as_mut() {
        n.iter_mut().for_each(|v| v.reverse());
    }
    // Same size and alignment: collected in place, no allocation.
    let faces: Vec<[i32; 3]> = triangles.into_iter().map(|t| t.map(|i| i as i32)).collect();
    Ok((
        rows(py, vertices)?,
        rows(py, faces)?,
        normals_rows(py, normals)?,
    ))
}

/// A Python sequence of `(N, 3)` rows (a numpy array) as a `Vec`.
pub(crate) fn rows_from<T>(array: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[T; 3]>>
where
    T: numpy::Element + Copy,
{
    let array = array
        .cast::<numpy::PyArray2<T>>()
        .map_err(|_| PyValueError::new_err(format!("{what} must be an (N, 3) array")))?;
    let view = array.readonly();
    let view = view.as_array();
    if view.ncols() != 3 {
        return Err(PyValueError::new_err(format!(
            "{what} must have 3 columns, not {}",
            view.ncols()
        )));
    }
    Ok(view
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect())
}
