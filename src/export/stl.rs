//! Binary STL output; whole meshes ([`write_stl`]) or streamed chunks
//! ([`StlSink`]). STL has no shared vertices: each facet stores its own
//! three corners and a unit normal computed from them (zero if degenerate).

use super::numbering::Numbering;
use crate::files::AtomicFile;
use crate::mesh::Mesh;
use crate::mesh::{used_after_finish, Chunk, MeshInfo, MeshSink, Totals};
use crate::{Error, Result};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

/// Bytes before the facet count.
const HEADER_BYTES: u64 = 80;

/// Writes `mesh` as a binary STL file.
///
/// Triangles must index existing vertices and number at most `u32::MAX`
/// ([`super::write_mesh`] checks both).
pub fn write_stl(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    write_header(w, count)?;
    for t in &mesh.triangles {
        let corner = |k: usize| -> io::Result<[f32; 3]> {
            mesh.vertices.get(t[k] as usize).copied().ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "triangle refers to a missing vertex",
                )
            })
        };
        write_facet(w, corner(0)?, corner(1)?, corner(2)?)?;
    }
    Ok(())
}

/// Streams a binary STL file, byte-identical to [`write_stl`] of the same
/// mesh.
///
/// A triangle's corners lie in its own chunk or the next, so the sink holds
/// one chunk back: a chunk's facets are written when the next chunk arrives
/// (or at the end). The facet count, known at the end, is written into the
/// header in place.
pub struct StlSink {
    out: Option<BufWriter<AtomicFile>>,
    numbering: Numbering,
    /// The chunk whose facets wait for the next chunk's vertices.
    held: Chunk,
}

impl StlSink {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<StlSink> {
        let mut out = BufWriter::with_capacity(1 << 20, AtomicFile::create(path)?);
        // The count is rewritten at the end.
        write_header(&mut out, 0).map_err(|e| Error::io(path, e))?;
        Ok(StlSink {
            out: Some(out),
            numbering: Numbering::new(path),
            held: Chunk::default(),
        })
    }

    /// Writes the facets of the held chunk, whose triangles may reach into
    /// `next` (the following chunk's vertices).
    fn write_held(&mut self, next: &[[f32; 3]]) -> Result<()> {
        let out = self.out.as_mut().ok_or_else(used_after_finish)?;
        let own = &self.held.vertices;
        for t in &self.held.triangles {
            let corner = |i: u32| {
                let i = i as usize;
                own.get(i)
                    .or_else(|| next.get(i - own.len()))
                    .copied()
                    .ok_or_else(|| {
                        self.numbering.error(format!(
                            "a triangle of plane {} names a vertex beyond the next chunk",
                            self.held.plane
                        ))
                    })
            };
            let (a, b, c) = (corner(t[0])?, corner(t[1])?, corner(t[2])?);
            write_facet(out, a, b, c).map_err(|e| Error::io(out.get_ref().path(), e))?;
        }
        Ok(())
    }
}

impl MeshSink for StlSink {
    fn begin(&mut self, _info: &MeshInfo) -> Result<()> {
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.numbering.accept(base, chunk)?;
        if self.numbering.triangles() > u64::from(u32::MAX) {
            return Err(self.numbering.error(format!(
                "the mesh has more than {} triangles, more than binary STL can count",
                u32::MAX
            )));
        }
        self.write_held(&chunk.vertices)?;
        self.held.plane = chunk.plane;
        self.held.vertices.clear();
        self.held.vertices.extend_from_slice(&chunk.vertices);
        self.held.triangles.clear();
        self.held.triangles.extend_from_slice(&chunk.triangles);
        Ok(())
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.numbering.finish(totals)?;
        self.write_held(&[])?;
        let out = self.out.take().ok_or_else(used_after_finish)?;
        let path = out.get_ref().path().to_path_buf();
        let count = self.numbering.triangles() as u32;
        let mut file = out
            .into_inner()
            .map_err(|e| Error::io(&path, e.into_error()))?;
        let patch = file
            .file()
            .seek(SeekFrom::Start(HEADER_BYTES))
            .and_then(|_| file.write_all(&count.to_le_bytes()));
        patch.map_err(|e| Error::io(&path, e))?;
        file.commit()
    }
}

/// The 80-byte header (which must not start with "solid", the mark of ASCII
/// STL) and the facet count.
fn write_header(w: &mut impl Write, count: u32) -> io::Result<()> {
    let mut header = [b' '; HEADER_BYTES as usize];
    let text = format!("binary STL written by tmc {}", env!("CARGO_PKG_VERSION"));
    header[..text.len()].copy_from_slice(text.as_bytes());
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())
}

/// One facet: normal, three corners, zero attribute bytes.
fn write_facet(w: &mut impl Write, a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> io::Result<()> {
    let mut bytes = [0u8; 50];
    for (out, x) in bytes
        .chunks_exact_mut(4)
        .zip(normal(a, b, c).iter().chain(&a).chain(&b).chain(&c))
    {
        out.copy_from_slice(&x.to_le_bytes());
    }
    w.write_all(&bytes)
}

/// The unit normal of triangle `a b c` (counter-clockwise), or zero.
fn normal(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [f32; 3] {
    let d = |p: [f32; 3], q: [f32; 3]| {
        [
            f64::from(p[0]) - f64::from(q[0]),
            f64::from(p[1]) - f64::from(q[1]),
            f64::from(p[2]) - f64::from(q[2]),
        ]
    };
    let (u, v) = (d(b, a), d(c, a));
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        [
            (n[0] / len) as f32,
            (n[1] / len) as f32,
            (n[2] / len) as f32,
        ]
    } else {
        [0.0; 3]
    }
}
