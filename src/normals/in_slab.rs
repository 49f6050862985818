//! [`SlabNormals`]: the gradient normals of a slab's chunks, computed by
//! the worker that triangulates the slab, chunk by chunk as the layers are
//! finished.

use super::batch::Batch;
use super::by_edge::{outward, BlockEdges, EdgeNormals};
use super::gradient::Layer;
use super::index_map::{Aligned, IndexMap};
use super::locate::Locator;
use super::on_edge::on_edge;
use super::samples::{with_planes, Samples, Visit};
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
    /// [`PENDING`](super::PENDING) where it is zero or not finite, for
    /// [`FillPending`](super::FillPending) to resolve from the triangles.
    ///
    /// The chunk's vertices lie in cell layer `chunk.plane` (the top
    /// plane's, in the layer below it): each is located in that layer from
    /// its position, offsets within [`SNAP`](super::locate::SNAP) of a
    /// face taken as on it, so a vertex on a grid edge weighs that edge's
    /// two ends only. A normal depends on the vertex and the samples alone:
    /// the same for any slab, thread or part.
    pub fn fill(&mut self, chunk: &mut Chunk) -> Result<()> {
        let Chunk {
            plane,
            vertices,
            normals,
            ..
        } = chunk;
        self.fill_vertices(*plane as usize, None, vertices, normals)
    }

    /// Sets `out` to the normals of a block's `vertices`, as
    /// [`fill`](Self::fill) gives them, the vertices on grid edges taken
    /// on the edges `edges` names (in order; see [`BlockEdges`]) instead of
    /// being located: the slab loop's way, which costs a fraction.
    pub fn fill_block(
        &mut self,
        edges: &BlockEdges,
        vertices: &[[f32; 3]],
        out: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        self.fill_vertices(edges.plane, Some(edges), vertices, out)
    }

    /// The work of [`fill`](Self::fill) and
    /// [`fill_block`](Self::fill_block) for the vertices of grid plane
    /// `plane`.
    fn fill_vertices(
        &mut self,
        plane: usize,
        edges: Option<&BlockEdges>,
        vertices: &[[f32; 3]],
        out: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        out.clear();
        if vertices.is_empty() {
            return Ok(());
        }
        make_room(out, vertices.len(), "the normals of a slab")?;
        let layer = plane.min(self.dims[2] - 2);
        let (planes, numbers) = self.window.around(layer)?;
        let visit = ChunkNormals {
            vertices,
            edges,
            out,
            map: &self.map,
            locator: &self.locator,
            layer,
            k: plane - layer,
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
    /// The edges of the first vertices, when the slab loop names them.
    edges: Option<&'c BlockEdges<'c>>,
    out: &'c mut Vec<[f32; 3]>,
    map: &'c WorldToIndex,
    locator: &'c Locator,
    layer: usize,
    /// The vertices' plane: the layer's lower (0) or upper (1).
    k: usize,
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
        match self.aligned {
            Some((origin, inverse)) => self.run(&field, fz, Aligned { origin, inverse }),
            None => {
                let map = self.map;
                self.run(&field, fz, map)
            }
        }
    }
}

impl ChunkNormals<'_> {
    /// The normals, with `map` for index coordinates and world gradients.
    #[inline(always)]
    fn run<P: Samples, M: IndexMap>(self, field: &Layer<P>, fz: [f64; 2], map: M) {
        let mut rest = self.vertices;
        let out = self.out;
        if let Some(edges) = self.edges {
            let by_edge = EdgeNormals {
                field,
                fz,
                layer: self.layer,
                k: self.k,
                map,
                full: self.map,
                sign: self.sign,
            };
            // Ends within the vertices and in order, whatever they say.
            let z_end = edges.ends[2].min(rest.len());
            let y_end = edges.ends[1].min(z_end);
            let x_end = edges.ends[0].min(y_end);
            let [x_rows, y_rows, z_rows] = edges.rows;
            let dy = edges.y_offset;
            // One batch for the three groups: a fresh one is zeroed (3 KB),
            // and three a block cost 1.0M instructions on cthead @ 1600.
            let mut batch = Batch::new();
            let batch = &mut batch;
            by_edge.along::<0>(x_rows, dy, 0, &rest[..x_end], batch, out);
            by_edge.along::<1>(y_rows, dy, x_end, &rest[x_end..y_end], batch, out);
            by_edge.along::<2>(z_rows, dy, y_end, &rest[y_end..z_end], batch, out);
            rest = &rest[z_end..];
        }
        // Elsewhere than on a named edge: on an inner grid edge found from
        // the position, else located and interpolated.
        let (full, layer, sign) = (self.map, self.layer, self.sign);
        let locator = self.locator;
        let general = |v: [f32; 3]| {
            let (cell, t) = locator.locate_in_layer(v, layer);
            full.gradient_to_world(field.gradient(cell, t))
        };
        let z = layer as f64;
        let extent = [field.nx as f64, field.ny as f64];
        out.extend(rest.iter().map(|&v| {
            let p = map.index(v);
            let g = match on_edge(field, fz, extent, [p[0], p[1], p[2] - z]) {
                Some(g) => {
                    let s = map.scale();
                    map.to_world([g[0] * s[0], g[1] * s[1], g[2] * s[2]])
                }
                None => general(v),
            };
            outward(g, sign)
        }));
    }
}
