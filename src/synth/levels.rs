//! From field values to stored samples: how a synthetic field maps onto
//! the range of each sample type, and the rounding to that type.

use crate::volume::ScalarType;

/// The stored value of a unit field value `f` (clamped to `[-1, 1]`),
/// before rounding:
///
/// * `f32`, `f64`: `f` itself;
/// * signed integers: `f * MAX` (`MAX` = 127, 32767, 2147483647), so the
///   surface `f = 0` is at 0;
/// * unsigned integers: `(f + 1) / 2 * MAX` (`MAX` = 255, 65535,
///   4294967295), so -1 is 0, 1 is `MAX` and the surface is at `MAX / 2`
///   (127.5, 32767.5, 2147483647.5).
pub fn unit_to_stored(f: f64, scalar: ScalarType) -> f64 {
    let (a, b) = unit_affine(scalar);
    f.clamp(-1.0, 1.0) * a + b
}

/// `(a, b)` with `unit_to_stored(f) = clamp(f, -1, 1) * a + b`.
fn unit_affine(scalar: ScalarType) -> (f64, f64) {
    match scalar {
        ScalarType::F16 | ScalarType::F32 | ScalarType::F64 => (1.0, 0.0),
        ScalarType::I8 => (i8::MAX as f64, 0.0),
        ScalarType::I16 => (i16::MAX as f64, 0.0),
        // The 64-bit integers as the 32-bit ones: every value exact in f64.
        ScalarType::I32 | ScalarType::I64 => (i32::MAX as f64, 0.0),
        ScalarType::U8 => (u8::MAX as f64 / 2.0, u8::MAX as f64 / 2.0),
        ScalarType::U16 => (u16::MAX as f64 / 2.0, u16::MAX as f64 / 2.0),
        ScalarType::U32 | ScalarType::U64 => (u32::MAX as f64 / 2.0, u32::MAX as f64 / 2.0),
    }
}

/// The stored value of `hu` Hounsfield units, before rounding and clamping
/// to the type's range:
///
/// * `f32`, `f64`, `i16`, `i32`: `hu` (air -1000, water 0);
/// * `u16`, `u32`: `hu + 1000` (air 0);
/// * `u8`: `(hu + 1000) / 10` (air 0, water 100, bone 1500 HU at 250);
/// * `i8`: `hu / 12.5` (air -80, water 0, bone 1500 HU at 120).
pub fn hounsfield_to_stored(hu: f64, scalar: ScalarType) -> f64 {
    let (a, b) = hounsfield_affine(scalar);
    hu * a + b
}

/// `(a, b)` with `hounsfield_to_stored(hu) = hu * a + b`.
fn hounsfield_affine(scalar: ScalarType) -> (f64, f64) {
    match scalar {
        ScalarType::F16 | ScalarType::F32 | ScalarType::F64 => (1.0, 0.0),
        ScalarType::I16 | ScalarType::I32 | ScalarType::I64 => (1.0, 0.0),
        ScalarType::U16 | ScalarType::U32 | ScalarType::U64 => (1.0, 1000.0),
        ScalarType::U8 => (0.1, 100.0),
        ScalarType::I8 => (0.08, 0.0),
    }
}

/// Which values a field produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Units {
    /// A unit field in `[-1, 1]`, mapped by [`unit_to_stored`].
    Unit,
    /// Hounsfield units, mapped by [`hounsfield_to_stored`].
    Hounsfield,
}

/// Maps field values (in `units`) to stored `scalar` values in place,
/// rounded to what the type stores: integers round to nearest (ties to even)
/// and clamp to the type's range, `f32` rounds to nearest. The results read
/// back exactly from a file of that type.
pub(crate) fn to_stored(values: &mut [f64], units: Units, scalar: ScalarType) {
    let (a, b) = match units {
        Units::Unit => unit_affine(scalar),
        Units::Hounsfield => hounsfield_affine(scalar),
    };
    // Clamping a unit field to [-1, 1] first changes nothing for the
    // integer types (the affine map sends it onto the type's range) but
    // keeps float fields in [-1, 1].
    let (lo, hi) = match units {
        Units::Unit => (-1.0, 1.0),
        Units::Hounsfield => (f64::NEG_INFINITY, f64::INFINITY),
    };
    let (low, high) = match scalar {
        ScalarType::F64 => {
            for v in values.iter_mut() {
                *v = v.clamp(lo, hi) * a + b;
            }
            return;
        }
        ScalarType::F32 => {
            for v in values.iter_mut() {
                *v = (v.clamp(lo, hi) * a + b) as f32 as f64;
            }
            return;
        }
        ScalarType::F16 => {
            for v in values.iter_mut() {
                *v = half::f16::from_f64(v.clamp(lo, hi) * a + b).to_f64();
            }
            return;
        }
        ScalarType::U8 => (0.0, u8::MAX as f64),
        ScalarType::I8 => (i8::MIN as f64, i8::MAX as f64),
        ScalarType::U16 => (0.0, u16::MAX as f64),
        ScalarType::I16 => (i16::MIN as f64, i16::MAX as f64),
        ScalarType::U32 => (0.0, u32::MAX as f64),
        ScalarType::I32 => (i32::MIN as f64, i32::MAX as f64),
        // Held to 32 bits' range (see `unit_affine`): exact in f64.
        ScalarType::I64 => (i32::MIN as f64, i32::MAX as f64),
        ScalarType::U64 => (0.0, u32::MAX as f64),
    };
    // Adding and subtracting 1.5 * 2^52 rounds to the nearest integer (ties
    // to even) for |v| < 2^51, in two vectorizable additions (`f64::round`
    // is a library call on baseline x86-64).
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    for v in values.iter_mut() {
        *v = ((v.clamp(lo, hi) * a + b).clamp(low, high) + MAGIC) - MAGIC;
    }
}
