//! [`Placement`]: where a vertex goes, from its fractional grid index to
//! world coordinates in `f32`.

use crate::grid::{Grid, IDENTITY};

/// The grid's index-to-world map, rounded to f32, with a shortcut for the
/// usual axis-aligned grid (bit for bit the same result: the zero terms of
/// an identity direction add nothing).
#[derive(Clone, Copy)]
pub(super) struct Placement {
    pub(super) grid: Grid,
    pub(super) axis_aligned: bool,
}

impl Placement {
    pub(super) fn new(grid: &Grid) -> Self {
        Placement {
            grid: *grid,
            axis_aligned: grid.direction == IDENTITY,
        }
    }

    /// The world position of a (fractional) grid index.
    #[inline]
    pub(super) fn at(&self, index: [f64; 3]) -> [f32; 3] {
        let g = &self.grid;
        if self.axis_aligned {
            std::array::from_fn(|i| (g.origin[i] + index[i] * g.spacing[i]) as f32)
        } else {
            g.world(index).map(|c| c as f32)
        }
    }
}
