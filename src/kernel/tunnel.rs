//! Does the level set join two contours through the cell? (Proposition 1.)
//!
//! A tunnel is a piece of level set shaped like a cylinder: two surface
//! components of one sign (see [`super::contour`]) that the cell boundary keeps
//! apart are joined through the cell's interior. We decide it exactly by
//! sweeping planes `w = t` through the cell: the plane cuts the four cell
//! edges parallel to `w`, and the bilinear function on the plane joins two
//! diagonal inside corners iff its saddle determinant
//! `D(t) = a0(t) a3(t) - a1(t) a2(t)` is positive. `D` is the paper's quadratic
//! equation for the pair of faces `u = 0, 1` and `v = 0, 1` read along `w`: its
//! roots are the heights of the inner hexagon's vertices. Two diagonal edges
//! join through the interior iff `D > 0` somewhere on the range of `t` where
//! both edges are inside. Joins between neighbouring edges happen on the
//! side faces already, where the face decider has seen them.
//!
//! Ties follow `{g > ε}`: the inside of an edge is a half-open interval whose
//! zero end is excluded, so inside corners join only where `D > 0` on an open
//! range; for the outside (`g <= ε`, ties included) the ranges are closed and
//! `D >= 0` suffices.
//!
//! The predicates are signs of polynomials of degree up to four in the
//! exact values `g + r` (see [`super::wide`]), decided exactly whenever
//! those are integers of at most 248 bits after scaling by a
//! common power of two: cells of integers (no residual) in `i64` up to 14
//! bits and in `i128` up to 26; beyond that, and for every cell with a
//! residual, in `f64`: on the values scaled to a unit range with one fixed
//! error bound (`Unit`, which settles nearly every float cell), then with
//! an error bound carried along (`Filtered`), then in 256-, 512- or
//! 1024-bit integers, each only where the one before was in doubt. Cells whose
//! values span more bits (values more than about 2^195 apart, far beyond
//! any float32 volume at a normal isovalue) are exact where `Unit` is sure
//! (its bound does not depend on the span) and otherwise keep the plain
//! `f64` answer on the rounded values, which can misjudge near-ties.

use super::contour::ContourSet;
use super::scale::{normalized, power_of_two};
use super::sweep_pairs::DIAGONALS;
use super::wide::{integers, Span};
use bnum::types::{I1024, I256, I512};
use std::convert::Infallible;
use std::hint::select_unpredictable;

mod arith;
mod hull;

use arith::{is_in, Doubt, Filtered, Logic, Num, Unit};
use hull::possible_pairs;

/// Two surface components (corner labels) that the interior joins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Join {
    /// Label of one component.
    pub a: u8,
    /// Label of the other.
    pub b: u8,
}

/// The first interior join of surface components of the same sign, in a
/// fixed order (inside components first); a join is a tunnel. A trilinear
/// cell holds at most one tunnel.
pub fn interior_joins(g: &[f64; 8], set: &ContourSet) -> Option<Join> {
    labelled_joins(g, None, set.tunnel_pairs, &set.corner_comp)
}

/// [`interior_joins`] of a set given by its tunnel sweeps `pairs` and its
/// corner labels `labels`, for the exact values `g + residual` (`None`: `g`
/// is exact).
pub fn labelled_joins(
    g: &[f64; 8],
    residual: Option<&[f64; 8]>,
    pairs: u8,
    labels: &[u8; 8],
) -> Option<Join> {
    if pairs == 0 {
        return None;
    }
    if residual.is_none() {
        if let Some(ints) = small_integers(g) {
            return small_joins(&ints, pairs, labels);
        }
    }
    // Float data: nearly always settled here, without the wider arithmetic.
    if let Some(join) = unit_joins(g, pairs, labels) {
        return join;
    }
    if let Some(residual) = residual {
        return wide_joins(g, residual, pairs, labels);
    }
    let Some(span) = Span::of(*g) else {
        // Infinite values: rounded.
        return exact(sweep_both(&normalized(g), pairs, labels));
    };
    match span.upscaled() {
        (scale, bits) if bits <= SMALL_BITS => {
            exact(sweep_both(&g.map(|v| (v * scale) as i64), pairs, labels))
        }
        // At most 26 bits: through i64, which converts without a library call.
        (scale, bits) if bits <= MEDIUM_BITS => exact(sweep_both(
            &g.map(|v| i128::from((v * scale) as i64)),
            pairs,
            labels,
        )),
        _ => wide_joins(g, &[0.0; 8], pairs, labels),
    }
}

/// [`labelled_joins`] of values `g` that the caller knows to be integers
/// of magnitude below `2^14` without residual (8-bit samples at an integer
/// isovalue: the slab loop's ambiguous cells), so that they are converted
/// without the test of `small_integers`. The same answer as
/// `labelled_joins(g, None, pairs, labels)`.
#[inline(never)]
pub fn small_integer_joins(g: &[f64; 8], pairs: u8, labels: &[u8; 8]) -> Option<Join> {
    debug_assert!(small_integers(g).is_some(), "{g:?}");
    if pairs == 0 {
        return None;
    }
    small_joins(&rounded_integers(&g.map(|v| v + ROUND)), pairs, labels)
}

/// [`labelled_joins`] of integers below `2^SMALL_BITS` in magnitude (every
/// 8- and 16-bit volume at an integer isovalue): no scaling, and only the
/// pairs whose determinant can have the sign of a join somewhere on the
/// cell's height (on lidc_chest_ct @ 114, about 4,200 of 10,346 pairs; see
/// `hull`).
#[inline(always)]
fn small_joins(ints: &[i64; 8], pairs: u8, labels: &[u8; 8]) -> Option<Join> {
    let pairs = possible_pairs(ints, pairs);
    if pairs == 0 {
        return None;
    }
    exact(sweep_both(ints, pairs, labels))
}

/// [`labelled_joins`] by a plain `f64` sweep on the values scaled by the
/// power of two that brings the sum of their magnitudes into `[1, 2)`, if
/// that sweep is sure of every sign it takes (see [`Unit`]); `None` if it
/// is not, or if the values do not scale so (infinities, NaN, sums below
/// 2^-1022 or from 2^1023, a value that scaling would flush to zero).
///
/// `g` may have a residual (`g + r` exact, `|r| <= 2^-53 |g|`): the bound
/// of [`Unit`] covers it as a rounding of the input, so it is not read.
#[inline(never)]
fn unit_joins(g: &[f64; 8], pairs: u8, labels: &[u8; 8]) -> Option<Option<Join>> {
    let sum = g.iter().fold(0.0, |s, v| s + v.abs());
    // The biased exponent e of the (non-negative) sum: 1..=2045 is a normal
    // sum in [2^(e - 1023), 2^(e - 1022)) below 2^1023, which the normal
    // double 2^(1023 - e) brings into [1, 2).
    let e = (sum.to_bits() >> 52) as i32;
    if !(1..=2045).contains(&e) {
        return None;
    }
    let scale = power_of_two(1023 - e);
    let h = g.map(|v| v * scale);
    // Scaling down can flush a tiny value to zero, which changes its sign.
    let kept = g
        .iter()
        .zip(&h)
        .fold(true, |k, (a, b)| k & ((*a == 0.0) == (*b == 0.0)));
    if !kept {
        return None;
    }
    sweep_both(&h.map(Unit), pairs, labels).ok()
}

/// [`labelled_joins`] for the exact values `g + residual` of a cell with a
/// residual, or beyond 26 bits: exact up to [`WIDEST_BITS`] bits (an `f64`
/// sweep with error bounds on `g`, redone in integers when a sign is in
/// doubt), rounded beyond.
#[cold]
#[inline(never)]
fn wide_joins(g: &[f64; 8], residual: &[f64; 8], pairs: u8, labels: &[u8; 8]) -> Option<Join> {
    let span = Span::of(g.iter().chain(residual).copied());
    let Some((span, scale)) = span.and_then(|s| Some((s, s.integer_scale(WIDEST_BITS)?))) else {
        return exact(sweep_both(&normalized(g), pairs, labels));
    };
    let (high, low) = (g.map(|v| scale.apply(v)), residual.map(|v| scale.apply(v)));
    match sweep_both(&high.map(Filtered::input), pairs, labels) {
        Ok(join) => join,
        Err(Doubt) => match span.bits() {
            bits if bits <= WIDE_BITS => {
                exact(sweep_both(&integers::<I256, 8>(&high, &low), pairs, labels))
            }
            bits if bits <= WIDER_BITS => {
                exact(sweep_both(&integers::<I512, 8>(&high, &low), pairs, labels))
            }
            _ => exact(sweep_both(
                &integers::<I1024, 8>(&high, &low),
                pairs,
                labels,
            )),
        },
    }
}

/// The answer of a sweep that has no doubts: an exact one, or a plain
/// `f64` one, which takes rounded signs at their word.
fn exact(sweep: Result<Option<Join>, Infallible>) -> Option<Join> {
    let Ok(join) = sweep;
    join
}

/// The first join among the diagonal pairs of `pairs`: inside pairs
/// (`h > 0`, bits 0 and 1) before outside ones (`h <= 0`, bits 2 and 3),
/// or [`Num::Doubt`] if a sign it needed was in doubt.
///
/// Each pair is tested without a branch (its terms are all computed and
/// then combined); only the loop over the pairs branches.
#[inline(always)]
fn sweep_both<T: Num>(h: &[T; 8], pairs: u8, labels: &[u8; 8]) -> Result<Option<Join>, T::Doubt> {
    let outside = h.map(|v| -v);
    let mut rest = pairs;
    while rest != 0 {
        let bit = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        let closed = bit >= 2;
        let region = select_unpredictable(closed, &outside, h);
        let diagonal = DIAGONALS[bit % 2];
        if pair_joins(region, diagonal, closed).decided()? {
            // The corner of each edge in the region (the lower one if both
            // are), as `may_join` chose it. (The signs of the values
            // themselves are never in doubt.)
            let corner = |e: usize| {
                region[e]
                    .input_in(closed)
                    .decided()
                    .map(|i| if i { e } else { e + 4 })
            };
            let (la, lb) = (labels[corner(diagonal.0)?], labels[corner(diagonal.1)?]);
            return Ok(Some(Join {
                a: la.min(lb),
                b: la.max(lb),
            }));
        }
    }
    Ok(None)
}

/// The eight values as `i64`s if they are all integers of magnitude below
/// `2^SMALL_BITS` (what [`Span::upscaled`] finds with scale 1, without its
/// bit by bit look at each value).
fn small_integers(g: &[f64; 8]) -> Option<[i64; 8]> {
    // Adding and taking away 1.5 * 2^52 rounds a value below 2^51 in
    // magnitude to an integer (the sum's last bit is worth 1), so it is
    // unchanged iff it is one. No short cut: eight tests side by side.
    // The integer is then the difference of the sum's bits and ROUND's (the
    // sum lies in [2^52, 2^53), where the last bit of the mantissa is worth
    // 1), which converts the eight side by side.
    const LIMIT: f64 = (1u64 << SMALL_BITS) as f64;
    let rounded = g.map(|v| v + ROUND);
    let small = g.iter().zip(&rounded).fold(true, |small, (&v, &r)| {
        small & (v.abs() < LIMIT) & (r - ROUND == v)
    });
    small.then(|| rounded_integers(&rounded))
}

/// Adding and taking away `ROUND` rounds a value below 2^51 in magnitude
/// to an integer (see [`small_integers`]).
const ROUND: f64 = 1.5 * (1u64 << 52) as f64;

/// The integers `v` of `v + ROUND` (`rounded`), for `|v|` below 2^51: the
/// difference of the sum's bits and `ROUND`'s, eight side by side (a cast
/// of each `f64` to `i64` saturates, and costs a few comparisons each).
#[inline(always)]
fn rounded_integers(rounded: &[f64; 8]) -> [i64; 8] {
    rounded.map(|r| r.to_bits() as i64 - ROUND.to_bits() as i64)
}

/// A fraction `p / q` with `q > 0`.
#[derive(Clone, Copy)]
struct Frac<T> {
    p: T,
    q: T,
}

impl<T: Num> Frac<T> {
    /// `self < o`, or `self <= o` if `or_equal`.
    #[inline(always)]
    fn below(self, o: Self, or_equal: bool) -> T::Bool {
        (self.p * o.q).below(o.p * self.q, or_equal)
    }

    fn less(self, o: Self) -> T::Bool {
        self.below(o, false)
    }
}

/// `x` if `c`, else `y`, without a branch (a plain `if` was compiled to
/// one).
#[inline(always)]
fn pick<T: Num>(c: T::Bool, x: Frac<T>, y: Frac<T>) -> Frac<T> {
    Frac {
        p: T::select(c, x.p, y.p),
        q: T::select(c, x.q, y.q),
    }
}

/// Does the diagonal pair `(k, kk, j, jj)` join through the interior, for
/// the region `h > 0` (open) or `h >= 0` (closed)? The edges `k` and `kk`
/// must each have a corner in the region.
#[inline(always)]
fn pair_joins<T: Num>(h: &[T; 8], diagonal: (usize, usize, usize, usize), closed: bool) -> T::Bool {
    let (k, kk, _, _) = diagonal;
    let (lo_k, hi_k) = range(h[k], h[k + 4], closed);
    let (lo_kk, hi_kk) = range(h[kk], h[kk + 4], closed);
    let lo = pick(lo_k.less(lo_kk), lo_kk, lo_k);
    let hi = pick(hi_k.less(hi_kk), hi_k, hi_kk);
    joined_on(h, diagonal, lo, hi, closed)
}

/// The range of `t` where the edge from `bottom` to `top` is in the region
/// (one of its ends must be).
#[inline(always)]
fn range<T: Num>(bottom: T, top: T, closed: bool) -> (Frac<T>, Frac<T>) {
    let zero = Frac {
        p: T::ZERO,
        q: T::ONE,
    };
    let one = Frac {
        p: T::ONE,
        q: T::ONE,
    };
    // Where the edge leaves the region going up, or enters it.
    let leaves = Frac {
        p: bottom,
        q: bottom - top,
    };
    let enters = Frac {
        p: -bottom,
        q: top - bottom,
    };
    (
        pick(bottom.input_in(closed), zero, enters),
        pick(top.input_in(closed), one, leaves),
    )
}

/// Is `D(t) = a_k a_kk - a_j a_jj` positive (or, closed, non-negative) somewhere
/// on the range from `lo` to `hi` (open, or closed)? Every term is computed
/// and the answer combined without a branch.
#[inline(always)]
fn joined_on<T: Num>(
    h: &[T; 8],
    (k, kk, j, jj): (usize, usize, usize, usize),
    lo: Frac<T>,
    hi: Frac<T>,
    closed: bool,
) -> T::Bool {
    // Closed: lo <= hi; open: lo < hi.
    let nonempty = lo.below(hi, closed);
    let (ak, bk) = (h[k], h[k + 4] - h[k]);
    let (akk, bkk) = (h[kk], h[kk + 4] - h[kk]);
    let (aj, bj) = (h[j], h[j + 4] - h[j]);
    let (ajj, bjj) = (h[jj], h[jj + 4] - h[jj]);
    // D(t) = A t^2 + B t + C.
    let qa = bk * bkk - bj * bjj;
    let qb = ak * bkk + bk * akk - aj * bjj - bj * ajj;
    let qc = ak * akk - aj * ajj;
    let value_at = |f: Frac<T>| qa * f.p * f.p + qb * f.p * f.q + qc * f.q * f.q;
    let ends = is_in(value_at(lo), closed) | is_in(value_at(hi), closed);
    // A maximum inside the range (a concave D), and its value.
    let vertex = Frac {
        p: qb,
        q: -(T::TWO * qa),
    };
    let peak = qa.below(T::ZERO, false)
        & lo.less(vertex)
        & vertex.less(hi)
        & is_in(qb * qb - T::FOUR * qa * qc, closed);
    nonempty & (ends | peak)
}

/// Magnitude bits up to which the sweep is exact in `i64`: with `|h| <
/// 2^b`, its largest terms (`value_at`, `qb^2 - 4 qa qc`) stay below
/// `2^(4b + 7)`, so `b <= 14` fits. Every 8-bit volume and most CTs
/// (12-bit values) qualify; `i128` takes the rest up to [`MEDIUM_BITS`].
const SMALL_BITS: i32 = 14;

/// Magnitude bits up to which the sweep is exact in `i128` (see
/// [`SMALL_BITS`]: `4 * 26 + 7 < 127`).
const MEDIUM_BITS: i32 = 26;

/// Magnitude bits up to which the sweep is exact in 256-bit integers
/// (`4 * 60 + 7 < 255`): every 32-bit integer volume at an integer or
/// half-integer isovalue, and 24-bit float mantissas up to 2^36 apart.
const WIDE_BITS: i32 = 60;

/// Magnitude bits up to which the sweep is exact in 512-bit integers
/// (`4 * 124 + 7 < 511`).
const WIDER_BITS: i32 = 124;

/// Magnitude bits up to which the sweep is exact, in 1024-bit integers
/// (`4 * 252 + 7 < 1023`), and up to which the [`Filtered`] sweep neither
/// overflows nor underflows (`2^(4 * 248 + 7) < 2^1023`).
const WIDEST_BITS: i32 = 248;

/// The eight values as integers after scaling by a power of two, if they
/// all are (with room for degree-four products in i128).
#[cfg(test)]
fn scaled_integers(g: &[f64; 8]) -> Option<[i128; 8]> {
    let (scale, bits) = Span::of(*g)?.upscaled();
    (bits <= MEDIUM_BITS).then(|| g.map(|v| (v * scale) as i128))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::contour;
    use crate::kernel::scale::power_of_two;

    /// The scale and bits of the `i64` and `i128` sweeps, if one of them
    /// takes the cell.
    fn integer_scale(g: &[f64; 8]) -> Option<(f64, i32)> {
        Span::of(*g)
            .map(Span::upscaled)
            .filter(|&(_, bits)| bits <= MEDIUM_BITS)
    }

    fn joins(g: [f64; 8]) -> Option<Join> {
        let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
        let set = contour::build(config, 0);
        interior_joins(&g, &set)
    }

    #[test]
    fn case_4_tunnel_iff_body_saddle_above_iso() {
        // Corners 0 and 7 inside. Symmetric values: the body saddle is at the
        // centre with value (a + 6b ... ) — test both sides of the threshold.
        let strong = joins([10.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 10.0]);
        assert_eq!(strong, Some(Join { a: 0, b: 7 }));
        let weak = joins([1.0, -10.0, -10.0, -10.0, -10.0, -10.0, -10.0, 1.0]);
        assert!(weak.is_none());
    }

    #[test]
    fn i64_and_i128_sweeps_agree_up_to_the_small_bound() {
        // Pseudo-random cells with values up to the i64 bound (and the bound
        // itself), both signs, many ties at zero.
        let limit = (1i64 << SMALL_BITS) - 1;
        let mut next = crate::kernel::xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut found = 0;
        for round in 0..20_000 {
            let g: [i64; 8] = std::array::from_fn(|_| match next() % 5 {
                0 => 0,
                1 => limit,
                2 => -limit,
                _ => (next() % (2 * limit as u64 + 1)) as i64 - limit,
            });
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0) << c));
            for joined in [0u8, 63, (round % 64) as u8] {
                let set = contour::build(config, joined);
                let labels = &set.corner_comp;
                // The inside pairs, then the outside ones.
                for pairs in [0b0011, 0b1100] {
                    let small = exact(sweep_both(&g, pairs, labels));
                    let wide = exact(sweep_both(&g.map(i128::from), pairs, labels));
                    assert_eq!(small, wide, "{g:?}");
                    found += usize::from(small.is_some());
                }
            }
        }
        assert!(found > 100, "only {found} joins: the cells test too little");
        let bits = integer_scale(&[limit as f64, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(bits, Some((1.0, SMALL_BITS)));
    }

    #[test]
    fn small_integers_are_integer_scale_at_scale_one() {
        let limit = 1i64 << SMALL_BITS;
        let values = [
            0.0,
            -0.0,
            1.0,
            -3.0,
            0.5,
            (limit - 1) as f64,
            -(limit - 1) as f64,
        ];
        let more = [limit as f64, 1e-300, f64::NAN, f64::INFINITY, 2.5, 1e20];
        for (i, &v) in values.iter().chain(&more).enumerate() {
            let g = [v, 2.0, -1.0, 0.0, 7.0, -7.0, values[i % values.len()], 1.0];
            let expected = match integer_scale(&g) {
                Some((scale, bits)) if scale == 1.0 && bits <= SMALL_BITS => {
                    Some(g.map(|v| v as i64))
                }
                _ => None,
            };
            assert_eq!(small_integers(&g), expected, "{g:?}");
        }
    }

    #[test]
    fn scaled_integers_detects_dyadic_values() {
        assert!(scaled_integers(&[0.5, -1.5, 2.0, 0.0, 1.0, 1.0, 1.0, 1.0]).is_some());
        assert!(scaled_integers(&[0.1, -1.5, 2.0, 0.0, 1.0, 1.0, 1.0, 1.0]).is_none());
        assert_eq!(
            scaled_integers(&[0.5, -1.5, 2.0, 0.0, 1.0, 1.0, 1.0, 0.25]),
            Some([2, -6, 8, 0, 4, 4, 4, 1])
        );
        assert_eq!(
            scaled_integers(&[65535.0, -3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).map(|v| v[0]),
            Some(65535)
        );
        assert!(
            scaled_integers(&[(1u64 << 30) as f64, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).is_none()
        );
    }

    #[test]
    fn skipping_cells_that_may_not_join_changes_nothing() {
        // Random cells, integer and fractional, with magnitudes far apart
        // (down to values that underflow when normalised), many ties at
        // zero: the pairs of the tables give what every pair that has a
        // corner of its sign on both edges, with different labels, gives
        // (found here from the values, not the configuration). Case 3 pairs
        // are among the latter and not the former.
        let mut next = crate::kernel::xorshift(0x9E37_79B9_7F4A_7C15u64);
        let tables = crate::kernel::tables::tables();
        let (mut skipped, mut found, mut case_3, mut rounded) = (0, 0, 0, 0);
        for _ in 0..400_000 {
            let g: [f64; 8] = std::array::from_fn(|_| {
                let r = next();
                let v = (r % 41) as f64 - 20.0;
                match r >> 60 {
                    0 => v * 1e-300,
                    1 => v * 1e150,
                    2 => v + 0.5,
                    3 => 0.0,
                    _ => v,
                }
            });
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if !tables.is_ambiguous[config as usize] {
                continue;
            }
            let joined = crate::kernel::cell::face_decisions(&g, None, config);
            let set = *tables.contour_set(config, joined);
            let mut every = 0;
            for (s, inside) in [true, false].into_iter().enumerate() {
                let corner = |k: usize| [k, k + 4].into_iter().find(|&c| (g[c] > 0.0) == inside);
                for (d, &(k, kk, _, _)) in DIAGONALS.iter().enumerate() {
                    if let (Some(a), Some(b)) = (corner(k), corner(kk)) {
                        if set.corner_comp[a] != set.corner_comp[b] {
                            every |= 1 << (2 * s + d);
                        }
                    }
                }
            }
            let full = interior_joins(
                &g,
                &ContourSet {
                    tunnel_pairs: every,
                    ..set
                },
            );
            let kept = interior_joins(&g, &set);
            let wide = Span::of(g).is_some_and(|s| s.integer_scale(WIDEST_BITS).is_some());
            if integer_scale(&g).is_some() || wide {
                assert_eq!(kept, full, "{g:?}");
            } else if kept != full {
                // Rounded sweeps (values beyond 248 bits apart) may find a
                // join in a case 3 pair that rounding made: the table
                // leaves those out, which is then the exact answer.
                assert!(kept.is_none() && every & !set.tunnel_pairs != 0, "{g:?}");
                rounded += 1;
            }
            skipped += usize::from(set.tunnel_pairs == 0);
            found += usize::from(full.is_some());
            case_3 += usize::from(every & !set.tunnel_pairs != 0);
        }
        assert!(
            skipped > 1000 && found > 100 && case_3 > 1000,
            "{skipped} skipped, {found} joins, {case_3} with case 3 pairs, {rounded} rounded"
        );
    }

    /// The joins of a cell as the kernel finds them: its configuration,
    /// its (exact) face decisions, and the sweeps the tables ask for.
    fn cell_joins(g: &[f64; 8]) -> Option<Join> {
        let tables = crate::kernel::tables::tables();
        let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
        if !tables.is_ambiguous[config as usize] {
            return None;
        }
        let joined = crate::kernel::cell::face_decisions(g, None, config);
        interior_joins(g, tables.contour_set(config, joined))
    }

    /// A cell of small integers in `-r..=r`, a third of them zero (ties).
    fn small_cell(next: &mut impl FnMut() -> u64, r: u64) -> [i64; 8] {
        std::array::from_fn(|_| match next() % 3 {
            0 => 0,
            _ => (next() % (2 * r + 1)) as i64 - r as i64,
        })
    }

    /// `small_integer_joins` answers as `labelled_joins`, for cells of 8-bit samples less an integer isovalue
    /// (magnitudes up to 255, a third ties) of every ambiguous
    /// configuration and decision, and every set of pairs the tables ask.
    #[test]
    fn small_integer_joins_agree_with_labelled_joins() {
        let tables = crate::kernel::tables::tables();
        let mut next = crate::kernel::xorshift(0x6a09_e667_f3bc_c909u64);
        let (mut tested, mut found) = (0, 0);
        for round in 0..400_000u64 {
            let ints = small_cell(&mut next, [3, 16, 255][(round % 3) as usize]);
            let g = ints.map(|v| v as f64);
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if !tables.is_ambiguous[config as usize] {
                continue;
            }
            let joined = crate::kernel::cell::face_decisions(&g, None, config);
            let set = tables.contour_set(config, joined);
            let expected = labelled_joins(&g, None, set.tunnel_pairs, &set.corner_comp);
            let got = small_integer_joins(&g, set.tunnel_pairs, &set.corner_comp);
            assert_eq!(got, expected, "{ints:?}");
            tested += usize::from(set.tunnel_pairs != 0);
            found += usize::from(expected.is_some());
        }
        assert!(
            tested > 10_000 && found > 100,
            "{tested} tested, {found} joins"
        );
    }

    #[test]
    fn the_cells_qa_found_have_no_tunnel() {
        // Exact ties (the unscaled cells are the answer) that plain
        // floating point took for tunnels.
        let cells: [([f64; 8], f64); 3] = [
            ([-3.0, 0.0, -3.0, 3.0, -3.0, 1.0, 2.0, -2.0], 134217729.0),
            ([-1.0, -3.0, -2.0, 2.0, 2.0, 0.0, 2.0, -2.0], 100000007.0),
            (
                [-3.0, 0.0, -3.0, 3.0, -3.0, 1.0, 2.0, -2.0],
                1.0 + f64::EPSILON / 2.0,
            ),
        ];
        for (small, factor) in cells {
            let scaled = small.map(|v| v * factor);
            assert_eq!(cell_joins(&scaled), cell_joins(&small), "{scaled:?}");
        }
        let [(qa, factor), ..] = cells;
        assert_eq!(cell_joins(&qa.map(|v| v * factor)), None);
    }

    #[test]
    fn multiples_of_small_cells_join_as_the_small_cells() {
        // Every predicate is a homogeneous polynomial, so a cell times a
        // positive factor joins exactly as the cell: small integers (exact in
        // i64, full of ties) against their multiples by a large odd factor
        // (up to 2^50, values up to 2^53) and a power of two.
        let mut next = crate::kernel::xorshift(0x2545_f491_4f6c_dd1du64);
        let (mut tested, mut joins) = (0, 0);
        for round in 0..200_000u64 {
            let small = small_cell(&mut next, 1 + round % 4);
            let bits = [20, 31, 40, 50][(round / 4 % 4) as usize];
            let factor = ((next() % (1 << bits)) | 1 | (1 << (bits - 1))) as f64;
            let power = power_of_two([0, -30, 12, -70, 60][(round / 16 % 5) as usize]);
            let g = small.map(|v| v as f64);
            let expected = cell_joins(&g);
            let scaled = g.map(|v| v * factor * power);
            assert_eq!(
                cell_joins(&scaled),
                expected,
                "{small:?} x {factor} x {power}"
            );
            tested += 1;
            joins += usize::from(expected.is_some());
        }
        assert!(joins > 1000, "only {joins} joins in {tested} cells");
    }

    #[test]
    fn wide_cells_match_the_sweep_in_i256() {
        // Random integers of up to 31 and up to 60 bits, and near-ties
        // (multiples of a small cell, nudged by one on some corners), scaled
        // by powers of two: the filtered f64 sweep, where it is sure, and
        // the kernel's answer, agree with the sweep in 256-bit integers.
        let mut next = crate::kernel::xorshift(0x9e37_79b9_7f4a_7c15u64);
        let (mut sure, mut doubts, mut joins) = (0, 0, 0);
        for round in 0..200_000u64 {
            let ints: [i64; 8] = match round % 3 {
                0 => std::array::from_fn(|_| (next() % (1 << 32)) as i64 - (1 << 31)),
                1 => {
                    // Up to 53 significant bits, shifted to at most 60.
                    let shift = next() % 8;
                    std::array::from_fn(|_| {
                        let m = (next() % (1 << 53)) as i64 - (1 << 52);
                        (m >> (next() % 40)) << shift
                    })
                }
                _ => {
                    let factor = (next() % (1 << 48)) as i64 | 1;
                    small_cell(&mut next, 3)
                        .map(|v| v * factor + (next() % 5) as i64 / 3 - (next() % 5) as i64 / 3)
                }
            };
            let power = power_of_two([0, -40, 20, -100][(round / 3 % 4) as usize]);
            let g = ints.map(|v| v as f64 * power);
            assert!(ints.iter().all(|&v| (v as f64 * power) / power == v as f64));
            let tables = crate::kernel::tables::tables();
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if !tables.is_ambiguous[config as usize] {
                continue;
            }
            let set = tables.contour_set(
                config,
                crate::kernel::cell::face_decisions(&g, None, config),
            );
            let (pairs, labels) = (set.tunnel_pairs, &set.corner_comp);
            let expected = exact(sweep_both(&ints.map(I256::from), pairs, labels));
            match sweep_both(&ints.map(|v| Filtered::input(v as f64)), pairs, labels) {
                Ok(join) => {
                    assert_eq!(join, expected, "filtered {ints:?}");
                    sure += 1;
                }
                Err(Doubt) => doubts += 1,
            }
            assert_eq!(interior_joins(&g, set), expected, "{ints:?} x {power}");
            joins += usize::from(expected.is_some());
        }
        assert!(
            sure > 10_000 && doubts > 100 && joins > 1000,
            "{sure} sure, {doubts} in doubt, {joins} joins"
        );
    }

    #[test]
    fn unit_sweep_is_right_where_it_is_sure() {
        // Integers of up to 60 bits (rounded to doubles, with what rounding
        // left as the residual the bound must cover), near-ties (multiples of
        // a small cell nudged by one on some corners) and exact ties, scaled
        // by powers of two: where the unit sweep is sure, it agrees with the
        // sweep in 256-bit integers on the exact values.
        let mut next = crate::kernel::xorshift(0x6a09_e667_f3bc_c909u64);
        let tables = crate::kernel::tables::tables();
        let (mut sure, mut doubts, mut joins, mut rounded) = (0, 0, 0, 0);
        for round in 0..300_000u64 {
            let ints: [i64; 8] = match round % 4 {
                0 => std::array::from_fn(|_| (next() % (1 << 32)) as i64 - (1 << 31)),
                1 => std::array::from_fn(|_| {
                    let m = (next() % (1 << 60)) as i64 - (1 << 59);
                    m >> (next() % 50)
                }),
                2 => {
                    let factor = (next() % (1 << 48)) as i64 | 1;
                    small_cell(&mut next, 3)
                        .map(|v| v * factor + (next() % 5) as i64 / 3 - (next() % 5) as i64 / 3)
                }
                _ => small_cell(&mut next, 4),
            };
            let power = power_of_two([0, -40, 20, -300, 300][(round / 4 % 5) as usize]);
            let g = ints.map(|v| v as f64 * power);
            let residual = ints.map(|v| (v - v as f64 as i64) as f64 * power);
            rounded += usize::from(residual.iter().any(|&r| r != 0.0));
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if !tables.is_ambiguous[config as usize] {
                continue;
            }
            let joined = crate::kernel::cell::face_decisions(&g, Some(&residual), config);
            let set = tables.contour_set(config, joined);
            let (pairs, labels) = (set.tunnel_pairs, &set.corner_comp);
            if pairs == 0 {
                continue;
            }
            let expected = exact(sweep_both(&ints.map(I256::from), pairs, labels));
            match unit_joins(&g, pairs, labels) {
                Some(join) => {
                    assert_eq!(join, expected, "{ints:?} x {power}");
                    sure += 1;
                }
                None => doubts += 1,
            }
            assert_eq!(
                labelled_joins(&g, Some(&residual), pairs, labels),
                expected,
                "{ints:?} x {power}"
            );
            joins += usize::from(expected.is_some());
        }
        assert!(
            sure > 20_000 && doubts > 1000 && joins > 1000 && rounded > 10_000,
            "{sure} sure, {doubts} in doubt, {joins} joins, {rounded} rounded"
        );
    }

    #[test]
    fn unit_sweep_declines_values_it_cannot_scale() {
        let labels = [0, 1, 1, 0, 1, 0, 0, 1];
        let cell = |a: f64, b: f64| [a, -b, -b, a, -b, a, a, -b];
        // A value flushed to zero by the scale, infinities, NaN, a sum
        // beyond 2^1023, and all zeros.
        assert!(unit_joins(&cell(1e300, 1e-310), 0b1111, &labels).is_none());
        assert!(unit_joins(&cell(f64::INFINITY, 1.0), 0b1111, &labels).is_none());
        assert!(unit_joins(&cell(f64::NAN, 1.0), 0b1111, &labels).is_none());
        assert!(unit_joins(&cell(f64::MAX / 4.0, 1.0), 0b1111, &labels).is_none());
        assert!(unit_joins(&[0.0; 8], 0b1111, &labels).is_none());
        // Ordinary values and values near the ends of the range are taken.
        assert!(unit_joins(&cell(1.0, 0.5), 0b1111, &labels).is_some());
        assert!(unit_joins(&cell(1e-300, 3e-301), 0b1111, &labels).is_some());
        assert!(unit_joins(&cell(1e300, 3e299), 0b1111, &labels).is_some());
    }
}
