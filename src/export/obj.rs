//! Wavefront OBJ output (text, 1-based indices); whole meshes
//! ([`write_obj`]) or streamed chunks ([`ObjSink`]).

use super::spooled::Spooled;
use crate::sink::{Chunk, MeshInfo, MeshSink, Totals};
use crate::{Mesh, Result};
use std::io::{self, Write};
use std::path::Path;

/// Writes `mesh` as an OBJ file: `v x y z` lines, then `f a b c` lines.
pub fn write_obj(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_header(w)?;
    for v in &mesh.vertices {
        write_vertex(w, v)?;
    }
    for t in &mesh.triangles {
        write_face(w, t.map(u64::from))?;
    }
    Ok(())
}

/// Streams an OBJ file, byte-identical to [`write_obj`] of the same mesh;
/// memory stays small whatever the mesh size (see [`super::create_sink`]).
pub struct ObjSink {
    body: Option<Spooled>,
}

impl ObjSink {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<ObjSink> {
        Ok(ObjSink {
            body: Some(Spooled::create(path)?),
        })
    }
}

impl MeshSink for ObjSink {
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
        body.finish(totals, |w, _, _| write_header(w))
    }
}

fn write_header(w: &mut impl Write) -> io::Result<()> {
    writeln!(w, "# written by tmc {}", env!("CARGO_PKG_VERSION"))
}

fn write_vertex(w: &mut impl Write, [x, y, z]: &[f32; 3]) -> io::Result<()> {
    writeln!(w, "v {x} {y} {z}")
}

fn write_face(w: &mut impl Write, [a, b, c]: [u64; 3]) -> io::Result<()> {
    writeln!(w, "f {} {} {}", a + 1, b + 1, c + 1)
}
