//! numpy arrays as sample sources, without a copy.
//!
//! A 3-D array indexed `[z][y][x]` (the CLI's `.npy` convention: the last
//! axis is x) becomes a [`StridedVolume`] over the array's own memory, in
//! whatever order and with whatever strides it has; a `numpy.memmap` (or a
//! view of one) becomes a [`StridedVolume`] over a map of the same file
//! that tmc makes itself, so that the pages of finished planes can be
//! dropped and a file larger than memory extracts in bounded memory.

use numpy::{PyArrayDescrMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;
use tmc::volume::{Endian, ScalarType, StridedLayout, StridedVolume};
use tmc::Grid;

/// Where an array's samples are: `(file, byte offset of sample [0,0,0])`
/// for a memory-mapped file that tmc should map itself, `None` for the
/// array's memory.
pub(crate) type MappedAt = Option<(PathBuf, u64)>;

/// The grid of `array` (x = last axis) with `spacing` and `origin` given
/// in x, y, z order, checked as the CLI checks a header's.
pub(crate) fn grid_of(shape: &[usize], spacing: [f64; 3], origin: [f64; 3]) -> PyResult<Grid> {
    let [nz, ny, nx] = match *shape {
        [a, b, c] => [a, b, c],
        _ => {
            return Err(PyValueError::new_err(format!(
                "expected a 3-D array of shape (nz, ny, nx), found shape {shape:?}"
            )))
        }
    };
    if shape.contains(&0) {
        return Err(PyValueError::new_err(format!(
            "dims {nx}x{ny}x{nz} contain a zero"
        )));
    }
    if spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return Err(PyValueError::new_err(format!(
            "spacing {spacing:?} must be finite and positive"
        )));
    }
    if origin.iter().any(|o| !o.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "origin {origin:?} must be finite"
        )));
    }
    Ok(Grid {
        dims: [nx, ny, nz],
        spacing,
        origin,
        direction: tmc::grid::IDENTITY,
    })
}

/// The type of numpy's dtype kind (`b'u'`, ...; `b'b'` is bool) and item
/// size, if tmc reads it.
pub(crate) fn scalar_of_kind(kind: u8, size: usize) -> Option<ScalarType> {
    match (kind, size) {
        (b'u' | b'b', 1) => Some(ScalarType::U8),
        (b'i', 1) => Some(ScalarType::I8),
        (b'u', 2) => Some(ScalarType::U16),
        (b'i', 2) => Some(ScalarType::I16),
        (b'u', 4) => Some(ScalarType::U32),
        (b'i', 4) => Some(ScalarType::I32),
        (b'f', 4) => Some(ScalarType::F32),
        (b'f', 8) => Some(ScalarType::F64),
        (b'i', 8) => Some(ScalarType::I64),
        (b'u', 8) => Some(ScalarType::U64),
        (b'f', 2) => Some(ScalarType::F16),
        _ => None,
    }
}

/// The stored type and byte order of `array`'s dtype, or a `TypeError`
/// naming the dtypes tmc reads (the CLI's words for a `.npy` file).
fn scalar_of(array: &Bound<'_, PyUntypedArray>) -> PyResult<(ScalarType, Endian)> {
    let dtype = array.dtype();
    let scalar = scalar_of_kind(dtype.kind(), dtype.itemsize());
    let endian = match dtype.byteorder() {
        b'<' => Some(Endian::Little),
        b'>' => Some(Endian::Big),
        b'=' | b'|' => Some(Endian::native()),
        _ => None,
    };
    match (scalar, endian) {
        (Some(s), Some(e)) => Ok((s, e)),
        _ => Err(PyTypeError::new_err(format!(
            "unsupported dtype '{}' (expected u1, i1, u2, i2, u4, i4, u8, i8, f2, f4 or f8)",
            dtype.str().map(|s| s.to_string()).unwrap_or_default()
        ))),
    }
}

/// `array` as a sample source (see the module docs). The volume borrows
/// the array's memory, so it must not outlive the array; `mapped` says
/// where the samples are in a file instead.
pub(crate) fn volume<'a>(
    array: &'a Bound<'_, PyUntypedArray>,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
) -> PyResult<StridedVolume<'a>> {
    let grid = grid_of(array.shape(), spacing, origin)?;
    let (scalar, endian) = scalar_of(array)?;
    let &[s0, s1, s2] = array.strides() else {
        unreachable!("grid_of checked that the array is 3-D")
    };
    let strides = [s2, s1, s0];
    if let Some((path, offset)) = mapped {
        let first = usize::try_from(offset)
            .map_err(|_| PyValueError::new_err(format!("file offset {offset} is too large")))?;
        let layout = StridedLayout {
            scalar,
            endian,
            first,
            strides,
        };
        return StridedVolume::map_file(&path, grid, layout).map_err(crate::errors::to_py);
    }
    // The bytes between the lowest and the highest sample address.
    let size = scalar.size() as isize;
    let (mut low, mut high) = (0isize, size);
    for (n, s) in grid.dims.iter().zip(strides) {
        let span = (*n as isize - 1).checked_mul(s).ok_or_else(too_large)?;
        if span < 0 {
            low = low.checked_add(span).ok_or_else(too_large)?;
        } else {
            high = high.checked_add(span).ok_or_else(too_large)?;
        }
    }
    // SAFETY: `as_array_ptr` points to the live PyArrayObject of `array`,
    // which the caller's reference keeps alive for 'a.
    let data = unsafe { (*array.as_array_ptr()).fields.data } as *const u8;
    // SAFETY: numpy guarantees that every element of a valid array lies in
    // memory owned by the array (or its base), which the reference keeps
    // alive for 'a: from `data + low` (the lowest element address) to
    // `data + high` (one past the highest element's last byte). The bytes
    // are only read. Python code in another thread could write to the array
    // while the GIL is released; as for any extension that releases the GIL
    // (and for a file mapped by the library), the documented contract is
    // that the array does not change during the call.
    let bytes = unsafe { std::slice::from_raw_parts(data.offset(low), (high - low) as usize) };
    let layout = StridedLayout {
        scalar,
        endian,
        first: low.unsigned_abs(),
        strides,
    };
    StridedVolume::borrowed(grid, layout, bytes).map_err(crate::errors::to_py)
}

fn too_large() -> PyErr {
    PyValueError::new_err("the array's strides span more than the address space")
}
