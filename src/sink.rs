//! Where the mesh goes: chunks streamed, in plane order, to a sink.
//!
//! The pipeline never holds the whole mesh. It hands a [`MeshSink`] one
//! [`Chunk`] per grid plane, in order, with the global number of the chunk's
//! first vertex. A sink may build a [`Mesh`] in memory ([`MeshBuilder`]),
//! write a `.tmesh` file, or stream a PLY/OBJ/OFF/STL file.

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
    /// One chunk; `base` is the global index of its first vertex.
    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()>;
    /// Called once after the last chunk; a file sink commits its output here.
    fn finish(&mut self, totals: &Totals) -> Result<()>;
}

/// Builds an in-memory [`Mesh`] (32-bit indices).
#[derive(Debug, Default)]
pub struct MeshBuilder {
    mesh: Mesh,
}

impl MeshBuilder {
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
        self.mesh.vertices.extend_from_slice(&chunk.vertices);
        // May point into the next chunk, whose own check bounds it.
        self.mesh.triangles.extend(
            chunk
                .triangles
                .iter()
                .map(|t| t.map(|i| (base + i as u64) as u32)),
        );
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> Result<()> {
        Ok(())
    }
}
