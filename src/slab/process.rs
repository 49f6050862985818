//! [`process_slab`]: the slab loop, one cell layer after the other through
//! the four passes of the module documentation.

use super::bits::{each_bit, uniform_alike};
use super::block::{check_local_indices, Block, NEXT_BLOCK, VERTICES};
use super::cells::{layer_cells, Ambiguous, Layer};
use super::edges::LayerNumbers;
use super::normals::BlockNormals;
use super::placement::Placement;
use super::plane::Plane;
use super::spares::{Scratch, Spares};
use super::window::Window;
use crate::error::make_room;
use crate::kernel::tables::tables;
use crate::kernel::CellMesh;
use crate::mesh::Chunk;
use crate::params::{ExtractParams, VertexValues};
use crate::volume::{Access, SampleSource};
use crate::{Error, Result, Stats};
use std::ops::Range;
use std::time::Instant;

/// Processes cell layers `layers` and returns one chunk per layer (plus the
/// chunk of the last plane when the range ends at the top of the grid) and
/// the counts. Buffers come from `spares` when it has some, and the slab's
/// work buffers go back there (the chunks' vectors are handed back by
/// whoever writes them). With `params.normals` each chunk gets its
/// vertices' normals from the gradient of `source`
/// ([`SlabNormals`](crate::normals::SlabNormals)); the source must then
/// hold the plane below the slab and the two above it too. With `values`
/// each chunk's [`Chunk::values`] are filled as it is made.
pub fn process_slab(
    source: &dyn SampleSource,
    params: &ExtractParams,
    layers: Range<usize>,
    spares: &Spares,
    values: Option<&VertexValues>,
) -> Result<(Vec<Chunk>, Stats)> {
    let per_vertex = PerVertex {
        gradients: params.normals.then_some(source),
        values,
    };
    process_window(source, params, layers, spares, None, per_vertex)
}

/// What the slab loop adds to each block's vertices besides their
/// positions, as soon as the block is complete: its planes are then still
/// in the caches, where a pass over the chunks after the slab would read
/// every sample near a vertex from memory again.
#[derive(Clone, Copy, Default)]
pub struct PerVertex<'a> {
    /// Normals from the gradient of this source, on the whole grid
    /// (`None`: no normals).
    pub gradients: Option<&'a dyn SampleSource>,
    /// Fills each chunk's [`Chunk::values`]
    /// ([`PipelineOptions::vertex_values`](crate::PipelineOptions::vertex_values)).
    pub values: Option<&'a VertexValues<'a>>,
}

/// [`process_slab`] of a source that is a [`Window`] of a larger grid
/// (`None`: the whole grid), with what `per_vertex` asks for each vertex.
pub fn process_window(
    source: &dyn SampleSource,
    params: &ExtractParams,
    layers: Range<usize>,
    spares: &Spares,
    window: Option<&Window>,
    per_vertex: PerVertex,
) -> Result<(Vec<Chunk>, Stats)> {
    let grid = *source.grid();
    let [nx, ny, nz] = grid.dims;
    let start = Instant::now();
    let mirrored = grid.is_mirrored();
    let place = match window {
        Some(window) => Placement::windowed(&grid, window),
        None => Placement::new(&grid),
    };
    let mut stats = Stats::default();
    let mut chunks = Vec::with_capacity(layers.len() + 1);
    let tables = tables();
    // What the loops make room for per row: a vertex per sample, the most
    // MC triangles per cell.
    let row = (nx, tables.mc_most * (nx - 1));
    let mut block = Block::sized_like((0, 0), row, spares)?;
    let mut ahead = ReadAhead::new(source, layers.start);
    let Scratch {
        planes: [lower, upper],
        dims,
        mut z_first,
        mut rows,
    } = spares
        .take_scratch()
        .filter(|s| s.dims == [nx, ny])
        .unwrap_or_else(|| Scratch::new(&grid));
    let mut bottom = Plane::new(lower);
    let mut top = Plane::new(upper);
    // The slab's first plane may belong to the slab below; its vertices are
    // numbered the same way here and there, and kept by the block of that plane.
    bottom.load(
        source,
        &place,
        params,
        layers.start,
        &mut block.vertices,
        &mut stats,
    )?;
    let mut cell = CellMesh::with_tie_margin(place.interior_margin);
    let mut waiting = Vec::with_capacity(nx);
    // The sizes of the last finished block (none yet).
    let mut finished = (0, 0);
    let interrupted = || source.interrupted();
    let mut normals = per_vertex
        .gradients
        .map(|field| BlockNormals::new(field, params, place.offset[1], ny));
    for z in layers.clone() {
        let mut next = Block::sized_like(finished, row, spares)?;
        ahead.reading(source, z + 1);
        top.load(
            source,
            &place,
            params,
            z + 1,
            &mut next.vertices,
            &mut stats,
        )?;
        // z-edges between the two planes.
        if place.axis_aligned {
            z_edges::<true>(
                &place,
                [&bottom, &top],
                z,
                &mut z_first,
                &mut block.vertices,
            )?;
        } else {
            z_edges::<false>(
                &place,
                [&bottom, &top],
                z,
                &mut z_first,
                &mut block.vertices,
            )?;
        }
        check_local_indices(block.vertices.len())?;
        let z_end = block.vertices.len();
        let layer = Layer {
            place: &place,
            params,
            tables,
            bottom: &bottom,
            top: &top,
            numbers: LayerNumbers {
                nx,
                top_tag: NEXT_BLOCK,
                bottom: &bottom.inside,
                top: &top.inside,
                bottom_x: &bottom.x_first,
                bottom_y: &bottom.y_first,
                top_x: &top.x_first,
                top_y: &top.y_first,
                z: &z_first,
            },
            interrupted: &interrupted,
        };
        rows.new_layer();
        let mut ambiguous = Ambiguous {
            waiting: &mut waiting,
            cell: &mut cell,
        };
        layer_cells(&layer, &mut rows, &mut block, &mut ambiguous, &mut stats)?;
        if let Some(normals) = &mut normals {
            normals.fill(&bottom, Some((&z_first, z_end)), &mut block)?;
        }
        finished = (block.vertices.len(), block.triangles.len());
        let chunk = std::mem::replace(&mut block, next).into_chunk(z, mirrored);
        chunks.push(with_values(chunk, per_vertex.values));
        std::mem::swap(&mut bottom, &mut top);
    }
    // The flat contours of the slab's table cells (see
    // `kernel::triangulate_ambiguous_deferred`).
    cell.flush_counts(&mut stats);
    if layers.end == nz - 1 {
        if let Some(normals) = &mut normals {
            normals.fill(&bottom, None, &mut block)?;
        }
        chunks.push(with_values(
            block.into_chunk(nz - 1, mirrored),
            per_vertex.values,
        ));
    } else {
        spares.give_chunk(block.into_chunk(layers.end, mirrored));
    }
    spares.give_scratch(Scratch {
        planes: [bottom.into_buffers(), top.into_buffers()],
        dims,
        z_first,
        rows,
    });
    // Release this slab's planes (its last plane is released by the slab
    // above, whose first plane it is). Should the slab below still be reading
    // the first one, its pages come back from the page cache.
    source.advise(layers.start..layers.end, Access::Done);
    stats.cell_seconds = start.elapsed().as_secs_f64() - stats.read_seconds;
    Ok((chunks, stats))
}

/// `chunk` with its [`Chunk::values`] filled by `values`, if given.
fn with_values(mut chunk: Chunk, values: Option<&VertexValues>) -> Chunk {
    if let Some(values) = values {
        values(&chunk.vertices, &mut chunk.values);
    }
    chunk
}

/// Appends the positions of the vertices on the z-edges between planes
/// `bottom` and `top` (cell layer `z`) to `vertices` and notes each row's first in
/// `z_first`; `ALIGNED` is `place.axis_aligned` (tested once per layer).
fn z_edges<const ALIGNED: bool>(
    place: &Placement,
    [bottom, top]: [&Plane; 2],
    z: usize,
    z_first: &mut [u32],
    vertices: &mut Vec<[f32; 3]>,
) -> Result<()> {
    let nx = place.grid.dims[0];
    let words = bottom.inside.words() - 1;
    for (y, first) in z_first.iter_mut().enumerate() {
        *first = vertices.len() as u32;
        if uniform_alike([bottom.inside.kind(y), top.inside.kind(y)]) {
            continue;
        }
        let (lower, upper) = (bottom.inside.row(y), top.inside.row(y));
        make_room(vertices, nx, VERTICES)?;
        for k in 0..words {
            each_bit(lower[k] ^ upper[k], k, |x| {
                let i = y * nx + x;
                let (a, b) = (bottom.rel(i), top.rel(i));
                vertices.push(place.edge_in::<ALIGNED>(place.index(x, y, z), 2, a, b));
                Ok::<(), Error>(())
            })?;
        }
    }
    Ok(())
}

/// Bytes of planes [`ReadAhead`] keeps advised ahead of the plane being
/// read (between this and twice this).
const READ_AHEAD_BYTES: usize = 64 << 20;

/// Read-ahead advice that rolls along with the slab and on past its end:
/// between `planes` and `2 * planes` planes ahead of the plane being read
/// are advised [`Access::Soon`], a batch of `planes` at a time (one call per
/// batch, not per layer, so that tiny planes cost no call each).
///
/// Advising a whole slab when it starts made the worker wait for the
/// kernel to queue all its reads (some 300 MiB for planes of 4096^2 u16)
/// before it could begin, and left nothing queued for the slab after;
/// rolling keeps the disk busier: a cold extraction of 131 planes of
/// 4096^2 u16 at two threads took 4.6-5.0 s against 5.1-5.5 s (dd of the
/// same bytes: 3.0-3.3 s; busy machine, see docs/performance.md).
struct ReadAhead {
    /// Planes per batch.
    planes: usize,
    /// Planes advised so far end here (exclusive).
    advised: usize,
    /// Planes in the grid.
    nz: usize,
}

impl ReadAhead {
    /// Advises the first batches from plane `first` on.
    fn new(source: &dyn SampleSource, first: usize) -> Self {
        let grid = source.grid();
        let plane_bytes = (grid.plane_len() * source.sample_bytes()).max(1);
        let mut ahead = ReadAhead {
            planes: (READ_AHEAD_BYTES / plane_bytes).clamp(1, 64),
            advised: first,
            nz: grid.dims[2],
        };
        ahead.reading(source, first);
        ahead
    }

    /// Plane `z` is about to be read: advises the next batch when fewer
    /// than `planes` planes beyond it are advised.
    fn reading(&mut self, source: &dyn SampleSource, z: usize) {
        if self.advised <= z + self.planes && self.advised < self.nz {
            let end = (z + 1 + 2 * self.planes).min(self.nz);
            let start = self.advised.max(z);
            source.advise(start..end, Access::Soon);
            self.advised = end;
        }
    }
}
