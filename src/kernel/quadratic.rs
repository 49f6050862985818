//! The three quadratic equations of Section 4, their saddle points and the
//! inner hexagon.
//!
//! Cut the cell by the plane `x_a = s` perpendicular to axis `a`. On the cut
//! the interpolant is bilinear with corner values `S00, S10, S01, S11`, each
//! linear in `s`, and the cut's level set is a hyperbola that degenerates into
//! two straight lines exactly where `D_a(s) = S00 S11 - S10 S01 = 0`. Those lines
//! run parallel to the two other axes and join opposite faces: they are the
//! lines of the paper's equation (4) (the paper writes the same quadratic once
//! per pair of opposite faces). Where they cross lies a saddle point of the
//! level set, and the six such points of a tunnel are the inner hexagon.
//!
//! Because every crossing line lies in two cuts, every hexagon vertex has its
//! x among the two roots of `D_x`, its y among those of `D_y` and its z among
//! those of `D_z`: the hexagon visits six corners of the box spanned by the
//! roots, leaving out one pair of opposite corners, and consecutive vertices
//! differ in exactly one coordinate. (The paper's printed listing of the
//! hexagon has errors; this is the order derived from that structure.)

use glam::DVec3;

/// Value of the trilinear interpolant of corner values `g` at local `p`.
pub fn trilinear(g: &[f64; 8], p: DVec3) -> f64 {
    let (x, y, z) = (p.x, p.y, p.z);
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let b00 = lerp(g[0], g[1], x);
    let b10 = lerp(g[2], g[3], x);
    let b01 = lerp(g[4], g[5], x);
    let b11 = lerp(g[6], g[7], x);
    lerp(lerp(b00, b10, y), lerp(b01, b11, y), z)
}

/// The cut's corner values as `alpha + beta * s`, indexed `[j][k]` with `j`
/// along the axis after the cut's and `k` along the one after that.
type Cut = [[(f64, f64); 2]; 2];

/// For each axis and cut slot `[j][k]`: the cell corners (at `s = 0`, at
/// `s = 1`) whose values the slot interpolates.
const CUT_CORNERS: [[[[usize; 2]; 2]; 2]; 3] = cut_corners();

const fn cut_corners() -> [[[[usize; 2]; 2]; 2]; 3] {
    let mut table = [[[[0; 2]; 2]; 2]; 3];
    let mut axis = 0;
    while axis < 3 {
        let mut j = 0;
        while j < 2 {
            let mut k = 0;
            while k < 2 {
                // Corner c = x + 2y + 4z.
                let low = j << ((axis + 1) % 3) | k << ((axis + 2) % 3);
                table[axis][j][k] = [low, low | 1 << axis];
                k += 1;
            }
            j += 1;
        }
        axis += 1;
    }
    table
}

/// The cut perpendicular to `axis` (a table lookup, so that the per-axis
/// loops of the callers compile to straight-line code).
fn cut(g: &[f64; 8], axis: usize) -> Cut {
    let corners = &CUT_CORNERS[axis];
    let slot = |j: usize, k: usize| {
        let [lo, hi] = corners[j][k];
        (g[lo], g[hi] - g[lo])
    };
    [[slot(0, 0), slot(0, 1)], [slot(1, 0), slot(1, 1)]]
}

/// Coefficients `(a, b, c)` of `D_axis(s) = a s^2 + b s + c`.
pub fn coefficients(g: &[f64; 8], axis: usize) -> (f64, f64, f64) {
    cut_coefficients(&cut(g, axis))
}

/// [`coefficients`] of a cut.
fn cut_coefficients(s: &Cut) -> (f64, f64, f64) {
    let ((a00, b00), (a01, b01)) = (s[0][0], s[0][1]);
    let ((a10, b10), (a11, b11)) = (s[1][0], s[1][1]);
    (
        b00 * b11 - b10 * b01,
        a00 * b11 + b00 * a11 - a10 * b01 - b10 * a01,
        a00 * a11 - a10 * a01,
    )
}

/// Real roots of `a s^2 + b s + c`, ascending, by the numerically stable
/// formula; `a == 0` is solved as a linear equation and a double root is
/// returned once.
///
/// Every candidate is computed first and one is then chosen, so that the
/// divisions and the square root start before the data-dependent tests
/// that pick the result are resolved.
pub fn roots(a: f64, b: f64, c: f64) -> Roots {
    let scale = a.abs().max(b.abs()).max(c.abs());
    let disc = b * b - 4.0 * a * c;
    let linear = -c / b;
    let double = -b / (2.0 * a);
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (r1, r2) = (q / a, c / q);
    let (len, values) = if scale == 0.0 || !scale.is_finite() {
        (0, [0.0; 2])
    } else if a.abs() <= 1e-14 * scale {
        (usize::from(b != 0.0), [linear; 2])
    } else if disc < 0.0 {
        (0, [0.0; 2])
    } else if disc == 0.0 {
        (1, [double; 2])
    } else {
        (2, [r1.min(r2), r1.max(r2)])
    };
    Roots { values, len }
}

/// Zero, one or two roots, ascending.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Roots {
    values: [f64; 2],
    len: usize,
}

impl Roots {
    /// The roots.
    pub fn as_slice(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

impl IntoIterator for Roots {
    type Item = f64;
    type IntoIter = std::iter::Take<std::array::IntoIter<f64, 2>>;

    fn into_iter(self) -> Self::IntoIter {
        self.values.into_iter().take(self.len)
    }
}

/// The saddle of the cut `x_axis = s`: the point where its two lines cross,
/// or `None` when the cut has no saddle.
pub fn cut_saddle(g: &[f64; 8], axis: usize, s: f64) -> Option<DVec3> {
    let (p, ok) = cut_crossing(&cut(g, axis), axis, s);
    ok.then_some(p)
}

/// The crossing of the lines of the cut `c` at `x_axis = s`, and whether
/// there is one (computed either way, for the branch-free caller).
#[inline]
fn cut_crossing(c: &Cut, axis: usize, s: f64) -> (DVec3, bool) {
    let v = |j: usize, k: usize| c[j][k].0 + c[j][k].1 * s;
    let (s00, s10, s01, s11) = (v(0, 0), v(1, 0), v(0, 1), v(1, 1));
    let eta = s00 - s10 - s01 + s11;
    let mut p = [0.0; 3];
    p[axis] = s;
    p[(axis + 1) % 3] = (s00 - s01) / eta;
    p[(axis + 2) % 3] = (s00 - s10) / eta;
    (DVec3::from_array(p), eta != 0.0 && eta.is_finite())
}

/// Up to six saddle points of the level set in a cell: the candidates of
/// every root slot, with a mask of those that are saddle points in the cell.
/// A point found lies within a tolerance of the cell and is clamped into it
/// when read, so that only the one or two points a cell uses pay for that.
///
/// Slot `2 axis + i` holds the crossing at root `i` of that axis' quadratic,
/// the roots in the order they were computed: only [`Saddles::iter`] needs
/// them ascending, and sorts. The points are stored axis by axis, as each
/// axis' two slots are computed, coordinate by coordinate within it:
/// `axes[axis][c][i]` (no shuffling of the eighteen values into another
/// order on the way out of [`saddle_points`]).
///
/// Where an axis' two roots are equal, its two points are either both found
/// or neither, and both are read as the first: sorted, as [`roots`] returns
/// them, both were that root, and the second, computed apart, may differ in
/// the sign of a zero (roots 0 and -0).
#[derive(Debug, Clone, Copy, Default)]
pub struct Saddles {
    axes: [[[f64; 2]; 3]; 3],
    found: u8,
}

/// A coordinate of a point found, clamped into the closed unit interval.
fn into_cell(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

impl Saddles {
    /// The point in `slot`, clamped into the closed unit cell.
    fn point(&self, slot: usize) -> DVec3 {
        let c = &self.axes[slot / 2];
        let i = slot % 2;
        DVec3::new(into_cell(c[0][i]), into_cell(c[1][i]), into_cell(c[2][i]))
    }

    /// Coordinate `axis` of the two slots of `axis`: its quadratic's roots.
    fn roots(&self, axis: usize) -> [f64; 2] {
        self.axes[axis][axis]
    }

    /// How many points were found.
    pub fn count(&self) -> u32 {
        self.found.count_ones()
    }

    /// Whether one or two points were found: `count()` in `1..=2`, without
    /// counting bits (no baseline x86-64 instruction does).
    pub fn one_or_two(&self) -> bool {
        let rest = self.found & self.found.wrapping_sub(1);
        self.found != 0 && rest & rest.wrapping_sub(1) == 0
    }

    /// Two points found, picked without a branch: those of the lowest two
    /// slots, the one twice when only one was found, and meaningless when
    /// none was. Their order may differ from that of [`Saddles::iter`],
    /// which sorts an axis' roots; their midpoint does not.
    pub fn first_two(&self) -> [DVec3; 2] {
        let first = (self.found.trailing_zeros() as usize).min(5);
        let rest = self.found & self.found.wrapping_sub(1);
        let second = if rest == 0 {
            first
        } else {
            rest.trailing_zeros() as usize
        };
        let second = second.min(5);
        // The two slots of one axis with equal roots: the first twice. (Only
        // when `first` is even can `second` be `first | 1`; the roots are then
        // those of slots `first` and `second`.)
        let roots = self.roots(first / 2);
        let tie = (second == first | 1) & (roots[1] == roots[0]);
        let second = std::hint::select_unpredictable(tie, first, second);
        [self.point(first), self.point(second)]
    }

    /// The points found, in the order of axis and ascending root.
    pub fn iter(&self) -> impl Iterator<Item = DVec3> + '_ {
        // The slots in that order, each with the slot it reads.
        let mut order = [(0, 0); 6];
        for axis in 0..3 {
            let roots = self.roots(axis);
            let first = 2 * axis;
            let (low, high) = if roots[1] < roots[0] {
                (first + 1, first)
            } else {
                (first, first + 1)
            };
            let tie = roots[1] == roots[0];
            order[first] = (low, low);
            order[first + 1] = (high, if tie { first } else { high });
        }
        order
            .into_iter()
            .filter(|&(slot, _)| self.found >> slot & 1 == 1)
            .map(|(_, read)| self.point(read))
    }
}

/// Saddle points of the level set inside the closed cell: for each axis, the
/// crossings of the lines found by that axis' quadratic. Both root slots of
/// every axis are worked out side by side and kept or dropped without a
/// branch.
///
/// Not inlined, so that the result is written straight into the caller's
/// variable: inlined, it was built apart and copied there by `memcpy`.
#[inline(never)]
pub fn saddle_points(g: &[f64; 8]) -> Saddles {
    // One call per axis, each inlined with its axis a constant: the corner
    // and coordinate indices are then fixed at compile time.
    let axes = [
        axis_saddles::<0>(g),
        axis_saddles::<1>(g),
        axis_saddles::<2>(g),
    ];
    Saddles {
        axes: axes.map(|axis| axis.coords),
        found: axes[0].found | axes[1].found | axes[2].found,
    }
}

/// The two slots of one axis: `coords[c][i]` is coordinate `c` of slot `i`.
#[derive(Clone, Copy)]
struct AxisSaddles {
    coords: [[f64; 2]; 3],
    /// Bit `2 axis + i` set iff slot `i` is a saddle point in the cell.
    found: u8,
}

/// The roots of `a s^2 + b s + c` that [`roots`] finds, for the two slots
/// of an axis: the values, unsorted, and which slots may hold a root. The
/// case (linear, double root or two) only picks the operands of slot 0's
/// division; both slots are then divided at once. Coefficients that are
/// not finite give no root, as in [`roots`].
///
/// A slot flagged that holds no root holds NaN or an infinity, which no
/// range test passes: `-c / 0` where the equation is linear with `b` zero,
/// NaN from the square root where there are no real roots.
#[inline(always)]
fn slot_roots(a: f64, b: f64, c: f64) -> ([f64; 2], [bool; 2]) {
    // Where some coefficient is NaN, so is `disc`, and then every root is
    // NaN: the care for NaN of `f64::max` is not needed.
    let max = |x: f64, y: f64| if x > y { x } else { y };
    let scale = max(a.abs(), max(b.abs(), c.abs()));
    let finite = scale < f64::INFINITY;
    let linear = a.abs() <= 1e-14 * scale;
    let disc = b * b - 4.0 * a * c;
    // `b + b.signum() * sqrt` of `roots`, the same for every `b` not NaN.
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    // Slot 0 holds the linear root, the double root or `q / a`; slot 1
    // holds `c / q`, a root only in the last case.
    let [num, den] = if linear {
        [-c, b]
    } else if disc == 0.0 {
        [-b, 2.0 * a]
    } else {
        [q, a]
    };
    let single = linear || disc == 0.0;
    ([num / den, c / q], [finite, finite & !single])
}

/// The saddle points that the quadratic of `AXIS` finds, in slots `2 AXIS`
/// and `2 AXIS + 1`: both computed side by side, each in the operations of
/// [`cut_crossing`].
#[inline(always)]
fn axis_saddles<const AXIS: usize>(g: &[f64; 8]) -> AxisSaddles {
    const TOL: f64 = 1e-9;
    let cut = cut(g, AXIS);
    let (a, b, c) = cut_coefficients(&cut);
    let (s, valid) = slot_roots(a, b, c);
    let s = Pair(s);
    let v = |j: usize, k: usize| Pair::splat(cut[j][k].0) + Pair::splat(cut[j][k].1) * s;
    let (s00, s10, s01, s11) = (v(0, 0), v(1, 0), v(0, 1), v(1, 1));
    let d = s00 - s10;
    let eta = d - s01 + s11;
    let next = (s00 - s01) / eta;
    let after = d / eta;
    // The crossing is in the cell iff `miss` is zero: the sum of how far
    // each coordinate lies outside [-TOL, 1 + TOL] (exactly zero iff it lies
    // inside, NaN for NaN) and `eta - eta` (zero iff `eta` is finite). A
    // few vector instructions, where the comparisons took three times as
    // many scalar ones. A zero `eta` leaves `next` infinite or NaN.
    let out_by = |x: Pair| (x - x.clamp(-TOL, 1.0 + TOL)).abs();
    #[allow(clippy::eq_op)]
    let miss = out_by(s) + out_by(next) + out_by(after) + (eta - eta);
    let inside = miss.0.map(|m| m == 0.0);
    let found = u8::from(valid[0] & inside[0]) | u8::from(valid[1] & inside[1]) << 1;
    let mut coords = [[0.0; 2]; 3];
    coords[AXIS] = s.0;
    coords[(AXIS + 1) % 3] = next.0;
    coords[(AXIS + 2) % 3] = after.0;
    AxisSaddles {
        coords,
        found: found << (2 * AXIS),
    }
}

/// Two values side by side, one per root slot of an axis, operated on as
/// pairs so that the compiler keeps each pair in one vector register.
#[derive(Clone, Copy)]
struct Pair([f64; 2]);

impl Pair {
    fn splat(x: f64) -> Pair {
        Pair([x; 2])
    }

    fn abs(self) -> Pair {
        Pair(self.0.map(f64::abs))
    }

    /// Each clamped into `[lo, hi]`, NaN to `hi` (one `minpd`, one `maxpd`).
    fn clamp(self, lo: f64, hi: f64) -> Pair {
        let min = |x: f64, y: f64| if x < y { x } else { y };
        let max = |x: f64, y: f64| if x > y { x } else { y };
        Pair(self.0.map(|x| max(min(x, hi), lo)))
    }
}

macro_rules! pair_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl std::ops::$trait for Pair {
            type Output = Pair;
            fn $method(self, o: Pair) -> Pair {
                Pair([self.0[0] $op o.0[0], self.0[1] $op o.0[1]])
            }
        }
    };
}
pair_op!(Add, add, +);
pair_op!(Sub, sub, -);
pair_op!(Mul, mul, *);
pair_op!(Div, div, /);

/// Two roots of the quadratic of `axis` in [0, 1], ascending. Used only when
/// the tunnel test has established that the hexagon exists: a double root
/// (a hexagon shrunk to a point) and roots pushed outside by rounding are
/// clamped rather than lost, so the result is always a usable hexagon.
fn two_roots(g: &[f64; 8], axis: usize) -> [f64; 2] {
    let (a, b, c) = coefficients(g, axis);
    let r = roots(a, b, c);
    let clamp = |s: f64| s.clamp(0.0, 1.0);
    match r.as_slice() {
        [] if a != 0.0 => [clamp(-b / (2.0 * a)); 2],
        [] => [0.5, 0.5],
        [s] => [clamp(*s); 2],
        [s, t, ..] => [clamp(*s), clamp(*t)],
    }
}

/// The inner hexagon: six points on the level set, consecutive ones joined by
/// straight lines parallel to an axis.
pub fn inner_hexagon(g: &[f64; 8]) -> [DVec3; 6] {
    let r = [two_roots(g, 0), two_roots(g, 1), two_roots(g, 2)];
    // The crossing in the cut x = r[0][0] is a hexagon vertex (0, a, b) in
    // root-index space; the left-out pair is (0, 1-a, 1-b) and (1, a, b).
    let (a, b) = match cut_saddle(g, 0, r[0][0]) {
        Some(p) => (
            usize::from((p.y - r[1][0]).abs() > (p.y - r[1][1]).abs()),
            usize::from((p.z - r[2][0]).abs() > (p.z - r[2][1]).abs()),
        ),
        None => (0, 0),
    };
    let left_out = [[0, 1 - a, 1 - b], [1, a, b]];
    let mut order = [[0usize; 3]; 6];
    order[0] = [0, a, b];
    // Walk to the neighbour (one index flipped) that is neither left out nor
    // already visited; flip y first so the walk direction is fixed.
    for i in 1..6 {
        let prev = order[i - 1];
        let before = if i >= 2 { Some(order[i - 2]) } else { None };
        let next = [1, 2, 0]
            .iter()
            .map(|&axis| {
                let mut n = prev;
                n[axis] = 1 - n[axis];
                n
            })
            .find(|n| !left_out.contains(n) && Some(*n) != before)
            .expect("a hexagon vertex has two neighbours on the hexagon");
        order[i] = next;
    }
    order.map(|[i, j, k]| DVec3::new(r[0][i], r[1][j], r[2][k]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stable_roots() {
        assert_eq!(roots(1.0, -3.0, 2.0).as_slice(), &[1.0, 2.0]);
        assert_eq!(roots(0.0, 2.0, -1.0).as_slice(), &[0.5]);
        assert_eq!(roots(1.0, -2.0, 1.0).as_slice(), &[1.0]);
        assert!(roots(1.0, 0.0, 1.0).as_slice().is_empty());
        assert!(roots(0.0, 0.0, 1.0).as_slice().is_empty());
        // Catastrophic cancellation in the textbook formula.
        let r = roots(1.0, -1e8, 1.0);
        assert!((r.as_slice()[0] - 1e-8).abs() < 1e-20);
    }

    #[test]
    fn first_two_and_count_agree_with_the_points_found() {
        let mut next = crate::kernel::xorshift(0x0dd5_eed5_1234_5678u64);
        let mut counts = [0usize; 7];
        for _ in 0..20_000 {
            let g: [f64; 8] = std::array::from_fn(|_| (next() % 9) as f64 - 4.0);
            let saddles = saddle_points(&g);
            let found: Vec<DVec3> = saddles.iter().collect();
            assert_eq!(saddles.count() as usize, found.len());
            assert_eq!(saddles.one_or_two(), (1..=2).contains(&found.len()));
            counts[found.len()] += 1;
            let [a, b] = saddles.first_two();
            match found.len() {
                0 => {}
                1 => assert_eq!([a, b], [found[0]; 2]),
                2 => assert!([a, b] == [found[0], found[1]] || [b, a] == [found[0], found[1]]),
                _ => {}
            }
        }
        assert!(counts[..4].iter().all(|&c| c > 100), "{counts:?}");
    }

    /// The points `saddle_points` found when it took each root of [`roots`]
    /// (ascending) one by one: the crossing, kept if in the cell.
    fn saddle_points_one_by_one(g: &[f64; 8]) -> Vec<DVec3> {
        const TOL: f64 = 1e-9;
        let mut found = Vec::new();
        for axis in 0..3 {
            let cut = cut(g, axis);
            let (a, b, c) = cut_coefficients(&cut);
            for s in roots(a, b, c) {
                let (p, ok) = cut_crossing(&cut, axis, s);
                if ok && p.to_array().iter().all(|x| (-TOL..=1.0 + TOL).contains(x)) {
                    found.push(DVec3::from_array(p.to_array().map(|x| x.clamp(0.0, 1.0))));
                }
            }
        }
        found
    }

    #[test]
    fn saddle_points_match_the_roots_one_by_one() {
        let mut next = crate::kernel::xorshift(0x9e37_79b9_7f4a_7c15u64);
        let mut counts = [0usize; 7];
        // Axes whose coefficients are not finite, linear, with a double
        // root, without real roots, with two.
        let mut kinds = [0usize; 5];
        for round in 0..300_000u32 {
            let g: [f64; 8] = std::array::from_fn(|_| {
                let r = next();
                let unit = (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                match round % 5 {
                    // Small integers: zero leading coefficients and double
                    // roots are common.
                    0 => (r % 9) as f64 - 4.0,
                    1 => (r % 3) as f64 - 1.0,
                    2 => unit,
                    // Values far apart: coefficients that overflow, vanish
                    // or are subnormal.
                    3 => unit * [1e300, 1e-300, 1.0, 1e150, 1e-160][(r % 5) as usize],
                    _ => [
                        0.0,
                        -0.0,
                        f64::MIN_POSITIVE,
                        5e-324,
                        -5e-324,
                        1.0,
                        -1.0,
                        f64::MAX,
                    ][(r % 8) as usize],
                }
            });
            let found: Vec<DVec3> = saddle_points(&g).iter().collect();
            let expected = saddle_points_one_by_one(&g);
            // Equal to the bit, but for the sign of a zero: `f64::min` and
            // `max`, which sort the roots, leave it unspecified (see
            // `equal_roots_give_one_point_twice`).
            let bits = |v: &[DVec3]| {
                v.iter()
                    .map(|p| p.to_array().map(|x| (x + 0.0).to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&found), bits(&expected), "{g:?}");
            counts[found.len()] += 1;
            for axis in 0..3 {
                let (a, b, c) = coefficients(&g, axis);
                let disc = b * b - 4.0 * a * c;
                let kind = if !a.abs().max(b.abs()).max(c.abs()).is_finite() {
                    0
                } else if a.abs() <= 1e-14 * a.abs().max(b.abs()).max(c.abs()) {
                    1
                } else if disc == 0.0 {
                    2
                } else if disc < 0.0 {
                    3
                } else {
                    4
                };
                kinds[kind] += 1;
            }
        }
        assert!(counts[..5].iter().all(|&c| c > 100), "{counts:?}");
        assert!(kinds.iter().all(|&c| c > 1000), "{kinds:?}");
    }

    #[test]
    fn equal_roots_give_one_point_twice() {
        // The quadratic of axis 1 has the roots 0 (as `q / a`, underflowed)
        // and -0 (as `c / q`): both slots read the crossing at the first,
        // as when the sorted roots were 0 twice.
        let g = [
            -2.67123038736488e-301,
            4.853691071312115e-161,
            3.5301514461418117e149,
            0.2956676059056478,
            -5.739951465167481e-303,
            4.799651061680731e-301,
            -0.44298088125269364,
            -6.140293119715201e148,
        ];
        let saddles = saddle_points(&g);
        let roots = saddles.roots(1);
        assert_eq!((roots[0], roots[1]), (0.0, 0.0));
        assert_ne!(roots[0].to_bits(), roots[1].to_bits());
        let found: Vec<[u64; 3]> = saddles
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect();
        assert_eq!(found.len(), 5);
        assert_eq!(found[2], found[3]);
        let first = cut_saddle(&g, 1, roots[0]).expect("a saddle");
        assert_eq!(
            found[2],
            first.to_array().map(|x| x.clamp(0.0, 1.0).to_bits())
        );
    }

    #[test]
    fn cut_corners_differ_only_along_the_axis() {
        for (axis, slots) in CUT_CORNERS.iter().enumerate() {
            for (j, row) in slots.iter().enumerate() {
                for (k, &[lo, hi]) in row.iter().enumerate() {
                    let at = |c: usize| [c & 1, c >> 1 & 1, c >> 2 & 1];
                    let (l, h) = (at(lo), at(hi));
                    assert_eq!((l[axis], h[axis]), (0, 1));
                    assert_eq!(l[(axis + 1) % 3], j);
                    assert_eq!(l[(axis + 2) % 3], k);
                    assert_eq!((h[(axis + 1) % 3], h[(axis + 2) % 3]), (j, k));
                }
            }
        }
    }

    #[test]
    fn quadratic_matches_cut_determinant() {
        let g = [0.3, -1.2, 0.7, 2.0, -0.4, 1.1, -2.5, 0.9];
        for axis in 0..3 {
            let (a, b, c) = coefficients(&g, axis);
            for s in [0.0, 0.3, 0.8, 1.0] {
                let p = |j: f64, k: f64| {
                    let mut q = [0.0; 3];
                    q[axis] = s;
                    q[(axis + 1) % 3] = j;
                    q[(axis + 2) % 3] = k;
                    trilinear(&g, DVec3::from_array(q))
                };
                let d = p(0.0, 0.0) * p(1.0, 1.0) - p(1.0, 0.0) * p(0.0, 1.0);
                assert!((a * s * s + b * s + c - d).abs() < 1e-12);
            }
        }
    }
}
