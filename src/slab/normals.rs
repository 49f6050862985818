//! [`BlockNormals`]: the normals of a block's vertices, given when the
//! block is complete, from the rows its vertices lie on.
//!
//! The vertices of block `z` are those of the crossed x- and y-edges of
//! plane `z` in raster order, then those of the z-edges up to plane
//! `z + 1`, then the cells' interior vertices (see the module
//! documentation); the planes keep the first vertex of each row of each
//! group. Those are handed to [`SlabNormals::fill_block`] as
//! [`BlockEdges`]: each edge vertex's row and edge direction are known,
//! its place along the row follows from its position, and only the
//! interior vertices are located from theirs.

use super::block::Block;
use super::plane::Plane;
use crate::normals::{BlockEdges, SlabNormals};
use crate::params::ExtractParams;
use crate::volume::SampleSource;
use crate::Result;

/// The gradient normals of one slab's blocks.
pub(super) struct BlockNormals<'a> {
    normals: SlabNormals<'a>,
    /// Added to the slab's row numbers: where a window of the grid starts.
    y_offset: usize,
    /// The slab's rows per plane.
    ny: usize,
}

impl<'a> BlockNormals<'a> {
    /// Normals from the gradient of `field` (the whole grid, of which the
    /// slab's source, `ny` rows per plane, is the window starting at row
    /// `y_offset`), extracted with `params`.
    pub(super) fn new(
        field: &'a dyn SampleSource,
        params: &ExtractParams,
        y_offset: usize,
        ny: usize,
    ) -> Self {
        BlockNormals {
            normals: SlabNormals::new(field, params),
            y_offset,
            ny,
        }
    }

    /// Sets `block.normals`, the block of `plane`, whose z-edge vertices
    /// (rows starting at `z_first`) end at `z_end`; `None` for the block
    /// of the grid's top plane, which has none.
    #[inline(never)]
    pub(super) fn fill(
        &mut self,
        plane: &Plane,
        z_edges: Option<(&[u32], usize)>,
        block: &mut Block,
    ) -> Result<()> {
        let ny = self.ny;
        let own = match z_edges {
            Some((z_first, _)) => z_first[0] as usize,
            None => block.vertices.len(),
        };
        let (z_rows, z_end) = match z_edges {
            Some((z_first, end)) => (&z_first[..ny], end),
            None => (&[][..], own),
        };
        let edges = BlockEdges {
            plane: plane.z,
            rows: [&plane.x_first[..ny], &plane.y_first[..ny - 1], z_rows],
            ends: [plane.y_first[0] as usize, own, z_end],
            y_offset: self.y_offset,
        };
        self.normals
            .fill_block(&edges, &block.vertices, &mut block.normals)
    }
}
