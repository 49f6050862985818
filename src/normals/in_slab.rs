//! [`SlabNormals`]: the gradient normals of a slab's chunks, computed by
//! the worker that triangulates the slab, chunk by chunk as the layers are
//! finished.

use super::gradient::Layer;
use super::locate::Locator;
use super::on_edge::on_edge;
use super::pending::PENDING;
use super::samples::{with_planes, Samples, Visit};
use super::vector::unit;
use super::window::Window;
use crate::error::make_room;
use crate::grid::WorldToIndex;
use crate::mesh::Chunk;
use crate::params::{ExtractParams, Inside};
use crate::volume::SampleSource;
use crate::Result;

/// What the normals of one slab need: the planes around the current cell
/// layer, the grid's world-to-index map and which way is out.
///
/// The planes are those of the field the slab triangulates (the padded
/// source with `close`). Planes the source lends are not copied; the
/// others are read into at most four `f64` planes (one more on each side
/// of the two a layer's cells need, for the central difference across
/// planes), which the memory budget counts.
pub struct SlabNormals<'a> {
    /// The planes around the current layer.
    window: Window<'a>,
    /// Where a vertex falls in the grid.
    locator: Locator,
    /// The grid's world-to-index map, for the chain rule.
    map: WorldToIndex,
    /// 1, or -1 where outward is down the gradient (`Inside::High`).
    sign: f64,
    /// The value a NaN sample takes in the differences.
    tie: f64,
    /// Samples per row, rows per plane, planes.
    dims: [usize; 3],
    /// For an axis-aligned grid (the identity direction): its origin and
    /// `1 / spacing`, with which index and world coordinates and gradients
    /// convert by one product per axis.
    aligned: Option<([f64; 3], [f64; 3])>,
}

impl<'a> SlabNormals<'a> {
    /// Normals for slabs of `source` (at least two samples along every
    /// axis, as the pass makes sure) extracted with `params`.
    pub fn new(source: &'a dyn SampleSource, params: &ExtractParams) -> Self {
        let grid = source.grid();
        SlabNormals {
            window: Window::new(source),
            locator: Locator::new(grid),
            map: grid.world_to_index(),
            sign: match params.inside {
                Inside::High => -1.0,
                Inside::Low => 1.0,
            },
            tie: params.iso,
            dims: grid.dims,
            aligned: (grid.direction == crate::grid::IDENTITY)
                .then(|| (grid.origin, grid.spacing.map(|s| 1.0 / s))),
        }
    }

    /// Sets `chunk.normals` to one normal per vertex: the central-difference
    /// gradient at the samples (one-sided at the volume's border)
    /// interpolated linearly to the vertex along its edge (trilinearly in
    /// its cell for a vertex inside a cell), taken to world coordinates
    /// through the grid's inverse map, normalized and pointed outward;
    /// [`PENDING`] where it is zero or not finite, for
    /// [`FillPending`](super::FillPending) to resolve from the triangles.
    ///
    /// The chunk's vertices lie in cell layer `chunk.plane` (the top
    /// plane's, in the layer below it): each is located in that layer from
    /// its position, offsets within [`SNAP`](super::locate::SNAP) of a
    /// face taken as on it, so a vertex on a grid edge weighs that edge's
    /// two ends only. A normal depends on the vertex and the samples alone:
    /// the same for any slab, thread or part.
    pub fn fill(&mut self, chunk: &mut Chunk) -> Result<()> {
        chunk.normals.clear();
        if chunk.vertices.is_empty() {
            return Ok(());
        }
        make_room(
            &mut chunk.normals,
            chunk.vertices.len(),
            "the normals of a slab",
        )?;
        let layer = (chunk.plane as usize).min(self.dims[2] - 2);
        let (planes, numbers) = self.window.around(layer)?;
        let visit = ChunkNormals {
            vertices: &chunk.vertices,
            out: &mut chunk.normals,
            locator: &self.locator,
            map: &self.map,
            layer,
            numbers,
            dims: self.dims,
            tie: self.tie,
            sign: self.sign,
            aligned: self.aligned,
        };
        with_planes(planes, visit);
        Ok(())
    }
}

/// The normals of one chunk's vertices, appended to `out`: the work of
/// [`SlabNormals::fill`] compiled once per sample type.
struct ChunkNormals<'c> {
    vertices: &'c [[f32; 3]],
    out: &'c mut Vec<[f32; 3]>,
    locator: &'c Locator,
    map: &'c WorldToIndex,
    layer: usize,
    numbers: [usize; 4],
    dims: [usize; 3],
    tie: f64,
    sign: f64,
    aligned: Option<([f64; 3], [f64; 3])>,
}

impl Visit for ChunkNormals<'_> {
    type Output = ();

    fn visit<P: Samples>(self, planes: [P; 4]) {
        let [nx, ny, _] = self.dims;
        let field = Layer {
            planes,
            numbers: self.numbers,
            nx,
            ny,
            tie: self.tie,
        };
        // What a difference across planes is multiplied by at the layer's
        // lower (1) and upper (2) plane: as `Layer::gradient` has it.
        let across = |k: usize| match self.numbers[k + 1] - self.numbers[k - 1] {
            1 => 1.0,
            _ => 0.5,
        };
        let fz = [across(1), across(2)];
        let (locator, map, layer, sign) = (self.locator, self.map, self.layer, self.sign);
        // Elsewhere than on an inner grid edge: locate and interpolate.
        let general = |v: [f32; 3]| {
            let (cell, t) = locator.locate_in_layer(v, layer);
            map.gradient_to_world(field.gradient(cell, t))
        };
        let z = layer as f64;
        let extent = [nx as f64, ny as f64];
        match self.aligned {
            Some((origin, inv)) => self.out.extend(self.vertices.iter().map(|&v| {
                let p = [0, 1, 2].map(|a| (f64::from(v[a]) - origin[a]) * inv[a]);
                let g = match on_edge(&field, fz, extent, [p[0], p[1], p[2] - z]) {
                    Some(g) => [g[0] * inv[0], g[1] * inv[1], g[2] * inv[2]],
                    None => general(v),
                };
                outward(g, sign)
            })),
            None => self.out.extend(self.vertices.iter().map(|&v| {
                let p = map.index(v.map(f64::from));
                let g = match on_edge(&field, fz, extent, [p[0], p[1], p[2] - z]) {
                    Some(g) => map.gradient_to_world(g),
                    None => general(v),
                };
                outward(g, sign)
            })),
        }
    }
}

/// `g` (a world gradient) times `sign`, normalized, as `f32`; [`PENDING`]
/// when it is zero or not finite. One square root for gradients of
/// ordinary size; [`unit()`] (which scales first) for tiny or huge ones.
#[inline(always)]
fn outward(g: [f64; 3], sign: f64) -> [f32; 3] {
    let squared = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if squared > 1e-200 && squared < 1e200 {
        let scale = sign / squared.sqrt();
        return g.map(|c| (c * scale) as f32);
    }
    unit(g.map(|c| sign * c)).unwrap_or(PENDING)
}
