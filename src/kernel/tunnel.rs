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
//! `D >= 0` suffices. The predicate is evaluated in exact integer arithmetic
//! (i128) whenever the eight values are integers after scaling by a power of
//! two (every integer volume, half-integer isovalues, ...), and in floating
//! point otherwise.

use super::contour::ContourSet;
use std::ops::{Add, Mul, Neg, Sub};

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
    let pairs = set.tunnel_pairs;
    if pairs == 0 {
        return None;
    }
    let labels = &set.corner_comp;
    if let Some(ints) = small_integers(g) {
        // Every 8- and 16-bit volume at an integer isovalue: no scaling.
        return sweep_both(&ints, pairs, labels);
    }
    match integer_scale(g) {
        Some((scale, bits)) if bits <= SMALL_BITS => {
            sweep_both(&g.map(|v| (v * scale) as i64), pairs, labels)
        }
        // At most 26 bits: through i64, which converts without a library call.
        Some((scale, _)) => sweep_both(&g.map(|v| i128::from((v * scale) as i64)), pairs, labels),
        None => sweep_both(&normalized(g), pairs, labels),
    }
}

/// The inside sweep of `h` over the pairs of `pairs & 0b11`, then, if it
/// found no join, the outside sweep over those of `pairs >> 2`.
fn sweep_both<T: Num>(h: &[T; 8], pairs: u8, labels: &[u8; 8]) -> Option<Join> {
    let inside = pairs & 0b11;
    let outside = pairs >> 2;
    let join = if inside != 0 {
        sweep(h, false, inside, labels)
    } else {
        None
    };
    if join.is_some() || outside == 0 {
        return join;
    }
    sweep(&h.map(|v| -v), true, outside, labels)
}

/// The eight values as `i64`s if they are all integers of magnitude below
/// `2^SMALL_BITS` (what [`integer_scale`] finds with scale 1, without its
/// bit by bit look at each value).
fn small_integers(g: &[f64; 8]) -> Option<[i64; 8]> {
    // Adding and taking away 1.5 * 2^52 rounds a value below 2^51 in
    // magnitude to an integer (the sum's last bit is worth 1), so it is
    // unchanged iff it is one. No short cut: eight tests side by side.
    const ROUND: f64 = 1.5 * (1u64 << 52) as f64;
    const LIMIT: f64 = (1u64 << SMALL_BITS) as f64;
    let small = g.iter().fold(true, |small, &v| {
        small & (v.abs() < LIMIT) & ((v + ROUND) - ROUND == v)
    });
    small.then(|| g.map(|v| v as i64))
}

/// The diagonal pairs of `w`-edges a sweep looks at, `(k, kk, j, jj)`: edges
/// `k` and `kk` (from corner `k` to `k + 4`) are joined where the plane's
/// saddle determinant `a_k a_kk - a_j a_jj` is positive.
const DIAGONALS: [(usize, usize, usize, usize); 2] = [(0, 3, 1, 2), (1, 2, 0, 3)];

/// Which sweeps can find a join for configuration `config` (bit `c` set:
/// corner `c` inside) with corner labels `labels`: bit `2 s + d` for the
/// diagonal pair `DIAGONALS[d]` on the inside (`s = 0`) or the outside
/// (`s = 1`). A pair can join only if each of its edges has a corner of that
/// sign and those corners carry different labels: otherwise the sweep passes
/// it over before any arithmetic. Depends on the configuration and face
/// decisions only, so the tables hold it.
///
/// Exact because the sweep sees the same signs as `config`: scaling to
/// integers or normalising never turns a nonzero value into zero.
pub fn may_join(config: u8, labels: &[u8; 8]) -> u8 {
    let inside = |c: usize| config >> c & 1 == 1;
    let mut pairs = 0;
    for (s, sign) in [true, false].into_iter().enumerate() {
        let corner = |k: usize| [k, k + 4].into_iter().find(|&c| inside(c) == sign);
        for (d, &(k, kk, _, _)) in DIAGONALS.iter().enumerate() {
            if let (Some(a), Some(b)) = (corner(k), corner(kk)) {
                if labels[a] != labels[b] {
                    pairs |= 1 << (2 * s + d);
                }
            }
        }
    }
    pairs
}

/// Arithmetic the sweep needs; exact for `i128`, rounded for `f64`.
trait Num:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    const TWO: Self;
    const FOUR: Self;
}

impl Num for i128 {
    const ZERO: Self = 0;
    const ONE: Self = 1;
    const TWO: Self = 2;
    const FOUR: Self = 4;
}

impl Num for i64 {
    const ZERO: Self = 0;
    const ONE: Self = 1;
    const TWO: Self = 2;
    const FOUR: Self = 4;
}

impl Num for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const FOUR: Self = 4.0;
}

/// A fraction `p / q` with `q > 0`.
#[derive(Clone, Copy)]
struct Frac<T> {
    p: T,
    q: T,
}

impl<T: Num> Frac<T> {
    fn less(self, o: Self) -> bool {
        self.p * o.q < o.p * self.q
    }
}

/// Sweeps one sign: `h > 0` inside (`closed = false`), or `h >= 0` for the
/// outside region given as `h = -g` (`closed = true`), over the diagonal
/// pairs of `DIAGONALS` whose bit is set in `pairs`; returns the first join
/// of two differently labelled diagonal edges in the interior. (Later joins
/// would only unite labels for pairs looked at after it, and only the first
/// join is triangulated.)
#[inline(always)]
fn sweep<T: Num>(h: &[T; 8], closed: bool, pairs: u8, labels: &[u8; 8]) -> Option<Join> {
    let is_in = |v: T| if closed { v >= T::ZERO } else { v > T::ZERO };
    for (d, (k, kk, j, jj)) in DIAGONALS.into_iter().enumerate() {
        if pairs >> d & 1 == 0 {
            continue;
        }
        let (Some(ik), Some(ikk)) = (
            range(h[k], h[k + 4], closed),
            range(h[kk], h[kk + 4], closed),
        ) else {
            continue;
        };
        let ck = if is_in(h[k]) { k } else { k + 4 };
        let ckk = if is_in(h[kk]) { kk } else { kk + 4 };
        let (la, lb) = (labels[ck], labels[ckk]);
        if la == lb {
            continue;
        }
        let lo = if ik.0.less(ikk.0) { ikk.0 } else { ik.0 };
        let hi = if ik.1.less(ikk.1) { ik.1 } else { ikk.1 };
        if joined_on(h, (k, kk, j, jj), lo, hi, closed) {
            return Some(Join {
                a: la.min(lb),
                b: la.max(lb),
            });
        }
    }
    None
}

/// The range of `t` where the edge from `bottom` to `top` is in the region.
#[inline(always)]
fn range<T: Num>(bottom: T, top: T, closed: bool) -> Option<(Frac<T>, Frac<T>)> {
    let is_in = |v: T| if closed { v >= T::ZERO } else { v > T::ZERO };
    let zero = Frac {
        p: T::ZERO,
        q: T::ONE,
    };
    let one = Frac {
        p: T::ONE,
        q: T::ONE,
    };
    match (is_in(bottom), is_in(top)) {
        (true, true) => Some((zero, one)),
        (true, false) => Some((
            zero,
            Frac {
                p: bottom,
                q: bottom - top,
            },
        )),
        (false, true) => Some((
            Frac {
                p: -bottom,
                q: top - bottom,
            },
            one,
        )),
        (false, false) => None,
    }
}

/// Is `D(t) = a_k a_kk - a_j a_jj` positive (or, closed, non-negative) somewhere
/// on the range from `lo` to `hi` (open, or closed)?
#[inline(always)]
fn joined_on<T: Num>(
    h: &[T; 8],
    (k, kk, j, jj): (usize, usize, usize, usize),
    lo: Frac<T>,
    hi: Frac<T>,
    closed: bool,
) -> bool {
    if closed {
        if hi.less(lo) {
            return false;
        }
    } else if !lo.less(hi) {
        return false;
    }
    let (ak, bk) = (h[k], h[k + 4] - h[k]);
    let (akk, bkk) = (h[kk], h[kk + 4] - h[kk]);
    let (aj, bj) = (h[j], h[j + 4] - h[j]);
    let (ajj, bjj) = (h[jj], h[jj + 4] - h[jj]);
    // D(t) = A t^2 + B t + C.
    let qa = bk * bkk - bj * bjj;
    let qb = ak * bkk + bk * akk - aj * bjj - bj * ajj;
    let qc = ak * akk - aj * ajj;
    let value_at = |f: Frac<T>| qa * f.p * f.p + qb * f.p * f.q + qc * f.q * f.q;
    let good = |v: T| if closed { v >= T::ZERO } else { v > T::ZERO };
    if good(value_at(lo)) || good(value_at(hi)) {
        return true;
    }
    if qa < T::ZERO {
        let vertex = Frac {
            p: qb,
            q: -(T::TWO * qa),
        };
        if lo.less(vertex) && vertex.less(hi) {
            return good(qb * qb - T::FOUR * qa * qc);
        }
    }
    false
}

/// Magnitude bits up to which the sweep is exact in `i64`: with `|h| <
/// 2^b`, its largest terms (`value_at`, `qb^2 - 4 qa qc`) stay below
/// `2^(4b + 7)`, so `b <= 14` fits. Every 8-bit volume and most CTs
/// (12-bit values) qualify; `i128` takes the rest up to 26 bits.
const SMALL_BITS: i32 = 14;

/// The eight values as integers after scaling by a power of two, if they
/// all are (with room for degree-four products in i128).
#[cfg(test)]
fn scaled_integers(g: &[f64; 8]) -> Option<[i128; 8]> {
    let (scale, _) = integer_scale(g)?;
    Some(g.map(|v| (v * scale) as i128))
}

/// The power of two that makes all eight values integers, and the
/// magnitude bits of the largest of those integers, if the values are
/// integers after such scaling and have at most 26 bits (room for
/// degree-four products in i128).
fn integer_scale(g: &[f64; 8]) -> Option<(f64, i32)> {
    const LIMIT_BITS: i32 = 26;
    // Each value is an odd integer times 2^e; scaling by 2^-min(e) (if
    // negative) makes all of them integers.
    let mut min_exp = 0i32;
    let mut max_bits = 0i32;
    for &v in g {
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
        min_exp = min_exp.min(exp + tz);
        // Magnitude below 2^(exp + tz + odd_bits).
        max_bits = max_bits.max(exp + tz + odd_bits);
    }
    let shift = -min_exp; // >= 0
    if max_bits + shift > LIMIT_BITS {
        return None;
    }
    // 0 <= shift <= LIMIT_BITS here (max_bits starts at 0).
    Some((power_of_two(shift), max_bits + shift))
}

/// `2^e` for `e` in the normal range of f64 (from the exponent bits, no
/// library call), `2^e` rounded by `powi` otherwise.
fn power_of_two(e: i32) -> f64 {
    if (-1022..=1023).contains(&e) {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        2f64.powi(e)
    }
}

/// The values scaled by a power of two so the largest magnitude is near 1
/// (exact but for values more than 2^1074 times smaller than the largest,
/// which become the smallest number of their sign rather than zero, so that
/// every sign is kept; keeps degree-four products away from overflow and
/// underflow).
fn normalized(g: &[f64; 8]) -> [f64; 8] {
    let scaled = scaled_down(g);
    std::array::from_fn(|c| {
        if scaled[c] == 0.0 && g[c] != 0.0 {
            f64::from_bits(1).copysign(g[c])
        } else {
            scaled[c]
        }
    })
}

/// The values scaled by the power of two that brings the largest magnitude
/// near 1 (rounded where it underflows).
fn scaled_down(g: &[f64; 8]) -> [f64; 8] {
    let max = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if max == 0.0 || !max.is_finite() {
        return *g;
    }
    // floor(log2(max)): the exponent bits of a normal number.
    let exp = if max >= f64::MIN_POSITIVE {
        ((max.to_bits() >> 52) & 0x7ff) as i32 - 1023
    } else {
        max.log2().floor() as i32
    };
    if exp > -1023 {
        let scale = power_of_two(-exp);
        g.map(|v| v * scale)
    } else {
        // A subnormal max: 2^-exp is beyond f64, so scale in two steps.
        let (half, rest) = (power_of_two(-exp / 2), power_of_two(-exp - -exp / 2));
        g.map(|v| v * half * rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::contour;

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
                for (closed, h) in [(false, g), (true, g.map(|v| -v))] {
                    let small = sweep(&h, closed, 0b11, labels);
                    let wide = sweep(&h.map(i128::from), closed, 0b11, labels);
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
    fn power_of_two_is_exact_over_the_whole_range() {
        for e in -1074..=1023 {
            assert_eq!(power_of_two(e), 2f64.powi(e), "2^{e}");
        }
    }

    #[test]
    fn normalized_puts_the_largest_magnitude_in_one_to_two() {
        for max in [1e-300, 3.0e-5, 0.99999999, 1.0, 7.5, 1e150, 1e-310] {
            let n = normalized(&[max, -max / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
            assert!((1.0..2.0).contains(&n[0]), "{max} -> {}", n[0]);
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
        // (down to values that underflow when normalised): the shortcut
        // gives what the full sweeps give.
        let mut next = crate::kernel::xorshift(0x9E37_79B9_7F4A_7C15u64);
        let tables = crate::kernel::tables::tables();
        let (mut skipped, mut found) = (0, 0);
        for _ in 0..200_000 {
            let g: [f64; 8] = std::array::from_fn(|_| {
                let r = next();
                let v = (r % 41) as f64 - 20.0;
                match r >> 60 {
                    0 => v * 1e-300,
                    1 => v * 1e150,
                    2 => v + 0.5,
                    _ => v,
                }
            });
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if !tables.is_ambiguous[config as usize] {
                continue;
            }
            let joined = crate::kernel::cell::face_decisions(&g, config);
            let set = *tables.contour_set(config, joined);
            let forced = ContourSet {
                tunnel_pairs: 0b1111,
                ..set
            };
            let full = interior_joins(&g, &forced);
            assert_eq!(interior_joins(&g, &set), full, "{g:?}");
            skipped += usize::from(set.tunnel_pairs == 0);
            found += usize::from(full.is_some());
        }
        assert!(
            skipped > 1000 && found > 100,
            "{skipped} skipped, {found} joins"
        );
    }
}
