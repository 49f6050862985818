//! Wavefront OBJ output (text, 1-based indices).

use crate::Mesh;
use std::io::{self, Write};

/// Writes `mesh` as an OBJ file: `v x y z` lines, then `f a b c` lines.
pub fn write_obj(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    writeln!(w, "# written by tmc {}", env!("CARGO_PKG_VERSION"))?;
    for [x, y, z] in &mesh.vertices {
        writeln!(w, "v {x} {y} {z}")?;
    }
    for [a, b, c] in &mesh.triangles {
        writeln!(w, "f {} {} {}", a + 1, b + 1, c + 1)?;
    }
    Ok(())
}
