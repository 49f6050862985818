//! [`Sample`]: the stored sample types (`u8` ... `f64`), how each converts
//! to `f64`, and how the slab loop compares it with the isovalue without
//! converting ([`Threshold`]).

use super::LentPlane;

/// A sample type an [`ArrayVolume`](super::ArrayVolume) can hold; every one converts to `f64`
/// exactly.
pub trait Sample: Copy + PartialOrd + Send + Sync + 'static {
    /// The value as an `f64`.
    fn to_f64(self) -> f64;
    /// Samples of this type as a [`LentPlane`].
    fn lend(samples: &[Self]) -> LentPlane<'_>;
    /// The test `to_f64() > iso` (`above`) or `to_f64() < iso` as a
    /// comparison in this type, so that a plane of 16-bit samples is
    /// classified 16 bits at a time rather than through `f64`. `iso` is
    /// finite. The default keeps the `f64` comparison.
    fn threshold(iso: f64, above: bool) -> Threshold<Self> {
        let _ = (iso, above);
        Threshold::ViaF64
    }
    /// Is `to_f64() - iso` exact in `f64` for every sample of this type?
    /// Then the slab loop need not look for rounding in the differences.
    /// The default says so only for `iso == 0`.
    fn subtracts_exactly(iso: f64) -> bool {
        iso == 0.0
    }
}

/// A comparison with the isovalue, as [`Sample::threshold`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold<T> {
    /// Compare through `f64`.
    ViaF64,
    /// No sample of the type passes.
    Nothing,
    /// Every sample of the type passes.
    Everything,
    /// `v > t` in the sample type.
    Above(T),
    /// `v < t` in the sample type.
    Below(T),
}

/// `impl Sample`: `$threshold(iso, above)` gives [`Sample::threshold`],
/// `$exact(iso)` [`Sample::subtracts_exactly`].
macro_rules! sample {
    ($($t:ty => $v:ident, $threshold:expr, $exact:expr;)*) => {$(
        impl Sample for $t {
            #[inline]
            fn to_f64(self) -> f64 {
                f64::from(self)
            }
            fn lend(samples: &[Self]) -> LentPlane<'_> {
                LentPlane::$v(samples)
            }
            fn threshold(iso: f64, above: bool) -> Threshold<Self> {
                $threshold(iso, above)
            }
            fn subtracts_exactly(iso: f64) -> bool {
                $exact(iso)
            }
        }
    )*};
}

/// Integers: `v > iso` iff `v > floor(iso)`, and `v < iso` iff
/// `v < ceil(iso)`, with the bound clamped to the type's range.
macro_rules! integer {
    ($t:ty) => {
        |iso, above| {
            let (min, max) = (f64::from(<$t>::MIN), f64::from(<$t>::MAX));
            integer_threshold(iso, above, min, max).map(|t| t as $t)
        }
    };
}

/// Integers: exact for every value of the type (see
/// [`integers_subtract_exactly`]).
macro_rules! integer_exact {
    ($t:ty) => {
        |iso| integers_subtract_exactly(iso, f64::from(<$t>::MIN), f64::from(<$t>::MAX))
    };
}

sample! {
    u8 => U8, integer!(u8), integer_exact!(u8);
    i8 => I8, integer!(i8), integer_exact!(i8);
    u16 => U16, integer!(u16), integer_exact!(u16);
    i16 => I16, integer!(i16), integer_exact!(i16);
    u32 => U32, integer!(u32), integer_exact!(u32);
    i32 => I32, integer!(i32), integer_exact!(i32);
    f32 => F32, f32_threshold, |iso| iso == 0.0;
    f64 => F64, |_, _| Threshold::ViaF64, |iso| iso == 0.0;
}

/// Is `v - iso` exact in `f64` for every integer `v` in `[min, max]`? With
/// `k` the fraction bits of `iso`, every difference is an integer times
/// `2^-k` of magnitude at most `(max |v| + |iso|) 2^k`, so it is exact when
/// that bound (as rounded) is below `2^53`.
fn integers_subtract_exactly(iso: f64, min: f64, max: f64) -> bool {
    if !iso.is_finite() {
        return false;
    }
    let (mut scaled, mut k) = (iso, 0);
    // Each doubling is exact and takes one fraction bit: at most 1074.
    while scaled.fract() != 0.0 {
        scaled *= 2.0;
        k += 1;
    }
    // `<`, not `<=`: a sum that rounds down to 2^53 is above it.
    (min.abs().max(max.abs()) + iso.abs()) * 2f64.powi(k) < (1u64 << 53) as f64
}

impl<T> Threshold<T> {
    fn map<U>(self, f: impl Fn(T) -> U) -> Threshold<U> {
        match self {
            Threshold::ViaF64 => Threshold::ViaF64,
            Threshold::Nothing => Threshold::Nothing,
            Threshold::Everything => Threshold::Everything,
            Threshold::Above(t) => Threshold::Above(f(t)),
            Threshold::Below(t) => Threshold::Below(f(t)),
        }
    }
}

/// The bound for integers in `[min, max]` (both exact in `f64`; the bound
/// returned is an integer in that range).
fn integer_threshold(iso: f64, above: bool, min: f64, max: f64) -> Threshold<f64> {
    if above {
        let t = iso.floor();
        if t >= max {
            Threshold::Nothing
        } else if t < min {
            Threshold::Everything
        } else {
            Threshold::Above(t)
        }
    } else {
        let t = iso.ceil();
        if t <= min {
            Threshold::Nothing
        } else if t > max {
            Threshold::Everything
        } else {
            Threshold::Below(t)
        }
    }
}

/// `f32`: `v > iso` iff `v > t` for `t` the largest `f32` not above `iso`
/// (no `f32` lies between them), and `v < iso` iff `v < t` for the
/// smallest `f32` not below it; NaN fails both, as in `f64`.
fn f32_threshold(iso: f64, above: bool) -> Threshold<f32> {
    let nearest = iso as f32;
    if above {
        if f64::from(nearest) > iso {
            Threshold::Above(next_down_f32(nearest))
        } else {
            Threshold::Above(nearest)
        }
    } else if f64::from(nearest) < iso {
        Threshold::Below(-next_down_f32(-nearest))
    } else {
        Threshold::Below(nearest)
    }
}

/// The next `f32` below `x` (`x` neither NaN nor `-inf`).
fn next_down_f32(x: f32) -> f32 {
    if x == 0.0 {
        -f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() - 1)
    } else {
        f32::from_bits(x.to_bits() + 1)
    }
}

/// Asked of a lent plane, answered by its sample type.
impl LentPlane<'_> {
    /// Is `get(i) - iso` exact in `f64` for every sample the type can hold
    /// (see [`Sample::subtracts_exactly`])?
    pub fn subtracts_exactly(&self, iso: f64) -> bool {
        match self {
            LentPlane::U8(_) => u8::subtracts_exactly(iso),
            LentPlane::I8(_) => i8::subtracts_exactly(iso),
            LentPlane::U16(_) => u16::subtracts_exactly(iso),
            LentPlane::I16(_) => i16::subtracts_exactly(iso),
            LentPlane::U32(_) => u32::subtracts_exactly(iso),
            LentPlane::I32(_) => i32::subtracts_exactly(iso),
            LentPlane::F32(_) => f32::subtracts_exactly(iso),
            LentPlane::F64(_) => f64::subtracts_exactly(iso),
            LentPlane::U16Bytes(_) | LentPlane::U16Swapped(_) => u16::subtracts_exactly(iso),
            LentPlane::I16Bytes(_) | LentPlane::I16Swapped(_) => i16::subtracts_exactly(iso),
            LentPlane::U32Bytes(_) | LentPlane::U32Swapped(_) => u32::subtracts_exactly(iso),
            LentPlane::I32Bytes(_) | LentPlane::I32Swapped(_) => i32::subtracts_exactly(iso),
            LentPlane::F32Bytes(_) | LentPlane::F32Swapped(_) => f32::subtracts_exactly(iso),
            LentPlane::F64Bytes(_) | LentPlane::F64Swapped(_) | LentPlane::View(_) => {
                f64::subtracts_exactly(iso)
            }
        }
    }
}

#[cfg(test)]
mod threshold_tests {
    use super::*;

    /// The native comparison agrees with the `f64` one for every sample
    /// of the type (or a spread of them) and isovalues at, between and
    /// beyond the samples.
    fn agrees<T: Sample>(samples: &[T]) {
        let mut isos: Vec<f64> = vec![-1e300, -5e9, 5e9, 1e300, -0.0, 0.0];
        for v in samples.iter().step_by(samples.len() / 500 + 1) {
            let x = v.to_f64();
            isos.extend([x, x - 0.5, x + 0.5, x - 1e-9, x + 1e-9]);
        }
        for &iso in &isos {
            for above in [true, false] {
                let expect = |v: T| {
                    if above {
                        v.to_f64() > iso
                    } else {
                        v.to_f64() < iso
                    }
                };
                let native = |v: T| match T::threshold(iso, above) {
                    Threshold::ViaF64 => expect(v),
                    Threshold::Nothing => false,
                    Threshold::Everything => true,
                    Threshold::Above(t) => v > t,
                    Threshold::Below(t) => v < t,
                };
                for &v in samples {
                    assert_eq!(native(v), expect(v), "iso {iso} above {above}");
                }
            }
        }
    }

    #[test]
    fn native_thresholds_agree_with_f64() {
        agrees(&(0..=u8::MAX).collect::<Vec<u8>>());
        agrees(&(i8::MIN..=i8::MAX).collect::<Vec<i8>>());
        agrees(
            &(0..=u16::MAX)
                .step_by(7)
                .chain([u16::MAX])
                .collect::<Vec<u16>>(),
        );
        agrees(
            &(i16::MIN..=i16::MAX)
                .step_by(7)
                .chain([i16::MAX])
                .collect::<Vec<i16>>(),
        );
        agrees(&[0, 1, 2, 1 << 20, u32::MAX - 1, u32::MAX]);
        agrees(&[i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX - 1, i32::MAX]);
        let mut floats = vec![
            f32::NEG_INFINITY,
            -f32::MAX,
            -1.5,
            -f32::from_bits(1),
            -0.0,
            0.0,
            f32::from_bits(1),
            f32::MIN_POSITIVE,
            0.1,
            1.0,
            16_777_217.0,
            f32::MAX,
            f32::INFINITY,
            f32::NAN,
        ];
        floats.extend((0..2000).map(|i| (i as f32 - 1000.0) * 0.37));
        agrees(&floats);
        // Isovalues that f32 cannot hold, next to samples it can.
        for iso in [0.1f64, -0.1, 1e-50, -1e-50, 3.4e38, 3.5e38, -3.5e38, 1e39] {
            for above in [true, false] {
                for &v in &floats {
                    let native = match f32::threshold(iso, above) {
                        Threshold::Above(t) => v > t,
                        Threshold::Below(t) => v < t,
                        other => panic!("{other:?}"),
                    };
                    let expect = if above {
                        f64::from(v) > iso
                    } else {
                        f64::from(v) < iso
                    };
                    assert_eq!(native, expect, "v {v} iso {iso} above {above}");
                }
            }
        }
    }
}
