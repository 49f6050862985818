//! Planes lent as stored: a source that holds a plane's samples in memory,
//! in native byte order and without scaling, lends them to the slab loop,
//! which then compares them with the isovalue in their own type and turns
//! into `f64` only the few samples next to the surface.
//!
//! A plane whose bytes are not aligned for their type (a file header of odd
//! length before 16-bit samples, say) is lent too, as arrays of bytes
//! decoded sample by sample (the `...Bytes` variants): before, such a plane
//! was read into `f64`s, 8 bytes of the process's own memory per sample and
//! per plane (two planes per worker: 1 GiB per worker for planes of
//! 8192 x 8192), where a lent plane stays in the page cache. Each type has
//! its own variant, so that a lent plane stays two words and the sample
//! loops look at its type once per plane.

use super::ScalarType;
use std::ops::Range;
use std::sync::Arc;

/// A plane held in a shared buffer: a decoded layer of chunks (Zarr,
/// HDF5) that the source's cache may drop while the plane is still in use,
/// so the holder keeps the buffer alive (see
/// [`SampleSource::share_plane`](super::SampleSource::share_plane) and
/// [`HeldPlanes`](super::HeldPlanes)).
#[derive(Debug, Clone)]
pub struct SharedPlane {
    /// The layer holding the plane, native byte order.
    pub data: Arc<Vec<u8>>,
    /// The plane's bytes in `data`, x fastest.
    pub bytes: Range<usize>,
    /// The type of its samples.
    pub scalar: ScalarType,
}

impl SharedPlane {
    /// The plane, lent in its own type (`None` if its bytes do not hold a
    /// whole number of samples).
    pub fn lent(&self) -> Option<LentPlane<'_>> {
        LentPlane::from_bytes(self.scalar, self.data.get(self.bytes.clone())?)
    }
}

/// The samples of one plane, x fastest, in the type they are stored in.
#[derive(Debug, Clone, Copy)]
pub enum LentPlane<'a> {
    /// Unsigned 8-bit samples.
    U8(&'a [u8]),
    /// Signed 8-bit samples.
    I8(&'a [i8]),
    /// Unsigned 16-bit samples.
    U16(&'a [u16]),
    /// Signed 16-bit samples.
    I16(&'a [i16]),
    /// Unsigned 32-bit samples.
    U32(&'a [u32]),
    /// Signed 32-bit samples.
    I32(&'a [i32]),
    /// 32-bit floats.
    F32(&'a [f32]),
    /// 64-bit floats.
    F64(&'a [f64]),
    /// Unsigned 16-bit samples, native byte order, at any alignment.
    U16Bytes(&'a [[u8; 2]]),
    /// Signed 16-bit samples, native byte order, at any alignment.
    I16Bytes(&'a [[u8; 2]]),
    /// Unsigned 32-bit samples, native byte order, at any alignment.
    U32Bytes(&'a [[u8; 4]]),
    /// Signed 32-bit samples, native byte order, at any alignment.
    I32Bytes(&'a [[u8; 4]]),
    /// 32-bit floats, native byte order, at any alignment.
    F32Bytes(&'a [[u8; 4]]),
    /// 64-bit floats, native byte order, at any alignment.
    F64Bytes(&'a [[u8; 8]]),
}

impl<'a> LentPlane<'a> {
    /// Native-endian samples of `scalar` packed in `bytes`: typed slices
    /// when the bytes are aligned for the type, else byte arrays (the
    /// `...Bytes` variants); `None` when the bytes do not hold a whole
    /// number of samples.
    pub fn from_bytes(scalar: ScalarType, bytes: &'a [u8]) -> Option<Self> {
        use bytemuck::try_cast_slice as cast;
        // Either cast fails only on the length: byte arrays have alignment 1.
        Some(match scalar {
            ScalarType::U8 => LentPlane::U8(bytes),
            ScalarType::I8 => LentPlane::I8(cast(bytes).ok()?),
            ScalarType::U16 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::U16Bytes), |s| Ok(Self::U16(s)))
                .ok()?,
            ScalarType::I16 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::I16Bytes), |s| Ok(Self::I16(s)))
                .ok()?,
            ScalarType::U32 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::U32Bytes), |s| Ok(Self::U32(s)))
                .ok()?,
            ScalarType::I32 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::I32Bytes), |s| Ok(Self::I32(s)))
                .ok()?,
            ScalarType::F32 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::F32Bytes), |s| Ok(Self::F32(s)))
                .ok()?,
            ScalarType::F64 => cast(bytes)
                .map_or_else(|_| cast(bytes).map(Self::F64Bytes), |s| Ok(Self::F64(s)))
                .ok()?,
        })
    }

    /// Are the samples integers (not floats)?
    pub fn is_integer(&self) -> bool {
        !matches!(
            self,
            LentPlane::F32(_) | LentPlane::F64(_) | LentPlane::F32Bytes(_) | LentPlane::F64Bytes(_)
        )
    }

    /// Sample `i` as an `f64` (exact for every type).
    #[inline(always)]
    pub fn get(&self, i: usize) -> f64 {
        match self {
            LentPlane::U8(s) => f64::from(s[i]),
            LentPlane::I8(s) => f64::from(s[i]),
            LentPlane::U16(s) => f64::from(s[i]),
            LentPlane::I16(s) => f64::from(s[i]),
            LentPlane::U32(s) => f64::from(s[i]),
            LentPlane::I32(s) => f64::from(s[i]),
            LentPlane::F32(s) => f64::from(s[i]),
            LentPlane::F64(s) => s[i],
            LentPlane::U16Bytes(s) => f64::from(u16::from_ne_bytes(s[i])),
            LentPlane::I16Bytes(s) => f64::from(i16::from_ne_bytes(s[i])),
            LentPlane::U32Bytes(s) => f64::from(u32::from_ne_bytes(s[i])),
            LentPlane::I32Bytes(s) => f64::from(i32::from_ne_bytes(s[i])),
            LentPlane::F32Bytes(s) => f64::from(f32::from_ne_bytes(s[i])),
            LentPlane::F64Bytes(s) => f64::from_ne_bytes(s[i]),
        }
    }

    /// Samples `at` as `f64`s, with one look at the type for all of them.
    #[inline(always)]
    pub fn get_many<const N: usize>(&self, at: [usize; N]) -> [f64; N] {
        match self {
            LentPlane::U8(s) => at.map(|i| f64::from(s[i])),
            LentPlane::I8(s) => at.map(|i| f64::from(s[i])),
            LentPlane::U16(s) => at.map(|i| f64::from(s[i])),
            LentPlane::I16(s) => at.map(|i| f64::from(s[i])),
            LentPlane::U32(s) => at.map(|i| f64::from(s[i])),
            LentPlane::I32(s) => at.map(|i| f64::from(s[i])),
            LentPlane::F32(s) => at.map(|i| f64::from(s[i])),
            LentPlane::F64(s) => at.map(|i| s[i]),
            LentPlane::U16Bytes(s) => at.map(|i| f64::from(u16::from_ne_bytes(s[i]))),
            LentPlane::I16Bytes(s) => at.map(|i| f64::from(i16::from_ne_bytes(s[i]))),
            LentPlane::U32Bytes(s) => at.map(|i| f64::from(u32::from_ne_bytes(s[i]))),
            LentPlane::I32Bytes(s) => at.map(|i| f64::from(i32::from_ne_bytes(s[i]))),
            LentPlane::F32Bytes(s) => at.map(|i| f64::from(f32::from_ne_bytes(s[i]))),
            LentPlane::F64Bytes(s) => at.map(|i| f64::from_ne_bytes(s[i])),
        }
    }

    /// Samples in the plane.
    pub fn len(&self) -> usize {
        match self {
            LentPlane::U8(s) => s.len(),
            LentPlane::I8(s) => s.len(),
            LentPlane::U16(s) => s.len(),
            LentPlane::I16(s) => s.len(),
            LentPlane::U32(s) => s.len(),
            LentPlane::I32(s) => s.len(),
            LentPlane::F32(s) => s.len(),
            LentPlane::F64(s) => s.len(),
            LentPlane::U16Bytes(s) | LentPlane::I16Bytes(s) => s.len(),
            LentPlane::U32Bytes(s) | LentPlane::I32Bytes(s) | LentPlane::F32Bytes(s) => s.len(),
            LentPlane::F64Bytes(s) => s.len(),
        }
    }

    /// Whether the plane has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
