//! Sample types, byte order, and decoding stored samples into `f64`.

use crate::{Error, Result};
use std::fmt;
use std::str::FromStr;

/// The scalar type of stored samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarType {
    /// unsigned 8-bit
    U8,
    /// signed 8-bit
    I8,
    /// unsigned 16-bit
    U16,
    /// signed 16-bit
    I16,
    /// unsigned 32-bit
    U32,
    /// signed 32-bit
    I32,
    /// 32-bit float
    F32,
    /// 64-bit float
    F64,
    /// signed 64-bit: read as `f64`, exactly within ±2^53 (numpy's
    /// default integer, `skimage.measure.label`'s output)
    I64,
    /// unsigned 64-bit: read as `f64`, exactly up to 2^53
    U64,
    /// 16-bit float (IEEE half): read as `f64`, always exactly
    F16,
}

/// Byte order of multi-byte samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Endian {
    /// least significant byte first
    #[default]
    Little,
    /// most significant byte first
    Big,
}

/// The short names accepted by [`ScalarType::from_name`], in display order.
const NAMES: &str = "u8, i8, u16, i16, u32, i32, f32, f64, i64, u64, f16";

impl ScalarType {
    /// Every scalar type: the eight the slab loop reads in their own type,
    /// smallest first, then the three it reads as `f64` (see
    /// [`ScalarType::is_lent`]).
    pub const ALL: [ScalarType; 11] = [
        ScalarType::U8,
        ScalarType::I8,
        ScalarType::U16,
        ScalarType::I16,
        ScalarType::U32,
        ScalarType::I32,
        ScalarType::F32,
        ScalarType::F64,
        ScalarType::I64,
        ScalarType::U64,
        ScalarType::F16,
    ];

    /// Can planes of this type be lent to the slab loop in their own type
    /// ([`LentPlane`](super::LentPlane))? The 64-bit integers and half
    /// floats cannot: their planes are read as `f64` (a copy per plane).
    pub fn is_lent(self) -> bool {
        !matches!(self, ScalarType::I64 | ScalarType::U64 | ScalarType::F16)
    }

    /// Bytes per sample.
    pub fn size(self) -> usize {
        match self {
            ScalarType::U8 | ScalarType::I8 => 1,
            ScalarType::U16 | ScalarType::I16 | ScalarType::F16 => 2,
            ScalarType::U32 | ScalarType::I32 | ScalarType::F32 => 4,
            ScalarType::F64 | ScalarType::I64 | ScalarType::U64 => 8,
        }
    }

    /// The short name (`u8`, `i16`, `f32`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ScalarType::U8 => "u8",
            ScalarType::I8 => "i8",
            ScalarType::U16 => "u16",
            ScalarType::I16 => "i16",
            ScalarType::U32 => "u32",
            ScalarType::I32 => "i32",
            ScalarType::F32 => "f32",
            ScalarType::F64 => "f64",
            ScalarType::I64 => "i64",
            ScalarType::U64 => "u64",
            ScalarType::F16 => "f16",
        }
    }

    /// Parses a short name (`u8, i8, u16, i16, u32, i32, f32, f64`) or a
    /// common long one (`uint8`, `int16`, `float32`, `float`, `double`, ...),
    /// ignoring case.
    pub fn from_name(name: &str) -> Option<ScalarType> {
        let t = match name.trim().to_ascii_lowercase().as_str() {
            "u8" | "uint8" => ScalarType::U8,
            "i8" | "int8" => ScalarType::I8,
            "u16" | "uint16" => ScalarType::U16,
            "i16" | "int16" => ScalarType::I16,
            "u32" | "uint32" => ScalarType::U32,
            "i32" | "int32" => ScalarType::I32,
            "f32" | "float32" | "float" => ScalarType::F32,
            "f64" | "float64" | "double" => ScalarType::F64,
            "i64" | "int64" => ScalarType::I64,
            "u64" | "uint64" => ScalarType::U64,
            "f16" | "float16" | "half" => ScalarType::F16,
            _ => return None,
        };
        Some(t)
    }

    /// Parses a numpy dtype description such as `<u2`, `|u1`, `>f4` or
    /// `<f8` into a type and byte order (`=` means native order; `|` is only
    /// meaningful for one-byte types and reads as little-endian). A bool
    /// (`|b1`) is its bytes, 0 and 1: `u8`.
    pub fn from_numpy_descr(descr: &str) -> Option<(ScalarType, Endian)> {
        let mut chars = descr.chars();
        let order = chars.next()?;
        let endian = match order {
            '<' | '|' => Endian::Little,
            '>' => Endian::Big,
            '=' => Endian::native(),
            _ => return None,
        };
        let t = match chars.as_str() {
            "u1" => ScalarType::U8,
            "i1" => ScalarType::I8,
            "u2" => ScalarType::U16,
            "i2" => ScalarType::I16,
            "u4" => ScalarType::U32,
            "i4" => ScalarType::I32,
            "f4" => ScalarType::F32,
            "f8" => ScalarType::F64,
            "i8" => ScalarType::I64,
            "u8" => ScalarType::U64,
            "f2" => ScalarType::F16,
            "b1" => ScalarType::U8,
            _ => return None,
        };
        Some((t, endian))
    }
}

impl fmt::Display for ScalarType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ScalarType {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        ScalarType::from_name(s).ok_or_else(|| {
            Error::Invalid(format!(
                "unknown sample type '{s}' (expected one of {NAMES})"
            ))
        })
    }
}

impl Endian {
    /// The byte order of this machine.
    pub fn native() -> Endian {
        if cfg!(target_endian = "big") {
            Endian::Big
        } else {
            Endian::Little
        }
    }

    /// The name (`little` or `big`).
    pub fn name(self) -> &'static str {
        match self {
            Endian::Little => "little",
            Endian::Big => "big",
        }
    }
}

impl fmt::Display for Endian {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A `match` on a [`ScalarType`] whose every arm calls the local macro
/// `$run!(T)` with that arm's sample type: code written once per sample
/// type and compiled for each.
macro_rules! for_each_scalar {
    ($scalar:expr, $run:ident) => {
        match $scalar {
            $crate::volume::ScalarType::U8 => $run!(u8),
            $crate::volume::ScalarType::I8 => $run!(i8),
            $crate::volume::ScalarType::U16 => $run!(u16),
            $crate::volume::ScalarType::I16 => $run!(i16),
            $crate::volume::ScalarType::U32 => $run!(u32),
            $crate::volume::ScalarType::I32 => $run!(i32),
            $crate::volume::ScalarType::F32 => $run!(f32),
            $crate::volume::ScalarType::F64 => $run!(f64),
            $crate::volume::ScalarType::I64 => $run!(i64),
            $crate::volume::ScalarType::U64 => $run!(u64),
            $crate::volume::ScalarType::F16 => $run!(half::f16),
        }
    };
}
pub(crate) use for_each_scalar;

/// Decodes the samples packed in `bytes` into `out`, one sample per element.
///
/// Integers convert exactly; floats widen exactly, NaN stays NaN.
///
/// # Panics
/// If `bytes.len() != out.len() * scalar.size()`.
pub fn decode_samples(scalar: ScalarType, endian: Endian, bytes: &[u8], out: &mut [f64]) {
    assert_eq!(
        bytes.len(),
        out.len() * scalar.size(),
        "decode_samples: byte count does not match sample count"
    );
    decode_strided(scalar, endian, bytes, 0, scalar.size(), out);
}

/// Decodes `out.len()` samples from `bytes`, sample `i` starting at byte
/// `start + i * stride` (a stride of `scalar.size()` means packed samples).
///
/// # Panics
/// If the last sample read would end past `bytes.len()`.
pub fn decode_strided(
    scalar: ScalarType,
    endian: Endian,
    bytes: &[u8],
    start: usize,
    stride: usize,
    out: &mut [f64],
) {
    if out.is_empty() {
        return;
    }
    let last_end = (out.len() - 1)
        .checked_mul(stride)
        .and_then(|v| v.checked_add(start))
        .and_then(|v| v.checked_add(scalar.size()));
    assert!(
        last_end.is_some_and(|end| end <= bytes.len()),
        "decode_strided: samples extend past the end of the bytes"
    );
    macro_rules! run {
        ($t:ty) => {{
            const N: usize = std::mem::size_of::<$t>();
            for (i, o) in out.iter_mut().enumerate() {
                let at = start + i * stride;
                let mut raw = [0u8; N];
                raw.copy_from_slice(&bytes[at..at + N]);
                let v = match endian {
                    Endian::Little => <$t>::from_le_bytes(raw),
                    Endian::Big => <$t>::from_be_bytes(raw),
                };
                *o = v.as_f64();
            }
        }};
    }
    for_each_scalar!(scalar, run)
}

/// A stored sample's value as an `f64`: exact for every type except the
/// 64-bit integers beyond ±2^53, which round to the nearest `f64` (as
/// numpy's `astype(float64)` does).
pub(crate) trait AsF64: Copy {
    /// The value as an `f64`.
    fn as_f64(self) -> f64;
}

macro_rules! as_f64_exactly {
    ($($t:ty),*) => {$(
        impl AsF64 for $t {
            #[inline(always)]
            fn as_f64(self) -> f64 {
                f64::from(self)
            }
        }
    )*};
}
as_f64_exactly!(u8, i8, u16, i16, u32, i32, f32, f64);

impl AsF64 for i64 {
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self as f64
    }
}

impl AsF64 for u64 {
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self as f64
    }
}

impl AsF64 for half::f16 {
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self.to_f64()
    }
}

/// Encodes `values` as samples of `scalar` in `endian` byte order into
/// `bytes`, one sample per value: the inverse of [`decode_samples`].
///
/// Integer types round to the nearest integer (ties to even) and saturate
/// at the type's range, NaN becoming 0; `f32` rounds to nearest;
/// `f64` is copied. Values that [`decode_samples`] produced encode back to
/// the same bytes.
///
/// # Panics
/// If `bytes.len() != values.len() * scalar.size()`.
pub fn encode_samples(scalar: ScalarType, endian: Endian, values: &[f64], bytes: &mut [u8]) {
    assert_eq!(
        bytes.len(),
        values.len() * scalar.size(),
        "encode_samples: byte count does not match sample count"
    );
    macro_rules! run {
        ($t:ty, $convert:expr) => {{
            const N: usize = std::mem::size_of::<$t>();
            let convert = $convert;
            let pairs = values.iter().zip(bytes.chunks_exact_mut(N));
            match endian {
                Endian::Little => {
                    for (v, out) in pairs {
                        out.copy_from_slice(&convert(*v).to_le_bytes());
                    }
                }
                Endian::Big => {
                    for (v, out) in pairs {
                        out.copy_from_slice(&convert(*v).to_be_bytes());
                    }
                }
            }
        }};
    }
    // `saturate` gives the two's complement bits of the rounded value, which
    // `as` truncates to the type exactly.
    match scalar {
        ScalarType::U8 => run!(u8, |v: f64| saturate(v, u8::MIN, u8::MAX) as u8),
        ScalarType::I8 => run!(i8, |v: f64| saturate(v, i8::MIN, i8::MAX) as i8),
        ScalarType::U16 => run!(u16, |v: f64| saturate(v, u16::MIN, u16::MAX) as u16),
        ScalarType::I16 => run!(i16, |v: f64| saturate(v, i16::MIN, i16::MAX) as i16),
        ScalarType::U32 => run!(u32, |v: f64| saturate(v, u32::MIN, u32::MAX)),
        ScalarType::I32 => run!(i32, |v: f64| saturate(v, i32::MIN, i32::MAX) as i32),
        ScalarType::F32 => run!(f32, |v: f64| v as f32),
        ScalarType::F64 => run!(f64, |v: f64| v),
        // Rounded to the nearest integer (ties to even), saturating, NaN 0.
        ScalarType::I64 => run!(i64, |v: f64| v.round_ties_even() as i64),
        ScalarType::U64 => run!(u64, |v: f64| v.round_ties_even() as u64),
        ScalarType::F16 => run!(half::f16, half::f16::from_f64),
    }
}

/// `v` clamped to `[min, max]` and rounded to the nearest integer (ties
/// to even), NaN becoming 0, as the low 32 bits of its two's complement.
///
/// Adding 1.5 * 2^52 to a |v| < 2^51 leaves the rounded integer in the low
/// bits of the sum's mantissa: two vector instructions, no `f64::round` (a
/// library call on baseline x86-64) and no checked float-to-integer cast,
/// which kept the loop from vectorizing.
fn saturate<T: Into<f64>>(v: f64, min: T, max: T) -> u32 {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let v = if v.is_nan() { 0.0 } else { v };
    (v.max(min.into()).min(max.into()) + MAGIC).to_bits() as u32
}
