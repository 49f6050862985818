//! An exact, independent topology oracle for tests.
//!
//! For a grid of integer samples `g` (already `value - iso`, scaled to
//! integers; x fastest) it computes the topology of `R = {T > ε}`, `ε → 0+`,
//! where `T` is the piecewise trilinear interpolant of `g`: the components of
//! `R`, the components of its complement in the grid box, and the Euler
//! characteristic of `R`. A sample is positive iff `g > 0` (ties are
//! outside). Nothing here uses the `tmc` crate. All arithmetic is exact
//! (`i128`, rationals compared by cross-multiplication), valid for
//! `|g| < 2^20`.
//!
//! ## Method
//! * Every component of `R` (of its complement) contains a grid vertex: the
//!   maximum (minimum) of the harmonic cell functions is reached on a vertex.
//!   So components are found with a union-find over vertices.
//! * Vertices are joined along grid edges (both ends of one class), across
//!   faces by the asymptotic decider, and through cells by a sweep along one
//!   axis (x unless told otherwise): the slice of a cell at parameter `s` is a
//!   bilinear square whose corners lie on the 4 cell edges parallel to the
//!   axis. The positive part of each such edge is one interval; two adjacent
//!   edges are joined when their intervals overlap, two opposite edges when
//!   the slice decider `D(s) = a_k a_k' - a_j a_j'` is positive somewhere on
//!   their common interval (`>= 0` on the closed interval for the
//!   complement).
//! * `χ_c(R ∩ open box)` is summed over the open cells of the grid (vertices,
//!   edges, faces, cubes). For a cube, `χ(R ∩ cube) = P - m_pos - m_neg` with
//!   `P` the positive components on the cube's surface and `m_pos`, `m_neg`
//!   the merges of positive and non-positive surface components made through
//!   the interior. `R ∩ open box` is an open 3-manifold homotopy equivalent to
//!   `R`, so `χ(R) = -χ_c(R ∩ open box)`.
//! * [`cell_euler_fubini`] recomputes a cube's `χ(R ∩ cube)` independently by
//!   Euler integration over the sweep parameter (exact, with the roots of the
//!   quadratic decider handled symbolically); the self-tests compare both.

use std::cmp::Ordering;

/// The topology of `R = {g > 0}` and of its complement in the grid box.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Topology {
    /// Components of `R`.
    pub pos_components: usize,
    /// Components of the complement of `R` inside the grid box.
    pub neg_components: usize,
    /// Euler characteristic of `R`.
    pub euler_r: i64,
    /// No positive sample lies on the grid boundary, so `∂R` is a closed
    /// surface inside the box.
    pub closed: bool,
    /// Components of the closed surface `∂R` (`pos + neg - 1`), when closed.
    pub surface_components: Option<usize>,
    /// Euler characteristic of the closed surface `∂R` (`2 χ(R)`), when
    /// closed.
    pub surface_euler: Option<i64>,
}

impl Topology {
    /// Total genus of the closed surface, `Σ g_i = components - χ(S) / 2`.
    pub fn surface_genus(&self) -> Option<i64> {
        Some(self.surface_components? as i64 - self.surface_euler? / 2)
    }
}

/// Topology of `{g > 0}` for the grid `g` of size `dims` (x fastest), with
/// the cell interiors swept along x.
pub fn topology(dims: [usize; 3], g: &[i64]) -> Topology {
    topology_along(dims, g, 0)
}

/// [`topology`] with the cell interiors swept along `axis` (0, 1 or 2); the
/// answer must not depend on it.
pub fn topology_along(dims: [usize; 3], g: &[i64], axis: usize) -> Topology {
    let [nx, ny, nz] = dims;
    assert_eq!(g.len(), nx * ny * nz, "grid size does not match dims");
    assert!(dims.iter().all(|&n| n >= 1) && axis < 3);
    assert!(
        g.iter().all(|v| v.abs() < 1 << 20),
        "oracle values must be below 2^20 in magnitude"
    );
    let stride = [1, nx, nx * ny];
    let index = |p: [usize; 3]| p[0] + nx * (p[1] + ny * p[2]);
    let interior = |p: [usize; 3], a: usize| p[a] > 0 && p[a] + 1 < dims[a];
    let positive = |i: usize| g[i] > 0;
    let points =
        || (0..nz).flat_map(move |z| (0..ny).flat_map(move |y| (0..nx).map(move |x| [x, y, z])));

    let mut uf = UnionFind::new(g.len());
    let (mut v_count, mut e_count, mut f_count, mut cube_euler) = (0i64, 0i64, 0i64, 0i64);

    for p in points() {
        let i = index(p);
        if positive(i) && (0..3).all(|a| interior(p, a)) {
            v_count += 1;
        }
        // Grid edges from p along each axis.
        for a in 0..3 {
            if p[a] + 1 >= dims[a] {
                continue;
            }
            let j = i + stride[a];
            if positive(i) == positive(j) {
                uf.union(i, j);
            }
            let open_in_box = (0..3).filter(|&b| b != a).all(|b| interior(p, b));
            if (positive(i) || positive(j)) && open_in_box {
                e_count += 1;
            }
        }
        // Faces with lower corner p, normal to each axis.
        for a in 0..3 {
            let (b0, b1) = others(a);
            if p[b0] + 1 >= dims[b0] || p[b1] + 1 >= dims[b1] {
                continue;
            }
            let corners = [
                i,
                i + stride[b0],
                i + stride[b1],
                i + stride[b0] + stride[b1],
            ];
            let h = corners.map(|c| g[c]);
            let labels = face_partition(h);
            for (k, &c) in corners.iter().enumerate() {
                uf.union(c, corners[labels[k] as usize]);
            }
            if interior(p, a) {
                f_count += count_classes(&labels, |k| h[k] > 0) as i64;
            }
        }
        // The cell with lower corner p.
        if (0..3).all(|a| p[a] + 1 < dims[a]) {
            let corners: [usize; 8] = std::array::from_fn(|c| {
                i + (c & 1) * stride[0] + ((c >> 1) & 1) * stride[1] + ((c >> 2) & 1) * stride[2]
            });
            let h = corners.map(|c| g[c]);
            let labels = cell_partition(&h, axis);
            for (k, &c) in corners.iter().enumerate() {
                uf.union(c, corners[labels[k] as usize]);
            }
            cube_euler += cell_euler_from(&h, &labels);
        }
    }

    let mut pos_roots = Vec::new();
    let mut neg_roots = Vec::new();
    let mut closed = true;
    for p in points() {
        let i = index(p);
        let root = uf.find(i);
        if positive(i) {
            pos_roots.push(root);
            if !(0..3).all(|a| interior(p, a)) {
                closed = false;
            }
        } else {
            neg_roots.push(root);
        }
    }
    for roots in [&mut pos_roots, &mut neg_roots] {
        roots.sort_unstable();
        roots.dedup();
    }
    let (pos, neg) = (pos_roots.len(), neg_roots.len());
    let euler_c = v_count - e_count + f_count - cube_euler;
    let euler_r = -euler_c;
    Topology {
        pos_components: pos,
        neg_components: neg,
        euler_r,
        closed,
        surface_components: closed.then(|| (pos + neg).saturating_sub(1)),
        surface_euler: closed.then_some(2 * euler_r),
    }
}

/// Converts samples that are integers or half-integers, and an isovalue of
/// the same kind, to the oracle's integers `2 * value - 2 * iso`.
///
/// # Panics
/// If a doubled value is not an integer.
pub fn scaled(values: &[f64], iso: f64) -> Vec<i64> {
    values
        .iter()
        .map(|&v| {
            let g = 2.0 * v - 2.0 * iso;
            assert!(
                g.fract() == 0.0 && g.abs() < 1e15,
                "{v} - {iso} is not a half-integer"
            );
            g as i64
        })
        .collect()
}

/// Surrounds a grid with `layers` layers of the value `fill`.
pub fn padded(dims: [usize; 3], g: &[i64], layers: usize, fill: i64) -> ([usize; 3], Vec<i64>) {
    let out_dims = dims.map(|n| n + 2 * layers);
    let mut out = vec![fill; out_dims.iter().product()];
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let o = (x + layers) + out_dims[0] * ((y + layers) + out_dims[1] * (z + layers));
                out[o] = g[x + dims[0] * (y + dims[1] * z)];
            }
        }
    }
    (out_dims, out)
}

/// The two axes other than `a`, in increasing order.
fn others(a: usize) -> (usize, usize) {
    match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// Number of classes in `labels` (each entry points at its class's
/// representative) among the entries selected by `keep`.
fn count_classes(labels: &[u8], keep: impl Fn(usize) -> bool) -> usize {
    (0..labels.len())
        .filter(|&k| keep(k) && labels[k] as usize == k)
        .count()
}

// ------------------------------------------------------------- faces ----

/// Partition of the corners of a square face with values
/// `[h00, h10, h01, h11]`: each entry is the index of its class's smallest
/// member. Positive corners are joined along positive sides and, when only
/// one diagonal is positive, across the face iff `h00 h11 - h10 h01 > 0`
/// (resp. `h10 h01 - h00 h11 > 0`); otherwise the other, non-positive
/// diagonal is joined (a tie joins the non-positive corners).
pub fn face_partition(h: [i64; 4]) -> [u8; 4] {
    let pos = h.map(|v| v > 0);
    let mut uf = SmallUf::<4>::new();
    for (a, b) in [(0, 1), (1, 3), (3, 2), (2, 0)] {
        if pos[a] == pos[b] {
            uf.union(a, b);
        }
    }
    let det = i128::from(h[0]) * i128::from(h[3]) - i128::from(h[1]) * i128::from(h[2]);
    if pos[0] && pos[3] && !pos[1] && !pos[2] {
        if det > 0 {
            uf.union(0, 3);
        } else {
            uf.union(1, 2);
        }
    } else if pos[1] && pos[2] && !pos[0] && !pos[3] {
        if -det > 0 {
            uf.union(1, 2);
        } else {
            uf.union(0, 3);
        }
    }
    uf.labels()
}

/// The same partition as [`face_partition`], computed from the positive
/// (open) and non-positive (closed) intervals of the two sides `h00-h10` and
/// `h01-h11`, as the cell sweep does. Exists to test that both agree.
pub fn face_partition_by_intervals(h: [i64; 4]) -> [u8; 4] {
    let k = Line::new(h[0], h[1]);
    let j = Line::new(h[2], h[3]);
    let mut uf = SmallUf::<4>::new();
    for (left, right) in [(0, 1), (2, 3)] {
        if (h[left] > 0) == (h[right] > 0) {
            uf.union(left, right);
        }
    }
    let rep_pos = |l: usize, r: usize| if h[l] > 0 { l } else { r };
    let rep_neg = |l: usize, r: usize| if h[l] <= 0 { l } else { r };
    if let (Some(a), Some(b)) = (k.positive(), j.positive()) {
        if max(a.0, b.0) < min(a.1, b.1) {
            uf.union(rep_pos(0, 1), rep_pos(2, 3));
        }
    }
    if let (Some(a), Some(b)) = (k.non_positive(), j.non_positive()) {
        if max(a.0, b.0) <= min(a.1, b.1) {
            uf.union(rep_neg(0, 1), rep_neg(2, 3));
        }
    }
    uf.labels()
}

// ------------------------------------------------------------- cells ----

/// Local corner `c = x + 2y + 4z` of a cell with the given coordinate bits.
fn corner(bits: [usize; 3]) -> usize {
    bits[0] | (bits[1] << 1) | (bits[2] << 2)
}

/// Partition of a cell's corners (values `h[c]`, `c = x + 2y + 4z`) into the
/// components of `R ∩ cell` and of its complement, from the cell's surface
/// (edges and face deciders) only. Entries are class representatives.
pub fn boundary_partition(h: &[i64; 8]) -> [u8; 8] {
    let mut uf = SmallUf::<8>::new();
    add_boundary(h, &mut uf);
    uf.labels()
}

fn add_boundary(h: &[i64; 8], uf: &mut SmallUf<8>) {
    for a in 0..3 {
        let (b0, b1) = others(a);
        for t in 0..2 {
            let mut c = [0usize; 4];
            for (k, ck) in c.iter_mut().enumerate() {
                let mut bits = [0; 3];
                bits[a] = t;
                bits[b0] = k & 1;
                bits[b1] = k >> 1;
                *ck = corner(bits);
            }
            let labels = face_partition(c.map(|i| h[i]));
            for k in 0..4 {
                uf.union(c[k], c[labels[k] as usize]);
            }
        }
    }
}

/// Partition of a cell's corners from the sweep along `axis` alone (which
/// also covers the cell's surface). Entries are class representatives.
pub fn sweep_partition(h: &[i64; 8], axis: usize) -> [u8; 8] {
    let mut uf = SmallUf::<8>::new();
    add_sweep(h, axis, &mut uf);
    uf.labels()
}

/// The full partition used by [`topology_along`]: surface and sweep.
pub fn cell_partition(h: &[i64; 8], axis: usize) -> [u8; 8] {
    let mut uf = SmallUf::<8>::new();
    add_boundary(h, &mut uf);
    add_sweep(h, axis, &mut uf);
    uf.labels()
}

/// `χ(R ∩ open cube) = P - m_pos - m_neg`, with the sweep along `axis`.
pub fn cell_euler(h: &[i64; 8], axis: usize) -> i64 {
    cell_euler_from(h, &cell_partition(h, axis))
}

fn cell_euler_from(h: &[i64; 8], full: &[u8; 8]) -> i64 {
    let surface = boundary_partition(h);
    let count = |labels: &[u8; 8], pos: bool| count_classes(labels, |c| (h[c] > 0) == pos) as i64;
    let p = count(&surface, true);
    let m_pos = p - count(full, true);
    let m_neg = count(&surface, false) - count(full, false);
    p - m_pos - m_neg
}

/// The cell's 4 edges parallel to `axis`, indexed `u + 2v` by their
/// coordinates along the other two axes, as (left corner, right corner).
fn sweep_edges(axis: usize) -> [(usize, usize); 4] {
    let (b0, b1) = others(axis);
    std::array::from_fn(|k| {
        let mut bits = [0; 3];
        bits[b0] = k & 1;
        bits[b1] = k >> 1;
        let left = corner(bits);
        (left, left | (1 << axis))
    })
}

/// Adjacent edge pairs of the sweep square, and the two diagonals with the
/// complementary pair.
const ADJACENT: [(usize, usize); 4] = [(0, 1), (0, 2), (1, 3), (2, 3)];
const DIAGONALS: [((usize, usize), (usize, usize)); 2] = [((0, 3), (1, 2)), ((1, 2), (0, 3))];

fn add_sweep(h: &[i64; 8], axis: usize, uf: &mut SmallUf<8>) {
    let edges = sweep_edges(axis);
    let lines = edges.map(|(l, r)| Line::new(h[l], h[r]));
    let rep_pos = |k: usize| {
        let (l, r) = edges[k];
        if h[l] > 0 {
            l
        } else {
            r
        }
    };
    let rep_neg = |k: usize| {
        let (l, r) = edges[k];
        if h[l] <= 0 {
            l
        } else {
            r
        }
    };
    for &(l, r) in &edges {
        if (h[l] > 0) == (h[r] > 0) {
            uf.union(l, r);
        }
    }
    let pos = lines.map(|l| l.positive());
    let neg = lines.map(|l| l.non_positive());
    for (k, j) in ADJACENT {
        if let (Some(a), Some(b)) = (pos[k], pos[j]) {
            if max(a.0, b.0) < min(a.1, b.1) {
                uf.union(rep_pos(k), rep_pos(j));
            }
        }
        if let (Some(a), Some(b)) = (neg[k], neg[j]) {
            if max(a.0, b.0) <= min(a.1, b.1) {
                uf.union(rep_neg(k), rep_neg(j));
            }
        }
    }
    for ((k, k2), (j, j2)) in DIAGONALS {
        let d = Quadratic::decider(&lines[k], &lines[k2], &lines[j], &lines[j2]);
        if let (Some(a), Some(b)) = (pos[k], pos[k2]) {
            let (lo, hi) = (max(a.0, b.0), min(a.1, b.1));
            if lo < hi && d.positive_inside_open(lo, hi) {
                uf.union(rep_pos(k), rep_pos(k2));
            }
        }
        if let (Some(a), Some(b)) = (neg[k], neg[k2]) {
            let (lo, hi) = (max(a.0, b.0), min(a.1, b.1));
            if lo <= hi && d.non_negative_inside_closed(lo, hi) {
                uf.union(rep_neg(k), rep_neg(k2));
            }
        }
    }
}

// ---------------------------------------------------- exact arithmetic ----

/// A rational `p / q` with `q > 0`.
#[derive(Debug, Clone, Copy)]
struct Rat {
    p: i128,
    q: i128,
}

impl Rat {
    fn new(p: i128, q: i128) -> Rat {
        assert!(q != 0);
        if q < 0 {
            Rat { p: -p, q: -q }
        } else {
            Rat { p, q }
        }
    }

    fn int(p: i128) -> Rat {
        Rat { p, q: 1 }
    }
}

impl PartialEq for Rat {
    fn eq(&self, other: &Rat) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Rat {}
impl PartialOrd for Rat {
    fn partial_cmp(&self, other: &Rat) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Rat {
    fn cmp(&self, other: &Rat) -> Ordering {
        (self.p * other.q).cmp(&(other.p * self.q))
    }
}

fn max(a: Rat, b: Rat) -> Rat {
    std::cmp::max(a, b)
}
fn min(a: Rat, b: Rat) -> Rat {
    std::cmp::min(a, b)
}

/// The values along a cell edge, `a(s) = l + d s` for `s` in `[0, 1]`.
#[derive(Debug, Clone, Copy)]
struct Line {
    l: i128,
    d: i128,
}

impl Line {
    fn new(left: i64, right: i64) -> Line {
        Line {
            l: i128::from(left),
            d: i128::from(right) - i128::from(left),
        }
    }

    /// The zero `-l / d` (requires `d != 0`).
    fn zero(&self) -> Rat {
        Rat::new(-self.l, self.d)
    }

    /// The positive set `{a > 0}` as the ends `(lo, hi)` of an interval that
    /// is open where `a = 0`: `[0, 1]`, `[0, τ)` or `(τ, 1]`.
    fn positive(&self) -> Option<(Rat, Rat)> {
        let right = self.l + self.d;
        match (self.l > 0, right > 0) {
            (true, true) => Some((Rat::int(0), Rat::int(1))),
            (true, false) => Some((Rat::int(0), self.zero())),
            (false, true) => Some((self.zero(), Rat::int(1))),
            (false, false) => None,
        }
    }

    /// The non-positive set `{a <= 0}`, a closed interval (maybe a point).
    fn non_positive(&self) -> Option<(Rat, Rat)> {
        let right = self.l + self.d;
        match (self.l <= 0, right <= 0) {
            (true, true) => Some((Rat::int(0), Rat::int(1))),
            (true, false) => Some((Rat::int(0), self.zero())),
            (false, true) => Some((self.zero(), Rat::int(1))),
            (false, false) => None,
        }
    }

    fn sign_at(&self, r: Rat) -> i8 {
        sign(self.l * r.q + self.d * r.p)
    }
}

fn sign(x: i128) -> i8 {
    x.signum() as i8
}

/// `D(s) = A s² + B s + C`.
#[derive(Debug, Clone, Copy)]
struct Quadratic {
    a: i128,
    b: i128,
    c: i128,
}

impl Quadratic {
    /// `a_k a_k' - a_j a_j'` for the diagonal `(k, k')` and the other
    /// diagonal `(j, j')`.
    fn decider(k: &Line, k2: &Line, j: &Line, j2: &Line) -> Quadratic {
        Quadratic {
            a: k.d * k2.d - j.d * j2.d,
            b: k.l * k2.d + k.d * k2.l - j.l * j2.d - j.d * j2.l,
            c: k.l * k2.l - j.l * j2.l,
        }
    }

    /// `sign(D(r))`.
    fn sign_at(&self, r: Rat) -> i8 {
        sign(self.a * r.p * r.p + self.b * r.p * r.q + self.c * r.q * r.q)
    }

    /// `sign(D'(r))`.
    fn slope_sign_at(&self, r: Rat) -> i8 {
        sign(2 * self.a * r.p + self.b * r.q)
    }

    fn discriminant(&self) -> i128 {
        self.b * self.b - 4 * self.a * self.c
    }

    /// The vertex `-B / (2A)` (requires `A != 0`).
    fn vertex(&self) -> Rat {
        Rat::new(-self.b, 2 * self.a)
    }

    /// Whether `D > 0` somewhere in the open interval `(lo, hi)`, `lo < hi`.
    fn positive_inside_open(&self, lo: Rat, hi: Rat) -> bool {
        self.sign_at(lo) > 0
            || self.sign_at(hi) > 0
            || (self.a < 0 && lo < self.vertex() && self.vertex() < hi && self.discriminant() > 0)
    }

    /// Whether `D >= 0` somewhere in the closed interval `[lo, hi]`.
    fn non_negative_inside_closed(&self, lo: Rat, hi: Rat) -> bool {
        self.sign_at(lo) >= 0
            || self.sign_at(hi) >= 0
            || (self.a < 0
                && lo <= self.vertex()
                && self.vertex() <= hi
                && self.discriminant() >= 0)
    }
}

// ------------------------------------------- Euler integration check ----

/// A point of the sweep parameter: a rational, or the smaller or bigger
/// root of the cell's decider (two distinct real roots, `A != 0`).
#[derive(Debug, Clone, Copy)]
enum Point {
    Rat(Rat),
    Root { big: bool },
}

/// Compares a rational with a root of `d` without square roots.
fn cmp_rat_root(r: Rat, big: bool, d: &Quadratic) -> Ordering {
    let s_d = d.sign_at(r);
    let s_a = sign(d.a);
    let left_of_vertex = r < d.vertex();
    match (big, s_d) {
        (false, 0) if left_of_vertex => Ordering::Equal,
        (false, 0) => Ordering::Greater,
        (true, 0) if left_of_vertex => Ordering::Less,
        (true, 0) => Ordering::Equal,
        // Outside both roots.
        (_, s) if s == s_a => {
            if left_of_vertex {
                Ordering::Less
            } else {
                Ordering::Greater
            }
        }
        // Strictly between the roots.
        (false, _) => Ordering::Greater,
        (true, _) => Ordering::Less,
    }
}

fn cmp_points(x: Point, y: Point, d: &Quadratic) -> Ordering {
    match (x, y) {
        (Point::Rat(a), Point::Rat(b)) => a.cmp(&b),
        (Point::Rat(a), Point::Root { big }) => cmp_rat_root(a, big, d),
        (Point::Root { big }, Point::Rat(b)) => cmp_rat_root(b, big, d).reverse(),
        (Point::Root { big: a }, Point::Root { big: b }) => a.cmp(&b),
    }
}

/// Signs of the 4 edge values and of the decider at `x`, and just right
/// of `x`.
fn signs_at(x: Point, lines: &[Line; 4], d: &Quadratic) -> ([i8; 4], i8, [i8; 4], i8) {
    let edge = |line: &Line| -> i8 {
        match x {
            Point::Rat(r) => line.sign_at(r),
            Point::Root { .. } if line.d == 0 => sign(line.l),
            Point::Root { .. } => sign(line.d) * (cmp_points(x, Point::Rat(line.zero()), d) as i8),
        }
    };
    let at = lines.map(|l| edge(&l));
    let right = std::array::from_fn(|k| if at[k] != 0 { at[k] } else { sign(lines[k].d) });
    let (d_at, slope) = match x {
        Point::Rat(r) => (d.sign_at(r), d.slope_sign_at(r)),
        Point::Root { big } => (0, if big { sign(d.a) } else { -sign(d.a) }),
    };
    let d_right = if d_at != 0 {
        d_at
    } else if slope != 0 {
        slope
    } else {
        sign(d.a)
    };
    (at, d_at, right, d_right)
}

/// Components of the positive set of an open bilinear square whose corner
/// signs are `a` (indexed like the sweep edges) and whose decider
/// `a0 a3 - a1 a2` has sign `d`.
fn slice_components(a: [i8; 4], d: i8) -> i64 {
    let pos = a.map(|s| s > 0);
    let mut uf = SmallUf::<4>::new();
    for (k, j) in ADJACENT {
        if pos[k] && pos[j] {
            uf.union(k, j);
        }
    }
    if pos[0] && pos[3] && d > 0 {
        uf.union(0, 3);
    }
    if pos[1] && pos[2] && d < 0 {
        uf.union(1, 2);
    }
    count_classes(&uf.labels(), |k| pos[k]) as i64
}

/// `χ(R ∩ open cube)` by Euler integration of the slices along `axis`:
/// `χ_c = Σ_points n(s) - Σ_open intervals n(J)`, `n` the number of (disk)
/// components of the open slice, and `χ = -χ_c` for the open 3-manifold.
/// Independent of the formula `P - m_pos - m_neg`.
pub fn cell_euler_fubini(h: &[i64; 8], axis: usize) -> i64 {
    let lines = sweep_edges(axis).map(|(l, r)| Line::new(h[l], h[r]));
    let d = Quadratic::decider(&lines[0], &lines[3], &lines[1], &lines[2]);
    let (zero, one) = (Rat::int(0), Rat::int(1));
    let inside = |x: Point| {
        cmp_points(Point::Rat(zero), x, &d) == Ordering::Less
            && cmp_points(x, Point::Rat(one), &d) == Ordering::Less
    };
    let mut points: Vec<Point> = lines
        .iter()
        .filter(|l| l.d != 0)
        .map(|l| Point::Rat(l.zero()))
        .collect();
    if d.a != 0 {
        match d.discriminant().cmp(&0) {
            Ordering::Greater => {
                points.extend([Point::Root { big: false }, Point::Root { big: true }])
            }
            Ordering::Equal => points.push(Point::Rat(d.vertex())),
            Ordering::Less => {}
        }
    } else if d.b != 0 {
        points.push(Point::Rat(Rat::new(-d.c, d.b)));
    }
    points.retain(|&x| inside(x));
    points.sort_by(|&x, &y| cmp_points(x, y, &d));
    points.dedup_by(|x, y| cmp_points(*x, *y, &d) == Ordering::Equal);

    let (_, _, right0, d_right0) = signs_at(Point::Rat(zero), &lines, &d);
    let mut euler_c = -slice_components(right0, d_right0);
    for &x in &points {
        let (at, d_at, right, d_right) = signs_at(x, &lines, &d);
        euler_c += slice_components(at, d_at) - slice_components(right, d_right);
    }
    -euler_c
}

// -------------------------------------------------------- union-finds ----

struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
        }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b)] = a.min(b);
        }
    }
}

/// A union-find on `N <= 8` elements whose labels are the smallest member
/// of each class.
struct SmallUf<const N: usize> {
    parent: [u8; N],
}

impl<const N: usize> SmallUf<N> {
    fn new() -> Self {
        SmallUf {
            parent: std::array::from_fn(|i| i as u8),
        }
    }

    fn find(&self, mut x: usize) -> usize {
        while self.parent[x] as usize != x {
            x = self.parent[x] as usize;
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b)] = a.min(b) as u8;
        }
    }

    fn labels(&self) -> [u8; N] {
        std::array::from_fn(|i| self.find(i) as u8)
    }
}
