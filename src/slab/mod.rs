//! The slab loop: cell layers along z, edge vertices numbered per row.
//!
//! Vertices are owned by grid planes. Block `z` holds, in this order: the
//! vertices on x-edges of plane `z` (raster order), those on its y-edges, the
//! vertices on z-edges between planes `z` and `z + 1`, and the interior
//! vertices of cell layer `z`, which also emits its triangles into block `z`
//! (row by row; in a row, the ambiguous cells' after the others').
//! A block's content depends on planes `z` and `z + 1` only, so any split of
//! the layers into slabs, on any number of threads, gives the same blocks.
//! Triangles point into their own block or into the first part of block
//! `z + 1` (its plane vertices, numbered the same way by both slabs that
//! see that plane), so each block leaves the slab as a [`Chunk`] with
//! indices relative to its first vertex, and the seam step only adds
//! offsets. Inside a slab no hashing is needed: an edge vertex's number
//! follows from the sign bits of its row (module `slab::edges`).
//!
//! [`process_slab`] runs four passes per cell layer `z`, each over whole
//! rows, as Flying Edges does:
//! 1. **load** plane `z + 1` (`Plane::load`): its samples relative to the
//!    isovalue, one inside bit per sample (compared in the samples' own type
//!    when the source lends its plane, module `bits`), and the vertices of its crossed x- and
//!    y-edges in raster order, keeping only each row's first number;
//! 2. **z-edges**: the vertices on the edges between planes `z` and
//!    `z + 1`, found where the two planes' bits differ;
//! 3. **cells** (`layer_cells`): each row's cells from the bits of its four
//!    corner rows: a run of 64 cells with all corners on one side costs one
//!    word operation, an unambiguous cell copies its triangles from the MC table, and the
//!    ambiguous cells of a row go to the [`kernel`](crate::kernel) after the
//!    others; every triangle corner is an edge number from module `edges` or an
//!    interior vertex of its cell;
//! 4. **emit**: block `z` becomes a [`Chunk`] (`Block::into_chunk`), and
//!    plane `z + 1` becomes the bottom plane of the next layer.

mod bits;
mod edges;
mod spares;

pub use spares::{chunk_bytes, Spares};

use crate::error::make_room;
use crate::kernel::tables::{tables, Tables};
use crate::kernel::wide::subtraction_residual;
use crate::kernel::{triangulate_ambiguous, CellMesh, Triangles, INTERIOR};
use crate::mesh::Chunk;
use crate::params::{ExtractParams, Inside, Method};
use crate::volume::{Access, LentPlane, IDENTITY};
use crate::{Error, Grid, Result, SampleSource, Stats};
use bits::{below, each_bit, next, uniform_alike, x_crossings, RowKind, SignBits};
use edges::{CellEdges, EdgeRows, LayerNumbers};
use glam::DVec3;
use spares::{PlaneBuffers, Scratch};
use std::ops::Range;
use std::time::Instant;

/// What the slab loop's growing vectors hold, for out-of-memory errors.
const VERTICES: &str = "the vertices of a slab";
const TRIANGLES: &str = "the triangles of a slab";
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
    fn into_chunk(mut self, plane: usize, mirrored: bool) -> Chunk {
        // A tagged reference `NEXT_BLOCK + r` becomes `own + r`, without a
        // branch: the tag bit selects the offset (wrapping arithmetic).
        let shift = (self.vertices.len() as u32).wrapping_sub(NEXT_BLOCK);
        let resolve = |r: u32| r.wrapping_add(shift & 0u32.wrapping_sub(r >> 31));
        if mirrored {
            for t in &mut self.triangles {
                let [a, b, c] = t.map(resolve);
                *t = [a, c, b];
            }
        } else {
            for r in self.triangles.as_flattened_mut() {
                *r = resolve(*r);
            }
        }
        Chunk {
            plane: plane as u64,
            triangles: self.triangles,
            vertices: self.vertices,
        }
    }

    /// An empty block with a quarter more room than the finished block
    /// `(vertices, triangles)` of the layer below needed, plus the room the
    /// loops ask for per row (`row`), so that a layer like it does not grow
    /// its vectors; its vectors are spares when there are some.
    fn sized_like(
        (vertices, triangles): (usize, usize),
        row: (usize, usize),
        spares: &Spares,
    ) -> Result<Block> {
        let (v, t) = spares.take_block();
        Ok(Block {
            vertices: empty_with_room(v, vertices + vertices / 4 + row.0, VERTICES)?,
            triangles: empty_with_room(t, triangles + triangles / 4 + row.1, TRIANGLES)?,
        })
    }
}

/// The empty vector `spare` if it has room for `n`, else a new one with that
/// room (growing `spare` would copy its whole stale capacity).
fn empty_with_room<T>(spare: Vec<T>, n: usize, what: &str) -> Result<Vec<T>> {
    debug_assert!(spare.is_empty());
    if spare.capacity() >= n {
        return Ok(spare);
    }
    drop(spare);
    let mut fresh = Vec::new();
    make_room(&mut fresh, n, what)?;
    Ok(fresh)
}

/// One plane of values relative to the isovalue, with the numbers of its
/// edge vertices; two of them are reused, plane after plane, by a slab.
///
/// The vertices of a plane's crossed edges are numbered in raster order,
/// x-edges first; only the number of each row's first vertex is kept (see
/// [`edges`]).
struct Plane<'s> {
    z: usize,
    /// The samples as the source lends them, if it does; else `read`.
    lent: Option<LentPlane<'s>>,
    /// The samples as read, when the source lends none.
    read: Vec<f64>,
    level: Level,
    /// Every sample's `rel` is exact (the sample type and the isovalue
    /// say so), so no cell needs residuals.
    exact: bool,
    /// Every sample's `rel` is also the plain `(value - iso) * sign`:
    /// integer samples, so never NaN, and `exact`, so never clamped.
    plain: bool,
    /// `rel(sample) > 0` per sample.
    inside: SignBits,
    /// Local index of the first x-edge vertex of each row.
    x_first: Vec<u32>,
    /// Local index of the first vertex on the y-edges between rows `y` and
    /// `y + 1`.
    y_first: Vec<u32>,
}

/// Which side of the isovalue is inside, and the value the kernel sees.
#[derive(Debug, Clone, Copy)]
struct Level {
    iso: f64,
    /// 1 for `Inside::High`, -1 for `Inside::Low`.
    sign: f64,
}

impl Level {
    fn new(params: &ExtractParams) -> Self {
        let sign = match params.inside {
            Inside::High => 1.0,
            Inside::Low => -1.0,
        };
        Level {
            iso: params.iso,
            sign,
        }
    }

    /// `value - iso` (`iso - value` for `Inside::Low`), NaN as 0 (a tie,
    /// outside), clamped to `±f64::MAX / 4` (infinities too) so that
    /// differences of two stay finite; the kernel scales the values of a
    /// cell out of its range itself.
    #[inline]
    fn rel(self, value: f64) -> f64 {
        let d = (value - self.iso) * self.sign;
        if d.is_nan() {
            0.0
        } else {
            d.clamp(-f64::MAX / 4.0, f64::MAX / 4.0)
        }
    }

    /// [`Level::rel`] of each of `values`, the same numbers, computed with
    /// selects instead of branches (NaN fails both comparisons and is
    /// replaced last) so that the eight run side by side. (`rel` itself
    /// stays as it is: the vertex loops compile worse with this form.)
    #[inline(always)]
    fn rel_all(self, values: [f64; 8]) -> [f64; 8] {
        const LIMIT: f64 = f64::MAX / 4.0;
        let mut out = [0.0; 8];
        for (g, v) in out.iter_mut().zip(values) {
            let d = (v - self.iso) * self.sign;
            let d = if d > LIMIT { LIMIT } else { d };
            let d = if d < -LIMIT { -LIMIT } else { d };
            *g = if d.is_nan() { 0.0 } else { d };
        }
        out
    }

    /// [`Level::rel`] of each of `values` where that is the plain
    /// `(value - iso) * sign` (see `Plane::plain`): without the clamps.
    #[inline(always)]
    fn plain_all(self, values: [f64; 8]) -> [f64; 8] {
        values.map(|v| (v - self.iso) * self.sign)
    }

    /// What rounding left out of `rel(v)` for each of `values`, so that
    /// the kernel can decide on the exact differences: 0 where the
    /// subtraction was exact, and for NaN and clamped values, which stay
    /// rounded. One pass of plain arithmetic over the eight, without a
    /// branch, so that it runs in vector registers.
    #[inline(always)]
    fn residuals(self, values: [f64; 8]) -> [f64; 8] {
        let mut out = [0.0; 8];
        for (r, &v) in out.iter_mut().zip(&values) {
            let d = v - self.iso;
            let rest = subtraction_residual(v, self.iso, d) * self.sign;
            // NaN (from NaN or infinite values) fails the test. Up to
            // `f64::MAX / 4` (not clamped), the residual is finite.
            *r = if d.abs() <= f64::MAX / 4.0 { rest } else { 0.0 };
        }
        out
    }
}

impl PlaneBuffers {
    /// New buffers for planes of `grid`.
    fn new(grid: &Grid) -> Self {
        let [nx, ny, _] = grid.dims;
        PlaneBuffers {
            read: Vec::new(),
            inside: SignBits::new(nx, ny),
            x_first: vec![0; ny],
            y_first: vec![0; ny],
        }
    }
}

impl Scratch {
    /// New buffers for a slab of `grid`.
    fn new(grid: &Grid) -> Self {
        Scratch {
            planes: [PlaneBuffers::new(grid), PlaneBuffers::new(grid)],
            z_first: vec![0; grid.dims[1]],
            rows: EdgeRows::new(grid.dims[0]),
        }
    }
}

impl<'s> Plane<'s> {
    /// A plane working in `buffers` (sized for the grid; stale entries are
    /// never read).
    fn new(buffers: PlaneBuffers) -> Self {
        let PlaneBuffers {
            read,
            inside,
            x_first,
            y_first,
        } = buffers;
        Plane {
            z: 0,
            lent: None,
            read,
            level: Level {
                iso: 0.0,
                sign: 1.0,
            },
            exact: true,
            plain: false,
            inside,
            x_first,
            y_first,
        }
    }

    /// The plane's buffers, for the next slab.
    fn into_buffers(self) -> PlaneBuffers {
        PlaneBuffers {
            read: self.read,
            inside: self.inside,
            x_first: self.x_first,
            y_first: self.y_first,
        }
    }

    /// The kernel's value of sample `i` (see [`Level::rel`]).
    #[inline]
    fn rel(&self, i: usize) -> f64 {
        rel_at(self.lent, &self.read, self.level, i)
    }

    /// The samples `at`, as `f64`s.
    #[inline(always)]
    fn values<const N: usize>(&self, at: [usize; N]) -> [f64; N] {
        match &self.lent {
            Some(samples) => samples.get_many(at),
            None => at.map(|i| self.read[i]),
        }
    }

    /// Reads and classifies plane `z`; appends the positions of its edge
    /// vertices to `owned`.
    fn load(
        &mut self,
        source: &'s dyn SampleSource,
        params: &ExtractParams,
        z: usize,
        owned: &mut Vec<[f32; 3]>,
        stats: &mut Stats,
    ) -> Result<()> {
        let place = Placement::new(source.grid());
        let [nx, ny, _] = place.grid.dims;
        self.z = z;
        let start = Instant::now();
        self.lent = source.lend_plane(z).filter(|p| p.len() == nx * ny);
        if self.lent.is_none() {
            let missing = (nx * ny).saturating_sub(self.read.len());
            make_room(&mut self.read, missing, "a plane of samples")?;
            self.read.resize(nx * ny, 0.0);
            source.read_plane(z, &mut self.read)?;
        }
        stats.planes_read += 1;
        stats.read_seconds += start.elapsed().as_secs_f64();
        let level = Level::new(params);
        self.level = level;
        self.exact = match self.lent {
            Some(samples) => samples.subtracts_exactly(level.iso),
            None => level.iso == 0.0,
        };
        self.plain = self.exact && self.lent.is_some_and(|s| s.is_integer());
        match self.lent {
            None => self
                .inside
                .classify(&self.read, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::U8(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::I8(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::U16(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::I16(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::U32(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::I32(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::F32(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
            Some(LentPlane::F64(s)) => self.inside.classify(s, nx, level.iso, level.sign > 0.0),
        }
        let (lent, read) = (self.lent, &self.read);
        let rel = |i: usize| rel_at(lent, read, level, i);
        let words = self.inside.words() - 1;
        // The plane's vertices open their block: local numbers start at 0.
        debug_assert!(owned.is_empty());
        for y in 0..ny {
            self.x_first[y] = owned.len() as u32;
            if self.inside.kind(y) != RowKind::Mixed {
                continue;
            }
            let row = self.inside.row(y);
            make_room(owned, nx, VERTICES)?;
            for k in 0..words {
                each_bit(x_crossings(row, k, nx), k, |x| {
                    let (a, b) = (rel(y * nx + x), rel(y * nx + x + 1));
                    owned.push(place.at([x as f64 + a / (a - b), y as f64, z as f64]));
                    Ok::<(), Error>(())
                })?;
            }
        }
        for y in 0..ny - 1 {
            self.y_first[y] = owned.len() as u32;
            if uniform_alike([self.inside.kind(y), self.inside.kind(y + 1)]) {
                continue;
            }
            let (lower, upper) = (self.inside.row(y), self.inside.row(y + 1));
            make_room(owned, nx, VERTICES)?;
            for k in 0..words {
                each_bit(lower[k] ^ upper[k], k, |x| {
                    let (a, b) = (rel(y * nx + x), rel((y + 1) * nx + x));
                    owned.push(place.at([x as f64, y as f64 + a / (a - b), z as f64]));
                    Ok::<(), Error>(())
                })?;
            }
        }
        check_local_indices(owned.len())
    }
}

/// The kernel's value of sample `i` of a plane, lent or read.
#[inline(always)]
fn rel_at(lent: Option<LentPlane>, read: &[f64], level: Level, i: usize) -> f64 {
    let value = match lent {
        Some(samples) => samples.get(i),
        None => read[i],
    };
    level.rel(value)
}

/// The grid's index-to-world map, rounded to f32, with a shortcut for the
/// usual axis-aligned grid (bit for bit the same result: the zero terms of
/// an identity direction add nothing).
#[derive(Clone, Copy)]
struct Placement {
    grid: Grid,
    axis_aligned: bool,
}

impl Placement {
    fn new(grid: &Grid) -> Self {
        Placement {
            grid: *grid,
            axis_aligned: grid.direction == IDENTITY,
        }
    }

    /// The world position of a (fractional) grid index.
    #[inline]
    fn at(&self, index: [f64; 3]) -> [f32; 3] {
        let g = &self.grid;
        if self.axis_aligned {
            std::array::from_fn(|i| (g.origin[i] + index[i] * g.spacing[i]) as f32)
        } else {
            g.world(index).map(|c| c as f32)
        }
    }
}

/// Processes cell layers `layers` and returns one chunk per layer (plus the
/// chunk of the last plane when the range ends at the top of the grid) and
/// the counts. Buffers come from `spares` when it has some, and the slab's
/// work buffers go back there (the chunks' vectors are handed back by
/// whoever writes them).
pub fn process_slab(
    source: &dyn SampleSource,
    params: &ExtractParams,
    layers: Range<usize>,
    spares: &Spares,
) -> Result<(Vec<Chunk>, Stats)> {
    let grid = *source.grid();
    let [nx, ny, nz] = grid.dims;
    let start = Instant::now();
    let mirrored = grid.is_mirrored();
    let place = Placement::new(&grid);
    let mut stats = Stats::default();
    let mut chunks = Vec::with_capacity(layers.len() + 1);
    let tables = tables();
    // What the loops make room for per row: a vertex per sample, the most
    // MC triangles per cell.
    let row = (nx, tables.mc_most * (nx - 1));
    let mut block = Block::sized_like((0, 0), row, spares)?;
    source.advise(layers.start..layers.end + 1, Access::Soon);
    let Scratch {
        planes: [lower, upper],
        mut z_first,
        mut rows,
    } = spares
        .take_scratch()
        .filter(|s| s.z_first.len() == ny)
        .unwrap_or_else(|| Scratch::new(&grid));
    let mut bottom = Plane::new(lower);
    let mut top = Plane::new(upper);
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
    let mut waiting = Vec::with_capacity(nx);
    // The sizes of the last finished block (none yet).
    let mut finished = (0, 0);
    for z in layers.clone() {
        let mut next = Block::sized_like(finished, row, spares)?;
        top.load(source, params, z + 1, &mut next.vertices, &mut stats)?;
        // z-edges between the two planes.
        let words = bottom.inside.words() - 1;
        for (y, first) in z_first.iter_mut().enumerate() {
            *first = block.vertices.len() as u32;
            if uniform_alike([bottom.inside.kind(y), top.inside.kind(y)]) {
                continue;
            }
            let (lower, upper) = (bottom.inside.row(y), top.inside.row(y));
            make_room(&mut block.vertices, nx, VERTICES)?;
            for k in 0..words {
                each_bit(lower[k] ^ upper[k], k, |x| {
                    let i = y * nx + x;
                    let (a, b) = (bottom.rel(i), top.rel(i));
                    block
                        .vertices
                        .push(place.at([x as f64, y as f64, z as f64 + a / (a - b)]));
                    Ok::<(), Error>(())
                })?;
            }
        }
        check_local_indices(block.vertices.len())?;
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
        };
        rows.new_layer();
        let mut ambiguous = Ambiguous {
            waiting: &mut waiting,
            cell: &mut cell,
        };
        layer_cells(&layer, &mut rows, &mut block, &mut ambiguous, &mut stats)?;
        finished = (block.vertices.len(), block.triangles.len());
        chunks.push(std::mem::replace(&mut block, next).into_chunk(z, mirrored));
        std::mem::swap(&mut bottom, &mut top);
    }
    if layers.end == nz - 1 {
        chunks.push(block.into_chunk(nz - 1, mirrored));
    } else {
        spares.give_chunk(block.into_chunk(layers.end, mirrored));
    }
    spares.give_scratch(Scratch {
        planes: [bottom.into_buffers(), top.into_buffers()],
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

fn local_index(block: &Block) -> Result<u32> {
    let n = block.vertices.len();
    check_local_indices(n)?;
    Ok(n as u32)
}

/// Fails when `n` vertices of one block would need local indices that
/// clash with the [`NEXT_BLOCK`] tag.
fn check_local_indices(n: usize) -> Result<()> {
    if n as u64 >= NEXT_BLOCK as u64 {
        return Err(Error::Invalid(
            "more than 2^31 vertices in one grid plane".into(),
        ));
    }
    Ok(())
}

/// What the cells of one layer are triangulated from.
struct Layer<'a> {
    place: &'a Placement,
    params: &'a ExtractParams,
    tables: &'a Tables,
    bottom: &'a Plane<'a>,
    top: &'a Plane<'a>,
    /// Where the numbers of the layer's edge vertices come from.
    numbers: LayerNumbers<'a>,
}

/// The ambiguous cells of a row that wait for the kernel, and its scratch.
struct Ambiguous<'a> {
    /// `(x, config)` of each, in row order (room for a row).
    waiting: &'a mut Vec<(usize, u8)>,
    cell: &'a mut CellMesh,
}

/// Triangulates the cells between planes `bottom` and `top`, visiting only
/// the cells whose corners are not all on one side. With `Method::Tmc`, a
/// row's ambiguous cells are set aside and triangulated after its other
/// cells (their triangles follow the row's): the loop over a row then holds
/// only the table look-ups of standard MC, and its code does not change
/// with the kernel's.
fn layer_cells(
    layer: &Layer,
    rows: &mut EdgeRows,
    block: &mut Block,
    ambiguous: &mut Ambiguous,
    stats: &mut Stats,
) -> Result<()> {
    let [nx, ny, _] = layer.place.grid.dims;
    let kernel = layer.params.method == Method::Tmc;
    let (bottom, top) = (layer.bottom, layer.top);
    let words = bottom.inside.words() - 1;
    for y in 0..ny - 1 {
        let kinds = [
            bottom.inside.kind(y),
            bottom.inside.kind(y + 1),
            top.inside.kind(y),
            top.inside.kind(y + 1),
        ];
        if uniform_alike(kinds) {
            continue;
        }
        // Room for the MC triangles of every cell of the row, so that they
        // are pushed without a check (an ambiguous cell keeps this room).
        make_room(
            &mut block.triangles,
            layer.tables.mc_most * (nx - 1),
            TRIANGLES,
        )?;
        let edges = rows.cell_row(y, &layer.numbers);
        let rows = [
            bottom.inside.row(y),
            bottom.inside.row(y + 1),
            top.inside.row(y),
            top.inside.row(y + 1),
        ];
        for k in 0..words {
            // Corner c (cube numbering, c = x + 2y + 4z) of cell x is bit x
            // of rows[c / 2], shifted by one sample when c is odd.
            let corners: [u64; 8] = std::array::from_fn(|c| {
                let row = rows[c / 2];
                if c % 2 == 0 {
                    row[k]
                } else {
                    next(row, k)
                }
            });
            let any = corners.iter().fold(0, |m, w| m | w);
            let all = corners.iter().fold(u64::MAX, |m, w| m & w);
            let mixed = any & !all & below(nx - 1, k);
            each_bit(mixed, k, |x| {
                let j = x % 64;
                let config = corners
                    .iter()
                    .enumerate()
                    .fold(0u8, |m, (c, w)| m | (((w >> j) & 1) as u8) << c);
                let t = layer.tables;
                if t.is_ambiguous[config as usize] {
                    stats.ambiguous_cells += 1;
                    if kernel {
                        ambiguous.waiting.push((x, config));
                        return Ok(());
                    }
                }
                // No reallocation: the row made room for `mc_most` per cell.
                let range =
                    t.mc_start[config as usize] as usize..t.mc_start[config as usize + 1] as usize;
                let edges = edges.cell(x);
                let refs = t.mc_tris[range].iter().map(|tri| tri.map(|e| edges.get(e)));
                block.triangles.extend(refs);
                Ok(())
            })?;
        }
        for &(x, config) in ambiguous.waiting.iter() {
            ambiguous_cell(
                layer,
                edges.cell(x),
                block,
                ambiguous.cell,
                stats,
                [x, y],
                config,
            )?;
        }
        ambiguous.waiting.clear();
    }
    Ok(())
}

/// Triangulates ambiguous cell `(x, y)` of the layer, of configuration
/// `config`, with the kernel.
#[inline(never)]
fn ambiguous_cell(
    layer: &Layer,
    edges: CellEdges,
    block: &mut Block,
    cell: &mut CellMesh,
    stats: &mut Stats,
    [x, y]: [usize; 2],
    config: u8,
) -> Result<()> {
    let Layer {
        place,
        tables: t,
        bottom,
        top,
        ..
    } = *layer;
    let nx = place.grid.dims[0];
    let i = y * nx + x;
    t.touch_sets(config);
    let corners = [i, i + 1, i + nx, i + nx + 1];
    let (low, high) = (bottom.values(corners), top.values(corners));
    let values: [f64; 8] = std::array::from_fn(|c| if c < 4 { low[c] } else { high[c - 4] });
    // Both planes were read with the same level.
    let level = bottom.level;
    let g = if bottom.plain && top.plain {
        level.plain_all(values)
    } else {
        level.rel_all(values)
    };
    let rest;
    let residual = if bottom.exact && top.exact {
        None
    } else {
        rest = level.residuals(values);
        (rest != [0.0; 8]).then_some(&rest)
    };
    cell.clear();
    let origin = DVec3::new(x as f64, y as f64, bottom.z as f64);
    match triangulate_ambiguous(&g, residual, config, stats, cell) {
        Triangles::Table(fans) => {
            // Edge vertices only, as MC.
            make_room(&mut block.triangles, fans.len(), TRIANGLES)?;
            let refs = fans.iter().map(|tri| tri.map(|e| edges.get(e)));
            block.triangles.extend(refs);
            Ok(())
        }
        Triangles::Centred(fans, centre) => push_cell(block, place, edges, fans, [origin + centre]),
        Triangles::Mesh => {
            let interior = cell.interior.iter().map(|p| origin + *p);
            push_cell(block, place, edges, &cell.triangles, interior)
        }
    }
}

/// Appends a cell's interior vertices (grid index coordinates) and its
/// triangles, whose refs from [`INTERIOR`] on point at those vertices, to
/// the block.
fn push_cell(
    block: &mut Block,
    place: &Placement,
    edges: CellEdges,
    triangles: &[[u8; 3]],
    interior: impl IntoIterator<Item = DVec3, IntoIter: ExactSizeIterator>,
) -> Result<()> {
    let interior = interior.into_iter();
    let first_interior = local_index(block)?;
    make_room(&mut block.vertices, interior.len(), VERTICES)?;
    make_room(&mut block.triangles, triangles.len(), TRIANGLES)?;
    for p in interior {
        block.vertices.push(place.at(p.to_array()));
    }
    let refs = triangles.iter().map(|tri| {
        tri.map(|r| {
            if r < INTERIOR {
                edges.get(r)
            } else {
                first_interior + (r - INTERIOR) as u32
            }
        })
    });
    block.triangles.extend(refs);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cells_values_are_the_vertex_loops_values() {
        let special = [
            0.0,
            -0.0,
            1.5,
            -2.25,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE / 4.0,
            f64::MAX / 4.0,
            -f64::MAX / 4.0,
        ];
        let mut tested = 0;
        for iso in [0.0, 0.3, -1e300, 1e308, f64::MAX] {
            for sign in [1.0, -1.0] {
                let level = Level { iso, sign };
                for window in special.windows(8) {
                    let values: [f64; 8] = window.try_into().expect("eight values");
                    let all = level.rel_all(values);
                    for (v, g) in values.iter().zip(all) {
                        assert_eq!(g.to_bits(), level.rel(*v).to_bits(), "{v} {iso} {sign}");
                        tested += 1;
                    }
                }
            }
        }
        assert_eq!(tested, 5 * 2 * 7 * 8);
    }

    #[test]
    fn plain_planes_need_no_clamps() {
        // Integer samples whose subtraction is exact, at the ends of their
        // types and at isovalues with fraction bits: `plain_all` must be
        // `rel` bit for bit wherever a plane would say `plain`.
        let u32s = [0u32, 1, 7, 65_535, u32::MAX - 1, u32::MAX];
        let i32s = [i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX];
        let u16s = [0u16, 1, 1000, u16::MAX];
        let planes = [
            LentPlane::U32(&u32s),
            LentPlane::I32(&i32s),
            LentPlane::U16(&u16s),
        ];
        let mut tested = 0;
        for iso in [0.0, -0.0, 0.5, -3.25, 1600.0, 2.0e9 + 0.125, -4.0e9, 1e300] {
            for plane in planes {
                if !plane.subtracts_exactly(iso) {
                    continue;
                }
                assert!(plane.is_integer());
                let values: Vec<f64> = (0..plane.len()).map(|i| plane.get(i)).collect();
                for sign in [1.0, -1.0] {
                    let level = Level { iso, sign };
                    let eight: [f64; 8] = std::array::from_fn(|i| values[i % values.len()]);
                    let plain = level.plain_all(eight);
                    for (v, g) in eight.iter().zip(plain) {
                        assert_eq!(g.to_bits(), level.rel(*v).to_bits(), "{v} {iso} {sign}");
                        tested += 1;
                    }
                }
            }
        }
        // Every isovalue but 1e300 subtracts exactly for all three types.
        assert_eq!(tested, 7 * 3 * 2 * 8);
    }
}
