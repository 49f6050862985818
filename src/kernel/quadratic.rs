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
#[derive(Debug, Clone, Copy, Default)]
pub struct Saddles {
    points: [DVec3; 6],
    found: u8,
}

/// A point found, clamped into the closed unit cell.
fn into_cell(p: DVec3) -> DVec3 {
    DVec3::from_array(p.to_array().map(|x| x.clamp(0.0, 1.0)))
}

impl Saddles {
    /// How many points were found.
    pub fn count(&self) -> u32 {
        self.found.count_ones()
    }

    /// The first two points found, in the order of [`Saddles::iter`], picked
    /// without a branch; the first twice when only one was found, and
    /// meaningless when none was.
    pub fn first_two(&self) -> [DVec3; 2] {
        let first = (self.found.trailing_zeros() as usize).min(5);
        let rest = self.found & self.found.wrapping_sub(1);
        let second = if rest == 0 {
            first
        } else {
            rest.trailing_zeros() as usize
        };
        [self.points[first], self.points[second.min(5)]].map(into_cell)
    }

    /// The points found, in the order of axis and ascending root.
    pub fn iter(&self) -> impl Iterator<Item = DVec3> + '_ {
        (0..6)
            .filter(|&i| self.found >> i & 1 == 1)
            .map(|i| into_cell(self.points[i]))
    }
}

/// Saddle points of the level set inside the closed cell: for each axis, the
/// crossings of the lines found by that axis' quadratic. Both root slots of
/// every axis are worked out and kept or dropped without a branch (see
/// [`roots`]).
pub fn saddle_points(g: &[f64; 8]) -> Saddles {
    let mut out = Saddles::default();
    // One call per axis, each inlined with its axis a constant: the corner
    // and coordinate indices are then fixed at compile time.
    axis_saddles(g, 0, &mut out);
    axis_saddles(g, 1, &mut out);
    axis_saddles(g, 2, &mut out);
    out
}

/// The saddle points that the quadratic of `axis` finds, into slots
/// `2 axis` and `2 axis + 1` of `out`.
#[inline(always)]
fn axis_saddles(g: &[f64; 8], axis: usize, out: &mut Saddles) {
    const TOL: f64 = 1e-9;
    let cut = cut(g, axis);
    let (a, b, c) = cut_coefficients(&cut);
    let r = roots(a, b, c);
    for (slot, &s) in r.values.iter().enumerate() {
        let (p, ok) = cut_crossing(&cut, axis, s);
        let p = p.to_array();
        let inside = p.iter().fold(ok & (slot < r.len), |m, &x| {
            m & (-TOL..=1.0 + TOL).contains(&x)
        });
        let i = 2 * axis + slot;
        out.points[i] = DVec3::from_array(p);
        out.found |= u8::from(inside) << i;
    }
}

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
            counts[found.len()] += 1;
            let [a, b] = saddles.first_two();
            if let Some(&p) = found.first() {
                assert_eq!(a, p);
            }
            match found.len() {
                0 => {}
                1 => assert_eq!(b, a),
                _ => assert_eq!(b, found[1]),
            }
        }
        assert!(counts[..4].iter().all(|&c| c > 100), "{counts:?}");
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
