//! [`BlockNormals`]: the normals of a block's vertices, computed as the
//! slab loop makes them.
//!
//! The vertices of block `z` are those of the crossed x- and y-edges of
//! plane `z` in raster order, then those of the z-edges up to plane
//! `z + 1`, then the cells' interior vertices (see the module
//! documentation). The loops that place the edge vertices note each one's
//! edge and offset along it as [`EdgeVertex`](crate::normals::EdgeVertex)es
//! (`Noted`), and each
//! group's normals follow as soon as the group is placed, from the layer
//! whose planes the loop has at hand: a plane's x- and y-edge vertices as
//! it is loaded (those of plane `z + 1` from cell layer `z`, whose planes
//! the z-edges and cells of layer `z` need next), then the z-edges', then
//! the cells' interior vertices, which are located from their positions.

use super::block::Block;
use super::notes::Noted;
use super::plane::Plane;
use crate::normals::SlabNormals;
use crate::params::ExtractParams;
use crate::volume::SampleSource;
use crate::Result;

/// The gradient normals of one slab's blocks.
pub(super) struct BlockNormals<'a> {
    normals: SlabNormals<'a>,
    /// The edge vertices of the group being placed.
    pub(super) noted: Noted,
}

impl<'a> BlockNormals<'a> {
    /// Normals from the gradient of `field` (the whole grid, of which the
    /// slab's source is a window or all), extracted with `params`.
    pub(super) fn new(field: &'a dyn SampleSource, params: &ExtractParams) -> Self {
        let normals = SlabNormals::new(field, params);
        let coordinates = normals.coordinates();
        BlockNormals {
            normals,
            noted: Noted {
                vertices: Vec::new(),
                coordinates,
            },
        }
    }

    /// Appends to `block.normals` those of the x- and y-edge vertices of
    /// `plane` (noted by `Plane::load`), taken in cell layer `layer`
    /// (the plane or the one below it).
    #[inline(never)]
    pub(super) fn plane_edges(
        &mut self,
        plane: &Plane,
        layer: usize,
        block: &mut Block,
    ) -> Result<()> {
        let noted = std::mem::take(&mut self.noted.vertices);
        let x_end = (plane.y_first[0] as usize).min(noted.len());
        let (x_edges, y_edges) = noted.split_at(x_end);
        let k = plane.z - layer;
        let out = &mut block.normals;
        let done = self
            .normals
            .on_edges(layer, k, 0, x_edges, out)
            .and_then(|()| self.normals.on_edges(layer, k, 1, y_edges, out));
        self.noted.vertices = noted;
        self.noted.vertices.clear();
        done
    }

    /// Appends to `block.normals` those of the z-edge vertices of cell
    /// layer `layer` (noted by the z-edge loop).
    #[inline(never)]
    pub(super) fn z_edges(&mut self, layer: usize, block: &mut Block) -> Result<()> {
        let done = self
            .normals
            .on_edges(layer, 0, 2, &self.noted.vertices, &mut block.normals);
        self.noted.vertices.clear();
        done
    }

    /// Appends to `block.normals` those of its vertices from `first` on,
    /// the interior vertices of cell layer `layer`.
    #[inline(never)]
    pub(super) fn cells(&mut self, layer: usize, first: usize, block: &mut Block) -> Result<()> {
        let vertices = &block.vertices[first.min(block.vertices.len())..];
        self.normals.in_cells(layer, vertices, &mut block.normals)
    }
}
