//! OFF (Object File Format) output, text.

use crate::Mesh;
use std::io::{self, Write};

/// Writes `mesh` as an OFF file: counts, vertices, then `3 a b c` faces.
pub fn write_off(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    writeln!(w, "OFF")?;
    writeln!(w, "{} {} 0", mesh.vertices.len(), mesh.triangles.len())?;
    for [x, y, z] in &mesh.vertices {
        writeln!(w, "{x} {y} {z}")?;
    }
    for [a, b, c] in &mesh.triangles {
        writeln!(w, "3 {a} {b} {c}")?;
    }
    Ok(())
}
