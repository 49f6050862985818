//! OFF (Object File Format) output, text; whole meshes ([`write_off`]) or
//! streamed chunks ([`OffSink`]).

use super::spooled::Spooled;
use crate::sink::{Chunk, MeshInfo, MeshSink, Totals};
use crate::{Mesh, Result};
use std::io::{self, Write};
use std::path::Path;

/// Writes `mesh` as an OFF file: counts, vertices, then `3 a b c` faces.
pub fn write_off(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_header(w, mesh.vertices.len() as u64, mesh.triangles.len() as u64)?;
    for v in &mesh.vertices {
        write_vertex(w, v)?;
    }
    for t in &mesh.triangles {
        write_face(w, t.map(u64::from))?;
    }
    Ok(())
}

/// Streams an OFF file, byte-identical to [`write_off`] of the same mesh;
/// memory stays small whatever the mesh size (see [`super::create_sink`]).
pub struct OffSink {
    body: Option<Spooled>,
}

impl OffSink {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<OffSink> {
        Ok(OffSink {
            body: Some(Spooled::create(path)?),
        })
    }
}

impl MeshSink for OffSink {
    fn begin(&mut self, _info: &MeshInfo) -> Result<()> {
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        let body = self.body.as_mut().ok_or_else(super::finished)?;
        body.chunk(base, chunk, |vertices, faces| {
            for v in &chunk.vertices {
                write_vertex(vertices, v)?;
            }
            for t in &chunk.triangles {
                write_face(faces, t.map(|i| base + u64::from(i)))?;
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
    writeln!(w, "OFF")?;
    writeln!(w, "{vertices} {faces} 0")
}

fn write_vertex(w: &mut impl Write, [x, y, z]: &[f32; 3]) -> io::Result<()> {
    writeln!(w, "{x} {y} {z}")
}

fn write_face(w: &mut impl Write, [a, b, c]: [u64; 3]) -> io::Result<()> {
    writeln!(w, "3 {a} {b} {c}")
}
