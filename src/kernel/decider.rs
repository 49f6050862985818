//! The asymptotic decider (Nielson and Hamann 1991) on one face.
//!
//! On an ambiguous face the inside corners sit on one diagonal. They are
//! joined inside the face iff the bilinear saddle value exceeds the isovalue.
//! With `g` the corner values minus the isovalue, the saddle value minus the
//! isovalue is `(g0 g2 - g1 g3) / (g0 + g2 - g1 - g3)`; the denominator is
//! positive on an ambiguous face whose inside diagonal is (0, 2), so only the
//! sign of the numerator matters. A tie (saddle value equal to the isovalue)
//! separates the inside corners, as `{T > iso + ε}` requires.

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
pub fn det2_sign(p: f64, q: f64, r: f64, s: f64) -> std::cmp::Ordering {
    let d = p * q - r * s;
    if d != 0.0 {
        return if d > 0.0 {
            std::cmp::Ordering::Greater
        } else {
            std::cmp::Ordering::Less
        };
    }
    let w = r * s;
    let e = (-r).mul_add(s, w); // w - r*s, exact
    let f = p.mul_add(q, -w); // p*q - w, rounded once
    (f + e)
        .partial_cmp(&0.0)
        .unwrap_or(std::cmp::Ordering::Equal)
}

/// Are the inside corners `a`, `c` of an ambiguous face joined across it?
///
/// `a` and `c` are the values of the inside diagonal (both `> 0`), `b` and
/// `d` those of the outside diagonal (both `<= 0`).
pub fn inside_joined(a: f64, c: f64, b: f64, d: f64) -> bool {
    det2_sign(a, c, b, d) == std::cmp::Ordering::Greater
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Ordering::*;

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
    fn tie_separates_inside_corners() {
        // g = [1, -1, 1, -1] around the face: saddle value exactly iso.
        assert!(!inside_joined(1.0, 1.0, -1.0, -1.0));
        assert!(inside_joined(2.0, 1.0, -1.0, -1.0));
    }
}
