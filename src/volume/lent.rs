//! Planes lent as stored: a source that holds a plane's samples in memory,
//! in native byte order and without scaling, lends them to the slab loop,
//! which then compares them with the isovalue in their own type and turns
//! into `f64` only the few samples next to the surface.
//!
//! A plane whose bytes are not aligned for their type (a file header of odd
//! length before 16-bit samples, say) is lent too, as [`Packed`] bytes
//! decoded sample by sample: before, such a plane was read into `f64`s,
//! 8 bytes of the process's own memory per sample and per plane (two
//! planes per worker: 1 GiB per worker for planes of 8192 x 8192), where
//! a lent plane stays in the page cache.

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
    /// Samples of a type wider than a byte, in native byte order, in bytes
    /// not aligned for that type.
    Packed(Packed<'a>),
}

/// Native-endian samples of one type packed in bytes at any alignment:
/// each sample is decoded when it is read.
#[derive(Debug, Clone, Copy)]
pub struct Packed<'a> {
    scalar: ScalarType,
    bytes: &'a [u8],
}

/// Sample `i` of `bytes` as `T`, read from `N` native-endian bytes.
macro_rules! decode {
    ($t:ty, $bytes:expr, $i:expr) => {{
        const N: usize = std::mem::size_of::<$t>();
        let at = $i * N;
        let mut b = [0u8; N];
        b.copy_from_slice(&$bytes[at..at + N]);
        <$t>::from_ne_bytes(b)
    }};
}

impl<'a> Packed<'a> {
    /// The samples' type.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }

    /// Sample `i` as an `f64` (exact for every type).
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        let b = self.bytes;
        match self.scalar {
            ScalarType::U8 => f64::from(b[i]),
            ScalarType::I8 => f64::from(b[i] as i8),
            ScalarType::U16 => f64::from(decode!(u16, b, i)),
            ScalarType::I16 => f64::from(decode!(i16, b, i)),
            ScalarType::U32 => f64::from(decode!(u32, b, i)),
            ScalarType::I32 => f64::from(decode!(i32, b, i)),
            ScalarType::F32 => f64::from(decode!(f32, b, i)),
            ScalarType::F64 => decode!(f64, b, i),
        }
    }

    /// Copies samples `start..start + out.len()` into `out`, whose type
    /// must be the samples' own (same size; bytes copied as they are).
    pub fn copy_to<T: bytemuck::Pod>(&self, start: usize, out: &mut [T]) {
        let size = std::mem::size_of::<T>();
        assert_eq!(
            size,
            self.scalar.size(),
            "decoded as a type of another size"
        );
        let bytes = &self.bytes[start * size..(start + out.len()) * size];
        bytemuck::cast_slice_mut::<T, u8>(out).copy_from_slice(bytes);
    }

    /// Samples held.
    pub fn len(&self) -> usize {
        self.bytes.len() / self.scalar.size()
    }

    /// Whether no sample is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl<'a> LentPlane<'a> {
    /// Native-endian samples of `scalar` packed in `bytes`: typed slices
    /// when the bytes are aligned for the type, else [`LentPlane::Packed`];
    /// `None` when the bytes do not hold a whole number of samples.
    pub fn from_bytes(scalar: ScalarType, bytes: &'a [u8]) -> Option<Self> {
        use bytemuck::try_cast_slice as cast;
        if !bytes.len().is_multiple_of(scalar.size()) {
            return None;
        }
        let packed = LentPlane::Packed(Packed { scalar, bytes });
        Some(match scalar {
            ScalarType::U8 => LentPlane::U8(bytes),
            ScalarType::I8 => LentPlane::I8(cast(bytes).ok()?),
            ScalarType::U16 => cast(bytes).map_or(packed, LentPlane::U16),
            ScalarType::I16 => cast(bytes).map_or(packed, LentPlane::I16),
            ScalarType::U32 => cast(bytes).map_or(packed, LentPlane::U32),
            ScalarType::I32 => cast(bytes).map_or(packed, LentPlane::I32),
            ScalarType::F32 => cast(bytes).map_or(packed, LentPlane::F32),
            ScalarType::F64 => cast(bytes).map_or(packed, LentPlane::F64),
        })
    }

    /// Are the samples integers (not floats)?
    pub fn is_integer(&self) -> bool {
        match self {
            LentPlane::Packed(p) => !matches!(p.scalar, ScalarType::F32 | ScalarType::F64),
            _ => !matches!(self, LentPlane::F32(_) | LentPlane::F64(_)),
        }
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
            LentPlane::Packed(p) => p.get(i),
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
            LentPlane::Packed(p) => at.map(|i| p.get(i)),
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
            LentPlane::Packed(p) => p.len(),
        }
    }

    /// Whether the plane has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
