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
//!
//! A plane stored in the other byte order (a big-endian file on a
//! little-endian machine) is lent as byte arrays too, each sample's bytes
//! swapped as it is read (the `...Swapped` variants).
//!
//! A plane whose samples are not stored as such anywhere (the border that
//! `--close` adds around another source's lent planes) is lent as a
//! [`PlaneView`], which computes each sample from the stored ones: the
//! slab loop classifies it a band of rows at a time, so no whole plane is
//! copied.

use super::ScalarType;

/// A plane computed from stored samples, lent as
/// [`LentPlane::View`]: the samples of a padded plane, say, read from the
/// inner source's lent plane with the border supplied on the fly. Its
/// samples count as `f64`s (NaN allowed), as a plane read with
/// [`SampleSource::read_plane`](super::SampleSource::read_plane) does.
pub trait PlaneView: Sync + std::fmt::Debug {
    /// Samples in the plane.
    fn len(&self) -> usize;

    /// Whether the plane has no samples.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sample `i` (x fastest) as an `f64`: the value `read_plane` gives.
    fn get(&self, i: usize) -> f64;

    /// Writes samples `start..start + out.len()` into `out` (what
    /// [`get`](Self::get) gives for each).
    fn range(&self, start: usize, out: &mut [f64]) {
        for (j, v) in out.iter_mut().enumerate() {
            *v = self.get(start + j);
        }
    }

    /// Writes the samples of the rows from `first` on into `out`, which
    /// holds whole rows of `row` samples (what [`get`](Self::get) gives for
    /// each).
    fn rows(&self, first: usize, row: usize, out: &mut [f64]) {
        self.range(first * row, out);
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
    /// Unsigned 16-bit samples in the other byte order (a big-endian file
    /// on a little-endian machine), at any alignment.
    U16Swapped(&'a [[u8; 2]]),
    /// Signed 16-bit samples in the other byte order, at any alignment.
    I16Swapped(&'a [[u8; 2]]),
    /// Unsigned 32-bit samples in the other byte order, at any alignment.
    U32Swapped(&'a [[u8; 4]]),
    /// Signed 32-bit samples in the other byte order, at any alignment.
    I32Swapped(&'a [[u8; 4]]),
    /// 32-bit floats in the other byte order, at any alignment.
    F32Swapped(&'a [[u8; 4]]),
    /// 64-bit floats in the other byte order, at any alignment.
    F64Swapped(&'a [[u8; 8]]),
    /// Samples computed from stored ones (see [`PlaneView`]), as `f64`s.
    View(&'a dyn PlaneView),
}

/// The bytes of a sample stored in the other byte order, in this
/// machine's.
#[inline(always)]
fn swapped<const N: usize>(mut bytes: [u8; N]) -> [u8; N] {
    bytes.reverse();
    bytes
}

impl<'a> LentPlane<'a> {
    /// Native-endian samples of `scalar` packed in `bytes`: typed slices
    /// when the bytes are aligned for the type, else byte arrays (the
    /// `...Bytes` variants); `None` for the types read as `f64`
    /// ([`ScalarType::is_lent`]) and when the bytes do not hold a whole
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
            // Read as `f64` instead (`ScalarType::is_lent`).
            ScalarType::I64 | ScalarType::U64 | ScalarType::F16 => return None,
        })
    }

    /// Samples of `scalar` packed in `bytes` in the other byte order than
    /// this machine's (the `...Swapped` variants; 8-bit samples have no
    /// byte order); `None` for the types read as `f64` and when the bytes
    /// do not hold a whole number of
    /// samples.
    pub fn from_foreign_bytes(scalar: ScalarType, bytes: &'a [u8]) -> Option<Self> {
        use bytemuck::try_cast_slice as cast;
        Some(match scalar {
            ScalarType::U8 | ScalarType::I8 => Self::from_bytes(scalar, bytes)?,
            ScalarType::U16 => Self::U16Swapped(cast(bytes).ok()?),
            ScalarType::I16 => Self::I16Swapped(cast(bytes).ok()?),
            ScalarType::U32 => Self::U32Swapped(cast(bytes).ok()?),
            ScalarType::I32 => Self::I32Swapped(cast(bytes).ok()?),
            ScalarType::F32 => Self::F32Swapped(cast(bytes).ok()?),
            ScalarType::F64 => Self::F64Swapped(cast(bytes).ok()?),
            ScalarType::I64 | ScalarType::U64 | ScalarType::F16 => return None,
        })
    }

    /// Are the samples integers (not floats)?
    pub fn is_integer(&self) -> bool {
        !matches!(
            self,
            LentPlane::F32(_)
                | LentPlane::F64(_)
                | LentPlane::F32Bytes(_)
                | LentPlane::F64Bytes(_)
                | LentPlane::F32Swapped(_)
                | LentPlane::F64Swapped(_)
                | LentPlane::View(_)
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
            LentPlane::U16Swapped(s) => f64::from(u16::from_ne_bytes(swapped(s[i]))),
            LentPlane::I16Swapped(s) => f64::from(i16::from_ne_bytes(swapped(s[i]))),
            LentPlane::U32Swapped(s) => f64::from(u32::from_ne_bytes(swapped(s[i]))),
            LentPlane::I32Swapped(s) => f64::from(i32::from_ne_bytes(swapped(s[i]))),
            LentPlane::F32Swapped(s) => f64::from(f32::from_ne_bytes(swapped(s[i]))),
            LentPlane::F64Swapped(s) => f64::from_ne_bytes(swapped(s[i])),
            LentPlane::View(v) => v.get(i),
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
            LentPlane::U16Swapped(_)
            | LentPlane::I16Swapped(_)
            | LentPlane::U32Swapped(_)
            | LentPlane::I32Swapped(_)
            | LentPlane::F32Swapped(_)
            | LentPlane::F64Swapped(_) => at.map(|i| self.get(i)),
            LentPlane::View(v) => at.map(|i| v.get(i)),
        }
    }

    /// Samples `start..start + out.len()` as `f64`s, written to `out`,
    /// with one look at the type for all of them.
    pub fn get_range(&self, start: usize, out: &mut [f64]) {
        let end = start + out.len();
        /// Converts `$s[start..end]` into `out` with `$f`.
        macro_rules! each {
            ($s:expr, $f:expr) => {
                for (o, v) in out.iter_mut().zip(&$s[start..end]) {
                    *o = $f(*v);
                }
            };
        }
        match self {
            LentPlane::U8(s) => each!(s, f64::from),
            LentPlane::I8(s) => each!(s, f64::from),
            LentPlane::U16(s) => each!(s, f64::from),
            LentPlane::I16(s) => each!(s, f64::from),
            LentPlane::U32(s) => each!(s, f64::from),
            LentPlane::I32(s) => each!(s, f64::from),
            LentPlane::F32(s) => each!(s, f64::from),
            LentPlane::F64(s) => out.copy_from_slice(&s[start..end]),
            LentPlane::U16Bytes(s) => each!(s, |b| f64::from(u16::from_ne_bytes(b))),
            LentPlane::I16Bytes(s) => each!(s, |b| f64::from(i16::from_ne_bytes(b))),
            LentPlane::U32Bytes(s) => each!(s, |b| f64::from(u32::from_ne_bytes(b))),
            LentPlane::I32Bytes(s) => each!(s, |b| f64::from(i32::from_ne_bytes(b))),
            LentPlane::F32Bytes(s) => each!(s, |b| f64::from(f32::from_ne_bytes(b))),
            LentPlane::F64Bytes(s) => each!(s, f64::from_ne_bytes),
            LentPlane::U16Swapped(s) => each!(s, |b| f64::from(u16::from_ne_bytes(swapped(b)))),
            LentPlane::I16Swapped(s) => each!(s, |b| f64::from(i16::from_ne_bytes(swapped(b)))),
            LentPlane::U32Swapped(s) => each!(s, |b| f64::from(u32::from_ne_bytes(swapped(b)))),
            LentPlane::I32Swapped(s) => each!(s, |b| f64::from(i32::from_ne_bytes(swapped(b)))),
            LentPlane::F32Swapped(s) => each!(s, |b| f64::from(f32::from_ne_bytes(swapped(b)))),
            LentPlane::F64Swapped(s) => each!(s, |b| f64::from_ne_bytes(swapped(b))),
            LentPlane::View(v) => v.range(start, out),
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
            LentPlane::U16Bytes(s)
            | LentPlane::I16Bytes(s)
            | LentPlane::U16Swapped(s)
            | LentPlane::I16Swapped(s) => s.len(),
            LentPlane::U32Bytes(s)
            | LentPlane::I32Bytes(s)
            | LentPlane::F32Bytes(s)
            | LentPlane::U32Swapped(s)
            | LentPlane::I32Swapped(s)
            | LentPlane::F32Swapped(s) => s.len(),
            LentPlane::F64Bytes(s) | LentPlane::F64Swapped(s) => s.len(),
            LentPlane::View(v) => v.len(),
        }
    }

    /// Whether the plane has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples stored in the other byte order read as their values, one
    /// by one, a few at once and as a range, at any alignment.
    #[test]
    fn swapped_planes_read_as_their_samples() {
        let u16s = [1u16, 0x0102, 65535];
        let f32s = [-1.5f32, 0.1, f32::MAX];
        let mut bytes = vec![0u8];
        bytes.extend(u16s.iter().flat_map(|v| v.swap_bytes().to_ne_bytes()));
        let mut floats = vec![0u8];
        floats.extend(
            f32s.iter()
                .flat_map(|v| v.to_bits().swap_bytes().to_ne_bytes()),
        );
        let u16_want = u16s.map(f64::from);
        let f32_want = f32s.map(f64::from);
        for (scalar, stored, want) in [
            (ScalarType::U16, &bytes[1..], &u16_want),
            (ScalarType::F32, &floats[1..], &f32_want),
        ] {
            let plane = LentPlane::from_foreign_bytes(scalar, stored).unwrap();
            assert_eq!(plane.len(), 3);
            let one_by_one: Vec<f64> = (0..3).map(|i| plane.get(i)).collect();
            assert_eq!(one_by_one, want);
            assert_eq!(plane.get_many([0, 1, 2]), *want);
            let mut range = [0.0; 2];
            plane.get_range(1, &mut range);
            assert_eq!(range, want[1..]);
        }
        assert!(LentPlane::from_foreign_bytes(ScalarType::U16, &bytes[..3]).is_none());
    }
}
