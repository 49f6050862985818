//! The global vertex numbering of a chunk stream, checked as the chunks
//! arrive: each chunk starts where the previous one ended, and each triangle
//! names a vertex of its own chunk or of the next one.
//!
//! A streaming writer emits a chunk's faces before the next chunk exists, so
//! the check that a triangle's far corner exists is deferred to the next
//! chunk (or to the end of the stream); it still happens before the output
//! is committed.

use crate::mesh::{Chunk, Totals};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// Counts vertices and triangles of a chunk stream and checks its indices.
#[derive(Debug)]
pub(crate) struct Numbering {
    path: PathBuf,
    vertices: u64,
    triangles: u64,
    /// The largest global index named by the triangles so far.
    largest: Option<u64>,
}

impl Numbering {
    /// A stream written to `path` (named in errors), before its first chunk.
    pub(crate) fn new(path: &Path) -> Numbering {
        Numbering {
            path: path.to_path_buf(),
            vertices: 0,
            triangles: 0,
            largest: None,
        }
    }

    /// Vertices received so far.
    pub(crate) fn vertices(&self) -> u64 {
        self.vertices
    }

    /// Triangles received so far.
    pub(crate) fn triangles(&self) -> u64 {
        self.triangles
    }

    /// Accepts the chunk whose first vertex is global vertex `base`.
    pub(crate) fn accept(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        let plane = chunk.plane;
        if base != self.vertices {
            return Err(self.error(format!(
                "the chunk of plane {plane} starts at vertex {base}, but {} vertices came before it",
                self.vertices
            )));
        }
        let end = base + chunk.vertices.len() as u64;
        if let Some(largest) = self.largest.filter(|&l| l >= end) {
            return Err(self.error(format!(
                "a triangle before plane {plane} names vertex {largest}, beyond the next chunk"
            )));
        }
        if let Some(local) = chunk.triangles.iter().flatten().max() {
            let global = base + u64::from(*local);
            self.largest = Some(self.largest.map_or(global, |l| l.max(global)));
        }
        self.vertices = end;
        self.triangles += chunk.triangles.len() as u64;
        Ok(())
    }

    /// Checks the end of the stream: every named vertex exists and the
    /// totals agree with the chunks received.
    pub(crate) fn finish(&self, totals: &Totals) -> Result<()> {
        if let Some(largest) = self.largest.filter(|&l| l >= self.vertices) {
            return Err(self.error(format!(
                "a triangle names vertex {largest}, but the mesh has {} vertices",
                self.vertices
            )));
        }
        if (totals.vertices, totals.triangles) != (self.vertices, self.triangles) {
            return Err(self.error(format!(
                "the totals ({} vertices, {} triangles) disagree with the chunks ({} vertices, {} triangles)",
                totals.vertices, totals.triangles, self.vertices, self.triangles
            )));
        }
        Ok(())
    }

    /// An error about the stream, naming the output.
    pub(crate) fn error(&self, message: String) -> Error {
        Error::Invalid(format!("{}: {message}", self.path.display()))
    }
}
