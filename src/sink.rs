//! Where the mesh goes: chunks streamed, in plane order, to a sink.
//!
//! The pipeline never holds the whole mesh. It hands a [`MeshSink`] one
//! [`Chunk`] per grid plane, in order, with the global number of the chunk's
//! first vertex. A sink may build a [`Mesh`] in memory ([`MeshBuilder`]),
//! write a `.tmesh` file, or stream a PLY/OBJ/OFF/STL file.

use crate::error::make_room;
use crate::pipeline::{Inside, Method};
use crate::{Error, Grid, Mesh, Result};

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
}

/// Builds an in-memory [`Mesh`] (32-bit indices).
///
/// Each chunk is copied into the mesh as it comes, so that the chunk's
/// vectors go back to the slabs still to be computed: memory that is
/// already paged in is written again instead of new pages being faulted
/// in (joining kept chunks at the end wrote the whole mesh to fresh pages
/// twice). The mesh's vectors grow by doubling; for large ones the
/// allocator remaps pages rather than copying them.
#[derive(Debug, Default)]
pub struct MeshBuilder {
    mesh: Mesh,
}

impl MeshBuilder {
    /// A builder with room for a mesh of known size (a replayed `.tmesh`),
    /// or [`Error::OutOfMemory`].
    pub fn with_room(vertices: usize, triangles: usize) -> Result<Self> {
        let mut mesh = Mesh::default();
        make_room(&mut mesh.vertices, vertices, "the mesh's vertices")?;
        make_room(&mut mesh.triangles, triangles, "the mesh's triangles")?;
        Ok(MeshBuilder { mesh })
    }

    /// The mesh built so far.
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }
}

impl MeshSink for MeshBuilder {
    fn begin(&mut self, _info: &MeshInfo) -> Result<()> {
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
        make_room(vertices, chunk.vertices.len(), "the mesh's vertices")?;
        make_room(triangles, chunk.triangles.len(), "the mesh's triangles")?;
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
