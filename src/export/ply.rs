//! PLY output: binary little-endian, float coordinates, `uchar uint` face
//! lists; whole meshes ([`write_ply`]) or streamed chunks ([`PlySink`]).

use super::spooled::Spooled;
use crate::sink::{Chunk, MeshInfo, MeshSink, Totals};
use crate::{Mesh, Result};
use std::io::{self, Write};
use std::path::Path;

/// Most vertices a PLY file can have: its face lists hold `uint` indices.
const MAX_VERTICES: u64 = 1 << 32;

/// Writes `mesh` as a binary little-endian PLY file.
pub fn write_ply(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_header(w, mesh.vertices.len() as u64, mesh.triangles.len() as u64)?;
    for v in &mesh.vertices {
        write_vertex(w, v)?;
    }
    for t in &mesh.triangles {
        write_face(w, *t)?;
    }
    Ok(())
}

/// Streams a binary little-endian PLY file, byte-identical to [`write_ply`]
/// of the same mesh; memory stays small whatever the mesh size (see
/// [`super::create_sink`] for how).
pub struct PlySink {
    body: Option<Spooled>,
}

impl PlySink {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<PlySink> {
        Ok(PlySink {
            body: Some(Spooled::create(path)?),
        })
    }
}

impl MeshSink for PlySink {
    fn begin(&mut self, _info: &MeshInfo) -> Result<()> {
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        let body = self.body.as_mut().ok_or_else(super::finished)?;
        if base + chunk.vertices.len() as u64 > MAX_VERTICES {
            return Err(body.numbering().error(format!(
                "the mesh has more than {MAX_VERTICES} vertices, more than PLY's 32-bit indices can name; write .obj, .off or .tmesh instead"
            )));
        }
        body.chunk(base, chunk, |vertices, faces| {
            for v in &chunk.vertices {
                write_vertex(vertices, v)?;
            }
            for t in &chunk.triangles {
                // In range: the check above bounds every vertex that can exist.
                write_face(faces, t.map(|i| (base + u64::from(i)) as u32))?;
            }
            Ok(())
        })
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        let body = self.body.take().ok_or_else(super::finished)?;
        body.finish(totals, |w, vertices, faces| {
            write_header(w, vertices, faces)
        })
    }
}

fn write_header(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()> {
    write!(
        w,
        "ply\n\
         format binary_little_endian 1.0\n\
         comment written by tmc {}\n\
         element vertex {vertices}\n\
         property float x\n\
         property float y\n\
         property float z\n\
         element face {faces}\n\
         property list uchar uint vertex_indices\n\
         end_header\n",
        env!("CARGO_PKG_VERSION"),
    )
}

fn write_vertex(w: &mut impl Write, v: &[f32; 3]) -> io::Result<()> {
    let mut bytes = [0u8; 12];
    for (out, c) in bytes.chunks_exact_mut(4).zip(v) {
        out.copy_from_slice(&c.to_le_bytes());
    }
    w.write_all(&bytes)
}

fn write_face(w: &mut impl Write, t: [u32; 3]) -> io::Result<()> {
    let mut bytes = [3u8; 13];
    for (out, i) in bytes[1..].chunks_exact_mut(4).zip(t) {
        out.copy_from_slice(&i.to_le_bytes());
    }
    w.write_all(&bytes)
}
