//! [`Level`]: which side of the isovalue is inside, and the value the kernel
//! sees for a sample (`value - iso`, signed, NaN as a tie, clamped), with
//! what rounding left out of it.

use crate::kernel::wide::subtraction_residual;
use crate::params::{ExtractParams, Inside};

/// Which side of the isovalue is inside, and the value the kernel sees.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Level {
    pub(super) iso: f64,
    /// 1 for `Inside::High`, -1 for `Inside::Low`.
    pub(super) sign: f64,
}

impl Level {
    pub(crate) fn new(params: &ExtractParams) -> Self {
        let sign = match params.inside {
            Inside::High => 1.0,
            Inside::Low => -1.0,
        };
        Level {
            iso: params.iso,
            sign,
        }
    }

    /// `value - iso` (`iso - value` for `Inside::Low`), NaN as 0 (a tie,
    /// outside), clamped to `±f64::MAX / 4` (infinities too) so that
    /// differences of two stay finite; the kernel scales the values of a
    /// cell out of its range itself.
    #[inline]
    pub(super) fn rel(self, value: f64) -> f64 {
        let d = (value - self.iso) * self.sign;
        if d.is_nan() {
            0.0
        } else {
            d.clamp(-f64::MAX / 4.0, f64::MAX / 4.0)
        }
    }

    /// [`Level::rel`] of each of `values`, the same numbers, computed with
    /// selects instead of branches (NaN fails both comparisons and is
    /// replaced last) so that the eight run side by side. (`rel` itself
    /// stays as it is: the vertex loops compile worse with this form.)
    #[inline(always)]
    pub(crate) fn rel_all(self, values: [f64; 8]) -> [f64; 8] {
        const LIMIT: f64 = f64::MAX / 4.0;
        let mut out = [0.0; 8];
        for (g, v) in out.iter_mut().zip(values) {
            let d = (v - self.iso) * self.sign;
            let d = if d > LIMIT { LIMIT } else { d };
            let d = if d < -LIMIT { -LIMIT } else { d };
            *g = if d.is_nan() { 0.0 } else { d };
        }
        out
    }

    /// [`Level::rel`] of each of `values` where that is the plain
    /// `(value - iso) * sign` (see `Plane::plain`): without the clamps.
    #[inline(always)]
    pub(super) fn plain_all(self, values: [f64; 8]) -> [f64; 8] {
        values.map(|v| (v - self.iso) * self.sign)
    }

    /// What rounding left out of `rel(v)` for each of `values`, so that
    /// the kernel can decide on the exact differences: 0 where the
    /// subtraction was exact, and for NaN and clamped values, which stay
    /// rounded. One pass of plain arithmetic over the eight, without a
    /// branch, so that it runs in vector registers.
    #[inline(always)]
    pub(crate) fn residuals(self, values: [f64; 8]) -> [f64; 8] {
        let mut out = [0.0; 8];
        for (r, &v) in out.iter_mut().zip(&values) {
            let d = v - self.iso;
            let rest = subtraction_residual(v, self.iso, d) * self.sign;
            // NaN (from NaN or infinite values) fails the test. Up to
            // `f64::MAX / 4` (not clamped), the residual is finite.
            *r = if d.abs() <= f64::MAX / 4.0 { rest } else { 0.0 };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::LentPlane;

    #[test]
    fn the_cells_values_are_the_vertex_loops_values() {
        let special = [
            0.0,
            -0.0,
            1.5,
            -2.25,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE / 4.0,
            f64::MAX / 4.0,
            -f64::MAX / 4.0,
        ];
        let mut tested = 0;
        for iso in [0.0, 0.3, -1e300, 1e308, f64::MAX] {
            for sign in [1.0, -1.0] {
                let level = Level { iso, sign };
                for window in special.windows(8) {
                    let values: [f64; 8] = window.try_into().expect("eight values");
                    let all = level.rel_all(values);
                    for (v, g) in values.iter().zip(all) {
                        assert_eq!(g.to_bits(), level.rel(*v).to_bits(), "{v} {iso} {sign}");
                        tested += 1;
                    }
                }
            }
        }
        assert_eq!(tested, 5 * 2 * 7 * 8);
    }

    #[test]
    fn plain_planes_need_no_clamps() {
        // Integer samples whose subtraction is exact, at the ends of their
        // types and at isovalues with fraction bits: `plain_all` must be
        // `rel` bit for bit wherever a plane would say `plain`.
        let u32s = [0u32, 1, 7, 65_535, u32::MAX - 1, u32::MAX];
        let i32s = [i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX];
        let u16s = [0u16, 1, 1000, u16::MAX];
        let planes = [
            LentPlane::U32(&u32s),
            LentPlane::I32(&i32s),
            LentPlane::U16(&u16s),
        ];
        let mut tested = 0;
        for iso in [0.0, -0.0, 0.5, -3.25, 1600.0, 2.0e9 + 0.125, -4.0e9, 1e300] {
            for plane in planes {
                if !plane.subtracts_exactly(iso) {
                    continue;
                }
                assert!(plane.is_integer());
                let values: Vec<f64> = (0..plane.len()).map(|i| plane.get(i)).collect();
                for sign in [1.0, -1.0] {
                    let level = Level { iso, sign };
                    let eight: [f64; 8] = std::array::from_fn(|i| values[i % values.len()]);
                    let plain = level.plain_all(eight);
                    for (v, g) in eight.iter().zip(plain) {
                        assert_eq!(g.to_bits(), level.rel(*v).to_bits(), "{v} {iso} {sign}");
                        tested += 1;
                    }
                }
            }
        }
        // Every isovalue but 1e300 subtracts exactly for all three types.
        assert_eq!(tested, 7 * 3 * 2 * 8);
    }
}
