//! `--require-surface`: a sink wrapper that refuses to finish an empty mesh,
//! so the output file is never committed when there is no surface.

use std::sync::atomic::AtomicBool;
use tmc::{Chunk, ChunkEncoder, Error, MeshInfo, MeshSink, Result, Totals};

/// Passes everything to `inner`, but fails instead of finishing when the
/// mesh has no triangle; `inner` is then dropped unfinished, which leaves
/// nothing at its output path.
pub(crate) struct RequireSurface<'a> {
    /// The sink that writes the output.
    pub inner: &'a mut dyn MeshSink,
    /// The error message for an empty mesh.
    pub message: String,
}

impl MeshSink for RequireSurface<'_> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.inner.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.inner.chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.inner.chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.check(totals)?;
        self.inner.finish(totals)
    }

    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.check(totals)?;
        self.inner.finish_cancellable(totals, cancel)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.inner.encoder()
    }
}

impl RequireSurface<'_> {
    /// Fails when the mesh has no triangle.
    fn check(&self, totals: &Totals) -> Result<()> {
        if totals.triangles == 0 {
            return Err(Error::Invalid(self.message.clone()));
        }
        Ok(())
    }
}
