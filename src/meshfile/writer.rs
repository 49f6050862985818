//! Writes `.tmesh` files as a [`MeshSink`]: chunks are appended as they
//! arrive, compressed by the pipeline's workers (the sink's
//! [`MeshSink::encoder`]) or here; the index and trailer close the file,
//! which then replaces its target atomically.

use super::payload::encode_payload;
use super::{encode_header, ChunkEntry, CHUNK_HEADER_BYTES, END_MAGIC, HEADER_BYTES};
use crate::files::AtomicFile;
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Totals};
use crate::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Bytes a [`TmeshWriter`] gathers before it writes them: a system call
/// per chunk header and payload took a third of the time of volumes with
/// many small planes.
const BUFFER_BYTES: usize = 1 << 20;

/// A `.tmesh` file being written.
pub struct TmeshWriter {
    /// The file, buffered; taken out (flushed) and committed by `finish`.
    /// One descriptor per file, not a second handle: a label pass holds a
    /// file per label open at once, and the limit on open files bounds
    /// how many labels it takes.
    out: Option<BufWriter<AtomicFile>>,
    /// Where the file appears, for errors.
    path: PathBuf,
    offset: u64,
    index: Vec<ChunkEntry>,
    bytes: u64,
    /// The chunks carry normals ([`MeshInfo::normals`]).
    normals: bool,
    /// The chunks carry a label per triangle ([`MeshInfo::labels`]).
    labels: bool,
}

impl TmeshWriter {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<TmeshWriter> {
        TmeshWriter::create_buffered(path, BUFFER_BYTES)
    }

    /// [`TmeshWriter::create`] gathering `buffer` bytes (instead of 1 MiB)
    /// before it writes them: for many files written at once (one per
    /// label), whose buffers together should stay small.
    pub fn create_buffered(path: &Path, buffer: usize) -> Result<TmeshWriter> {
        Ok(TmeshWriter::around(AtomicFile::create(path)?, path, buffer))
    }

    /// [`TmeshWriter::create_buffered`] for an intermediate file that the
    /// run reads and removes ([`AtomicFile::scratch`]: not synced to disk).
    pub fn create_scratch(path: &Path, buffer: usize) -> Result<TmeshWriter> {
        Ok(TmeshWriter::around(
            AtomicFile::scratch(path)?,
            path,
            buffer,
        ))
    }

    fn around(file: AtomicFile, path: &Path, buffer: usize) -> TmeshWriter {
        TmeshWriter {
            out: Some(BufWriter::with_capacity(buffer, file)),
            path: path.to_path_buf(),
            offset: 0,
            index: Vec::new(),
            bytes: 0,
            normals: false,
            labels: false,
        }
    }

    /// Bytes written so far.
    pub fn bytes_written(&self) -> u64 {
        self.bytes
    }

    /// Appends `data` after the chunks written so far; readers skip it (the
    /// index locates the chunks). Part files keep their record there.
    pub fn append_section(&mut self, data: &[u8]) -> Result<()> {
        self.write(data)
    }

    fn write(&mut self, data: &[u8]) -> Result<()> {
        let out = self.out.as_mut().expect("writer already finished");
        out.write_all(data).map_err(|e| Error::io(&self.path, e))?;
        self.offset += data.len() as u64;
        self.bytes += data.len() as u64;
        Ok(())
    }
}

impl MeshSink for TmeshWriter {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.normals = info.normals;
        self.labels = info.labels;
        let header = encode_header(info);
        debug_assert_eq!(header.len(), HEADER_BYTES);
        self.write(&header)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        if chunk.vertices.is_empty() && chunk.triangles.is_empty() {
            return Ok(());
        }
        let normals = if self.normals {
            chunk.vertices.len()
        } else {
            0
        };
        if chunk.normals.len() != normals {
            return Err(Error::Invalid(format!(
                "a chunk of {} vertices has {} normals, the file {}",
                chunk.vertices.len(),
                chunk.normals.len(),
                if self.normals { "one each" } else { "none" }
            )));
        }
        let labels = if self.labels {
            chunk.triangles.len()
        } else {
            0
        };
        if chunk.labels.len() != labels {
            return Err(Error::Invalid(format!(
                "a chunk of {} triangles has {} labels, the file {}",
                chunk.triangles.len(),
                chunk.labels.len(),
                if self.labels { "one each" } else { "none" }
            )));
        }
        // Compressed by the worker that made the chunk, when it came
        // through the pipeline (see `encoder`).
        let made;
        let payload = match chunk.encoded.is_empty() {
            true => {
                made = encode_payload(chunk)?;
                &made
            }
            false => &chunk.encoded,
        };
        let mut h = [0u8; CHUNK_HEADER_BYTES];
        h[0..4].copy_from_slice(b"CHNK");
        h[4..8].copy_from_slice(&crc32fast::hash(payload).to_le_bytes());
        h[8..16].copy_from_slice(&chunk.plane.to_le_bytes());
        h[16..24].copy_from_slice(&base.to_le_bytes());
        h[24..28].copy_from_slice(&(chunk.vertices.len() as u32).to_le_bytes());
        h[28..32].copy_from_slice(&(chunk.triangles.len() as u32).to_le_bytes());
        h[32..40].copy_from_slice(&(payload.len() as u64).to_le_bytes());
        let crc = crc32fast::hash(&h[..40]);
        h[40..44].copy_from_slice(&crc.to_le_bytes());
        self.index.push(ChunkEntry {
            offset: self.offset,
            vertex_base: base,
            vertex_count: chunk.vertices.len() as u32,
            triangle_count: chunk.triangles.len() as u32,
            plane: chunk.plane,
        });
        self.write(&h)?;
        self.write(payload)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        Some(encode_payload)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        let index_offset = self.offset;
        let mut entries =
            crate::error::try_vec::<u8>("the .tmesh chunk index", self.index.len() * 32)?;
        for e in &self.index {
            entries.extend_from_slice(&e.offset.to_le_bytes());
            entries.extend_from_slice(&e.vertex_base.to_le_bytes());
            entries.extend_from_slice(&e.vertex_count.to_le_bytes());
            entries.extend_from_slice(&e.triangle_count.to_le_bytes());
            entries.extend_from_slice(&e.plane.to_le_bytes());
        }
        let mut head = Vec::with_capacity(16);
        head.extend_from_slice(b"INDX");
        head.extend_from_slice(&crc32fast::hash(&entries).to_le_bytes());
        head.extend_from_slice(&(self.index.len() as u64).to_le_bytes());
        self.write(&head)?;
        self.write(&entries)?;
        let mut trailer = Vec::with_capacity(32);
        trailer.extend_from_slice(&index_offset.to_le_bytes());
        trailer.extend_from_slice(&totals.vertices.to_le_bytes());
        trailer.extend_from_slice(&totals.triangles.to_le_bytes());
        trailer.extend_from_slice(&END_MAGIC);
        self.write(&trailer)?;
        let out = self.out.take().expect("finished once");
        let file = out
            .into_inner()
            .map_err(|e| Error::io(&self.path, e.into_error()))?;
        file.commit()
    }
}
