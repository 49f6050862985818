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
/// Kahan's fused-multiply-add evaluation: the rounding error of `r * s` is
/// recovered exactly, so the result is zero iff the exact value is zero and
/// otherwise has the exact value's sign. Symmetric in `p <-> q` and `r <-> s`,
/// so both cells sharing a face get the same answer.
pub fn det2_sign(p: f64, q: f64, r: f64, s: f64) -> std::cmp::Ordering {
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
    fn tie_separates_inside_corners() {
        // g = [1, -1, 1, -1] around the face: saddle value exactly iso.
        assert!(!inside_joined(1.0, 1.0, -1.0, -1.0));
        assert!(inside_joined(2.0, 1.0, -1.0, -1.0));
    }
}
