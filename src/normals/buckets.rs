//! Vertices located in the grid and sorted by cell layer, so that a walk
//! over the layers finds each layer's vertices together.

use crate::error::try_filled;
use crate::grid::{Grid, WorldToIndex};
use crate::Result;

/// How close to a cell's face an offset is taken as on it: offsets within
/// this of 0 or 1 are snapped to exactly that.
///
/// Marching cubes puts its vertices on grid edges, but they reach the
/// normals as `f32` world coordinates, so the two offsets that should be 0
/// or 1 come back off by the rounding of the coordinates (relative `6e-8`
/// of them, about `2e-5` of a cell at index 256 with unit spacing). Snapped,
/// an edge vertex weighs only the edge's two ends (see
/// [`Layer::gradient`](super::gradient::Layer::gradient)); the normal moves
/// by at most about this fraction of the difference between neighbouring
/// samples' gradients, well below what the interpolation itself is off by.
pub const SNAP: f64 = 1e-4;

/// Where a world position falls in the grid: the cell (lowest corner, each
/// index clamped to `0..=dims - 2`) and the position inside it (each
/// coordinate in `[0, 1]`).
///
/// Invariant: a grid with fewer than two samples along an axis is never
/// located in (the caller refuses it), so `dims - 2` does not underflow.
#[derive(Debug, Clone, Copy)]
pub struct Locator {
    /// The grid's world-to-index map.
    map: WorldToIndex,
    /// The grid's sample counts.
    dims: [usize; 3],
    /// The last index along each axis, `dims - 1`, as `f64`.
    last: [f64; 3],
}

impl Locator {
    /// A locator for `grid` (at least two samples along every axis).
    pub fn new(grid: &Grid) -> Self {
        Locator {
            map: grid.world_to_index(),
            dims: grid.dims,
            last: grid.dims.map(|d| (d - 1) as f64),
        }
    }

    /// The cell holding `world` and the position in it, each offset within
    /// [`SNAP`] of 0 or 1 made exactly that. A position outside the grid
    /// (rounding of `f32` vertices, or a vertex that is not of this grid)
    /// is clamped onto it; a non-finite one goes to index 0. Small rounding
    /// does not matter: the interpolated gradient is continuous across
    /// cells.
    #[inline(always)]
    pub fn locate(&self, world: [f32; 3]) -> ([usize; 3], [f64; 3]) {
        let index = self.map.index([
            f64::from(world[0]),
            f64::from(world[1]),
            f64::from(world[2]),
        ]);
        let snap = |offset: f64| {
            if offset < SNAP {
                0.0
            } else if offset > 1.0 - SNAP {
                1.0
            } else {
                offset
            }
        };
        let (x, tx) = self.axis(0, index[0]);
        let (y, ty) = self.axis(1, index[1]);
        let (z, tz) = self.axis(2, index[2]);
        ([x, y, z], [snap(tx), snap(ty), snap(tz)])
    }

    /// The cell layer holding `world`: `locate(world).0[2]`, for a third of
    /// the work.
    #[inline(always)]
    pub fn layer(&self, world: [f32; 3]) -> usize {
        let world = [
            f64::from(world[0]),
            f64::from(world[1]),
            f64::from(world[2]),
        ];
        self.axis(2, self.map.index(world)[2]).0
    }

    /// The cell along axis `a` holding `index` (clamped into the grid, 0 if
    /// not finite) and the offset in it, in `[0, 1]`.
    #[inline(always)]
    fn axis(&self, a: usize, index: f64) -> (usize, f64) {
        // Comparisons, cheaper than `f64::max` and `min` (which must look
        // for NaN): NaN and infinities fail the first test, as they should.
        let last = self.last[a];
        let p = if index >= 0.0 && index <= last {
            index
        } else if index > last && index.is_finite() {
            last
        } else {
            0.0
        };
        // `p` is in [0, dims - 1]: the cast truncates, which is the floor
        // for a value that is not negative (and much cheaper than
        // `f64::floor` without SSE4.1); through `i64`, whose conversions
        // are single instructions, unlike those of `usize`.
        let cell = (p as i64 as usize).min(self.dims[a] - 2);
        (cell, p - cell as i64 as f64)
    }
}

/// Vertex numbers sorted by cell layer (stable: in mesh order within a
/// layer), with where each layer's vertices start.
///
/// Invariant: `starts.len() == layers + 1`, `starts` is non-decreasing,
/// `starts[layers] == order.len()`, and the vertices of layer `z` are
/// `order[starts[z]..starts[z + 1]]`.
#[derive(Debug)]
pub struct Buckets {
    /// Vertex numbers, layer by layer.
    pub order: Vec<u32>,
    /// Start of each layer in `order`, and its end.
    pub starts: Vec<usize>,
}

impl Buckets {
    /// Sorts `vertices` (at most `u32::MAX` of them: triangles number them
    /// with `u32`) by the cell layer `locator` puts them in; a counting
    /// sort, two passes, one count per layer and two `u32` per vertex (the
    /// layers found in the first pass, so that the second does not locate
    /// again, and the order).
    pub fn new(locator: &Locator, vertices: &[[f32; 3]]) -> Result<Self> {
        let layers = locator.dims[2] - 1;
        let mut starts = try_filled("the vertices per layer", layers + 1, 0usize)?;
        let mut layer_of = try_filled("the vertices' layers", vertices.len(), 0u32)?;
        for (layer, &v) in layer_of.iter_mut().zip(vertices) {
            let z = locator.layer(v);
            starts[z + 1] += 1;
            // `u32::MAX` (a layer `u32` cannot hold): locate again below.
            *layer = u32::try_from(z).unwrap_or(u32::MAX);
        }
        for z in 0..layers {
            starts[z + 1] += starts[z];
        }
        let mut next = starts.clone();
        let mut order = try_filled("the vertices sorted by layer", vertices.len(), 0u32)?;
        for (i, (&layer, &v)) in layer_of.iter().zip(vertices).enumerate() {
            let z = match layer {
                u32::MAX => locator.layer(v),
                z => z as usize,
            };
            order[next[z]] = i as u32;
            next[z] += 1;
        }
        Ok(Buckets { order, starts })
    }
}
