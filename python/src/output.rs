//! Meshes handed to Python as numpy arrays in tmc's layout, moved rather
//! than copied where the element type stays the same (scikit-image's
//! layout is written by its sink, `skimage.rs`).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tmc::Mesh;

/// `(N, 3)` numpy array owning `rows` (no copy).
pub(crate) fn rows<'py, T: numpy::Element>(
    py: Python<'py>,
    rows: Vec<[T; 3]>,
) -> PyResult<Bound<'py, PyAny>> {
    let n = rows.len();
    let flat = PyArray1::from_vec(py, rows.into_flattened());
    Ok(flat.reshape([n, 3])?.into_any())
}

/// Vertices, triangles and (if computed) normals as numpy arrays.
type MeshArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
);

/// Vertices (widened to float64), triangles, normals and per-triangle
/// labels of `mesh` as numpy arrays, in tmc's layout: the normals `(N, 3)`
/// float32 and the labels `(M,)` uint32, or `None` where the mesh has none
/// (an empty mesh that has them gives empty arrays).
pub(crate) fn mesh_arrays<'py>(
    py: Python<'py>,
    mesh: Mesh,
) -> PyResult<(MeshArrays<'py>, Option<Bound<'py, PyAny>>)> {
    let Mesh {
        vertices,
        triangles,
        normals,
        labels,
    } = mesh;
    let wide: Vec<[f64; 3]> = vertices.iter().map(|v| v.map(f64::from)).collect();
    drop(vertices);
    let labels = labels.map(|labels| PyArray1::from_vec(py, labels).into_any());
    Ok((arrays(py, wide, triangles, normals)?, labels))
}

/// tmc's layout: vertices `[x, y, z]` as float64, triangles as uint32,
/// normals (if computed) as float32, each moved into numpy without a copy.
pub(crate) fn arrays<'py>(
    py: Python<'py>,
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
) -> PyResult<MeshArrays<'py>> {
    Ok((
        rows(py, vertices)?,
        rows(py, triangles)?,
        normals.map(|n| rows(py, n)).transpose()?,
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
