//! [`BlockEdges`] and `EdgeNormals`: the normals of vertices whose grid
//! edge the slab loop names, so that nothing has to find the edge again
//! from the vertex's `f32` position.
//!
//! Locating a vertex from its position (rounding its three index
//! coordinates, testing which two lie on grid lines, checking the bounds)
//! cost more than its gradient did. The slab loop knows the edge of every
//! vertex it places on one; it hands the edges of a block over in vertex
//! order, and only the position along the edge is read from the vertex:
//! the offset from the edge's lower end, which is what an interpolation
//! from the position gives ([`Layer::gradient`] at that offset), so a
//! vertex gets the same normal whether its edge is named or located.

use super::gradient::Layer;
use super::locate::SNAP;
use super::samples::Samples;
use super::vector::unit;
use super::PENDING;
use crate::grid::WorldToIndex;

/// Where a block's vertices lie, group by group and row by row, in the
/// block's vertex order: the vertices on the x-edges of plane `plane`,
/// row by row, then those on its y-edges (between rows `y` and `y + 1`),
/// then those on the z-edges from `plane` to `plane + 1`; the block's
/// vertices after these are inside cells.
///
/// Invariants: `rows[a][r]` is the index of the first vertex of group `a`
/// on (slab) row `r`, non-decreasing; group `a` ends at `ends[a]`, where
/// group `a + 1` begins. The row `r` of the slab is row `r + y_offset` of
/// the grid (a window's offset). Along its row a vertex is found from its
/// position: on an x-edge, the lower end's `x` is the floor of its index
/// coordinate; on a y- or z-edge, `x` is that coordinate rounded.
#[derive(Debug, Clone, Copy)]
pub struct BlockEdges<'a> {
    /// The grid plane that owns the block.
    pub plane: usize,
    /// The first vertex of each row of each group.
    pub rows: [&'a [u32]; 3],
    /// Where each group ends.
    pub ends: [usize; 3],
    /// Added to a slab row to give the grid row.
    pub y_offset: usize,
}

/// How index coordinates and index gradients relate to world ones: one
/// product per axis on an axis-aligned grid, the full map otherwise.
pub(super) trait IndexMap: Copy {
    /// Index coordinate `axis` of world position `v`.
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64;
    /// The index coordinates of world position `v`.
    fn index(&self, v: [f32; 3]) -> [f64; 3];
    /// What index-space differences along each axis are multiplied by
    /// before [`to_world`](Self::to_world): `1 / spacing` where that is
    /// all the chain rule does (then `to_world` does nothing), else 1.
    fn scale(&self) -> [f64; 3];
    /// An index-space gradient, multiplied by [`scale`](Self::scale), in
    /// world coordinates.
    fn to_world(&self, g: [f64; 3]) -> [f64; 3];
}

/// An axis-aligned grid: its origin and `1 / spacing`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Aligned {
    pub(super) origin: [f64; 3],
    pub(super) inverse: [f64; 3],
}

impl IndexMap for Aligned {
    #[inline(always)]
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64 {
        (f64::from(v[axis]) - self.origin[axis]) * self.inverse[axis]
    }

    #[inline(always)]
    fn index(&self, v: [f32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| self.coordinate(v, a))
    }

    #[inline(always)]
    fn scale(&self) -> [f64; 3] {
        self.inverse
    }

    #[inline(always)]
    fn to_world(&self, g: [f64; 3]) -> [f64; 3] {
        g
    }
}

impl IndexMap for &WorldToIndex {
    #[inline(always)]
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64 {
        WorldToIndex::index(self, v.map(f64::from))[axis]
    }

    #[inline(always)]
    fn index(&self, v: [f32; 3]) -> [f64; 3] {
        WorldToIndex::index(self, v.map(f64::from))
    }

    #[inline(always)]
    fn scale(&self) -> [f64; 3] {
        [1.0; 3]
    }

    #[inline(always)]
    fn to_world(&self, g: [f64; 3]) -> [f64; 3] {
        self.gradient_to_world(g)
    }
}

/// What the normals of one block's edge vertices are computed from.
pub(super) struct EdgeNormals<'f, P, M> {
    /// The four planes around the block's cell layer.
    pub(super) field: &'f Layer<P>,
    /// What a difference across planes is multiplied by at the layer's
    /// lower and upper plane.
    pub(super) fz: [f64; 2],
    /// The cell layer.
    pub(super) layer: usize,
    /// Where the x- and y-edges lie: the layer's lower (0) or upper (1)
    /// plane.
    pub(super) k: usize,
    /// Index coordinates from positions, gradients to world.
    pub(super) map: M,
    /// The full map, for the gradients of edges on a plane's border.
    pub(super) full: &'f WorldToIndex,
    /// 1, or -1 where outward is down the gradient.
    pub(super) sign: f64,
}

impl<P: Samples, M: IndexMap> EdgeNormals<'_, P, M> {
    /// Appends to `out` the normals of `vertices`, the group of the edges
    /// along axis `AXIS` (vertex `j` is the block's vertex `first + j`),
    /// whose rows start at `rows` (block indices): the two ends' central
    /// differences interpolated at the vertex's offset along the edge
    /// (read from its position), the chain rule, normalized; [`PENDING`]
    /// where that vanishes.
    ///
    /// One loop per axis, the planes and factors in locals: an edge whose
    /// ends are inside their plane's border (the common case) costs the
    /// samples it reads, a bounds check per plane and no branch on the
    /// axis; any other goes to [`on_border`](Self::on_border).
    #[inline(always)]
    pub(super) fn along<const AXIS: usize>(
        &self,
        rows: &[u32],
        y_offset: usize,
        first: usize,
        vertices: &[[f32; 3]],
        out: &mut Vec<[f32; 3]>,
    ) {
        let field = self.field;
        let (nx, ny) = (field.nx, field.ny);
        let [p0, p1, p2, p3] = field.planes;
        // The planes below, at and above the x- and y-edges' plane.
        let (below, here, above) = match self.k {
            0 => (p0, p1, p2),
            _ => (p1, p2, p3),
        };
        let layer = self.layer as f64;
        // `x - 1 < limit_x` (wrapping) is `1 <= x && x + reach_x < nx`.
        let (reach_x, reach_y) = match AXIS {
            0 => (2, 1),
            1 => (1, 2),
            _ => (1, 1),
        };
        let limit_x = nx.saturating_sub(reach_x + 1);
        // The lower end's x: at most the last cell's along x, the last
        // sample's otherwise.
        let last_x = (nx - 1 - usize::from(AXIS == 0)) as f64;
        let (map, sign) = (self.map, self.sign);
        // The central differences' factors (a half, or what a difference
        // across planes takes at the lower and upper end), with the grid's
        // scale folded in when the map has one per axis.
        let scale = map.scale();
        let [sx, sy] = [0.5 * scale[0], 0.5 * scale[1]];
        let [f0, f1] = self.fz.map(|f| f * scale[2]);
        let (fa, fb) = match (AXIS, self.k) {
            (2, _) => (f0, f1),
            (_, 0) => (f0, f0),
            _ => (f1, f1),
        };
        let (minus, at) = (P::minus, P::at);
        let lift = if AXIS == 0 { 0.0 } else { 0.5 };
        let end = first + vertices.len();
        for (r, &start) in rows.iter().enumerate() {
            let stop = rows.get(r + 1).map_or(end, |&s| s as usize);
            let (start, stop) = ((start as usize).max(first), stop.min(end));
            if start >= stop {
                continue;
            }
            let y = r + y_offset;
            let inner_y = y.wrapping_sub(1) < ny.saturating_sub(reach_y + 1);
            let row = y * nx;
            let normal = |v: [f32; 3]| -> [f32; 3] {
                // The floor (or, `+ 0.5`, the nearest) of the x coordinate
                // clamped to `[0, last_x]`, NaN to 0: comparisons and one
                // truncation through `i64` (a single instruction, where a
                // saturating cast to `usize` takes a dozen).
                let px = map.coordinate(v, 0);
                let c = px + lift;
                let x = if c >= 0.0 {
                    if c <= last_x {
                        c as i64 as usize
                    } else {
                        last_x as i64 as usize
                    }
                } else {
                    0
                };
                let w = match AXIS {
                    0 => px - x as f64,
                    1 => map.coordinate(v, 1) - y as f64,
                    _ => map.coordinate(v, 2) - layer,
                };
                if !(inner_y && x.wrapping_sub(1) < limit_x && (SNAP..=1.0 - SNAP).contains(&w)) {
                    return self.on_border(AXIS, [x, y], w);
                }
                let i = row + x;
                // Runs of samples cut around the edge, one bounds check
                // each: differences at the lower end (a) and the upper (b).
                let (a, b) = match AXIS {
                    0 => {
                        // Rows y - 1, y, y + 1 from x - 1 on.
                        let h = here.sub(i - nx - 1, i + nx + 3);
                        let (o, u) = (above.sub(i, i + 2), below.sub(i, i + 2));
                        let m = nx + 1;
                        (
                            [
                                minus(at(h, m + 1), at(h, m - 1)),
                                minus(at(h, m + nx), at(h, 1)),
                                minus(at(o, 0), at(u, 0)),
                            ],
                            [
                                minus(at(h, m + 2), at(h, m)),
                                minus(at(h, m + nx + 1), at(h, 2)),
                                minus(at(o, 1), at(u, 1)),
                            ],
                        )
                    }
                    1 => {
                        // Rows y - 1 to y + 2 from x - 1 on.
                        let h = here.sub(i - nx - 1, i + 2 * nx + 2);
                        let (o, u) = (above.sub(i, i + nx + 1), below.sub(i, i + nx + 1));
                        let m = nx + 1;
                        (
                            [
                                minus(at(h, m + 1), at(h, m - 1)),
                                minus(at(h, m + nx), at(h, 1)),
                                minus(at(o, 0), at(u, 0)),
                            ],
                            [
                                minus(at(h, m + nx + 1), at(h, m + nx - 1)),
                                minus(at(h, m + 2 * nx), at(h, m)),
                                minus(at(o, nx), at(u, nx)),
                            ],
                        )
                    }
                    _ => (z_end(p0, p1, p2, i, nx), z_end(p1, p2, p3, i, nx)),
                };
                let (w_low, w_high) = (1.0 - w, w);
                let g = [
                    sx * (w_low * a[0] + w_high * b[0]),
                    sy * (w_low * a[1] + w_high * b[1]),
                    w_low * (a[2] * fa) + w_high * (b[2] * fb),
                ];
                if P::MAY_BE_NAN && (g[0] + g[1] + g[2]).is_nan() {
                    return self.on_border(AXIS, [x, y], w);
                }
                outward(map.to_world(g), sign)
            };
            for &v in &vertices[start - first..stop - first] {
                out.push(normal(v));
            }
        }
    }

    /// The normal of a vertex at offset `w` on an edge with
    /// an end on its plane's border, at an end, or next to a NaN sample:
    /// [`Layer::gradient`] of the edge's cell at that offset (snapped as
    /// a located vertex's is).
    #[cold]
    #[inline(never)]
    fn on_border(&self, axis: usize, [x, y]: [usize; 2], w: f64) -> [f32; 3] {
        let field = self.field;
        let w = if w >= SNAP {
            if w > 1.0 - SNAP {
                1.0
            } else {
                w
            }
        } else {
            0.0
        };
        let (cx, cy) = (x.min(field.nx - 2), y.min(field.ny - 2));
        let mut t = [(x - cx) as f64, (y - cy) as f64, self.k as f64];
        t[axis] = w;
        let g = field.gradient([cx, cy], t);
        outward(self.full.gradient_to_world(g), self.sign)
    }
}

/// The differences of the central differences at sample `i` of plane
/// `here` (not on its border), `below` and `above` being the planes
/// around it (not yet divided by the distances).
#[inline(always)]
fn z_end<P: Samples>(below: P, here: P, above: P, i: usize, nx: usize) -> [f64; 3] {
    // Rows y - 1 to y + 1 around `i`.
    let h = here.sub(i - nx, i + nx + 1);
    let [over] = above.wide::<1>(i);
    let [under] = below.wide::<1>(i);
    [
        P::minus(P::at(h, nx + 1), P::at(h, nx - 1)),
        P::minus(P::at(h, 2 * nx), P::at(h, 0)),
        P::minus(over, under),
    ]
}

/// `g` (a world gradient) times `sign`, normalized, as `f32`; [`PENDING`]
/// when it is zero or not finite. One square root for gradients of
/// ordinary size; [`unit()`] (which scales first) for tiny or huge ones.
#[inline(always)]
pub(super) fn outward(g: [f64; 3], sign: f64) -> [f32; 3] {
    let squared = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if squared > 1e-200 && squared < 1e200 {
        let scale = sign / squared.sqrt();
        return g.map(|c| (c * scale) as f32);
    }
    unit(g.map(|c| sign * c)).unwrap_or(PENDING)
}
