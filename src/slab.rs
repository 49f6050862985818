//! The slab loop: cell layers along z, with per-plane edge-vertex caches.
//!
//! Vertices are owned by grid planes. Block `z` holds, in this order: the
//! vertices on x-edges of plane `z` (raster order), those on its y-edges, the
//! vertices on z-edges between planes `z` and `z + 1`, and the interior
//! vertices of cell layer `z`, which also emits its triangles into block `z`.
//! A block's content depends on planes `z` and `z + 1` only, so any split of
//! the layers into slabs, on any number of threads, gives the same blocks.
//! Triangles point into their own block or into the first part of block
//! `z + 1` (its plane vertices, numbered the same way by both slabs that
//! see that plane), so each block leaves the slab as a [`Chunk`] with
//! indices relative to its first vertex, and the seam step only adds
//! offsets. Inside a slab no hashing is needed: edge caches are plain arrays.

use crate::kernel::cell::INTERIOR;
use crate::kernel::tables::tables;
use crate::kernel::{triangulate_ambiguous, CellMesh};
use crate::pipeline::{ExtractParams, Inside, Method};
use crate::sink::Chunk;
use crate::volume::Access;
use crate::{Error, Grid, Result, SampleSource, Stats};
use glam::DVec3;
use std::ops::Range;
use std::time::Instant;

/// No vertex on this edge.
const NONE: u32 = u32::MAX;
/// Set in a triangle's vertex reference when it points into block `z + 1`.
const NEXT_BLOCK: u32 = 1 << 31;

/// The vertices owned by one grid plane and the triangles of the cell layer
/// above it, while the layer is being built: triangle entries are local
/// indices, possibly tagged [`NEXT_BLOCK`].
#[derive(Debug, Default, Clone)]
struct Block {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl Block {
    /// The finished block as a chunk: references into the next block follow
    /// this block's own vertices. A mirroring index-to-world map reverses the
    /// winding, so that triangles stay counter-clockwise seen from outside.
    fn into_chunk(self, plane: usize, mirrored: bool) -> Chunk {
        let own = self.vertices.len() as u32;
        let resolve = |r: u32| {
            if r & NEXT_BLOCK != 0 {
                own + (r & !NEXT_BLOCK)
            } else {
                r
            }
        };
        Chunk {
            plane: plane as u64,
            triangles: self
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(resolve);
                    if mirrored {
                        [a, c, b]
                    } else {
                        [a, b, c]
                    }
                })
                .collect(),
            vertices: self.vertices,
        }
    }
}

/// One plane of values relative to the isovalue, with its edge vertices;
/// two of them are reused, plane after plane, by a slab.
struct Plane {
    z: usize,
    /// `value - iso` (or `iso - value`), NaN replaced by 0 (outside).
    g: Vec<f64>,
    /// `g > 0` per sample, as 0 or 1.
    inside: Vec<u8>,
    /// Per square of the plane (indexed by its first sample `y * nx + x`),
    /// the inside bits of its corners `x + 2y`: the lower or upper half of
    /// a cell's configuration, so a cell costs two byte loads to classify.
    square: Vec<u8>,
    /// Local vertex index per x-edge (`(nx - 1) * ny`), or [`NONE`].
    xe: Vec<u32>,
    /// Local vertex index per y-edge (`nx * (ny - 1)`), or [`NONE`].
    ye: Vec<u32>,
    /// Where the sign changes along each row, to skip uniform runs of cells.
    rows: Vec<RowSigns>,
}

/// The signs along one row of a plane, summarised: every sample before
/// `first` has the sign `lead`, every sample from `last` on has the sign
/// `tail` (Flying Edges' trimming).
#[derive(Debug, Clone, Copy, Default)]
struct RowSigns {
    lead: bool,
    tail: bool,
    /// First sample whose sign differs from its predecessor (`nx` if none).
    first: usize,
    /// Last such sample (0 if none).
    last: usize,
}

/// The range of positions along a row where rows with these summaries can
/// disagree in sign or change sign: outside it all of them are uniform and
/// equal. `shift` is 1 for cells (cell x spans samples x and x + 1) and 0 for
/// samples.
fn active_range(rows: &[RowSigns], shift: usize, len: usize) -> Range<usize> {
    let lead = rows[0].lead;
    let tail = rows[0].tail;
    let start = if rows.iter().all(|r| r.lead == lead) {
        rows.iter()
            .map(|r| r.first)
            .min()
            .unwrap_or(0)
            .saturating_sub(shift)
    } else {
        0
    };
    let end = if rows.iter().all(|r| r.tail == tail) {
        rows.iter().map(|r| r.last).max().unwrap_or(len)
    } else {
        len
    };
    start.min(end)..end.min(len)
}

impl Plane {
    fn new(grid: &Grid) -> Self {
        let [nx, ny, _] = grid.dims;
        Plane {
            z: 0,
            g: vec![0.0; nx * ny],
            inside: vec![0; nx * ny],
            square: vec![0; nx * ny],
            xe: vec![NONE; (nx - 1) * ny],
            ye: vec![NONE; nx * (ny - 1)],
            rows: vec![RowSigns::default(); ny],
        }
    }

    /// Reads and classifies plane `z`; appends the positions of its edge
    /// vertices to `owned`.
    fn load(
        &mut self,
        source: &dyn SampleSource,
        params: &ExtractParams,
        z: usize,
        owned: &mut Vec<[f32; 3]>,
        stats: &mut Stats,
    ) -> Result<()> {
        let grid = *source.grid();
        let [nx, ny, _] = grid.dims;
        self.z = z;
        let start = Instant::now();
        source.read_plane(z, &mut self.g)?;
        stats.planes_read += 1;
        stats.read_seconds += start.elapsed().as_secs_f64();
        let (iso, sign) = match params.inside {
            Inside::High => (params.iso, 1.0),
            Inside::Low => (params.iso, -1.0),
        };
        for (v, inside) in self.g.iter_mut().zip(self.inside.iter_mut()) {
            let d = (*v - iso) * sign;
            *v = if d.is_nan() {
                0.0
            } else {
                d.clamp(-1e150, 1e150)
            };
            *inside = u8::from(*v > 0.0);
        }
        let (g, s) = (&self.g, &self.inside);
        let mut count = 0u32;
        for y in 0..ny {
            let row = y * nx;
            let signs = &s[row..row + nx];
            let slots = &mut self.xe[y * (nx - 1)..(y + 1) * (nx - 1)];
            slots.fill(NONE);
            let mut first = nx;
            let mut last = 0;
            for x in 0..nx - 1 {
                if signs[x] != signs[x + 1] {
                    first = first.min(x + 1);
                    last = x + 1;
                    slots[x] = count;
                    count += 1;
                    let (a, b) = (g[row + x], g[row + x + 1]);
                    owned.push(physical(
                        &grid,
                        [x as f64 + a / (a - b), y as f64, z as f64],
                    ));
                }
            }
            self.rows[y] = RowSigns {
                lead: signs[0] != 0,
                tail: signs[nx - 1] != 0,
                first,
                last,
            };
        }
        for y in 0..ny - 1 {
            let row = y * nx;
            let (lower, upper) = (&s[row..row + nx], &s[row + nx..row + 2 * nx]);
            let slots = &mut self.ye[row..row + nx];
            slots.fill(NONE);
            for x in active_range(&[self.rows[y], self.rows[y + 1]], 0, nx) {
                if lower[x] != upper[x] {
                    slots[x] = count;
                    count += 1;
                    let (a, b) = (g[row + x], g[row + nx + x]);
                    owned.push(physical(
                        &grid,
                        [x as f64, y as f64 + a / (a - b), z as f64],
                    ));
                }
            }
            let squares = &mut self.square[row..row + nx - 1];
            for (x, q) in squares.iter_mut().enumerate() {
                *q = lower[x] | lower[x + 1] << 1 | upper[x] << 2 | upper[x + 1] << 3;
            }
        }
        Ok(())
    }
}

/// The world position of a grid index, rounded to f32.
fn physical(grid: &Grid, index: [f64; 3]) -> [f32; 3] {
    grid.world(index).map(|c| c as f32)
}

/// Processes cell layers `layers` and returns one chunk per layer (plus the
/// chunk of the last plane when the range ends at the top of the grid) and
/// the counts.
pub fn process_slab(
    source: &dyn SampleSource,
    params: &ExtractParams,
    layers: Range<usize>,
) -> Result<(Vec<Chunk>, Stats)> {
    let grid = *source.grid();
    let [nx, ny, nz] = grid.dims;
    let start = Instant::now();
    let mirrored = grid.is_mirrored();
    let mut stats = Stats::default();
    let mut chunks = Vec::with_capacity(layers.len() + 1);
    let mut block = Block::default();
    source.advise(layers.start..layers.end + 1, Access::Soon);
    let mut bottom = Plane::new(&grid);
    let mut top = Plane::new(&grid);
    // The slab's first plane may belong to the slab below; its vertices are
    // numbered the same way here and there, and kept by the block of that plane.
    bottom.load(
        source,
        params,
        layers.start,
        &mut block.vertices,
        &mut stats,
    )?;
    let mut cell = CellMesh::new();
    let mut ze = vec![NONE; nx * ny];
    for z in layers.clone() {
        let mut next = Block::default();
        top.load(source, params, z + 1, &mut next.vertices, &mut stats)?;
        // z-edges between the two planes.
        ze.fill(NONE);
        for y in 0..ny {
            for x in active_range(&[bottom.rows[y], top.rows[y]], 0, nx) {
                let i = y * nx + x;
                if bottom.inside[i] != top.inside[i] {
                    let (a, b) = (bottom.g[i], top.g[i]);
                    ze[i] = local_index(&block)?;
                    block.vertices.push(physical(
                        &grid,
                        [x as f64, y as f64, z as f64 + a / (a - b)],
                    ));
                }
            }
        }
        layer_cells(
            &grid, params, &bottom, &top, &ze, &mut block, &mut cell, &mut stats,
        )?;
        chunks.push(std::mem::replace(&mut block, next).into_chunk(z, mirrored));
        std::mem::swap(&mut bottom, &mut top);
    }
    if layers.end == nz - 1 {
        chunks.push(block.into_chunk(nz - 1, mirrored));
    }
    // Release this slab's planes (its last plane is released by the slab
    // above, whose first plane it is). Should the slab below still be reading
    // the first one, its pages come back from the page cache.
    source.advise(layers.start..layers.end, Access::Done);
    stats.cell_seconds = start.elapsed().as_secs_f64() - stats.read_seconds;
    Ok((chunks, stats))
}

fn local_index(block: &Block) -> Result<u32> {
    let n = block.vertices.len() as u64;
    if n >= NEXT_BLOCK as u64 {
        return Err(Error::Invalid(
            "more than 2^31 vertices in one grid plane".into(),
        ));
    }
    Ok(n as u32)
}

/// Triangulates the cells between planes `bottom` and `top`.
#[allow(clippy::too_many_arguments)]
fn layer_cells(
    grid: &Grid,
    params: &ExtractParams,
    bottom: &Plane,
    top: &Plane,
    ze: &[u32],
    block: &mut Block,
    cell: &mut CellMesh,
    stats: &mut Stats,
) -> Result<()> {
    let [nx, ny, _] = grid.dims;
    let t = tables();
    let z = bottom.z;
    for y in 0..ny - 1 {
        let rows = [
            bottom.rows[y],
            bottom.rows[y + 1],
            top.rows[y],
            top.rows[y + 1],
        ];
        for x in active_range(&rows, 1, nx - 1) {
            let i = y * nx + x;
            let config = bottom.square[i] | top.square[i] << 4;
            if config == 0 || config == 255 {
                continue;
            }
            let xi = y * (nx - 1) + x;
            // Edge numbering of `kernel::cube`; upper-plane edges belong to
            // the next block.
            let edge_refs = [
                bottom.xe[xi],
                bottom.xe[xi + nx - 1],
                top.xe[xi] | NEXT_BLOCK,
                top.xe[xi + nx - 1] | NEXT_BLOCK,
                bottom.ye[i],
                bottom.ye[i + 1],
                top.ye[i] | NEXT_BLOCK,
                top.ye[i + 1] | NEXT_BLOCK,
                ze[i],
                ze[i + 1],
                ze[i + nx],
                ze[i + nx + 1],
            ];
            let edge_ref = |e: u8| edge_refs[e as usize];
            let ambiguous = t.is_ambiguous[config as usize];
            if ambiguous {
                stats.ambiguous_cells += 1;
            }
            if !ambiguous || params.method == Method::Mc {
                let range =
                    t.mc_start[config as usize] as usize..t.mc_start[config as usize + 1] as usize;
                for tri in &t.mc_tris[range] {
                    block.triangles.push(tri.map(edge_ref));
                }
                continue;
            }
            let idx = [i, i + 1, i + nx, i + nx + 1];
            let g: [f64; 8] = [
                bottom.g[idx[0]],
                bottom.g[idx[1]],
                bottom.g[idx[2]],
                bottom.g[idx[3]],
                top.g[idx[0]],
                top.g[idx[1]],
                top.g[idx[2]],
                top.g[idx[3]],
            ];
            cell.clear();
            triangulate_ambiguous(&g, config, stats, cell);
            let first_interior = local_index(block)?;
            for p in &cell.interior {
                let index = DVec3::new(x as f64, y as f64, z as f64) + *p;
                block.vertices.push(physical(grid, index.to_array()));
            }
            for tri in &cell.triangles {
                block.triangles.push(tri.map(|r| {
                    if r < INTERIOR {
                        edge_ref(r)
                    } else {
                        first_interior + (r - INTERIOR) as u32
                    }
                }));
            }
        }
    }
    Ok(())
}
