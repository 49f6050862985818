//! The cell kernel: one cell of the grid, triangulated as in Grosso (2016).
//!
//! The kernel is told as the paper's sections:
//! * [`cube`]: names of corners, edges and faces of the reference cell;
//! * [`decider`]: the asymptotic decider on a face (exact sign);
//! * [`contour`]: closed contours from edge intersections and face decisions;
//! * [`tables`]: the standard MC table and the contour table, built once
//!   from [`contour`] for all 256 sign configurations;
//! * [`sweep_pairs`]: which pairs of surface components a tunnel could
//!   join, from the configuration alone (held in the tables);
//! * [`tunnel`]: does the level set join two contours through the cell (a
//!   tunnel)? Decided exactly, ties included;
//! * [`scale`]: a cell's values scaled by a power of two, out of overflow;
//! * [`wide`]: a cell's exact values as wide integers, for the decisions
//!   that must not round;
//! * [`quadratic`]: the three quadratic equations, their roots, the saddle
//!   points and the inner hexagon;
//! * [`triangulate`]: the triangulation rules of Section 5;
//! * [`ties`]: where a vertex goes on an edge that ends at a tie (a
//!   sample equal to the isovalue);
//! * [`cell_mesh`]: what a cell hands back (triangles over edge and
//!   interior vertices);
//! * [`cell`]: puts them together for one ambiguous cell.
//!
//! Values given to the kernel are `g = value - iso` (or `iso - value` for
//! `--inside low`), with NaN already replaced by 0, and, where that
//! subtraction was rounded, its residual; a corner is inside iff `g > 0`,
//! so the kernel always triangulates `{g > ε}` for infinitesimal ε, and
//! decides on the exact differences.

pub mod cell;
pub mod cell_mesh;
pub mod contour;
pub mod cube;
pub mod decider;
pub mod quadratic;
pub mod scale;
pub mod sweep_pairs;
pub mod tables;
pub mod ties;
pub mod triangulate;
pub mod tunnel;
pub mod wide;

pub use cell::{triangulate_ambiguous, triangulate_ambiguous_deferred, Known};
pub use cell_mesh::{CellMesh, Triangles, VertexRef, INTERIOR};

/// A xorshift generator for the kernel's randomised tests (`seed` nonzero).
#[cfg(test)]
pub(crate) fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}
