//! Writes a part file: a `.tmesh` file of the part's chunks with its
//! [`PartRecord`] between the last chunk and the index.

use super::PartRecord;
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Totals};
use crate::meshfile::TmeshWriter;
use crate::Result;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// A part file being written; it appears at its path when finished.
pub struct PartWriter {
    inner: TmeshWriter,
    record: PartRecord,
}

impl PartWriter {
    /// Starts the part file `path` that will record `record`.
    pub fn create(path: &Path, record: PartRecord) -> Result<PartWriter> {
        Ok(PartWriter {
            inner: TmeshWriter::create(path)?,
            record,
        })
    }
}

impl MeshSink for PartWriter {
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
        self.inner.append_section(&self.record.encode())?;
        self.inner.finish(totals)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.inner.encoder()
    }
}
