//! [`write_labeled_ply`]: the surfaces of several labels in one binary PLY
//! file, each face with a `uint label` property, assembled from one
//! `.tmesh` file per label.

use crate::files::AtomicFile;
use crate::meshfile::TmeshReader;
use crate::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Writes `path` (atomically) as one binary little-endian PLY holding the
/// mesh of every `(label, tmesh)` in turn: the vertices of the first label,
/// then the second's ..., then the faces in the same order, each face
/// `vertex_indices` (as tmc's PLY writes them) followed by `uint label`.
/// Each label's mesh is the bytes of its `.tmesh` file, its indices moved
/// past the labels before it, so the vertices and faces of one label are
/// those a PLY of that label alone holds. The files are read one chunk at
/// a time, twice (vertices, then faces). Stops with
/// [`Error::Interrupted`] once `cancel` is set, leaving nothing at `path`.
pub fn write_labeled_ply(path: &Path, parts: &[(u32, &Path)], cancel: &AtomicBool) -> Result<()> {
    let mut readers = Vec::with_capacity(parts.len());
    let (mut vertices, mut faces) = (0u64, 0u64);
    for &(label, tmesh) in parts {
        let reader = TmeshReader::open(tmesh)?;
        vertices += reader.vertices();
        faces += reader.triangles();
        readers.push((label, reader));
    }
    if vertices > u64::from(u32::MAX) {
        return Err(Error::Invalid(format!(
            "{}: {vertices} vertices do not fit the PLY's 32-bit indices",
            path.display()
        )));
    }
    let mut file = AtomicFile::create(path)?;
    let io = |e| Error::io(path, e);
    {
        let mut w = BufWriter::with_capacity(1 << 20, file.file());
        super::ply::write_header_with(&mut w, vertices, faces, "", "property uint label\n")
            .map_err(io)?;
        let stop = || -> Result<()> {
            match cancel.load(Ordering::Relaxed) {
                true => Err(Error::Interrupted),
                false => Ok(()),
            }
        };
        for (_, reader) in &mut readers {
            for i in 0..reader.entries().len() {
                stop()?;
                let chunk = reader.chunk(i)?;
                for v in &chunk.vertices {
                    for c in v {
                        w.write_all(&c.to_le_bytes()).map_err(io)?;
                    }
                }
            }
        }
        let mut first = 0u64;
        for (label, reader) in &mut readers {
            for i in 0..reader.entries().len() {
                stop()?;
                let base = first + reader.entries()[i].vertex_base;
                let chunk = reader.chunk(i)?;
                for t in &chunk.triangles {
                    w.write_all(&[3]).map_err(io)?;
                    for &k in t {
                        let index = base + u64::from(k);
                        w.write_all(&(index as u32).to_le_bytes()).map_err(io)?;
                    }
                    w.write_all(&label.to_le_bytes()).map_err(io)?;
                }
            }
            first += reader.vertices();
        }
        w.flush().map_err(io)?;
    }
    file.commit()
}
