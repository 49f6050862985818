//! Where the mesh goes: chunks streamed, in plane order, to a sink.
//!
//! The pipeline never holds the whole mesh. It hands a [`MeshSink`] one
//! [`Chunk`] per grid plane, in order, with the global number of the chunk's
//! first vertex. A sink may build a [`Mesh`] in memory ([`MeshBuilder`]),
//! write a `.tmesh` file, or stream a PLY/OBJ/OFF/STL file.

use crate::error::make_room;
use crate::pipeline::{Inside, Method};
use crate::{Error, Grid, Mesh, Result};
use std::sync::atomic::{AtomicBool, Ordering};

/// The vertices owned by one grid plane and the triangles of the cell layer
/// above it.
///
/// Triangle indices are relative to the chunk's first vertex. They may point
/// past the chunk's own vertices, into the vertices of the *next* chunk
/// (the vertices on the next plane's edges, which come first there), but
/// never further.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Chunk {
    /// Grid plane (z index) that owns the vertices.
    pub plane: u64,
    /// Vertex positions, physical coordinates.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside, relative indices.
    pub triangles: Vec<[u32; 3]>,
}

/// What a sink may want to record about the extraction.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshInfo {
    /// The input grid (before any `--close` padding).
    pub grid: Grid,
    /// The isovalue.
    pub iso: f64,
    /// The cell algorithm.
    pub method: Method,
    /// Which side is the object.
    pub inside: Inside,
    /// Whether surfaces were closed at the volume border.
    pub close: bool,
}

/// Totals known when the last chunk has been sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Totals {
    /// Vertices in the mesh.
    pub vertices: u64,
    /// Triangles in the mesh.
    pub triangles: u64,
    /// Chunks sent.
    pub chunks: u64,
}

/// A consumer of chunks, called from one thread, in plane order.
pub trait MeshSink {
    /// Called once before the first chunk.
    fn begin(&mut self, info: &MeshInfo) -> Result<()>;
    /// One chunk; `base` is the global index of its first vertex. The
    /// chunk is lent: the pipeline reuses its vectors for later slabs.
    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()>;
    /// Called once after the last chunk; a file sink commits its output here.
    fn finish(&mut self, totals: &Totals) -> Result<()>;
    /// [`MeshSink::finish`] that stops with [`Error::Interrupted`], leaving
    /// nothing at the output path, once `cancel` is set. The pipeline calls
    /// this one when it has a cancel flag. The default looks at the flag
    /// once and then finishes; a sink whose finishing takes long (PLY, OBJ
    /// and OFF copy their spools into the output) looks at it as it goes,
    /// and a wrapper passes it on.
    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        if cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        self.finish(totals)
    }
}

/// Builds an in-memory [`Mesh`] (32-bit indices).
///
/// Each chunk is copied into the mesh as it comes, so that the chunk's
/// vectors go back to the slabs still to be computed: memory that is
/// already paged in is written again instead of new pages being faulted
/// in (joining kept chunks at the end wrote the whole mesh to fresh pages
/// twice). When the mesh's vectors are full they grow to what the planes
/// so far predict for the whole grid, so that they are rarely copied.
#[derive(Debug, Default)]
pub struct MeshBuilder {
    mesh: Mesh,
    /// Grid planes, from [`MeshSink::begin`] (0: not known).
    planes: u64,
}

impl MeshBuilder {
    /// A builder with room for a mesh of known size (a replayed `.tmesh`),
    /// or [`Error::OutOfMemory`].
    pub fn with_room(vertices: usize, triangles: usize) -> Result<Self> {
        let mut mesh = Mesh::default();
        make_room(&mut mesh.vertices, vertices, "the mesh's vertices")?;
        make_room(&mut mesh.triangles, triangles, "the mesh's triangles")?;
        Ok(MeshBuilder { mesh, planes: 0 })
    }

    /// The mesh built so far.
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }
}

/// Makes room in `v` for `n` more items, growing it, when it is full, to
/// the extrapolation of its length after plane `plane` of `planes` (a
/// quarter more), or to what the allocator's doubling gives if that is
/// more or cannot be had.
fn make_room_for_all<T>(
    v: &mut Vec<T>,
    n: usize,
    plane: u64,
    planes: u64,
    what: &str,
) -> Result<()> {
    if v.capacity() - v.len() >= n {
        return Ok(());
    }
    let needed = (v.len() + n) as u64;
    let done = plane.saturating_add(1).min(planes).max(1);
    let predicted = needed.saturating_mul(planes.max(done)) / done;
    let wanted = predicted.saturating_add(predicted / 4) as usize;
    if wanted > v.capacity() * 2 && v.try_reserve_exact(wanted - v.len()).is_ok() {
        return Ok(());
    }
    make_room(v, n, what)
}

impl MeshSink for MeshBuilder {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        // Padded by one plane on each side with `--close`.
        self.planes = info.grid.dims[2] as u64 + if info.close { 2 } else { 0 };
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        let end = base + chunk.vertices.len() as u64;
        if end > u32::MAX as u64 {
            return Err(Error::Invalid(format!(
                "the mesh has more than {} vertices, more than an in-memory mesh with 32-bit indices holds; write a .tmesh file instead",
                u32::MAX
            )));
        }
        let (vertices, triangles) = (&mut self.mesh.vertices, &mut self.mesh.triangles);
        let (plane, planes) = (chunk.plane, self.planes);
        let what = "the mesh's vertices";
        make_room_for_all(vertices, chunk.vertices.len(), plane, planes, what)?;
        let what = "the mesh's triangles";
        make_room_for_all(triangles, chunk.triangles.len(), plane, planes, what)?;
        vertices.extend_from_slice(&chunk.vertices);
        // May point into the next chunk, whose own check bounds it.
        let base = base as u32;
        triangles.extend(chunk.triangles.iter().map(|t| t.map(|i| base + i)));
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> Result<()> {
        Ok(())
    }
}
