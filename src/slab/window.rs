//! [`Window`]: a rectangle of a grid's planes that a slab is triangulated
//! in, the rest of the planes known to hold no surface.

use crate::grid::Grid;

/// A rectangle of a grid's planes that a slab is triangulated in: the
/// source handed to [`process_window`](super::process_window) holds the samples from `offset`
/// on, its grid has the window's x and y sizes and the whole grid's
/// origin, spacing, directions and z size.
///
/// The chunks are those of the whole grid when every crossed edge and
/// every cell with a corner inside lies in the window (a window that holds
/// every inside sample of the slab's planes and one sample more on each
/// side, clipped to the grid): vertices and triangles come in the same
/// raster order, and vertices are placed from the whole grid's indices.
#[derive(Debug, Clone, Copy)]
pub struct Window {
    /// The whole grid.
    pub full: Grid,
    /// The whole grid's x and y index of the window's sample (0, 0).
    pub offset: [usize; 2],
}
