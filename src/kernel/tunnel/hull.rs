//! A cheap exact pre-test of the tunnel sweep ([`super`]): which diagonal
//! pairs can join at all, from the saddle determinant's extremes on the
//! whole cell height, before the sweep finds where each pair's edges are in
//! the region.
//!
//! Both diagonal pairs of [`DIAGONALS`] share one polynomial: with `a_c(t) =
//! h_c (1 - t) + h_(c+4) t` the value on the `w`-edge from corner `c` at
//! height `t`, the first pair's determinant is `D(t) = a0 a3 - a1 a2` and
//! the second's `a1 a2 - a0 a3 = -D(t)`. The outside sweep runs on `-h`,
//! whose products are those of `h`, so it sees the same `D` and `-D`.
//!
//! The sweep of a pair answers "joined" only where `D` (or `-D`) is
//! positive, or closed non-negative, at some `t` of the range `[lo, hi]`
//! where both of its edges are in the region: at `lo` or `hi` (`ends`) or at
//! the vertex of a concave `D` strictly between them (`peak`: the vertex
//! value has the sign of the discriminant). That range lies in `[0, 1]`
//! (`lo` is 0 or where an edge enters the region, `hi` 1 or where one leaves
//! it), and a vertex strictly between them lies strictly inside `(0, 1)`.
//! So if `D <= 0` everywhere on `[0, 1]` (closed: `D < 0`) the sweep
//! cannot find the pair joined, and it need not run; [`possible_pairs`]
//! decides that exactly from `D(0)`, `D(1)` and, when the vertex of a
//! concave `D` lies strictly inside `(0, 1)`, the sign of its value.
//! Leaving out pairs that cannot join keeps the first join among the
//! others, so [`super::sweep_both`] on the pairs left gives the same
//! answer.

use super::super::sweep_pairs::DIAGONALS;

/// The pairs of `pairs` (bits as in [`super::labelled_joins`]: `2 s + d`,
/// `s = 0` inside, `1` outside, `d` the index in [`DIAGONALS`]) whose sweep
/// can find a join in the cell `h` (see the module doc): with `E = D` for
/// `d = 0` and `E = -D` for `d = 1`, those where `E > 0` (inside) or `E >= 0`
/// (outside) somewhere on `[0, 1]`.
///
/// `E` is `qa t^2 + qb t + E(0)`; its largest value on `[0, 1]` is `E(0)`,
/// `E(1)`, or, if its vertex `-qb / (2 qa)` lies strictly inside `(0, 1)`
/// with `qa < 0` (a maximum; `0 < qb < -2 qa` says both, since it makes
/// `qa` negative), the vertex value `-disc / (4 qa)`, which has the sign of
/// the discriminant `disc = qb^2 - 4 qa E(0)`. All terms are integers, so
/// `x >= 0` is `x + 1 > 0`: the outside sweeps add 1.
///
/// Exact for `|h| < 2^14` (every term fits in `i64`): products of two values
/// are below `2^28`, `E(0)` and `E(1)` below `2^29`, `m = 2 B1` (the middle
/// Bernstein coefficient, doubled) below `2^30`, the coefficients
/// `qa = E(0) - m + E(1)` and `qb = m - 2 E(0)` below `2^31`, and `qb^2` and
/// `4 qa E(0)` below `2^62`, so the discriminant (plus 1) below `2^63`.
#[inline(always)]
pub(super) fn possible_pairs(h: &[i64; 8], pairs: u8) -> u8 {
    let (k, kk, j, jj) = DIAGONALS[0];
    // D(t) in Bernstein form: D(0) (1 - t)^2 + m t (1 - t) + D(1) t^2.
    let low = h[k] * h[kk] - h[j] * h[jj];
    let high = h[k + 4] * h[kk + 4] - h[j + 4] * h[jj + 4];
    let m = h[k] * h[kk + 4] + h[k + 4] * h[kk] - h[j] * h[jj + 4] - h[j + 4] * h[jj];
    let mut kept = 0;
    let mut rest = pairs;
    while rest != 0 {
        let bit = rest.trailing_zeros();
        rest &= rest - 1;
        // E = D or -D, and 1 to add for the outside's `>= 0`.
        let sign = 1 - 2 * i64::from(bit & 1);
        let tie = i64::from(bit >= 2);
        let (low, m, high) = (sign * low, sign * m, sign * high);
        let qa = low - m + high;
        let qb = m - 2 * low;
        let disc = qb * qb - 4 * qa * low;
        let peak = (qb > 0) & (qb + 2 * qa < 0);
        let ends = low.max(high) + tie > 0;
        kept |= u8::from(ends | (peak & (disc + tie > 0))) << bit;
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::super::{exact, pair_joins, sweep_both, SMALL_BITS};
    use super::*;
    use crate::kernel::cell::face_decisions;
    use crate::kernel::tables::tables;

    /// A random cell: small values full of ties (equal values, zeros: values
    /// at the isovalue), mid-sized ones, or values near the `i64` bound of
    /// [`SMALL_BITS`], by `kind`.
    fn cell(next: &mut impl FnMut() -> u64, kind: u64) -> [i64; 8] {
        let limit = (1i64 << SMALL_BITS) - 1;
        std::array::from_fn(|_| {
            let r = next();
            match kind {
                0 => (r % 5) as i64 - 2,
                1 => match r % 4 {
                    0 => 0,
                    _ => (r >> 8) as i64 % 7 - 3,
                },
                2 => (r >> 8) as i64 % 401 - 200,
                _ => match r % 4 {
                    0 => 0,
                    1 => limit,
                    2 => -limit,
                    _ => (r >> 8) as i64 % (2 * limit + 1) - limit,
                },
            }
        })
    }

    #[test]
    fn pairs_ruled_out_never_join() {
        // Millions of cells, each with the pairs its tables ask for: every
        // pair the sweep finds joined is one the pre-test keeps, and the
        // sweep over the kept pairs gives the sweep over all of them (the
        // first join), so the pre-test changes no answer. The counts check
        // that the cells reach both outcomes often.
        let mut next = crate::kernel::xorshift(0xd1b5_4a32_d192_ed03u64);
        let t = tables();
        let (mut tested, mut ruled_out, mut joined) = (0u64, 0u64, 0u64);
        for round in 0..3_000_000u64 {
            let h = cell(&mut next, round % 4);
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(h[c] > 0) << c));
            if !t.is_ambiguous[config as usize] {
                continue;
            }
            let g = h.map(|v| v as f64);
            let set = t.contour_set(config, face_decisions(&g, None, config));
            let pairs = set.tunnel_pairs;
            if pairs == 0 {
                continue;
            }
            let kept = possible_pairs(&h, pairs);
            let outside = h.map(|v| -v);
            for bit in 0..4 {
                if pairs >> bit & 1 == 0 {
                    continue;
                }
                let closed = bit >= 2;
                let region = if closed { &outside } else { &h };
                let joins = pair_joins(region, DIAGONALS[bit % 2], closed);
                assert!(!joins || kept >> bit & 1 == 1, "{h:?} pair {bit}");
                tested += 1;
                ruled_out += u64::from(kept >> bit & 1 == 0);
                joined += u64::from(joins);
            }
            let labels = &set.corner_comp;
            assert_eq!(
                exact(sweep_both(&h, pairs & kept, labels)),
                exact(sweep_both(&h, pairs, labels)),
                "{h:?}"
            );
        }
        assert!(
            ruled_out > 100_000 && joined > 10_000 && tested > ruled_out + joined,
            "{tested} pairs, {ruled_out} ruled out, {joined} joined"
        );
    }

    #[test]
    fn the_bound_is_tight_at_ties() {
        // Determinants that vanish at both ends, or touch zero inside.
        // a0 = 1 - t, a3 = t, a1 = a2 = 0: D = t (1 - t) >= 0, 0 at the ends.
        let h = [1, 0, 0, 0, 0, 0, 0, 1];
        assert_eq!(possible_pairs(&h, 0b1111), 0b1101);
        // D = 0 everywhere: only the closed sweeps may join.
        assert_eq!(possible_pairs(&[0; 8], 0b1111), 0b1100);
        // D = -(t (1 - t)): the mirror image; only the pairs asked for.
        let h = [0, 1, 0, 0, 0, 0, 1, 0];
        assert_eq!(possible_pairs(&h, 0b1111), 0b1110);
        assert_eq!(possible_pairs(&h, 0b0101), 0b0100);
        // D = (1 - 2t)^2 >= 0 with a double root at 1/2: -D is never positive
        // but touches zero there (the dip's discriminant is zero).
        // a0 = 1 - 2t, a3 = 1 - 2t: h0 = 1, h4 = -1, h3 = 1, h7 = -1.
        let h = [1, 0, 0, 1, -1, 0, 0, -1];
        assert_eq!(possible_pairs(&h, 0b1111), 0b1101);
    }
}
