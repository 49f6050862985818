//! [`IndexMap`]: how the normals take a vertex's world position to index
//! coordinates and an index-space gradient to world coordinates, one
//! product per axis on an axis-aligned grid ([`Aligned`]), the full map
//! otherwise.

use crate::grid::WorldToIndex;

/// How index coordinates and index gradients relate to world ones: one
/// product per axis on an axis-aligned grid, the full map otherwise.
pub(super) trait IndexMap: Copy {
    /// Index coordinate `axis` of world position `v`.
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64;
    /// The index coordinates of world position `v`.
    fn index(&self, v: [f32; 3]) -> [f64; 3];
    /// What index-space differences along each axis are multiplied by
    /// before [`to_world`](Self::to_world): `1 / spacing` where that is
    /// all the chain rule does (then `to_world` does nothing), else 1.
    fn scale(&self) -> [f64; 3];
    /// An index-space gradient, multiplied by [`scale`](Self::scale), in
    /// world coordinates.
    fn to_world(&self, g: [f64; 3]) -> [f64; 3];
}

/// An axis-aligned grid: its origin and `1 / spacing`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Aligned {
    pub(super) origin: [f64; 3],
    pub(super) inverse: [f64; 3],
}

impl IndexMap for Aligned {
    #[inline(always)]
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64 {
        (f64::from(v[axis]) - self.origin[axis]) * self.inverse[axis]
    }

    #[inline(always)]
    fn index(&self, v: [f32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| self.coordinate(v, a))
    }

    #[inline(always)]
    fn scale(&self) -> [f64; 3] {
        self.inverse
    }

    #[inline(always)]
    fn to_world(&self, g: [f64; 3]) -> [f64; 3] {
        g
    }
}

impl IndexMap for &WorldToIndex {
    #[inline(always)]
    fn coordinate(&self, v: [f32; 3], axis: usize) -> f64 {
        WorldToIndex::index(self, v.map(f64::from))[axis]
    }

    #[inline(always)]
    fn index(&self, v: [f32; 3]) -> [f64; 3] {
        WorldToIndex::index(self, v.map(f64::from))
    }

    #[inline(always)]
    fn scale(&self) -> [f64; 3] {
        [1.0; 3]
    }

    #[inline(always)]
    fn to_world(&self, g: [f64; 3]) -> [f64; 3] {
        self.gradient_to_world(g)
    }
}
