//! `tmc._tmc`: the Rust side of the Python package `tmc`.
//!
//! A thin layer over the `tmc` library: numpy arrays become
//! [`tmc::volume::StridedVolume`]s without a copy (`array.rs`), paths open
//! with the CLI's readers, every extraction runs with the GIL released and
//! stops on Ctrl-C (`interrupt.rs`), and meshes go back to numpy without a
//! copy where the types allow (`output.rs`), lazy arrays (dask, ...) a slice
//! of planes at a time (`sliced.rs`), or are written in
//! scikit-image's layout by the extraction's sink (`skimage.rs`); a label
//! map's labels come in one pass (`labels.rs`). The Python API (argument
//! handling, `Mesh`, `marching_cubes`) is in `python/tmc/__init__.py`.

#![deny(clippy::undocumented_unsafe_blocks)]

mod array;
mod compare;
mod errors;
mod extract;
mod interrupt;
mod labels;
mod mesh_io;
mod output;
mod record;
mod skimage;
mod sliced;
mod values;

use pyo3::prelude::*;

/// The extension module, imported by the `tmc` package as `tmc._tmc`.
#[pymodule]
fn _tmc(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(extract::extract, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(extract::extract_to, m)?)?;
    m.add_function(wrap_pyfunction!(extract::marching_cubes, m)?)?;
    m.add_function(wrap_pyfunction!(labels::extract_labels, m)?)?;
    m.add_function(wrap_pyfunction!(labels::extract_labels_to, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_io::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_io::write_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_io::preview_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_io::check_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_io::info, m)?)?;
    m.add_function(wrap_pyfunction!(extract::worker_threads, m)?)?;
    m.add_function(wrap_pyfunction!(extract::stored_shape, m)?)?;
    m.add_function(wrap_pyfunction!(record::_restore_record, m)?)?;
    m.add_class::<sliced::SlicedArray>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
