//! Wavefront OBJ output (text, 1-based indices); whole meshes
//! ([`write_obj`]) or streamed chunks ([`ObjSink`]).

use super::spooled::{write_whole, Layout, SpooledSink};
use crate::mesh::Mesh;
use std::io::{self, Write};

/// The OBJ layout: a comment, `v x y z` lines, then `f a b c` lines; with
/// normals, each `v` line followed by its `vn nx ny nz` line (the `n`-th
/// `vn` is the `n`-th vertex's normal) and faces `f a//a b//b c//c`.
#[derive(Debug)]
pub struct Obj;

impl Layout for Obj {
    fn header(w: &mut impl Write, _vertices: u64, _faces: u64) -> io::Result<()> {
        writeln!(w, "# written by tmc {}", env!("CARGO_PKG_VERSION"))
    }

    fn vertex(w: &mut impl Write, [x, y, z]: &[f32; 3]) -> io::Result<()> {
        writeln!(w, "v {x} {y} {z}")
    }

    fn face(w: &mut impl Write, [a, b, c]: [u64; 3]) -> io::Result<()> {
        writeln!(w, "f {} {} {}", a + 1, b + 1, c + 1)
    }

    const NORMALS: bool = true;

    fn vertex_with_normal(
        w: &mut impl Write,
        v: &[f32; 3],
        [x, y, z]: &[f32; 3],
    ) -> io::Result<()> {
        Self::vertex(w, v)?;
        writeln!(w, "vn {x} {y} {z}")
    }

    fn face_with_normals(w: &mut impl Write, t: [u64; 3]) -> io::Result<()> {
        let [a, b, c] = t.map(|i| i + 1);
        writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")
    }
}

/// Streams an OBJ file, byte-identical to [`write_obj`] of the same mesh.
pub type ObjSink = SpooledSink<Obj>;

/// Writes `mesh` as an OBJ file.
pub fn write_obj(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    write_whole::<Obj>(w, mesh)
}
