//! [`EdgeVertex`] and `EdgeNormals`: the normals of vertices whose grid
//! edge the slab loop names as it places them, so that nothing has to
//! find the edge again from the vertex's `f32` position.
//!
//! Locating a vertex from its position (rounding its three index
//! coordinates, testing which two lie on grid lines, checking the bounds)
//! cost more than its gradient did, and so did walking a block's rows
//! again to learn each vertex's row. The slab loop knows the edge of every
//! vertex it places on one; as it places it, it notes the edge's lower
//! end and the vertex's offset along the edge read back from the `f32`
//! position (the index coordinate less the end's), which is what an
//! interpolation from the position gives ([`Layer::gradient`] at that
//! offset), so a vertex gets the same normal whether its edge is named or
//! located.

use super::batch::{Batch, Factors, BATCH};
use super::gradient::Layer;
use super::index_map::IndexMap;
use super::locate::SNAP;
use super::samples::Samples;
use super::vector::unit;
use super::PENDING;
use crate::grid::WorldToIndex;

/// A vertex on a grid edge as the slab loop places it: the edge's lower
/// end (sample `x` of row `y` of its plane, in the whole grid's numbering)
/// and the vertex's offset from it along the edge, as its `f32` position
/// gives it back ([`IndexCoordinates::offset`](super::IndexCoordinates::offset)).
/// The plane and the edge direction are those of the group the vertex is
/// handed over in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeVertex {
    /// The lower end's sample along the row.
    pub x: usize,
    /// The lower end's row.
    pub y: usize,
    /// The offset along the edge from the lower end.
    pub offset: f64,
}

/// What the normals of one group of edge vertices are computed from.
pub(super) struct EdgeNormals<'f, P, M> {
    /// The four planes around the vertices' cell layer.
    pub(super) field: &'f Layer<P>,
    /// What a difference across planes is multiplied by at the layer's
    /// lower and upper plane.
    pub(super) fz: [f64; 2],
    /// Where the x- and y-edges lie: the layer's lower (0) or upper (1)
    /// plane.
    pub(super) k: usize,
    /// Gradients to world coordinates.
    pub(super) map: M,
    /// The full map, for the gradients of edges on a plane's border.
    pub(super) full: &'f WorldToIndex,
    /// 1, or -1 where outward is down the gradient.
    pub(super) sign: f64,
}

impl<P: Samples, M: IndexMap> EdgeNormals<'_, P, M> {
    /// Appends to `out` the normals of `vertices`, on edges along axis
    /// `AXIS`: the two ends' central differences interpolated at the
    /// vertex's offset along the edge, the chain rule, normalized;
    /// [`PENDING`] where that vanishes.
    ///
    /// One loop per axis, the planes and factors in locals, no look at
    /// rows: an edge whose ends are inside their plane's border and whose
    /// offset is not within [`SNAP`] of an end (the common case) costs the
    /// samples it reads, a few runs of neighbours each with one bounds
    /// check; any other goes to [`on_border`](Self::on_border). The
    /// differences are gathered into a [`Batch`], whose arithmetic runs
    /// [`BATCH`] vertices at a time ([`finish`](Self::finish)).
    #[inline(always)]
    pub(super) fn along<const AXIS: usize>(
        &self,
        vertices: &[EdgeVertex],
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
        // `x - 1 < limit_x` (wrapping) is `1 <= x && x + reach_x < nx`,
        // and so for y.
        let (reach_x, reach_y) = match AXIS {
            0 => (2, 1),
            1 => (1, 2),
            _ => (1, 1),
        };
        let (limit_x, limit_y) = (
            nx.saturating_sub(reach_x + 1),
            ny.saturating_sub(reach_y + 1),
        );
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
        // Row `y` of plane `p`: every row of one length, `nx`, so that the
        // reads at one `x` share their bounds checks.
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
        // The rows of samples the vertices of row `y` read (its edges not
        // on the plane's border along y), cut when `y` changes.
        let rows_of = |y: usize| -> [P::Run; 8] {
            match AXIS {
                0 => {
                    let [down, mid, up] = [y - 1, y, y + 1].map(|y| cut(here, y));
                    [down, mid, up, cut(below, y), cut(above, y), mid, mid, mid]
                }
                1 => {
                    let [down, low, high, up] = [y - 1, y, y + 1, y + 2].map(|y| cut(here, y));
                    let [under_low, under_high] = [y, y + 1].map(|y| cut(below, y));
                    let [over_low, over_high] = [y, y + 1].map(|y| cut(above, y));
                    [
                        down, low, high, up, under_low, under_high, over_low, over_high,
                    ]
                }
                _ => {
                    let [down1, mid1, up1] = [y - 1, y, y + 1].map(|y| cut(p1, y));
                    let [down2, mid2, up2] = [y - 1, y, y + 1].map(|y| cut(p2, y));
                    [down1, mid1, up1, down2, mid2, up2, cut(p0, y), cut(p3, y)]
                }
            }
        };
        // The differences at the two ends of the edge from sample `x` of
        // the rows `r`.
        let gather = |r: &[P::Run; 8], x: usize| -> ([f64; 3], [f64; 3]) {
            match AXIS {
                0 => {
                    let ends = |x| central(r[1], r[0], r[2], r[3], r[4], x);
                    (ends(x), ends(x + 1))
                }
                1 => (
                    central(r[1], r[0], r[2], r[4], r[6], x),
                    central(r[2], r[1], r[3], r[5], r[7], x),
                ),
                _ => (
                    central(r[1], r[0], r[2], r[6], r[4], x),
                    central(r[4], r[3], r[5], r[1], r[7], x),
                ),
            }
        };
        let mut batch = Batch::new();
        let mut rows = [cut(here, 0); 8];
        // The row `rows` were cut for (none yet).
        let mut cut_for = usize::MAX;
        for group in vertices.chunks(BATCH) {
            for (j, e) in group.iter().enumerate() {
                let (x, y, w) = (e.x, e.y, e.offset);
                batch.at[j] = y * nx + x;
                if !(x.wrapping_sub(1) < limit_x
                    && y.wrapping_sub(1) < limit_y
                    && (SNAP..=1.0 - SNAP).contains(&w))
                {
                    batch.offset[j] = f64::NAN;
                    batch.border[j] = w;
                    continue;
                }
                if y != cut_for {
                    rows = rows_of(y);
                    cut_for = y;
                }
                let (a, b) = gather(&rows, x);
                for axis in 0..3 {
                    batch.low[axis][j] = a[axis];
                    batch.high[axis][j] = b[axis];
                }
                batch.offset[j] = w;
            }
            self.finish::<AXIS>(&mut batch, group.len(), factors, out);
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
