//! Binary STL output. STL has no shared vertices: each facet stores its own
//! three corners and a unit normal computed from them (zero if degenerate).

use crate::Mesh;
use std::io::{self, Write};

/// Writes `mesh` as a binary STL file.
///
/// Triangles must index existing vertices and number at most `u32::MAX`
/// ([`super::write_mesh`] checks both).
pub fn write_stl(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    // The header must not start with "solid", which marks ASCII STL.
    let mut header = [b' '; 80];
    let text = format!("binary STL written by tmc {}", env!("CARGO_PKG_VERSION"));
    header[..text.len()].copy_from_slice(text.as_bytes());
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())?;
    for t in &mesh.triangles {
        let corner = |k: usize| -> io::Result<[f32; 3]> {
            mesh.vertices.get(t[k] as usize).copied().ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    "triangle refers to a missing vertex",
                )
            })
        };
        let (a, b, c) = (corner(0)?, corner(1)?, corner(2)?);
        for x in normal(a, b, c).iter().chain(&a).chain(&b).chain(&c) {
            w.write_all(&x.to_le_bytes())?;
        }
        w.write_all(&[0, 0])?;
    }
    Ok(())
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
