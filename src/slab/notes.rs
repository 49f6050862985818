//! [`Notes`]: what the vertex loops hand each edge vertex to besides
//! keeping its position, so that its normal needs not find its edge
//! again ([`Noted`], for `slab::normals`).

use crate::normals::{EdgeVertex, IndexCoordinates};

/// The edge vertices the loops note as they place them, for their
/// normals: each one's edge and offset along it.
pub(super) struct Noted {
    /// The vertices noted since the last group's normals.
    pub(super) vertices: Vec<EdgeVertex>,
    /// How a vertex's offset along its edge is read from its position.
    pub(super) coordinates: IndexCoordinates,
}

/// What the vertex loops do with each edge vertex they place besides
/// keeping its position: nothing (`()`, the loops compile to what they
/// are without normals), or note it for its normal ([`Noted`]).
pub(super) trait Notes {
    /// Notes the vertex at `v` on the edge from sample `x` of row `y`
    /// (the whole grid's numbers) along `axis`, whose index coordinate
    /// along `axis` is `start` at that end.
    fn note(&mut self, v: [f32; 3], axis: usize, start: f64, x: usize, y: usize);
}

impl Notes for () {
    #[inline(always)]
    fn note(&mut self, _: [f32; 3], _: usize, _: f64, _: usize, _: usize) {}
}

impl Notes for Noted {
    #[inline(always)]
    fn note(&mut self, v: [f32; 3], axis: usize, start: f64, x: usize, y: usize) {
        let offset = self.coordinates.offset(v, axis, start);
        self.vertices.push(EdgeVertex { x, y, offset });
    }
}
