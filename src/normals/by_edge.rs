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

use super::batch::{Batch, Factors, BATCH};
use super::gradient::Layer;
use super::index_map::IndexMap;
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

/// Where the vertices of one edge direction lie along their rows.
struct Walk {
    /// `x - 1 < limit_x` (wrapping) for an edge whose ends are inside
    /// their plane's border along x.
    limit_x: usize,
    /// The largest lower end's x, as `f64`.
    last_x: f64,
    /// Added to the x coordinate before its floor is taken: 0 for x-edges,
    /// a half (the nearest grid line) for the others.
    lift: f64,
    /// The cell layer's lower plane, as `f64`.
    layer: f64,
    /// Samples per row.
    nx: usize,
}

impl<P: Samples, M: IndexMap> EdgeNormals<'_, P, M> {
    /// Appends to `out` the normals of `vertices`, the group of the edges
    /// along axis `AXIS` (vertex `j` is the block's vertex `first + j`),
    /// whose rows start at `rows` (block indices): the two ends' central
    /// differences interpolated at the vertex's offset along the edge
    /// (read from its position), the chain rule, normalized; [`PENDING`]
    /// where that vanishes.
    ///
    /// One loop per axis, the planes and factors in locals. For a row of
    /// vertices the rows of samples their edges' ends need are cut once,
    /// all of one length, so that a vertex's reads share a few bounds
    /// checks; an edge whose ends are inside their plane's border (the
    /// common case) costs the samples it reads; any other goes to
    /// [`on_border`](Self::on_border). The differences are gathered into a
    /// [`Batch`], whose arithmetic runs [`BATCH`] vertices at a time
    /// ([`finish`](Self::finish)): `batch`, shared by a block's three
    /// calls (whatever its slots hold is overwritten before it is read).
    #[inline(always)]
    pub(super) fn along<const AXIS: usize>(
        &self,
        rows: &[u32],
        y_offset: usize,
        first: usize,
        vertices: &[[f32; 3]],
        batch: &mut Batch,
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
        // `x - 1 < limit_x` (wrapping) is `1 <= x && x + reach_x < nx`.
        let (reach_x, reach_y) = match AXIS {
            0 => (2, 1),
            1 => (1, 2),
            _ => (1, 1),
        };
        let walk = Walk {
            limit_x: nx.saturating_sub(reach_x + 1),
            // The lower end's x: at most the last cell's along x, the last
            // sample's otherwise.
            last_x: (nx - 1 - usize::from(AXIS == 0)) as f64,
            lift: if AXIS == 0 { 0.0 } else { 0.5 },
            layer: self.layer as f64,
            nx,
        };
        // The central differences' factors (a half, or what a difference
        // across planes takes at the lower and upper end), with the grid's
        // scale folded in when the map has one per axis.
        let scale = self.map.scale();
        let [f0, f1] = self.fz.map(|f| f * scale[2]);
        let (fa, fb) = match (AXIS, self.k) {
            (2, _) => (f0, f1),
            (_, 0) => (f0, f0),
            _ => (f1, f1),
        };
        let factors = Factors {
            x: 0.5 * scale[0],
            y: 0.5 * scale[1],
            z_low: fa,
            z_high: fb,
        };
        let minus = |a: P::Run, b: P::Run, i: usize, j: usize| P::minus(P::at(a, i), P::at(b, j));
        // Row `y` of plane `p`: every row of one length, `nx`.
        let cut = |p: P, y: usize| p.sub(y * nx, y * nx + nx);
        // The central differences (not yet divided) at sample `x` of row
        // `mid`, between rows `down` and `up`, and planes `under` and `over`.
        let central = |mid, down, up, under, over, x: usize| {
            [
                minus(mid, mid, x + 1, x - 1),
                minus(up, down, x, x),
                minus(over, under, x, x),
            ]
        };
        let end = first + vertices.len();
        // Slots of `batch` taken.
        let mut n = 0;
        for (r, &start) in rows.iter().enumerate() {
            let stop = rows.get(r + 1).map_or(end, |&s| s as usize);
            let (start, stop) = ((start as usize).max(first), stop.min(end));
            if start >= stop {
                continue;
            }
            let y = r + y_offset;
            let row = &vertices[start - first..stop - first];
            let mut fill = |gather: &dyn Fn(usize) -> ([f64; 3], [f64; 3]), inner: bool| {
                self.row::<AXIS>(&walk, row, y, inner, gather, batch, &mut n, factors, out)
            };
            if y.wrapping_sub(1) >= ny.saturating_sub(reach_y + 1) {
                // Every edge of the row has an end on the plane's border.
                fill(&|_| ([0.0; 3], [0.0; 3]), false);
                continue;
            }
            match AXIS {
                0 => {
                    let [down, mid, up] = [y - 1, y, y + 1].map(|y| cut(here, y));
                    let (over, under) = (cut(above, y), cut(below, y));
                    let ends = |x| central(mid, down, up, under, over, x);
                    fill(&|x| (ends(x), ends(x + 1)), true);
                }
                1 => {
                    let [down, low, high, up] = [y - 1, y, y + 1, y + 2].map(|y| cut(here, y));
                    let [over_low, over_high] = [y, y + 1].map(|y| cut(above, y));
                    let [under_low, under_high] = [y, y + 1].map(|y| cut(below, y));
                    let a = |x| central(low, down, high, under_low, over_low, x);
                    fill(
                        &|x| (a(x), central(high, low, up, under_high, over_high, x)),
                        true,
                    );
                }
                _ => {
                    let [down1, mid1, up1] = [y - 1, y, y + 1].map(|y| cut(p1, y));
                    let [down2, mid2, up2] = [y - 1, y, y + 1].map(|y| cut(p2, y));
                    let (under, over) = (cut(p0, y), cut(p3, y));
                    let a = |x| central(mid1, down1, up1, under, mid2, x);
                    fill(&|x| (a(x), central(mid2, down2, up2, mid1, over, x)), true);
                }
            }
        }
        self.finish::<AXIS>(batch, n, factors, out);
    }

    /// Gathers the vertices `row` (of grid row `y`) into `batch`, whose
    /// first `n` slots are taken, finishing it whenever it is full: the
    /// differences at the two ends of a vertex's edge from `gather` (given
    /// the lower end's x) when `inner` (the row's edges are not on the
    /// plane's border along y) and the edge is inside it along x, else
    /// the normal from [`on_border`](Self::on_border).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn row<const AXIS: usize>(
        &self,
        walk: &Walk,
        row: &[[f32; 3]],
        y: usize,
        inner: bool,
        gather: &dyn Fn(usize) -> ([f64; 3], [f64; 3]),
        batch: &mut Batch,
        n: &mut usize,
        factors: Factors,
        out: &mut Vec<[f32; 3]>,
    ) {
        let map = self.map;
        for &v in row {
            if *n == BATCH {
                self.finish::<AXIS>(batch, BATCH, factors, out);
                *n = 0;
            }
            let j = *n;
            *n += 1;
            // The floor (or, `+ 0.5`, the nearest) of the x coordinate
            // clamped to `[0, last_x]`, NaN to 0: `max` with 0 (which
            // takes 0 for NaN) and `min`, one instruction each, and one
            // truncation through `i64` (a single instruction, where a
            // saturating cast to `usize` takes a dozen; comparisons and
            // branches took a dozen too).
            let px = map.coordinate(v, 0);
            let x = (px + walk.lift).max(0.0).min(walk.last_x) as i64 as usize;
            let w = match AXIS {
                0 => px - x as f64,
                1 => map.coordinate(v, 1) - y as f64,
                _ => map.coordinate(v, 2) - walk.layer,
            };
            batch.at[j] = y * walk.nx + x;
            if !(inner && x.wrapping_sub(1) < walk.limit_x && (SNAP..=1.0 - SNAP).contains(&w)) {
                batch.offset[j] = f64::NAN;
                batch.border[j] = w;
                continue;
            }
            let (a, b) = gather(x);
            for axis in 0..3 {
                batch.low[axis][j] = a[axis];
                batch.high[axis][j] = b[axis];
            }
            batch.offset[j] = w;
        }
    }

    /// Appends to `out` the normals of the first `n` slots of `batch`
    /// (edges along `AXIS`, differences multiplied by `factors`): from
    /// [`Batch::normalize`] where the gradient is of ordinary size, else
    /// from [`exact`](Self::exact).
    #[inline(always)]
    fn finish<const AXIS: usize>(
        &self,
        batch: &mut Batch,
        n: usize,
        factors: Factors,
        out: &mut Vec<[f32; 3]>,
    ) {
        batch.normalize(factors, self.map, self.sign);
        let n = n.min(BATCH);
        let ordinary = |s: f64| s > 1e-200 && s < 1e200;
        // One test for the batch (in vector registers), then the slots.
        if batch.squared[..n]
            .iter()
            .fold(false, |odd, &s| odd | !ordinary(s))
        {
            for j in 0..n {
                if !ordinary(batch.squared[j]) {
                    batch.normal[j] = self.exact(AXIS, batch, j, factors);
                }
            }
        }
        out.extend_from_slice(&batch.normal[..n]);
    }

    /// The normal of slot `j` of `batch` (edges along `axis`) whose
    /// gradient is not of ordinary size: [`on_border`](Self::on_border)
    /// for an edge on a plane's border or a NaN gradient, else what
    /// [`outward`] gives.
    #[cold]
    #[inline(never)]
    fn exact(&self, axis: usize, batch: &Batch, j: usize, factors: Factors) -> [f32; 3] {
        let (i, nx) = (batch.at[j], self.field.nx);
        let w = batch.offset[j];
        if w.is_nan() {
            return self.on_border(axis, [i % nx, i / nx], batch.border[j]);
        }
        let g = batch.gradient(j, factors);
        if P::MAY_BE_NAN && (g[0] + g[1] + g[2]).is_nan() {
            return self.on_border(axis, [i % nx, i / nx], w);
        }
        outward(self.map.to_world(g), self.sign)
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
