//! PLY output: binary little-endian, float coordinates, `uchar uint` face
//! lists; whole meshes ([`write_ply`]) or streamed chunks ([`PlySink`]).

use super::spooled::{write_whole, Layout, SpooledSink};
use crate::mesh::Mesh;
use std::io::{self, Write};

/// The PLY layout: binary little-endian, float x, y, z, `uchar uint` faces.
#[derive(Debug)]
pub struct Ply;

impl Layout for Ply {
    /// Its face lists hold `uint` indices.
    const MAX_VERTICES: u64 = 1 << 32;
    const TOO_MANY: &'static str =
        "more than PLY's 32-bit indices can name; write .obj, .off or .tmesh instead";

    fn header(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()> {
        write_header(w, vertices, faces, "")
    }

    fn vertex(w: &mut impl Write, v: &[f32; 3]) -> io::Result<()> {
        let mut bytes = [0u8; 12];
        for (out, c) in bytes.chunks_exact_mut(4).zip(v) {
            out.copy_from_slice(&c.to_le_bytes());
        }
        w.write_all(&bytes)
    }

    const NORMALS: bool = true;

    fn header_with_normals(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()> {
        write_header(w, vertices, faces, NORMAL_PROPERTIES)
    }

    /// x, y, z, nx, ny, nz: six little-endian `float`s.
    fn vertex_with_normal(w: &mut impl Write, v: &[f32; 3], normal: &[f32; 3]) -> io::Result<()> {
        let mut bytes = [0u8; 24];
        for (out, c) in bytes.chunks_exact_mut(4).zip(v.iter().chain(normal)) {
            out.copy_from_slice(&c.to_le_bytes());
        }
        w.write_all(&bytes)
    }

    fn face(w: &mut impl Write, t: [u64; 3]) -> io::Result<()> {
        // Indices below MAX_VERTICES: the sink checks before writing.
        let mut bytes = [3u8; 13];
        for (out, i) in bytes[1..].chunks_exact_mut(4).zip(t) {
            out.copy_from_slice(&(i as u32).to_le_bytes());
        }
        w.write_all(&bytes)
    }

    const LABELS: bool = true;

    /// The faces end in `property uint label`.
    fn header_with_labels(
        w: &mut impl Write,
        vertices: u64,
        faces: u64,
        normals: bool,
    ) -> io::Result<()> {
        let extra = if normals { NORMAL_PROPERTIES } else { "" };
        write_header_with(w, vertices, faces, extra, LABEL_PROPERTY)
    }

    /// The face, then its label as a little-endian `uint`.
    fn face_with_label(
        w: &mut impl Write,
        t: [u64; 3],
        _normals: bool,
        label: u32,
    ) -> io::Result<()> {
        Self::face(w, t)?;
        w.write_all(&label.to_le_bytes())
    }
}

/// Streams a PLY file, byte-identical to [`write_ply`] of the same mesh.
pub type PlySink = SpooledSink<Ply>;

/// Writes `mesh` as a PLY file.
pub fn write_ply(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_whole::<Ply>(w, mesh)
}

/// The face property of a labelled mesh, after the vertex indices.
const LABEL_PROPERTY: &str = "property uint label\n";

/// The vertex properties of the normals, after x, y and z.
const NORMAL_PROPERTIES: &str = "property float nx\nproperty float ny\nproperty float nz\n";

/// The header; `extra` is what follows the z property (the normals' or nothing).
fn write_header(w: &mut impl Write, vertices: u64, faces: u64, extra: &str) -> io::Result<()> {
    write_header_with(w, vertices, faces, extra, "")
}

/// The header of tmc's binary PLY; `extra` follows the z property and
/// `face_extra` the face's `vertex_indices`.
fn write_header_with(
    w: &mut impl Write,
    vertices: u64,
    faces: u64,
    extra: &str,
    face_extra: &str,
) -> io::Result<()> {
    write!(
        w,
        "ply\n\
         format binary_little_endian 1.0\n\
         comment written by tmc {}\n\
         element vertex {vertices}\n\
         property float x\n\
         property float y\n\
         property float z\n\
         {extra}\
         element face {faces}\n\
         property list uchar uint vertex_indices\n\
         {face_extra}\
         end_header\n",
        env!("CARGO_PKG_VERSION"),
    )
}
