//! Planes lent as stored: a source that holds a plane's samples in memory,
//! in native byte order and without scaling, lends them to the slab loop,
//! which then compares them with the isovalue in their own type and turns
//! into `f64` only the few samples next to the surface.

use super::ScalarType;

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
}

impl<'a> LentPlane<'a> {
    /// Native-endian samples of `scalar` packed in `bytes`, or `None` when
    /// the bytes are not aligned for the type (those must be decoded).
    pub fn from_bytes(scalar: ScalarType, bytes: &'a [u8]) -> Option<Self> {
        use bytemuck::try_cast_slice as cast;
        Some(match scalar {
            ScalarType::U8 => LentPlane::U8(bytes),
            ScalarType::I8 => LentPlane::I8(cast(bytes).ok()?),
            ScalarType::U16 => LentPlane::U16(cast(bytes).ok()?),
            ScalarType::I16 => LentPlane::I16(cast(bytes).ok()?),
            ScalarType::U32 => LentPlane::U32(cast(bytes).ok()?),
            ScalarType::I32 => LentPlane::I32(cast(bytes).ok()?),
            ScalarType::F32 => LentPlane::F32(cast(bytes).ok()?),
            ScalarType::F64 => LentPlane::F64(cast(bytes).ok()?),
        })
    }

    /// Are the samples integers (not floats)?
    pub fn is_integer(&self) -> bool {
        !matches!(self, LentPlane::F32(_) | LentPlane::F64(_))
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
        }
    }

    /// Whether the plane has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
