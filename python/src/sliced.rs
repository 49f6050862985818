//! Lazy array-likes (a `dask.array`, an `xarray.DataArray` backed by dask,
//! a Zarr array in memory) read a slice of planes at a time, so that an
//! array larger than memory extracts in bounded memory.
//!
//! The package (`tmc/_stored.py`) wraps such an array in a [`SlicedArray`]:
//! a Python function giving planes `first..last` as one C-ordered block
//! of native-order samples seen as bytes, the array's `(nz, ny, nx)`, its
//! dtype and the planes to read at once (its chunks' depth, bounded). The
//! library reads it as a [`LayeredVolume`]: each layer is one call of the
//! function, made by the worker that first needs the layer, with the GIL
//! taken for the call (the extraction runs with it released, see
//! `interrupt.rs`); the array's own library computes the slice.

use crate::array::{grid_of, scalar_of_kind};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use std::ops::Range;
use std::sync::{Mutex, PoisonError};
use tmc::volume::{LayerReader, LayeredVolume, ScalarType};

/// An array to read a slice of planes at a time (see the module docs).
#[pyclass(frozen, module = "tmc._tmc")]
pub(crate) struct SlicedArray {
    fetch: Py<PyAny>,
    shape: [usize; 3],
    scalar: ScalarType,
    depth: usize,
}

#[pymethods]
impl SlicedArray {
    /// `fetch(first, last)` gives planes `first..last` of an array of
    /// `shape` `(nz, ny, nx)` and `dtype` (numpy's kind and size, as
    /// `"u2"`) as a 1-D uint8 array of their native-order bytes, C order;
    /// `depth` planes are read at once.
    #[new]
    fn new(fetch: Py<PyAny>, shape: [usize; 3], dtype: &str, depth: usize) -> PyResult<Self> {
        let bytes = dtype.as_bytes();
        let scalar = match bytes {
            [kind, size @ b'1'..=b'8'] => scalar_of_kind(*kind, usize::from(size - b'0')),
            _ => None,
        }
        .ok_or_else(|| PyTypeError::new_err(format!("unsupported dtype '{dtype}'")))?;
        Ok(SlicedArray {
            fetch,
            shape,
            scalar,
            depth,
        })
    }
}

/// The reader of a [`SlicedArray`]'s layers. The first exception the
/// function raised is kept, so that the call raises it rather than the
/// library's line about it.
pub(crate) struct PySlices {
    fetch: Py<PyAny>,
    plane_bytes: usize,
    raised: Mutex<Option<PyErr>>,
}

impl PySlices {
    /// The first exception `fetch` raised, taken.
    pub(crate) fn take_raised(&self) -> Option<PyErr> {
        self.raised
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
    }

    /// Planes `planes`, one buffer each, from one call of `fetch`.
    fn call(&self, py: Python<'_>, planes: &Range<usize>) -> PyResult<Vec<Vec<u8>>> {
        let block = self.fetch.call1(py, (planes.start, planes.end))?;
        let block = block.bind(py).cast::<PyArray1<u8>>().map_err(|_| {
            PyTypeError::new_err("the array's slice did not come back as the bytes of its samples")
        })?;
        let block = block.readonly();
        let bytes = block.as_slice()?;
        let expected = planes.len() * self.plane_bytes;
        if bytes.len() != expected {
            return Err(PyTypeError::new_err(format!(
                "planes {}..{} of the array came back as {} bytes, not {expected}",
                planes.start,
                planes.end,
                bytes.len()
            )));
        }
        Ok(bytes
            .chunks_exact(self.plane_bytes.max(1))
            .map(<[u8]>::to_vec)
            .collect())
    }
}

impl LayerReader for PySlices {
    fn read_layer(&self, planes: Range<usize>) -> tmc::Result<Vec<Vec<u8>>> {
        Python::attach(|py| self.call(py, &planes)).map_err(|e| {
            let text = format!(
                "reading planes {}..{} of the array raised {e}",
                planes.start, planes.end
            );
            self.raised
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .get_or_insert(e);
            tmc::Error::Invalid(text)
        })
    }
}

/// `array` as a volume on the call's grid (`spacing` and `origin` in x, y,
/// z order, checked as for a numpy array).
pub(crate) fn volume(
    array: &Bound<'_, SlicedArray>,
    spacing: [f64; 3],
    origin: [f64; 3],
) -> PyResult<LayeredVolume<PySlices>> {
    let py = array.py();
    let array = array.get();
    let grid = grid_of(&array.shape, spacing, origin)?;
    let reader = PySlices {
        fetch: array.fetch.clone_ref(py),
        plane_bytes: grid.plane_len() * array.scalar.size(),
        raised: Mutex::new(None),
    };
    LayeredVolume::new(grid, array.scalar, array.depth, reader).map_err(crate::errors::to_py)
}
