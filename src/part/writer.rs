//! Writes a part file: a `.tmesh` file of the part's chunks with its
//! [`PartRecord`] between the last chunk and the index.

use super::{InputId, PartRecord, PartSpec};
use crate::meshfile::TmeshWriter;
use crate::sink::{Chunk, MeshInfo, MeshSink, Totals};
use crate::Result;
use std::path::Path;

/// A part file being written; it appears at its path when finished.
pub struct PartWriter {
    inner: TmeshWriter,
    record: PartRecord,
}

impl PartWriter {
    /// Starts the part file `path` for part `spec` of `input`.
    pub fn create(path: &Path, spec: PartSpec, input: &Path, id: InputId) -> Result<PartWriter> {
        Ok(PartWriter {
            inner: TmeshWriter::create(path)?,
            record: PartRecord {
                tmc_version: env!("CARGO_PKG_VERSION").to_string(),
                index: spec.index,
                count: spec.count,
                layers: [0, 0],
                total_layers: 0,
                input: id,
                input_name: input.display().to_string(),
            },
        })
    }
}

impl MeshSink for PartWriter {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        // The layers as the pipeline cuts them (padded with --close).
        let pad = if info.close { 2 } else { 0 };
        let total = (info.grid.dims[2] + pad).saturating_sub(1);
        let range = super::layer_range(total, self.record.index, self.record.count)?;
        self.record.layers = [range.start, range.end];
        self.record.total_layers = total;
        self.inner.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.inner.chunk(base, chunk)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.inner.append_section(&self.record.encode())?;
        self.inner.finish(totals)
    }
}
