//! A cell's exact values as integers, for the predicates that must not
//! round.
//!
//! The kernel is given `g = value - iso` rounded to `f64` and, where that
//! subtraction was not exact, what the rounding left out (the residual `r`,
//! from Knuth's TwoSum), so that `g + r` is the exact difference. Every
//! decision the kernel takes is the sign of a polynomial in those exact
//! values, homogeneous of degree two (a face) or up to four (a tunnel), so
//! it may scale them by any power of two. `Span` finds the power that
//! makes all of them integers and how many bits those integers then have;
//! `integers` builds them in a type wide enough for products of up to
//! four (`bnum`'s fixed-size integers; 256, 512 or 1024 bits).

use bnum::cast::As;
use bnum::types::{I1024, I256, I512};

/// Where the binary digits of some finite values lie: each nonzero value
/// is an odd integer times `2^e` with `e >= low`, and below `2^high` in
/// magnitude (both 0 if all values are zero). Scaling by `2^-low` makes
/// them integers of `high - low` bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Span {
    pub(super) low: i32,
    pub(super) high: i32,
}

impl Span {
    /// The span of `values`, if they are all finite.
    pub(super) fn of(values: impl IntoIterator<Item = f64>) -> Option<Span> {
        let (mut low, mut high) = (i32::MAX, i32::MIN);
        for v in values {
            if v == 0.0 {
                continue;
            }
            if !v.is_finite() {
                return None;
            }
            let bits = v.to_bits();
            let biased = ((bits >> 52) & 0x7ff) as i32;
            let fraction = bits & ((1u64 << 52) - 1);
            let (mantissa, exp) = if biased == 0 {
                (fraction, -1074)
            } else {
                (fraction | (1u64 << 52), biased - 1075)
            };
            let tz = mantissa.trailing_zeros() as i32;
            let odd_bits = 64 - (mantissa >> tz).leading_zeros() as i32;
            low = low.min(exp + tz);
            // Magnitude below 2^(exp + tz + odd_bits).
            high = high.max(exp + tz + odd_bits);
        }
        Some(if low == i32::MAX {
            Span { low: 0, high: 0 }
        } else {
            Span { low, high }
        })
    }

    /// The power of two (up or down) that makes all values integers, if
    /// they then have at most `bits` bits (at most about 1000).
    pub(super) fn integer_scale(self, bits: i32) -> Option<Scale> {
        let shift = -self.low;
        let (first, second) = (shift / 2, shift - shift / 2);
        let normal = -1022..=1023;
        (self.high - self.low <= bits && normal.contains(&first) && normal.contains(&second)).then(
            || Scale {
                first: super::scale::power_of_two(first),
                second: super::scale::power_of_two(second),
            },
        )
    }

    /// The power of two that makes all values integers, never below 1, and
    /// the magnitude bits of the largest of those integers (at least 0):
    /// what the tunnel test's `i64` and `i128` sweeps use.
    pub(super) fn upscaled(self) -> (f64, i32) {
        let shift = (-self.low).max(0);
        // A shift beyond the normal range gives more bits than any sweep takes.
        (
            super::scale::power_of_two(shift.min(1023)),
            self.high.max(0) + shift,
        )
    }

    /// Bits of the integers [`Span::integer_scale`] makes.
    pub(super) fn bits(self) -> i32 {
        self.high - self.low
    }
}

/// A power of two as two normal factors, applied one after the other, so
/// that values whose lowest bits lie below `2^-1022` (subnormal residuals,
/// cells of tiny values) still scale to integers. Exact for the values of
/// the span it was made for: every intermediate keeps their lowest bit at
/// `2^-1074` or above, and their magnitude below `2^1024`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Scale {
    first: f64,
    second: f64,
}

impl Scale {
    /// `v` times the power of two.
    #[inline]
    pub(super) fn apply(self, v: f64) -> f64 {
        v * self.first * self.second
    }
}

/// Integer types wide enough for the kernel's exact predicates.
pub(super) trait WideInt: Copy {
    /// The integer an integer-valued `f64` stands for, exactly.
    fn of_integral(v: f64) -> Self;
    /// `self + other`.
    fn plus(self, other: Self) -> Self;
}

macro_rules! wide_int {
    ($t:ty) => {
        impl WideInt for $t {
            #[inline]
            fn of_integral(v: f64) -> Self {
                // Exact: `v` is an integer well inside the type's range.
                v.as_::<$t>()
            }
            #[inline]
            fn plus(self, other: Self) -> Self {
                self + other
            }
        }
    };
}

wide_int!(I256);
wide_int!(I512);
wide_int!(I1024);

/// The exact integers `high + low` (both integer-valued after scaling by
/// [`Span::integer_scale`]), in type `T`.
pub(super) fn integers<T: WideInt, const N: usize>(high: &[f64; N], low: &[f64; N]) -> [T; N] {
    std::array::from_fn(|i| T::of_integral(high[i]).plus(T::of_integral(low[i])))
}

/// The exact residual of `a - b`: `(a - b) - fl(a - b)`, as a double
/// (Knuth's TwoSum; exact for finite inputs whose difference does not
/// overflow). Zero iff the subtraction was exact.
#[inline(always)]
pub fn subtraction_residual(a: f64, b: f64, difference: f64) -> f64 {
    let b_neg = -b;
    let a_part = difference - b_neg;
    let b_part = difference - a_part;
    (a - a_part) + (b_neg - b_part)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::scale::power_of_two;

    #[test]
    fn span_finds_the_integer_scale_either_way() {
        let span = |g: [f64; 2]| Span::of(g).unwrap();
        // 3 * 2^40 and 1: 42 bits at scale 1.
        let scaled = |s: Span, v: f64| s.integer_scale(60).map(|k| k.apply(v));
        let s = span([3.0 * (1u64 << 40) as f64, -1.0]);
        assert_eq!(scaled(s, 1.0), Some(1.0));
        assert_eq!(s.bits(), 42);
        // 2^71 and 2^11: 61 bits after scaling down by 2^11, too many;
        // 2^70 and 2^11: 60 bits.
        let s = span([power_of_two(71), -power_of_two(11)]);
        assert_eq!(s.integer_scale(60), None);
        let s = span([power_of_two(70), -power_of_two(11)]);
        assert_eq!(scaled(s, 1.0), Some(power_of_two(-11)));
        // 0.75 and 2^-50: 51 bits after scaling up by 2^50.
        let s = span([0.75, power_of_two(-50)]);
        assert_eq!(scaled(s, 1.0), Some(power_of_two(50)));
        assert!(Span::of([f64::INFINITY; 8]).is_none());
        assert_eq!(scaled(Span::of([0.0; 8]).unwrap(), 1.0), Some(1.0));
        // Below 2^-1022: 3 * 2^-1010 and the smallest subnormal scale to
        // 3 * 2^64 and 1 (a scale of 2^1074, beyond a double, in two steps).
        let tiny = f64::from_bits(1);
        let s = span([3.0 * power_of_two(-1010), tiny]);
        assert_eq!(scaled(s, tiny), None);
        let k = s.integer_scale(70).unwrap();
        assert_eq!(
            (k.apply(tiny), k.apply(3.0 * power_of_two(-1010))),
            (1.0, 3.0 * power_of_two(64))
        );
        // And down from near the largest double: 2^1000 + 2^960 to 2^40 + 1.
        let s = span([power_of_two(1000) + power_of_two(960), power_of_two(990)]);
        let k = s.integer_scale(60).unwrap();
        assert_eq!(
            k.apply(power_of_two(1000) + power_of_two(960)),
            power_of_two(40) + 1.0
        );
    }

    #[test]
    fn residuals_make_the_difference_exact() {
        // 3 - fl(1/3) needs 56 bits; the residual holds the rest. Checked
        // in integers: everything scaled by 2^54 is an integer.
        let third = 1.0 / 3.0;
        let d = 3.0 - third;
        let r = subtraction_residual(3.0, third, d);
        assert_ne!(r, 0.0);
        let scale = power_of_two(54);
        let exact = 3i128 * (1 << 54) - (third * scale) as i128;
        assert_eq!((d * scale) as i128 + (r * scale) as i128, exact);
        // Exact subtractions leave nothing.
        for (a, b) in [
            (1000.0, 500.0),
            (0.3, 0.3),
            (0.75, 0.5),
            (1.5, -0.25),
            (5.0, 0.0),
        ] {
            assert_eq!(subtraction_residual(a, b, a - b), 0.0, "{a} - {b}");
        }
    }

    #[test]
    fn integers_are_exact_in_every_width() {
        let high = [
            power_of_two(200) + power_of_two(148),
            -power_of_two(90),
            0.0,
        ];
        let low = [1.0, 3.0, -(power_of_two(52) + 1.0)];
        let wide: [I1024; 3] = integers(&high, &low);
        let expected = [
            (I1024::ONE << 200u32) + (I1024::ONE << 148u32) + I1024::ONE,
            -(I1024::ONE << 90u32) + I1024::THREE,
            -(I1024::ONE << 52u32) - I1024::ONE,
        ];
        assert_eq!(wide, expected);
        let narrow: [I256; 3] = integers(&[-7.0, 0.5e3, 0.0], &[1.0, 0.0, -2.0]);
        assert_eq!(narrow, [-6, 500, -2].map(I256::from));
    }
}
