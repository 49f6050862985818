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
    /// The same, handing the chunk over: a sink that keeps chunks (the
    /// in-memory [`MeshBuilder`]) takes them without copying. By default
    /// the same as [`MeshSink::chunk`].
    fn take_chunk(&mut self, base: u64, chunk: Chunk) -> Result<()> {
        self.chunk(base, &chunk)
    }
    /// Called once after the last chunk; a file sink commits its output here.
    fn finish(&mut self, totals: &Totals) -> Result<()>;
}

/// Builds an in-memory [`Mesh`] (32-bit indices).
///
/// Chunks are kept as they come and joined once at the end, into vectors of
/// exactly the final size, several chunks at a time on rayon's current pool:
/// a mesh grown chunk by chunk would be copied again at every doubling and
/// fault in its pages on the thread that feeds the workers.
#[derive(Debug, Default)]
pub struct MeshBuilder {
    chunks: Vec<(u64, Chunk)>,
    vertices: u64,
    triangles: usize,
}

impl MeshBuilder {
    /// The mesh built so far. Panics if memory for it cannot be had; see
    /// [`MeshBuilder::try_into_mesh`].
    pub fn into_mesh(self) -> Mesh {
        self.try_into_mesh().unwrap_or_else(|e| panic!("{e}"))
    }

    /// The mesh built so far, or [`Error::OutOfMemory`] if its vertex and
    /// triangle arrays cannot be allocated.
    pub fn try_into_mesh(self) -> Result<Mesh> {
        use rayon::prelude::*;
        let nv = self.vertices as usize;
        let mut vertices = crate::error::try_zeroed_vec("the mesh's vertices", nv)?;
        let mut triangles = crate::error::try_zeroed_vec("the mesh's triangles", self.triangles)?;
        let mut jobs = Vec::with_capacity(self.chunks.len());
        let (mut v_rest, mut t_rest) = (&mut vertices[..], &mut triangles[..]);
        for (base, chunk) in &self.chunks {
            let (v, vr) = std::mem::take(&mut v_rest).split_at_mut(chunk.vertices.len());
            let (t, tr) = std::mem::take(&mut t_rest).split_at_mut(chunk.triangles.len());
            (v_rest, t_rest) = (vr, tr);
            jobs.push((*base as u32, chunk, v, t));
        }
        jobs.into_par_iter().for_each(|(base, chunk, v, t)| {
            v.copy_from_slice(&chunk.vertices);
            // May point into the next chunk, whose own check bounds it.
            for (out, tri) in t.iter_mut().zip(&chunk.triangles) {
                *out = tri.map(|i| base + i);
            }
        });
        Ok(Mesh {
            vertices,
            triangles,
        })
    }
}

impl MeshSink for MeshBuilder {
    fn begin(&mut self, _info: &MeshInfo) -> Result<()> {
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.take_chunk(base, chunk.clone())
    }

    fn take_chunk(&mut self, base: u64, chunk: Chunk) -> Result<()> {
        let end = base + chunk.vertices.len() as u64;
        if end > u32::MAX as u64 {
            return Err(Error::Invalid(format!(
                "the mesh has more than {} vertices, more than an in-memory mesh with 32-bit indices holds; write a .tmesh file instead",
                u32::MAX
            )));
        }
        self.vertices = end;
        self.triangles += chunk.triangles.len();
        self.chunks.push((base, chunk));
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> Result<()> {
        Ok(())
    }
}
