//! Vertices located in the grid and sorted by cell layer, so that a walk
//! over the layers finds each layer's vertices together.

use crate::error::try_filled;
use crate::grid::{Grid, WorldToIndex};
use crate::Result;

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
}

impl Locator {
    /// A locator for `grid` (at least two samples along every axis).
    pub fn new(grid: &Grid) -> Self {
        Locator {
            map: grid.world_to_index(),
            dims: grid.dims,
        }
    }

    /// The cell holding `world` and the position in it. A position outside
    /// the grid (rounding of `f32` vertices, or a vertex that is not of
    /// this grid) is clamped onto it; a non-finite one goes to index 0.
    /// Small rounding does not matter: the interpolated gradient is
    /// continuous across cells.
    pub fn locate(&self, world: [f32; 3]) -> ([usize; 3], [f64; 3]) {
        let index = self.map.index(world.map(f64::from));
        let mut cell = [0; 3];
        let mut t = [0.0; 3];
        for a in 0..3 {
            let last = (self.dims[a] - 1) as f64;
            let p = if index[a].is_finite() {
                index[a].clamp(0.0, last)
            } else {
                0.0
            };
            // `p` is in [0, dims - 1]: the cast truncates, which is the
            // floor for a value that is not negative (and much cheaper
            // than `f64::floor` without SSE4.1).
            cell[a] = (p as usize).min(self.dims[a] - 2);
            t[a] = p - cell[a] as f64;
        }
        (cell, t)
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
    /// sort, two passes, one `u32` per vertex and one count per layer.
    pub fn new(locator: &Locator, vertices: &[[f32; 3]]) -> Result<Self> {
        let layers = locator.dims[2] - 1;
        let mut starts = try_filled("the vertices per layer", layers + 1, 0usize)?;
        for &v in vertices {
            starts[locator.locate(v).0[2] + 1] += 1;
        }
        for z in 0..layers {
            starts[z + 1] += starts[z];
        }
        let mut next = starts.clone();
        let mut order = try_filled("the vertices sorted by layer", vertices.len(), 0u32)?;
        for (i, &v) in vertices.iter().enumerate() {
            let z = locator.locate(v).0[2];
            order[next[z]] = i as u32;
            next[z] += 1;
        }
        Ok(Buckets { order, starts })
    }
}
