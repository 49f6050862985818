//! [`Placement`]: where a vertex goes, from its fractional grid index to
//! world coordinates in `f32`; on an edge that ends at a tie, away from the
//! tie (see [`kernel::ties`](crate::kernel::ties)).

use super::window::Window;
use crate::grid::{Grid, IDENTITY};
use crate::kernel::ties::TIE_OFFSET;

/// The grid's index-to-world map, rounded to f32, with a shortcut for the
/// usual axis-aligned grid (bit for bit the same result: the zero terms of
/// an identity direction add nothing).
#[derive(Clone, Copy)]
pub(super) struct Placement {
    pub(super) grid: Grid,
    pub(super) axis_aligned: bool,
    /// `f32` tells a vertex [`TIE_OFFSET`] of an edge from the edge's end
    /// everywhere in the grid (see [`resolves_offset`]); when not, a
    /// tie's vertex is placed by [`Placement::far_tie_fraction`].
    pub(super) resolves_ties: bool,
    /// How far an interior vertex that ties would put on or near its
    /// cell's boundary keeps from it ([`CellMesh::tie_margin`](crate::kernel::CellMesh::tie_margin)):
    /// [`TIE_OFFSET`] where that resolves, else [`interior_tie_margin`].
    pub(super) interior_margin: f64,
    /// A crossing closer than this to an end of its edge (a fraction of
    /// the edge) may round onto the end sample in `f32` and is checked
    /// ([`Placement::near_end_fraction`]): [`TIE_OFFSET`] where `f32`
    /// resolves it everywhere in the grid, else `0.5` (every crossing).
    pub(super) near: f64,
    /// The x and y grid index of the slab's sample (0, 0) (not zero only
    /// when the slab is a [`Window`] of the grid), added to
    /// every index before it is placed, so that a window places its
    /// vertices bit for bit where the whole grid does. An integer, added
    /// before the index turns into `f64` (one integer add in the vertex
    /// loops, folded into their address arithmetic, where an `f64` offset
    /// cost a float add per coordinate).
    pub(super) offset: [usize; 2],
}

impl Placement {
    pub(super) fn new(grid: &Grid) -> Self {
        Placement {
            grid: *grid,
            axis_aligned: grid.direction == IDENTITY,
            resolves_ties: resolves_offset(grid, TIE_OFFSET),
            near: near_end(resolves_offset(grid, TIE_OFFSET)),
            interior_margin: interior_tie_margin(grid),
            offset: [0; 2],
        }
    }

    /// The placement of a window of `window.full` whose own grid (its
    /// dims, the whole grid's origin, spacing and directions) is `grid`:
    /// ties are resolved (and interior tie vertices keep their margin) as in
    /// the whole grid.
    pub(super) fn windowed(grid: &Grid, window: &Window) -> Self {
        Placement {
            grid: *grid,
            axis_aligned: grid.direction == IDENTITY,
            resolves_ties: resolves_offset(&window.full, TIE_OFFSET),
            near: near_end(resolves_offset(&window.full, TIE_OFFSET)),
            interior_margin: interior_tie_margin(&window.full),
            offset: window.offset,
        }
    }

    /// The grid index of the slab's sample `(x, y)` on plane `z`, as the
    /// whole grid numbers it.
    #[inline(always)]
    pub(super) fn index(&self, x: usize, y: usize, z: usize) -> [f64; 3] {
        [
            exact_f64(x + self.offset[0]),
            exact_f64(y + self.offset[1]),
            exact_f64(z),
        ]
    }

    /// The world position of a (fractional) grid index.
    #[inline]
    pub(super) fn at(&self, index: [f64; 3]) -> [f32; 3] {
        if self.axis_aligned {
            self.at_in::<true>(index)
        } else {
            self.at_in::<false>(index)
        }
    }

    /// [`Placement::at`] where `ALIGNED` is [`Placement::axis_aligned`]:
    /// the vertex loops test it once per plane, not once per vertex.
    #[inline(always)]
    fn at_in<const ALIGNED: bool>(&self, index: [f64; 3]) -> [f32; 3] {
        debug_assert_eq!(ALIGNED, self.axis_aligned);
        let g = &self.grid;
        if ALIGNED {
            std::array::from_fn(|i| (g.origin[i] + index[i] * g.spacing[i]) as f32)
        } else {
            g.world(index).map(|c| c as f32)
        }
    }

    /// The world position of the vertex on the crossed edge from grid index
    /// `start` along `axis`, whose values are `a` at `start` and `b` at the
    /// other end: `start` moved along `axis` by [`Placement::crossing`].
    #[cfg(test)]
    fn edge(&self, start: [f64; 3], axis: usize, a: f64, b: f64) -> [f32; 3] {
        if self.axis_aligned {
            self.edge_in::<true>(start, axis, a, b)
        } else {
            self.edge_in::<false>(start, axis, a, b)
        }
    }

    /// The world position of the vertex on the crossed edge from grid index
    /// `start` along `axis`, whose values are `a` at `start` and `b` at the
    /// other end: `start` moved along `axis` by [`Placement::crossing`].
    /// `ALIGNED` is [`Placement::axis_aligned`], which the vertex loops
    /// test once per plane (each loop is compiled for both).
    #[inline(always)]
    pub(super) fn edge_in<const ALIGNED: bool>(
        &self,
        mut start: [f64; 3],
        axis: usize,
        a: f64,
        b: f64,
    ) -> [f32; 3] {
        start[axis] += self.crossing(start, axis, a, b);
        self.at_in::<ALIGNED>(start)
    }

    /// Where the vertex of the crossed edge from `start` along `axis`
    /// (values `a` and `b` at its ends) lies, as a fraction of the edge from
    /// `start`: the linear crossing `a / (a - b)`, or, when either end is a
    /// tie, [`TIE_OFFSET`] of the edge away from it (in a grid whose `f32`
    /// coordinates may not resolve that, [`Placement::far_tie_fraction`]).
    /// One test in the loop, `a b = 0` (a product that underflows, neither
    /// value 0, comes back to the plain crossing). The tie's offset is a
    /// select, not a call: tie vertices are common on integer data (a
    /// quarter of bonsai's at 40), and a fraction, not a position, leaves
    /// the vertex loops the one `at` they had before ties.
    #[inline(always)]
    fn crossing(&self, start: [f64; 3], axis: usize, a: f64, b: f64) -> f64 {
        if a * b == 0.0 && (a == 0.0 || b == 0.0) {
            if !self.resolves_ties {
                return self.far_tie_fraction(start[0], start[1], start[2], axis, a == 0.0);
            }
            if a == 0.0 {
                TIE_OFFSET
            } else {
                1.0 - TIE_OFFSET
            }
        } else {
            let t = a / (a - b);
            // Within `near` of an end the crossing may round onto the end
            // sample (a negated range test: a NaN takes the branch too).
            if !(t >= self.near && t <= 1.0 - self.near) {
                return self.near_end_fraction(start[0], start[1], start[2], axis, t);
            }
            t
        }
    }

    /// The crossing `t` of the edge from `(x, y, z)` along `axis`, unless
    /// its `f32` position is that of the edge's end sample nearer to `t`:
    /// then the fraction a tie at that sample would give ([`TIE_OFFSET`] of
    /// the edge from it, or further where `f32` needs it:
    /// [`Placement::far_tie_fraction`]). A crossing very near a sample (a
    /// value within about 2^-14 of the edge's difference from the
    /// isovalue, near the origin; less far from it) rounds onto the
    /// sample, where the crossings of the sample's other edges may round
    /// too, and the triangles between them would have no area. Only those
    /// vertices move, so every other vertex keeps its bytes; the move is a
    /// function of the edge alone, like a tie's. (Scalars, as in
    /// [`Placement::far_tie_fraction`], and cold: the vertex loops keep
    /// their registers.)
    #[cold]
    #[inline(never)]
    fn near_end_fraction(&self, x: f64, y: f64, z: f64, axis: usize, t: f64) -> f64 {
        let start = [x, y, z];
        let at_start = t <= 0.5 || t.is_nan();
        let mut end = start;
        if !at_start {
            end[axis] += 1.0;
        }
        let mut p = start;
        p[axis] += t;
        if self.at(p) != self.at(end) {
            return t;
        }
        if self.resolves_ties {
            if at_start {
                TIE_OFFSET
            } else {
                1.0 - TIE_OFFSET
            }
        } else {
            self.far_tie_fraction(x, y, z, axis, at_start)
        }
    }

    /// [`Placement::crossing`] of an edge from `(x, y, z)` along `axis` that
    /// ends at a tie (at its start when `at_start`, else at its other end)
    /// in a grid whose `f32` coordinates may not resolve [`TIE_OFFSET`]
    /// ([`resolves_offset`]): the first of that offset, twice, four
    /// times ... it (up to half the edge) whose `f32` position is not the
    /// tie sample's own, so that the vertices round the tie stay apart. A
    /// function of the edge alone: every slab and part places it alike.
    /// (Coordinates as scalars, not an array: the call stays out of the
    /// vertex loops' registers.)
    #[cold]
    #[inline(never)]
    fn far_tie_fraction(&self, x: f64, y: f64, z: f64, axis: usize, at_start: bool) -> f64 {
        let start = [x, y, z];
        let fraction = |offset: f64| if at_start { offset } else { 1.0 - offset };
        let mut tie = start;
        if !at_start {
            tie[axis] += 1.0;
        }
        let sample = self.at(tie);
        let mut offset = TIE_OFFSET;
        loop {
            let mut p = start;
            p[axis] += fraction(offset);
            if self.at(p) != sample || offset >= 0.5 {
                return fraction(offset);
            }
            offset *= 2.0;
        }
    }
}

/// [`Placement::near`] of a grid that resolves [`TIE_OFFSET`] or not.
fn near_end(resolves_ties: bool) -> f64 {
    if resolves_ties {
        TIE_OFFSET
    } else {
        0.5
    }
}

/// A grid index as `f64`, the same value as `i as f64`: through `i64`,
/// which x86-64 converts in one instruction where `usize` takes six (an
/// index is below `isize::MAX`, so the conversion is the same rounding of
/// the same integer; exact below 2^53).
#[inline(always)]
fn exact_f64(i: usize) -> f64 {
    i as i64 as f64
}

/// The margin an interior vertex of a tie cell (and, where it is above
/// [`TIE_OFFSET`], of every cell) keeps from the cell's boundary, a
/// fraction of the cell per axis: the first of [`TIE_OFFSET`],
/// twice, four times ... it (up to `1/4`) that `f32` world coordinates
/// resolve everywhere in the grid ([`resolves_offset`]), so that such a
/// vertex is apart from the points of the boundary (edge vertices, grid
/// samples) and from the interior vertex of the cell across, which keeps
/// the same margin on the other side. A function of the grid alone, like
/// [`Placement::far_tie_fraction`], so every slab and part places alike;
/// [`TIE_OFFSET`] on the usual grid (where it changes nothing). Beyond
/// about 2^20 spacings from the origin (an `f32` unit in the last place
/// above a sixteenth of the spacing) even `1/4` is not resolved.
fn interior_tie_margin(grid: &Grid) -> f64 {
    let mut margin = TIE_OFFSET;
    while margin < 0.25 && !resolves_offset(grid, margin) {
        margin *= 2.0;
    }
    margin
}

/// Whether `f32` world coordinates tell apart every point of the grid and
/// the points `offset` of an edge from it: the smallest world step of
/// that offset along an index axis (its largest coordinate, at least a
/// third of the step for unit direction columns) is at least four `f32`
/// units in the last place at the largest world coordinate the grid can
/// reach (`|origin| + Σ dims · spacing`), so that rounding, half a unit at
/// most each, cannot merge them. True for the usual grid (spacing 1,
/// `|origin| + Σ dims` below 2^12); false for NaN or infinite
/// coordinates.
fn resolves_offset(grid: &Grid, offset: f64) -> bool {
    if grid.origin.iter().any(|o| !o.is_finite()) {
        // `f64::max` below would skip a NaN.
        return false;
    }
    let reach: f64 = (0..3)
        .map(|j| grid.dims[j] as f64 * grid.spacing[j].abs())
        .sum();
    let largest = grid.origin.iter().fold(0.0f64, |m, o| m.max(o.abs())) + reach;
    let step = (0..3)
        .map(|j| {
            let column = (0..3).fold(0.0f64, |m, i| m.max(grid.direction[i][j].abs()));
            offset * grid.spacing[j].abs() * column
        })
        .fold(f64::INFINITY, f64::min);
    let top = largest as f32;
    if !top.is_finite() || !step.is_finite() {
        return false;
    }
    let ulp = f64::from(f32::from_bits(top.to_bits() + 1) - top);
    step >= 4.0 * ulp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tie_vertices_keep_off_the_tie_in_f32() {
        // Grids near the origin resolve the offset; far from it, or with a
        // tiny spacing, the vertex moves further, but never onto the tie.
        let mut resolved = 0;
        for (origin, spacing) in [(0.0, 1.0), (1e3, 0.5), (1e6, 1.0), (0.0, 1e-40), (2e4, 1.0)] {
            let grid = Grid {
                dims: [300, 300, 300],
                spacing: [spacing; 3],
                origin: [origin; 3],
                ..Grid::unit([300, 300, 300])
            };
            let place = Placement::new(&grid);
            resolved += usize::from(place.resolves_ties);
            for x in [0usize, 1, 150, 298] {
                let start = [x as f64, 7.0, 9.0];
                let low = place.at(start);
                let high = place.at([x as f64 + 1.0, 7.0, 9.0]);
                let from_low = place.edge(start, 0, 0.0, 5.0);
                let from_high = place.edge(start, 0, 5.0, 0.0);
                assert_ne!(from_low, low, "{origin} {spacing} {x}");
                assert_ne!(from_high, high, "{origin} {spacing} {x}");
                // The first of 2^-10, 2^-9 ... (up to half the edge) of the
                // edge from the tie whose position is not the tie's.
                for (axis, at_start) in [(0, true), (1, false), (2, true), (2, false)] {
                    let end = if at_start { 0.0 } else { 1.0 };
                    let mut tie = start;
                    tie[axis] += end;
                    let sample = place.at(tie);
                    let expect = std::iter::successors(Some(TIE_OFFSET), |o| Some(o * 2.0))
                        .map(|o| {
                            let mut p = start;
                            p[axis] += if at_start { o } else { 1.0 - o };
                            (o, place.at(p))
                        })
                        .find(|&(o, p)| p != sample || o >= 0.5)
                        .map(|(_, p)| p);
                    let (a, b) = if at_start { (0.0, 2.0) } else { (2.0, 0.0) };
                    assert_eq!(Some(place.edge(start, axis, a, b)), expect, "{axis}");
                }
                // Edges without a tie: the plain crossing, also where the
                // product of the two values underflows.
                assert_eq!(
                    place.edge(start, 0, 1.0, -3.0),
                    place.at([x as f64 + 0.25, 7.0, 9.0])
                );
                assert_eq!(
                    place.edge(start, 1, 1e-200, -3e-200),
                    place.at([x as f64, 7.25, 9.0])
                );
            }
        }
        assert_eq!(resolved, 3);
    }

    #[test]
    fn crossings_that_round_onto_a_sample_move_off_it() {
        // A value 2^-40 of the edge's difference above the isovalue puts the
        // crossing within f32's rounding of the sample, near the origin as
        // far from it; such a vertex goes where a tie's would, every other
        // crossing stays where the plain formula puts it.
        for (origin, spacing) in [(0.0, 1.0), (1e3, 0.5), (1e6, 1.0), (0.0, 1e-40)] {
            let grid = Grid {
                dims: [3000, 300, 300],
                spacing: [spacing; 3],
                origin: [origin; 3],
                ..Grid::unit([3000, 300, 300])
            };
            let place = Placement::new(&grid);
            let tiny = 2f64.powi(-40);
            let mut moved = 0;
            for x in [0usize, 1, 1500, 2998] {
                let start = [x as f64, 7.0, 9.0];
                for axis in 0..3 {
                    let mut end = start;
                    end[axis] += 1.0;
                    let (low, high) = (place.at(start), place.at(end));
                    let near_low = place.edge(start, axis, tiny, -1.0);
                    let near_high = place.edge(start, axis, -1.0, tiny);
                    assert_ne!(near_low, low, "{origin} {spacing} {x} {axis}");
                    assert_ne!(near_high, high, "{origin} {spacing} {x} {axis}");
                    // A tie's position (a tie at that end) where the plain
                    // crossing rounds onto the sample, else the plain one.
                    let plain = |t: f64| {
                        let mut p = start;
                        p[axis] += t;
                        place.at(p)
                    };
                    let (t_low, t_high) = (tiny / (tiny + 1.0), -1.0 / (-1.0 - tiny));
                    let expect_low = match plain(t_low) {
                        p if p == low => place.edge(start, axis, 0.0, -1.0),
                        p => p,
                    };
                    let expect_high = match plain(t_high) {
                        p if p == high => place.edge(start, axis, -1.0, 0.0),
                        p => p,
                    };
                    assert_eq!(near_low, expect_low);
                    assert_eq!(near_high, expect_high);
                    moved += usize::from(plain(t_low) == low) + usize::from(plain(t_high) == high);
                    // The plain crossing elsewhere, bit for bit.
                    let mut middle = start;
                    middle[axis] += 0.25;
                    assert_eq!(place.edge(start, axis, 1.0, -3.0), place.at(middle));
                }
            }
            // Most of these crossings round onto their sample: the test
            // sees the move, not only vertices that never needed it.
            assert!(moved >= 12, "{origin} {spacing}: {moved}");
        }
    }

    #[test]
    fn interior_margin_widens_only_where_f32_needs_it() {
        let margin = |origin: f64, spacing: f64| {
            let grid = Grid {
                spacing: [spacing; 3],
                origin: [origin; 3],
                ..Grid::unit([300, 300, 300])
            };
            Placement::new(&grid).interior_margin
        };
        assert_eq!(margin(0.0, 1.0), TIE_OFFSET);
        assert_eq!(margin(1e3, 0.5), TIE_OFFSET);
        // 2^18 + 900: an f32 unit of 2^-5, four of them 1/8 of a spacing.
        assert_eq!(margin(262_144.0, 1.0), 0.125);
        assert_eq!(margin(262_144.0, 2.0), 0.0625);
        // Nothing resolves: a quarter of the cell at most.
        assert_eq!(margin(1e9, 1.0), 0.25);
        assert_eq!(margin(f64::NAN, 1.0), 0.25);
    }
}
