//! [`Locator`]: where a vertex falls in the grid, from its position.

use crate::grid::{Grid, WorldToIndex};

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

    /// The cell (its x and y; the layer is `layer`) holding `world` and
    /// the position in it, each offset within [`SNAP`] of 0 or 1 made
    /// exactly that (a position outside the grid clamped onto it, a
    /// non-finite one to index 0). The z offset is taken from that layer's lower plane, clamped into `[0, 1]`
    /// and snapped as the others. For the vertices of a chunk, which lie in
    /// a known layer: one that rounding of its `f32` coordinates put a hair
    /// into the layer below or above is taken back onto the layer's plane,
    /// not moved into the neighbouring layer's planes.
    #[inline(always)]
    pub fn locate_in_layer(&self, world: [f32; 3], layer: usize) -> ([usize; 2], [f64; 3]) {
        let index = self.map.index([
            f64::from(world[0]),
            f64::from(world[1]),
            f64::from(world[2]),
        ]);
        let (x, tx) = self.axis(0, index[0]);
        let (y, ty) = self.axis(1, index[1]);
        let tz = index[2] - layer as f64;
        // NaN fails both tests and goes to the lower plane.
        let tz = if tz >= SNAP {
            if tz > 1.0 - SNAP {
                1.0
            } else {
                tz
            }
        } else {
            0.0
        };
        ([x, y], [snap(tx), snap(ty), tz])
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

/// `offset` (in `[0, 1]`) within [`SNAP`] of 0 or 1 made exactly that.
#[inline(always)]
fn snap(offset: f64) -> f64 {
    if offset < SNAP {
        0.0
    } else if offset > 1.0 - SNAP {
        1.0
    } else {
        offset
    }
}
