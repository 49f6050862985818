//! [`Placement`]: where a vertex goes, from its fractional grid index to
//! world coordinates in `f32`; on an edge that ends at a tie, away from the
//! tie (see [`kernel::ties`](crate::kernel::ties)).

use crate::grid::{Grid, IDENTITY};
use crate::kernel::ties::TIE_OFFSET;

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

    /// The world position of the vertex on the crossed edge from grid index
    /// `start` along `axis`, whose values are `a` at `start` and `b` at the
    /// other end: the linear crossing, or [`Placement::tie_vertex`] when
    /// either end is a tie.
    #[inline]
    pub(super) fn edge(&self, mut start: [f64; 3], axis: usize, a: f64, b: f64) -> [f32; 3] {
        if a == 0.0 || b == 0.0 {
            return self.tie_vertex(start, axis, a == 0.0);
        }
        start[axis] += a / (a - b);
        self.at(start)
    }

    /// The vertex on an edge that ends at a tie (at `start` if `at_start`,
    /// else at the other end): [`TIE_OFFSET`] of the edge away from the
    /// tie, or the first of twice, four times ... that offset (up to half
    /// the edge) whose `f32` position is not the tie sample's own, so that
    /// the vertices round the tie stay apart where `f32` cannot resolve the
    /// offset (coordinates beyond about `2^13` spacings). A function of the
    /// edge alone: every slab and part places it alike.
    #[cold]
    #[inline(never)]
    fn tie_vertex(&self, start: [f64; 3], axis: usize, at_start: bool) -> [f32; 3] {
        let mut tie = start;
        if !at_start {
            tie[axis] += 1.0;
        }
        let sample = self.at(tie);
        let mut offset = TIE_OFFSET;
        loop {
            let mut p = start;
            p[axis] += if at_start { offset } else { 1.0 - offset };
            let position = self.at(p);
            if position != sample || offset >= 0.5 {
                return position;
            }
            offset *= 2.0;
        }
    }
}
