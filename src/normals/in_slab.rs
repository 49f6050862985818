//! [`SlabNormals`]: the gradient normals of a slab's chunks, computed by
//! the worker that triangulates the slab, chunk by chunk as the layers are
//! finished.

use super::by_edge::{outward, EdgeNormals, EdgeVertex};
use super::gradient::Layer;
use super::index_map::{Aligned, IndexCoordinates, IndexMap};
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
    aligned: Option<Aligned>,
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
            aligned: (grid.direction == crate::grid::IDENTITY).then(|| Aligned {
                origin: grid.origin,
                inverse: grid.spacing.map(|s| 1.0 / s),
            }),
        }
    }

    /// How an edge vertex's offset along its edge is read from its
    /// position, for [`on_edges`](Self::on_edges).
    pub fn coordinates(&self) -> IndexCoordinates {
        IndexCoordinates {
            aligned: self.aligned,
            full: self.map,
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
        normals.clear();
        self.in_cells(*plane as usize, vertices, normals)
    }

    /// Appends to `out` the normals of `vertices`, which lie on the edges
    /// along `axis` of grid plane `layer + k` (`k` 0 or 1; for `axis` 2,
    /// the edges from plane `layer` to `layer + 1`, `k` 0), each named by
    /// its lower end and its offset along the edge as read from its
    /// position ([`coordinates`](Self::coordinates)): what
    /// [`fill`](Self::fill) gives them, without locating them. A plane's
    /// vertices may be taken in either layer it bounds: the planes and
    /// factors are the same.
    pub fn on_edges(
        &mut self,
        layer: usize,
        k: usize,
        axis: usize,
        vertices: &[EdgeVertex],
        out: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        debug_assert!(layer + 2 <= self.dims[2] && k <= 1 && axis <= 2);
        debug_assert!(axis < 2 || k == 0);
        self.visit(layer, k, Work::Edges { axis, vertices }, out)
    }

    /// Appends to `out` the normals of `vertices`, which lie in the cell
    /// layer below grid plane `plane` or above it, each located from its
    /// position as [`fill`](Self::fill) does.
    pub fn in_cells(
        &mut self,
        plane: usize,
        vertices: &[[f32; 3]],
        out: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        let layer = plane.min(self.dims[2] - 2);
        self.visit(layer, plane - layer, Work::Located { vertices }, out)
    }

    /// Appends the normals of `work`'s vertices, in cell layer `layer`
    /// (the x- and y-edges on its plane `k`), to `out`.
    fn visit(&mut self, layer: usize, k: usize, work: Work, out: &mut Vec<[f32; 3]>) -> Result<()> {
        let n = match work {
            Work::Edges { vertices, .. } => vertices.len(),
            Work::Located { vertices } => vertices.len(),
        };
        if n == 0 {
            return Ok(());
        }
        make_room(out, n, "the normals of a slab")?;
        let (planes, numbers) = self.window.around(layer)?;
        let visit = ChunkNormals {
            work,
            out,
            map: &self.map,
            locator: &self.locator,
            layer,
            k,
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

/// Which vertices [`ChunkNormals`] gives normals.
#[derive(Clone, Copy)]
enum Work<'c> {
    /// Vertices on the edges along `axis`, named by the slab loop.
    Edges {
        axis: usize,
        vertices: &'c [EdgeVertex],
    },
    /// Vertices located from their positions.
    Located { vertices: &'c [[f32; 3]] },
}

/// The normals of some of one layer's vertices, appended to `out`: the
/// work of [`SlabNormals`] compiled once per sample type.
struct ChunkNormals<'c> {
    work: Work<'c>,
    out: &'c mut Vec<[f32; 3]>,
    map: &'c WorldToIndex,
    locator: &'c Locator,
    layer: usize,
    /// The x- and y-edge vertices' plane: the layer's lower (0) or upper
    /// (1).
    k: usize,
    numbers: [usize; 4],
    dims: [usize; 3],
    tie: f64,
    sign: f64,
    aligned: Option<Aligned>,
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
            Some(aligned) => self.run(&field, fz, aligned),
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
        let out = self.out;
        let vertices = match self.work {
            Work::Edges { axis, vertices } => {
                let by_edge = EdgeNormals {
                    field,
                    fz,
                    k: self.k,
                    map,
                    full: self.map,
                    sign: self.sign,
                };
                match axis {
                    0 => by_edge.along::<0>(vertices, out),
                    1 => by_edge.along::<1>(vertices, out),
                    _ => by_edge.along::<2>(vertices, out),
                }
                return;
            }
            Work::Located { vertices } => vertices,
        };
        // On an inner grid edge found from the position, else located and
        // interpolated.
        let (full, layer, sign) = (self.map, self.layer, self.sign);
        let locator = self.locator;
        let general = |v: [f32; 3]| {
            let (cell, t) = locator.locate_in_layer(v, layer);
            full.gradient_to_world(field.gradient(cell, t))
        };
        let z = layer as f64;
        let extent = [field.nx as f64, field.ny as f64];
        out.extend(vertices.iter().map(|&v| {
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
