//! One ambiguous cell, from its eight values to triangles (Algorithm 1).

use super::cell_mesh::{CellMesh, Triangles, VertexRef};
use super::contour::ContourSet;
use super::cube::{EDGE_CORNERS, FACE_CORNERS};
use super::decider::{inside_joined, residual_det2_sign};
use super::quadratic::{inner_hexagon, saddle_points, Saddles};
use super::scale::normalized;
use super::tables::tables;
use super::ties::{edge_fraction, TIE_OFFSET};
use super::triangulate::{costs, fan, fan_around, ring_assignment, strip};
use super::tunnel::{labelled_joins, small_integer_joins};
use crate::Stats;
use glam::DVec3;
use std::cmp::Ordering::{Greater, Less};

/// Position of the vertex on edge `e` in local coordinates (linear
/// interpolation, ties apart: [`edge_fraction`], as the slab loop places it).
pub fn edge_point(g: &[f64; 8], e: usize) -> DVec3 {
    let [a, b] = EDGE_CORNERS[e];
    let t = edge_fraction(g[a], g[b]);
    let pa = DVec3::new((a & 1) as f64, (a >> 1 & 1) as f64, (a >> 2 & 1) as f64);
    let pb = DVec3::new((b & 1) as f64, (b >> 1 & 1) as f64, (b >> 2 & 1) as f64);
    pa + (pb - pa) * t
}

/// Positions of the vertices of `contour`, in its order (see [`edge_point`]).
fn edge_points<'a>(g: &'a [f64; 8], contour: &'a [u8]) -> impl Iterator<Item = DVec3> + 'a {
    contour.iter().map(|&e| edge_point(g, e as usize))
}

/// Face decisions of a cell: bit `f` set iff the inside corners of
/// ambiguous face `f` are joined across it (asymptotic decider), for the
/// exact values `g + residual` (`None`: `g` is exact).
///
/// All six faces at once without a branch (or the one face alone when only
/// one is ambiguous: about two thirds of the ambiguous cells of cthead):
/// with `d = g0 g2 - g1 g3` over the face's corners, the inside corners are
/// joined iff `d > 0` when corner 0 of the face is inside and iff `d < 0`
/// otherwise (the same difference of the same rounded products, negated;
/// see [`det2_sign`](super::decider::det2_sign) for why its sign is exact
/// when nonzero). Only faces where the rounded products tie go to
/// the exact decider. Inlined into the kernel (a call, its prologue and
/// the tables' look-up again cost about a fifth of the decision).
#[inline(always)]
pub fn face_decisions(g: &[f64; 8], residual: Option<&[f64; 8]>, config: u8) -> u8 {
    let ambiguous = tables().ambiguous_faces[config as usize];
    if let Some(residual) = residual {
        return residual_decisions(g, residual, config, ambiguous);
    }
    if ambiguous.is_power_of_two() {
        // One ambiguous face (about two thirds of those of cthead): that face
        // alone, by the same rule.
        let f = ambiguous.trailing_zeros() as usize;
        let q = FACE_CORNERS[f];
        let d = g[q[0]] * g[q[2]] - g[q[1]] * g[q[3]];
        let (positive, negative) = (d > 0.0, d < 0.0);
        if !(positive | negative) {
            return exact_decisions(g, ambiguous);
        }
        let first_inside = config >> q[0] & 1 == 1;
        return u8::from(if first_inside { positive } else { negative }) << f;
    }
    let (mut positive, mut negative, mut first_inside) = (0u8, 0u8, 0u8);
    for (f, q) in FACE_CORNERS.iter().enumerate() {
        let d = g[q[0]] * g[q[2]] - g[q[1]] * g[q[3]];
        positive |= u8::from(d > 0.0) << f;
        negative |= u8::from(d < 0.0) << f;
        first_inside |= (config >> q[0] & 1) << f;
    }
    let joined = (positive & first_inside) | (negative & !first_inside);
    let ties = ambiguous & !(positive | negative);
    if ties == 0 {
        return joined & ambiguous;
    }
    (joined & ambiguous & !ties) | exact_decisions(g, ties)
}

/// [`face_decisions`] on the `ambiguous` faces of a cell whose values
/// `g + residual` were rounded: by the sign of `d` in exact arithmetic (see
/// [`residual_det2_sign`]), except on faces whose four corners are exact
/// or whose values are too far apart for it, which are decided as in a
/// cell without residuals (so that the cell sharing the face, which may
/// have none, decides alike).
#[cold]
#[inline(never)]
fn residual_decisions(g: &[f64; 8], residual: &[f64; 8], config: u8, ambiguous: u8) -> u8 {
    let mut joined = 0u8;
    let mut rounded = None;
    for (f, q) in FACE_CORNERS.iter().enumerate() {
        if ambiguous >> f & 1 == 0 {
            continue;
        }
        let (v, r) = (q.map(|c| g[c]), q.map(|c| residual[c]));
        let sign = if r == [0.0; 4] {
            None
        } else {
            residual_det2_sign(v, r)
        };
        let face_joined = match sign {
            // Joined iff the sign of d is that of corner 0's value.
            Some(sign) => {
                sign == if config >> q[0] & 1 == 1 {
                    Greater
                } else {
                    Less
                }
            }
            None => *rounded.get_or_insert_with(|| face_decisions(g, None, config)) >> f & 1 == 1,
        };
        joined |= u8::from(face_joined) << f;
    }
    joined
}

/// The asymptotic decider, exact, on each face of `faces` (rare: only
/// rounded ties come here).
#[cold]
#[inline(never)]
fn exact_decisions(g: &[f64; 8], faces: u8) -> u8 {
    let mut joined = 0u8;
    for (f, q) in FACE_CORNERS.iter().enumerate() {
        if faces >> f & 1 == 0 {
            continue;
        }
        // Scaled by a power of two that depends on the face's values only,
        // so that no product overflows or underflows and both cells sharing
        // the face decide alike.
        let v = face_scaled(q.map(|c| g[c]));
        let (i0, o0) = if v[0] > 0.0 { (0, 1) } else { (1, 0) };
        if inside_joined(v[i0], v[i0 + 2], v[o0], v[o0 + 2]) {
            joined |= 1 << f;
        }
    }
    joined
}

/// The four values of a face scaled by the power of two that brings the
/// largest magnitude near 1 (infinities as `±f64::MAX / 4` first): signs and
/// the sign of `v0 v2 - v1 v3` are kept unless the values are more than
/// about 2^500 apart.
fn face_scaled(v: [f64; 4]) -> [f64; 4] {
    let v = v.map(|x| x.clamp(-f64::MAX / 4.0, f64::MAX / 4.0));
    let n = normalized(&[v[0], v[1], v[2], v[3], 0.0, 0.0, 0.0, 0.0]);
    [n[0], n[1], n[2], n[3]]
}

/// Triangulates an ambiguous cell (Definition 1) with values `g` (inside iff
/// `> 0`) and configuration `config`; counts the paper's Table 1 in `stats`.
/// The triangles are either the tables' or appended to `out` (see
/// [`Triangles`]).
///
/// `residual`, if given, is what rounding left out of `g` (`g + residual`
/// are the exact values, `|residual| <= 2^-53 |g|`, as when `g = value -
/// iso` is rounded; see [`subtraction_residual`](super::wide::subtraction_residual)):
/// face and tunnel decisions are taken on the exact values, the vertex
/// positions on `g`.
///
/// Values of any magnitude are taken. The face decisions are made on `g`
/// itself (and the residual), each a function of the face's four values
/// only, so that the two cells sharing a face always agree; the rest of the kernel works on the
/// cell's values scaled by a power of two when their largest magnitude lies
/// outside about `[2^-200, 2^197]`.
pub fn triangulate_ambiguous(
    g: &[f64; 8],
    residual: Option<&[f64; 8]>,
    config: u8,
    stats: &mut Stats,
    out: &mut CellMesh,
) -> Triangles {
    triangulate::<false>(g, residual, config, Known::Nothing, stats, out)
}

/// [`triangulate_ambiguous`] for a caller that triangulates many cells with
/// one `out` (the slab loop): the flat contours of a cell that takes the
/// table's fans (most ambiguous cells) are counted in `out`, one increment
/// per cell, and reach `stats` only at [`CellMesh::flush_counts`], which the
/// caller must call before it reads or hands on `stats`. Everything else,
/// triangles and all other counts, is as [`triangulate_ambiguous`] gives it.
///
/// `known` is what the caller knows of `g` (see [`Known`]), which spares
/// the kernel tests whose answer that knowledge gives.
///
/// Inlined into the one caller, the slab loop's ambiguous cell, where the
/// call's prologue and the [`Triangles`] handed back through memory cost
/// as much as the range test.
#[inline(always)]
pub fn triangulate_ambiguous_deferred(
    g: &[f64; 8],
    residual: Option<&[f64; 8]>,
    config: u8,
    known: Known,
    stats: &mut Stats,
    out: &mut CellMesh,
) -> Triangles {
    triangulate::<true>(g, residual, config, known, stats, out)
}

/// What the caller of [`triangulate_ambiguous_deferred`] knows of an
/// ambiguous cell's values `g` (whose signs `config` holds).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Known {
    /// Nothing: any values, with or without residual.
    Nothing,
    /// `g` are the exact differences `value - iso` (or `iso - value`) of
    /// integer samples of at most 32 bits and the isovalue, without
    /// residual. Such a cell is always in `in_kernel_range`, which is
    /// then not tested: an ambiguous cell has a corner inside (`g' > 0`)
    /// and one outside (`g <= 0`), whose samples differ, so by at least 1,
    /// and so do `g'` and `g` (both exact), so the larger magnitude is at
    /// least 1/2 and the sum of the magnitudes, rounded or not, is above
    /// 2^-197; the isovalue lies between those two samples, so every `|g|`
    /// is at most 2^33 and the sum at most about 2^36, below 2^197. (The
    /// test `integer_differences_are_in_range` checks this on samples of
    /// every integer type, at their ends, and isovalues of every kind.)
    Integers,
    /// [`Known::Integers`] of 8-bit samples and an integer isovalue: `g`
    /// are integers, of magnitude at most 255 (the isovalue lies between
    /// two of the samples), which the tunnel test takes as they are
    /// ([`small_integer_joins`]) instead of testing and converting them.
    SmallIntegers,
}

/// [`triangulate_ambiguous`], its table cells' flat contours counted in
/// `out` if `DEFER`, and the tests that `known` answers left out (see
/// [`triangulate_ambiguous_deferred`]).
#[inline(always)]
fn triangulate<const DEFER: bool>(
    g: &[f64; 8],
    residual: Option<&[f64; 8]>,
    config: u8,
    known: Known,
    stats: &mut Stats,
    out: &mut CellMesh,
) -> Triangles {
    debug_assert!(known == Known::Nothing || (residual.is_none() && in_kernel_range(g)));
    let joined = face_decisions(g, residual, config);
    if known == Known::Nothing && !in_kernel_range(g) {
        return triangulate_rescaled::<DEFER>(g, residual, config, joined, stats, out);
    }
    let small = known == Known::SmallIntegers;
    triangulate_decided::<DEFER>(g, (g, residual), config, joined, small, stats, out)
}

/// [`triangulate_ambiguous`] of a cell in [`in_kernel_range`] whose face
/// decisions are `joined`: its vertices placed with `g`, its tunnel decided
/// on `tested` (the values `g` was scaled from, if it was, and their
/// residual), and if `small` on `g` as integers ([`Known::SmallIntegers`]).
#[inline(always)]
fn triangulate_decided<const DEFER: bool>(
    g: &[f64; 8],
    tested: (&[f64; 8], Option<&[f64; 8]>),
    config: u8,
    joined: u8,
    small: bool,
    stats: &mut Stats,
    out: &mut CellMesh,
) -> Triangles {
    let t = tables();
    let index = t.set_index(config, joined);
    let head = t.heads[index];
    let tunnel = if head.tunnel_pairs == 0 {
        None
    } else if small {
        small_integer_joins(g, head.tunnel_pairs, &head.labels)
            .and_then(|j| tunnel_contours(&t.contours[index], j.a, j.b))
    } else {
        labelled_joins(tested.0, tested.1, head.tunnel_pairs, &head.labels)
            .and_then(|j| tunnel_contours(&t.contours[index], j.a, j.b))
    };
    // No tunnel, and flat contours but for at most one that meets a face
    // twice (most ambiguous cells): the table's fans, found without reading
    // the set itself unless the interior vertex needs its contour.
    if tunnel.is_none() && head.fan_len != 0 {
        if DEFER {
            out.count_table_cell(index);
        } else {
            count_flat_contours(stats, head.flat_counts, 1);
        }
        let n = usize::from(head.centred_len);
        if n == 0 {
            return Triangles::Table(t.fans(head));
        }
        count_ambiguous(stats, n);
        let contour = || t.contours[index].contour(usize::from(head.centred));
        let centre = interior_vertex(&saddle_points(g), g, contour);
        return Triangles::Centred(t.fans(head), interior_clamp(g, centre, out.tie_margin));
    }
    let set = &t.contours[index];
    if let Some((c1, c2)) = tunnel {
        stats.tunnels += 1;
        triangulate_tunnel(g, set.contour(c1), set.contour(c2), out);
    }
    let mut saddles = None;
    for i in 0..set.count as usize {
        if tunnel.is_some_and(|(c1, c2)| i == c1 || i == c2) {
            continue;
        }
        let contour = set.contour(i);
        let n = contour.len();
        if n == 12 {
            stats.contours_12 += 1;
            triangulate_twelve(g, contour, out);
        } else if set.meets_face_twice >> i & 1 == 1 {
            count_ambiguous(stats, n);
            let saddles = saddles.get_or_insert_with(|| saddle_points(g));
            let centre = out.push_interior(interior_vertex(saddles, g, || contour));
            fan_around(contour, centre, &mut out.triangles);
        } else {
            count_flat(stats, n);
            fan(contour, &mut out.triangles);
        }
    }
    let margin = out.tie_margin;
    for p in &mut out.interior {
        *p = interior_clamp(g, *p, margin);
    }
    Triangles::Mesh
}

/// Is the largest magnitude of `g` within about `[2^-200, 2^200]`? Then
/// every product of up to four values the kernel forms (the quadratics'
/// discriminants are the largest) is far from overflow, and from underflow
/// where it matters. Tested on the sum of the magnitudes, which lies
/// between the largest and eight times it (a few instructions, side by
/// side); NaN and infinities fail it.
#[inline]
fn in_kernel_range(g: &[f64; 8]) -> bool {
    const LOW: f64 = 1.0 / (1u128 << 100) as f64 / (1u128 << 97) as f64; // 2^-197
    const HIGH: f64 = (1u128 << 100) as f64 * (1u128 << 97) as f64; // 2^197
    let sum = g.iter().fold(0.0, |s, v| s + v.abs());
    (LOW..=HIGH).contains(&sum)
}

/// [`triangulate_decided`] of a cell out of [`in_kernel_range`]: on its
/// values scaled by the power of two that brings the largest near 1 (NaN as
/// 0, infinities as `±f64::MAX / 4`), which keeps every sign; its tunnel is
/// decided on the values before scaling (the test is homogeneous).
#[cold]
#[inline(never)]
fn triangulate_rescaled<const DEFER: bool>(
    g: &[f64; 8],
    residual: Option<&[f64; 8]>,
    config: u8,
    joined: u8,
    stats: &mut Stats,
    out: &mut CellMesh,
) -> Triangles {
    let finite = g.map(|v| {
        if v.is_nan() {
            0.0
        } else {
            v.clamp(-f64::MAX / 4.0, f64::MAX / 4.0)
        }
    });
    let scaled = normalized(&finite);
    if !in_kernel_range(&scaled) {
        // All zero: no corner is inside, so there is nothing to triangulate.
        return Triangles::Table(&[]);
    }
    triangulate_decided::<DEFER>(
        &scaled,
        (&finite, residual),
        config,
        joined,
        false,
        stats,
        out,
    )
}

impl CellMesh {
    /// Notes that a cell took the table fans of contour set `index`.
    #[inline(always)]
    fn count_table_cell(&mut self, index: usize) {
        match self.table_cells.get_mut(index) {
            Some(cells) => *cells += 1,
            None => self.first_table_cell(index),
        }
    }

    /// [`CellMesh::count_table_cell`] before the counters are sized (one
    /// per contour set).
    #[cold]
    #[inline(never)]
    fn first_table_cell(&mut self, index: usize) {
        self.table_cells.resize(tables().heads.len(), 0);
        self.table_cells[index] += 1;
    }

    /// Adds the flat contours of the cells noted since the last flush to
    /// `stats` (the paper's Table 1) and forgets them. Once per slab, so its
    /// look at every contour set costs nothing measurable.
    pub fn flush_counts(&mut self, stats: &mut Stats) {
        for (cells, head) in self.table_cells.iter_mut().zip(&tables().heads) {
            if *cells != 0 {
                count_flat_contours(stats, head.flat_counts, *cells);
                *cells = 0;
            }
        }
    }
}

/// Counts `cells` times the flat contours `flat_counts` of a contour set
/// ([`SetHead::flat_counts`](super::tables::SetHead::flat_counts): four
/// bits per vertex count, 3 to 6) in the paper's Table 1.
fn count_flat_contours(stats: &mut Stats, flat_counts: u16, cells: u64) {
    for (i, count) in stats.contours.iter_mut().enumerate() {
        *count += cells * u64::from(flat_counts >> (4 * i) & 0xf);
    }
}

/// Counts a flat contour of `n` vertices in the paper's Table 1.
fn count_flat(stats: &mut Stats, n: usize) {
    if (3..=6).contains(&n) {
        stats.contours[n - 3] += 1;
    }
}

/// Counts a contour of `n` vertices that meets a face twice (the paper's
/// ambiguous contours, Table 1).
fn count_ambiguous(stats: &mut Stats, n: usize) {
    if (6..=9).contains(&n) {
        stats.ambiguous_contours[n - 6] += 1;
    }
}

/// The two contours bounding the tunnel that joins surface components `a`
/// and `b`: each separates one of them from the region `x` they both touch.
fn tunnel_contours(set: &ContourSet, a: u8, b: u8) -> Option<(usize, usize)> {
    let n = set.count as usize;
    let other = |i: usize, c: u8| {
        if set.inside_comp[i] == c {
            Some(set.outside_comp[i])
        } else if set.outside_comp[i] == c {
            Some(set.inside_comp[i])
        } else {
            None
        }
    };
    for i in 0..n {
        for j in 0..n {
            if let (Some(x), Some(y)) = (other(i, a), other(j, b)) {
                if i != j && x == y {
                    return Some((i, j));
                }
            }
        }
    }
    None
}

/// A tunnel: both contours strip-joined to the inner triangle, winding round
/// it in opposite directions (so the two strips meet with opposite edge
/// orientations), each contour assigned to alternate hexagon vertices.
fn triangulate_tunnel(g: &[f64; 8], c1: &[u8], c2: &[u8], out: &mut CellMesh) {
    let hex = open_hexagon(g, out.tie_margin);
    let alternate = |parity: usize| [0, 1, 2].map(|k| hex[2 * k + parity]);
    // The first candidate is taken whatever its cost, so that a cost that
    // is not a number still leaves a valid pair of assignments.
    let mut best: Option<(f64, [u8; 12], [u8; 12])> = None;
    for parity in 0..2 {
        let cost1 = costs(edge_points(g, c1), |p, k| {
            p.distance_squared(alternate(parity)[k])
        });
        let cost2 = costs(edge_points(g, c2), |p, k| {
            p.distance_squared(alternate(1 - parity)[k])
        });
        for dir in [1, -1] {
            let (ca, a1) = ring_assignment(&cost1[..c1.len()], dir);
            let (cb, a2) = ring_assignment(&cost2[..c2.len()], -dir);
            if best.is_none_or(|b| ca + cb < b.0) {
                best = Some((ca + cb, a1, a2));
            }
        }
    }
    let (_, a1, a2) = best.expect("four candidates");
    let inner = inner_triangle(&hex, out);
    strip(c1, &a1[..c1.len()], inner, out);
    strip(c2, &a2[..c2.len()], inner, out);
}

/// The 12-vertex contour: a strip to the inner triangle, closed by it.
fn triangulate_twelve(g: &[f64; 8], contour: &[u8], out: &mut CellMesh) {
    let hex = open_hexagon(g, out.tie_margin);
    let cost = costs(edge_points(g, contour), |p, k| {
        p.distance_squared(hex[2 * k])
            .min(p.distance_squared(hex[2 * k + 1]))
    });
    let (c_up, a_up) = ring_assignment(&cost[..contour.len()], 1);
    let (c_down, a_down) = ring_assignment(&cost[..contour.len()], -1);
    let (dir, asg) = if c_up <= c_down {
        (1, a_up)
    } else {
        (-1, a_down)
    };
    let inner = inner_triangle(&hex, out);
    strip(contour, &asg[..contour.len()], inner, out);
    // The strip uses each inner edge against the walking direction; the cap
    // uses it along.
    if dir == 1 {
        out.push_triangle([inner[0], inner[1], inner[2]]);
    } else {
        out.push_triangle([inner[0], inner[2], inner[1]]);
    }
}

/// An interior vertex clamped into the cell: into the closed unit cube, and
/// further, into the cube `margin` inside it ([`TIE_OFFSET`], or more on a
/// grid far from the origin: [`CellMesh::tie_margin`]), in a cell with a tie
/// corner (a value 0), or where the vertex lies on the cell's boundary and
/// a face of the cell has a saddle tie (`g0 g2 = g1 g3`: its saddle value
/// is the isovalue). At such ties the level set holds edges of the cell or
/// crosses itself on a face, and a saddle point of it can lie on the
/// cell's boundary, where the cell across that boundary may put its own
/// interior vertex, or an edge vertex lies; strictly inside, an interior
/// vertex is apart from both, which keep to the boundary. Elsewhere the
/// vertex is the paper's, bit for bit, but on a grid far from the origin
/// (a margin above [`TIE_OFFSET`]): there every interior vertex of every
/// cell moves, the unit cube shrunk onto the inner one, because `f32`
/// world coordinates do not resolve a vertex a little inside a face from
/// the face, where the cell across may put its own interior vertex (two
/// were seen sharing a position, `cthead @ 1150` at an origin of `1.6e5`).
#[inline]
fn interior_clamp(g: &[f64; 8], p: DVec3, margin: f64) -> DVec3 {
    let p = p.clamp(DVec3::ZERO, DVec3::ONE);
    if margin > TIE_OFFSET {
        // Far from the origin: every interior vertex, the unit cube mapped
        // onto the inner one (a clamp would put two vertices near one edge
        // on one point, and `f32` cannot tell apart what is close).
        return DVec3::splat(margin) + p * (1.0 - 2.0 * margin);
    }
    let inner = p.clamp(DVec3::splat(margin), DVec3::splat(1.0 - margin));
    if inner == p {
        // Already inside the inner cube (most vertices): no tie test.
        return p;
    }
    let touches = p.min_element() == 0.0 || p.max_element() == 1.0;
    if g.contains(&0.0) || touches && face_saddle_tie(g) {
        inner
    } else {
        p
    }
}

/// Whether an ambiguous face of the cell (inside corners on one diagonal,
/// outside ones on the other) has `g0 g2 = g1 g3` (products rounded; the
/// values of integer data at an integer or half-integer isovalue give them
/// exactly): its saddle value is the isovalue.
fn face_saddle_tie(g: &[f64; 8]) -> bool {
    FACE_CORNERS.iter().any(|q| {
        let inside = q.map(|c| g[c] > 0.0);
        let ambiguous = inside[0] == inside[2] && inside[1] == inside[3] && inside[0] != inside[1];
        ambiguous && g[q[0]] * g[q[2]] == g[q[1]] * g[q[3]]
    })
}

/// The inner hexagon of a tunnel or 12-vertex contour (see
/// [`inner_hexagon`]), open: where two consecutive vertices coincide (a
/// quadratic with a double root: a body saddle whose value is the isovalue,
/// a tie), the hexagon of the level a little above, `g - δ` for `δ` 2^-20,
/// then 2^-16 and 2^-12 of the cell's largest magnitude, the first whose
/// vertices are apart: the level set of `{g > ε}` opens there into a
/// tunnel whose waist is about the square root of that fraction (2^-10 of
/// the cell at first). Without such a tie the hexagon is `inner_hexagon(g)`.
///
/// On a grid far from the origin (`margin`, [`CellMesh::tie_margin`], above
/// [`TIE_OFFSET`]) vertices closer than `margin` on every axis count as
/// coinciding, and `δ` goes on to 2^-8, 2^-6 and 2^-4: `f32` world
/// coordinates do not tell apart the vertices of a tunnel that narrow (three
/// interior vertices of `bonsai @ 40` at an origin of `1.6e5`, 0.004 of the
/// cell apart, fell on one point). On the usual grid nothing changes.
fn open_hexagon(g: &[f64; 8], margin: f64) -> [DVec3; 6] {
    let far = margin > TIE_OFFSET;
    let apart = |a: DVec3, b: DVec3| a != b && !(far && (a - b).abs().max_element() < margin);
    let closed = |h: &[DVec3; 6]| (0..6).any(|i| !apart(h[i], h[(i + 1) % 6]));
    let hex = inner_hexagon(g);
    if !closed(&hex) {
        return hex;
    }
    let largest = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let fractions = [-20, -16, -12, -8, -6, -4].map(|e| 2f64.powi(e));
    for fraction in &fractions[..if far { 6 } else { 3 }] {
        let shifted = g.map(|v| v - largest * fraction);
        let open = inner_hexagon(&shifted);
        if !closed(&open) {
            return open;
        }
    }
    hex
}

/// The three interior vertices of a tunnel: midpoints of the hexagon's
/// vertex pairs (0, 1), (2, 3), (4, 5) (equation 7).
fn inner_triangle(hex: &[DVec3; 6], out: &mut CellMesh) -> [VertexRef; 3] {
    [0, 1, 2].map(|k| out.push_interior((hex[2 * k] + hex[2 * k + 1]) * 0.5))
}

/// The interior vertex of an ambiguous contour: the crossing of the single
/// lines (a saddle point), or the midpoint of the two saddle points nearest
/// to the contour's centroid when there are more; the centroid if rounding
/// left no saddle point in the cell. With one or two saddle points the
/// centroid decides nothing, and neither it nor the contour is looked at.
#[inline(always)]
fn interior_vertex<'c>(
    saddles: &Saddles,
    g: &[f64; 8],
    contour: impl FnOnce() -> &'c [u8],
) -> DVec3 {
    // One or two saddle points (most cells), without a branch on which: with
    // one, `b` is `a` and the midpoint is `a` exactly (doubling and halving
    // are exact); with two, their order does not matter. Only the rare
    // other counts take a branch.
    let [a, b] = saddles.first_two();
    if saddles.one_or_two() {
        return (a + b) * 0.5;
    }
    let contour = contour();
    let centroid = edge_points(g, contour).sum::<DVec3>() / contour.len() as f64;
    let distance = |p: &DVec3| p.distance_squared(centroid);
    let mut nearest: Option<(DVec3, Option<DVec3>)> = None;
    for s in saddles.iter() {
        nearest = Some(match nearest {
            None => (s, None),
            Some((a, _)) if distance(&s) < distance(&a) => (s, Some(a)),
            Some((a, None)) => (a, Some(s)),
            Some((a, Some(b))) if distance(&s) < distance(&b) => (a, Some(s)),
            Some(keep) => keep,
        });
    }
    match nearest {
        None => centroid,
        Some((a, None)) => a,
        Some((a, Some(b))) => (a + b) * 0.5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of a cell, small integers (many exact ties) if `integers`,
    /// random reals in `[-0.5, 0.5)` otherwise, and their configuration.
    fn random_cell(next: &mut impl FnMut() -> u64, integers: bool) -> ([f64; 8], u8) {
        let g: [f64; 8] = std::array::from_fn(|_| {
            let r = next();
            if integers {
                (r % 7) as f64 - 3.0
            } else {
                (r >> 11) as f64 / (1u64 << 52) as f64 - 0.5
            }
        });
        let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
        (g, config)
    }

    #[test]
    fn all_faces_at_once_agree_with_the_decider_face_by_face() {
        // Small integers (many exact ties: saddle value equal to the
        // isovalue) and random reals, in every configuration they give.
        let mut next = crate::kernel::xorshift(0x5851_f42d_4c95_7f2du64);
        let mut ties = 0;
        for round in 0..200_000u32 {
            let (g, config) = random_cell(&mut next, round % 2 == 0);
            let ambiguous = tables().ambiguous_faces[config as usize];
            let tied = FACE_CORNERS
                .iter()
                .enumerate()
                .any(|(f, q)| ambiguous >> f & 1 == 1 && g[q[0]] * g[q[2]] == g[q[1]] * g[q[3]]);
            ties += usize::from(tied);
            assert_eq!(
                face_decisions(&g, None, config),
                exact_decisions(&g, ambiguous),
                "{g:?}"
            );
        }
        assert!(ties > 1000, "only {ties} cells with a tie");
    }

    /// The claim of `triangulate_ambiguous_deferred` with `integers`: exact
    /// differences of integer samples (at most 32 bits) and an isovalue, of
    /// mixed sign, are in `in_kernel_range`. Samples at the integer types'
    /// ends and random ones; isovalues on a sample, half-way, tiny or
    /// subnormal beside one; either side inside. (Differences of float
    /// samples can lie out of range: the last assertion, so the check can
    /// fail.)
    #[test]
    fn integer_differences_are_in_range() {
        use crate::kernel::wide::subtraction_residual;
        let mut next = crate::kernel::xorshift(0x1f83_d9ab_fb41_bd6bu64);
        let ends = [
            0.0,
            1.0,
            -1.0,
            127.0,
            -128.0,
            255.0,
            32767.0,
            -32768.0,
            65535.0,
            2147483647.0,
            -2147483648.0,
            4294967295.0,
        ];
        let offsets = [0.0, 0.5, -0.5, 1e-300, -1e-300, 5e-324, -5e-324, 1e-9];
        let mut checked = 0;
        for round in 0..200_000u64 {
            let v: [f64; 8] = std::array::from_fn(|_| {
                let r = next();
                match r % 4 {
                    0 => ends[(r >> 8) as usize % ends.len()],
                    1 => f64::from((r >> 32) as u32),
                    2 => f64::from((r >> 32) as i32),
                    _ => f64::from((r >> 32) as u8) - 128.0,
                }
            });
            let r = next();
            let iso = v[(r % 8) as usize] + offsets[(r >> 8) as usize % offsets.len()];
            let sign = if round % 2 == 0 { 1.0 } else { -1.0 };
            let g = v.map(|x| (x - iso) * sign);
            let exact = v
                .iter()
                .all(|&x| subtraction_residual(x, iso, x - iso) == 0.0);
            let mixed = g.iter().any(|&x| x > 0.0) && g.iter().any(|&x| x <= 0.0);
            if exact && mixed {
                assert!(in_kernel_range(&g), "{v:?} {iso} {sign}");
                checked += 1;
            }
        }
        assert!(checked > 50_000, "only {checked} cells");
        assert!(!in_kernel_range(&[
            1e-300, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.0
        ]));
    }

    /// The deferred entry point triangulates as the immediate one, and after
    /// `flush_counts` its statistics are the same (before it, the table
    /// cells' flat contours are missing, so the comparison is not vacuous).
    #[test]
    fn deferred_counts_agree_after_the_flush() {
        let mut next = crate::kernel::xorshift(0x3c6e_f372_fe94_f82bu64);
        let (mut now, mut later) = (Stats::default(), Stats::default());
        let (mut a, mut b) = (CellMesh::new(), CellMesh::new());
        let mut cells = 0;
        while cells < 20_000 {
            let (g, config) = random_cell(&mut next, cells % 2 == 0);
            if !tables().is_ambiguous[config as usize] {
                continue;
            }
            cells += 1;
            a.clear();
            b.clear();
            let x = triangulate_ambiguous(&g, None, config, &mut now, &mut a);
            let y = triangulate_ambiguous_deferred(
                &g,
                None,
                config,
                Known::Nothing,
                &mut later,
                &mut b,
            );
            assert_eq!(x, y, "{g:?}");
            assert_eq!((&a.triangles, &a.interior), (&b.triangles, &b.interior));
        }
        assert_ne!(now.contours, later.contours);
        b.flush_counts(&mut later);
        assert_eq!(now, later);
        assert!(now.contours.iter().all(|&n| n > 100), "{:?}", now.contours);
        // Flushed counts are forgotten.
        b.flush_counts(&mut later);
        assert_eq!(now, later);
    }
}
