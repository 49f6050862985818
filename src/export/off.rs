//! OFF (Object File Format) output, text; whole meshes ([`write_off`]) or
//! streamed chunks ([`OffSink`]).

use super::spooled::{write_whole, Layout, SpooledSink};
use crate::mesh::Mesh;
use std::io::{self, Write};

/// The OFF layout: `OFF`, the counts, vertices, then `3 a b c` faces.
#[derive(Debug)]
pub struct Off;

impl Layout for Off {
    fn header(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()> {
        writeln!(w, "OFF")?;
        writeln!(w, "{vertices} {faces} 0")
    }

    fn vertex(w: &mut impl Write, [x, y, z]: &[f32; 3]) -> io::Result<()> {
        writeln!(w, "{x} {y} {z}")
    }

    fn face(w: &mut impl Write, [a, b, c]: [u64; 3]) -> io::Result<()> {
        writeln!(w, "3 {a} {b} {c}")
    }
}

/// Streams an OFF file, byte-identical to [`write_off`] of the same mesh.
pub type OffSink = SpooledSink<Off>;

/// Writes `mesh` as an OFF file.
pub fn write_off(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_whole::<Off>(w, mesh)
}
