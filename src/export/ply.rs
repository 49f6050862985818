//! PLY output: binary little-endian, float coordinates, `uchar uint` face
//! lists.

use crate::Mesh;
use std::io::{self, Write};

/// Writes `mesh` as a binary little-endian PLY file.
pub fn write_ply(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write!(
        w,
        "ply\n\
         format binary_little_endian 1.0\n\
         comment written by tmc {}\n\
         element vertex {}\n\
         property float x\n\
         property float y\n\
         property float z\n\
         element face {}\n\
         property list uchar uint vertex_indices\n\
         end_header\n",
        env!("CARGO_PKG_VERSION"),
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        for c in v {
            w.write_all(&c.to_le_bytes())?;
        }
    }
    for t in &mesh.triangles {
        w.write_all(&[3])?;
        for i in t {
            w.write_all(&i.to_le_bytes())?;
        }
    }
    Ok(())
}
