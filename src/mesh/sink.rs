//! Where the mesh goes: chunks streamed, in plane order, to a [`MeshSink`].
//!
//! The pipeline never holds the whole mesh. It hands a sink one [`Chunk`]
//! per grid plane, in order, with the global number of the chunk's first
//! vertex. A sink may build a [`Mesh`](super::Mesh) in memory
//! ([`MeshBuilder`](super::MeshBuilder)), write a `.tmesh` file, or stream
//! a PLY/OBJ/OFF/STL file.

use super::Chunk;
use crate::grid::Grid;
use crate::params::{Inside, Method};
use crate::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};

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
    /// Whether every chunk carries vertex normals (`Chunk::normals`).
    pub normals: bool,
    /// Whether every chunk carries a label per triangle (`Chunk::labels`):
    /// the mesh is the union of several labels' surfaces.
    pub labels: bool,
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

/// How a sink turns a chunk into the bytes it writes ([`MeshSink::encoder`]):
/// a function of the chunk alone, so that any thread may call it.
pub type ChunkEncoder = fn(&Chunk) -> Result<Vec<u8>>;

/// A consumer of chunks, called from one thread, in plane order.
pub trait MeshSink {
    /// Called once before the first chunk.
    fn begin(&mut self, info: &MeshInfo) -> Result<()>;
    /// One chunk; `base` is the global index of its first vertex. The
    /// chunk is lent: the pipeline reuses its vectors for later slabs.
    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()>;
    /// [`MeshSink::chunk`] that stops with [`Error::Interrupted`] once
    /// `cancel` is set; the sink is then only dropped. The pipeline, `tmc
    /// convert` and `tmc merge` call this one when they have a cancel flag.
    /// The default looks at the flag once and then takes the chunk; a sink
    /// whose chunks take long (PLY, OBJ and OFF format every number of a
    /// chunk, and a dense layer of a large plane has millions) looks at it
    /// as it goes, and a wrapper passes it on.
    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        if cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        self.chunk(base, chunk)
    }
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
    /// How this sink encodes a chunk, if it writes bytes that depend on the
    /// chunk alone (a `.tmesh` chunk's compressed payload): the pipeline then
    /// calls it on the worker that made each chunk and hands the bytes over
    /// in [`Chunk::encoded`], which the sink writes instead of encoding the
    /// chunk again. The default has none; a wrapper passes on its inner
    /// sink's.
    fn encoder(&self) -> Option<ChunkEncoder> {
        None
    }
}

/// The error of a sink used after it finished (a file sink gives up its
/// file in [`MeshSink::finish`]).
pub(crate) fn used_after_finish() -> Error {
    Error::Invalid("the mesh sink was used after it finished".into())
}
