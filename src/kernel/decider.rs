//! The asymptotic decider (Nielson and Hamann 1991) on one face.
//!
//! On an ambiguous face the inside corners sit on one diagonal. They are
//! joined inside the face iff the bilinear saddle value exceeds the isovalue.
//! With `g` the corner values minus the isovalue, the saddle value minus the
//! isovalue is `(g0 g2 - g1 g3) / (g0 + g2 - g1 - g3)`; the denominator is
//! positive on an ambiguous face whose inside diagonal is (0, 2), so only the
//! sign of the numerator matters. A tie (saddle value equal to the isovalue)
//! separates the inside corners, as `{T > iso + ε}` requires.

use super::wide::{integers, Span, WideInt};
use bnum::types::{I1024, I256, I512};
use std::cmp::Ordering;

/// Sign of `p * q - r * s`, exact for finite inputs (no overflow assumed).
///
/// First the plain difference of the rounded products: rounding is
/// monotonic, so `p q > r s` gives `fl(p q) >= fl(r s)`, and the difference
/// of two different floats is never rounded to zero; a nonzero difference
/// therefore has the exact sign. Only when the rounded products are equal
/// does it take Kahan's fused-multiply-add evaluation: the rounding error of
/// `r * s` is recovered exactly, so the result is zero iff the exact value is
/// zero and otherwise has the exact value's sign. (Without a hardware FMA in
/// the target's baseline `mul_add` is a library call, kept for these
/// near-ties.) Symmetric in `p <-> q` and `r <-> s`, so both cells sharing a
/// face get the same answer.
pub fn det2_sign(p: f64, q: f64, r: f64, s: f64) -> Ordering {
    let d = p * q - r * s;
    if d != 0.0 {
        return if d > 0.0 {
            Ordering::Greater
        } else {
            Ordering::Less
        };
    }
    let w = r * s;
    let e = (-r).mul_add(s, w); // w - r*s, exact
    let f = p.mul_add(q, -w); // p*q - w, rounded once
    (f + e).partial_cmp(&0.0).unwrap_or(Ordering::Equal)
}

/// Sign of `(v0 + r0)(v2 + r2) - (v1 + r1)(v3 + r3)` for the values `v` of
/// a face (in its corner order) and their residuals `r` (`|r[i]| <= 2^-53
/// |v[i]|`, what rounding `v` left out), exact for finite inputs; `None`
/// if the values span more than 508 bits (as clamped infinities do), where
/// the caller keeps the answer it gives without residuals.
///
/// First the rounded `v0 v2 - v1 v3`, whose error is below `2^-48 (|v0 v2|
/// + |v1 v3|)` when those products neither overflow nor come near
/// underflow; only a difference within that bound is redone in integers of
/// 256, 512 or 1024 bits (see [`super::wide`]; `|e| < 2^(bits + 1)`, so
/// products and their difference fit). Symmetric under the reflection
/// `[v0, v3, v2, v1]` in which the neighbouring cell sees the face.
pub fn residual_det2_sign(v: [f64; 4], r: [f64; 4]) -> Option<Ordering> {
    let (diagonal, other) = (v[0] * v[2], v[1] * v[3]);
    let d = diagonal - other;
    let size = diagonal.abs() + other.abs();
    const BOUND: f64 = 1.0 / (1u64 << 48) as f64;
    const TINY: f64 = f64::from_bits((1023 - 800) << 52); // 2^-800
    if d.abs() > size * BOUND && size > TINY && size.is_finite() {
        return d.partial_cmp(&0.0);
    }
    exact_det2_sign(v, r)
}

/// [`residual_det2_sign`] in integers.
#[cold]
#[inline(never)]
fn exact_det2_sign(v: [f64; 4], r: [f64; 4]) -> Option<Ordering> {
    fn sign<T: WideInt + Ord + std::ops::Mul<Output = T>>(
        high: &[f64; 4],
        low: &[f64; 4],
    ) -> Ordering {
        let e: [T; 4] = integers(high, low);
        (e[0] * e[2]).cmp(&(e[1] * e[3]))
    }
    let span = Span::of(v.iter().chain(&r).copied())?;
    let scale = span.integer_scale(508)?;
    let (high, low) = (v.map(|x| scale.apply(x)), r.map(|x| scale.apply(x)));
    Some(match span.bits() {
        bits if bits <= 125 => sign::<I256>(&high, &low),
        bits if bits <= 252 => sign::<I512>(&high, &low),
        _ => sign::<I1024>(&high, &low),
    })
}

/// Are the inside corners `a`, `c` of an ambiguous face joined across it?
///
/// `a` and `c` are the values of the inside diagonal (both `> 0`), `b` and
/// `d` those of the outside diagonal (both `<= 0`).
pub fn inside_joined(a: f64, c: f64, b: f64, d: f64) -> bool {
    det2_sign(a, c, b, d) == Ordering::Greater
}

#[cfg(test)]
mod tests {
    use super::*;
    use Ordering::*;

    #[test]
    fn exact_sign_on_ties_and_cancellation() {
        assert_eq!(det2_sign(3.0, 4.0, 2.0, 6.0), Equal);
        assert_eq!(det2_sign(3.0, 4.0, 2.0, 5.0), Greater);
        let big = (1u64 << 40) as f64;
        // (2^40 + 1)^2 - (2^40)(2^40 + 2) = 1, invisible to plain f64.
        assert_eq!(det2_sign(big + 1.0, big + 1.0, big, big + 2.0), Greater);
        assert_eq!(det2_sign(big, big + 2.0, big + 1.0, big + 1.0), Less);
    }

    #[test]
    fn the_plain_difference_shortcut_agrees_with_exact_arithmetic() {
        // Near-ties (rounded products equal or one ulp apart) and random
        // values, scaled to large and small magnitudes, against the sign
        // computed exactly in i128.
        let mut next = crate::kernel::xorshift(0x2545_f491_4f6c_dd1du64);
        for round in 0..200_000u32 {
            let exponent = [0, 40, -40, 400, -400][round as usize % 5];
            let scale = 2f64.powi(exponent);
            // 40-bit integers: exact as f64, their products rounded.
            let int = |r: u64| (r % (1 << 40)) as i64 - (1 << 39);
            let small = |r: u64| (r % 8193) as i64 - 4096;
            let [ip, iq, ir, is] = if round % 2 == 0 {
                // Near-ties: (a + x)(a + y) - a (a + x + y + d) = x y - a d,
                // tiny next to the products when d = 0.
                let (a, x, y) = (int(next()) / 2, small(next()), small(next()));
                let d = [0, 0, 0, 1, -1][(next() % 5) as usize];
                [a + x, a + y, a, a + x + y + d]
            } else {
                [int(next()), int(next()), int(next()), int(next())]
            };
            let exact = (i128::from(ip) * i128::from(iq)).cmp(&(i128::from(ir) * i128::from(is)));
            let [p, q, r, s] = [ip, iq, ir, is].map(|v| v as f64 * scale);
            assert_eq!(det2_sign(p, q, r, s), exact, "{p} {q} {r} {s}");
        }
    }

    #[test]
    fn residuals_break_the_ties_of_the_rounded_values() {
        // Integer samples v at iso = fl(1/3) = 1/3 - δ: the exact values are
        // g = (h + 3δ) / 3 with h = 3v - 1, so where h0 h2 = h1 h3 the sign
        // of the face determinant is that of 3δ (h0 + h2 - h1 - h3). The
        // rounded differences alone lose δ.
        let iso = 1.0 / 3.0;
        let (mut ties, mut rounded_wrong) = (0, 0);
        let range = -7i64..=7;
        for v0 in range.clone() {
            for v1 in range.clone() {
                for v2 in range.clone() {
                    for v3 in range.clone() {
                        let v = [v0, v1, v2, v3];
                        let h = v.map(|x| 3 * x - 1);
                        let tie_break = h[0] + h[2] - h[1] - h[3];
                        if h[0] * h[2] != h[1] * h[3] || tie_break == 0 {
                            continue;
                        }
                        ties += 1;
                        let g = v.map(|x| x as f64 - iso);
                        let rest = std::array::from_fn(|i| {
                            super::super::wide::subtraction_residual(v[i] as f64, iso, g[i])
                        });
                        let expected = tie_break.cmp(&0);
                        assert_eq!(residual_det2_sign(g, rest), Some(expected), "{v:?}");
                        rounded_wrong += usize::from(det2_sign(g[0], g[2], g[1], g[3]) != expected);
                    }
                }
            }
        }
        assert!(
            ties > 50 && rounded_wrong > 10,
            "{ties} ties, {rounded_wrong} rounded wrong"
        );
    }

    #[test]
    fn residual_sign_agrees_with_integers_far_from_ties() {
        // Random values with random residuals (below half an ulp), some
        // faces near a tie: the filtered sign is the exact one, computed
        // here in i128 from 40-bit integers scaled down.
        let mut next = crate::kernel::xorshift(0x1234_5678_9abc_def1u64);
        for round in 0..100_000u32 {
            let int = |r: u64| (r % (1 << 40)) as i64 - (1 << 39);
            // Values of 40 bits with residuals of up to 12 more bits.
            let e: [i128; 4] = std::array::from_fn(|_| {
                i128::from(int(next())) << 12 | i128::from((next() % 4096) as i64)
            });
            let e = if round % 2 == 0 {
                // Near-tie: e3 chosen so that e0 e2 - e1 e3 is small.
                let e3 = if e[1] == 0 { 1 } else { e[0] * e[2] / e[1] };
                [e[0], e[1], e[2], e3]
            } else {
                e
            };
            let exact = (e[0] * e[2]).cmp(&(e[1] * e[3]));
            let scale = 2f64.powi(-60);
            let g = e.map(|x| x as f64);
            let rest: [f64; 4] = std::array::from_fn(|i| (e[i] - g[i] as i128) as f64);
            assert!(rest
                .iter()
                .zip(&g)
                .all(|(r, v)| r.abs() <= v.abs() * f64::EPSILON));
            let (g, rest) = (g.map(|x| x * scale), rest.map(|x| x * scale));
            assert_eq!(residual_det2_sign(g, rest), Some(exact), "{e:?}");
        }
    }

    #[test]
    fn residual_sign_is_the_same_for_both_cells_of_a_face() {
        // The neighbouring cell sees the face reflected, [v0, v3, v2, v1]:
        // the same sign; rotated by one corner the determinant changes sign.
        // Values of every magnitude, clamped infinities included (there the
        // answer is left to the caller, for both alike).
        let mut next = crate::kernel::xorshift(0x0ddc_0ffe_e15e_a5e5u64);
        let pick = |r: u64| match r % 6 {
            0 => f64::MAX / 4.0,
            1 => 1e-300,
            2 => 0.25,
            3 => 3.0,
            4 => 2f64.powi(53),
            _ => (r >> 8) as f64 / (1u64 << 52) as f64,
        };
        for _ in 0..100_000 {
            let v: [f64; 4] = std::array::from_fn(|_| {
                let r = next();
                pick(r) * if r >> 63 == 1 { -1.0 } else { 1.0 }
            });
            let r: [f64; 4] = std::array::from_fn(|i| {
                let frac = (next() % 2049) as f64 / 2048.0 - 0.5;
                v[i] * f64::EPSILON / 2.0 * frac
            });
            let sign = residual_det2_sign(v, r);
            let reflected = residual_det2_sign([v[0], v[3], v[2], v[1]], [r[0], r[3], r[2], r[1]]);
            assert_eq!(sign, reflected, "{v:?} {r:?}");
            let rotated = residual_det2_sign([v[1], v[2], v[3], v[0]], [r[1], r[2], r[3], r[0]]);
            assert_eq!(sign.map(Ordering::reverse), rotated, "{v:?} {r:?}");
        }
    }

    #[test]
    fn tie_separates_inside_corners() {
        // g = [1, -1, 1, -1] around the face: saddle value exactly iso.
        assert!(!inside_joined(1.0, 1.0, -1.0, -1.0));
        assert!(inside_joined(2.0, 1.0, -1.0, -1.0));
    }
}
