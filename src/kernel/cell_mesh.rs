//! What the kernel hands back for one cell: triangles over the cell's edge
//! vertices and its interior vertices.
//!
//! Every part of the kernel and the slab loop speak these types, so they
//! sit apart from the code that makes them.

use super::ties::TIE_OFFSET;
use glam::DVec3;

/// A vertex of a cell's triangles: `0..12` is the vertex on that cell edge,
/// `INTERIOR + i` is interior vertex `i` of the cell.
pub type VertexRef = u8;

/// First [`VertexRef`] of the interior vertices.
pub const INTERIOR: u8 = 12;

/// Triangles of one cell, with the positions of its interior vertices in
/// local coordinates (the unit cube).
#[derive(Debug, Clone)]
pub struct CellMesh {
    /// Triangles as vertex refs, counter-clockwise seen from outside.
    pub triangles: Vec<[VertexRef; 3]>,
    /// Interior vertices, local coordinates in [0, 1]^3.
    pub interior: Vec<DVec3>,
    /// How far (a fraction of the cell, per axis) an interior vertex that
    /// ties would put on or near the cell's boundary keeps from it:
    /// [`TIE_OFFSET`] (the default), or more on a grid whose `f32`
    /// coordinates cannot tell that offset from the boundary (far from the
    /// origin; the slab loop's `Placement` chooses it per grid, so every
    /// slab and part places alike). Between `TIE_OFFSET` and `1/4`. Above
    /// `TIE_OFFSET`, every interior vertex keeps that margin, tie or not,
    /// and a tunnel's hexagon opens that wide (`kernel::cell`'s
    /// `interior_clamp` and `open_hexagon`).
    pub tie_margin: f64,
    /// Per contour set (index into the tables' sets), the cells that took
    /// its table fans and whose flat contours are not yet counted in a
    /// `Stats` (`triangulate_ambiguous_deferred`, `CellMesh::flush_counts`,
    /// both in `kernel::cell`, which sizes it on first use): one increment
    /// per cell in place of four additions of a few bits each.
    pub(super) table_cells: Vec<u64>,
}

impl CellMesh {
    /// An empty cell mesh with room for the largest case, whose tie
    /// vertices keep [`TIE_OFFSET`] of the cell from its boundary.
    pub fn new() -> Self {
        Self::with_tie_margin(TIE_OFFSET)
    }

    /// [`CellMesh::new`] with interior tie vertices `margin` of the cell
    /// from its boundary (see [`CellMesh::tie_margin`]; clamped to
    /// `[TIE_OFFSET, 1/4]`).
    pub fn with_tie_margin(margin: f64) -> Self {
        CellMesh {
            triangles: Vec::with_capacity(48),
            interior: Vec::with_capacity(8),
            tie_margin: margin.clamp(TIE_OFFSET, 0.25),
            table_cells: Vec::new(),
        }
    }

    /// Appends a triangle.
    pub fn push_triangle(&mut self, t: [VertexRef; 3]) {
        self.triangles.push(t);
    }

    pub(super) fn push_interior(&mut self, p: DVec3) -> VertexRef {
        self.interior.push(p.clamp(DVec3::ZERO, DVec3::ONE));
        INTERIOR + (self.interior.len() - 1) as u8
    }

    /// Empties the mesh for reuse (the counts of
    /// [`CellMesh::flush_counts`] are kept).
    pub fn clear(&mut self) {
        self.triangles.clear();
        self.interior.clear();
    }
}

impl Default for CellMesh {
    fn default() -> Self {
        Self::new()
    }
}

/// Where [`triangulate_ambiguous`](super::triangulate_ambiguous) left a cell's triangles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Triangles {
    /// Fans over the cell's edge vertices, straight from the tables (flat
    /// contours and no tunnel); the cell mesh is left as it was, so the
    /// caller copies them as it copies MC triangles.
    Table(&'static [[VertexRef; 3]]),
    /// Fans from the tables, one of them round the one interior vertex
    /// [`INTERIOR`], at the given local coordinates (a contour that meets a
    /// face twice, the others flat, no tunnel); the cell mesh is left as it
    /// was.
    Centred(&'static [[VertexRef; 3]], DVec3),
    /// Appended to the cell mesh, with the interior vertices they use.
    Mesh,
}
