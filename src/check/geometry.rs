//! [`check_geometry`]: the two geometric defects a mesh can have without a
//! topological one: triangles of zero area, and vertices at the same
//! position (which a tool that merges by position, or computes normals,
//! cannot tell apart).

use super::report::Geometry;
use crate::mesh::Mesh;
use std::cmp::Ordering;

/// How many triangle numbers a [`Geometry`] lists per defect.
pub const FIRST_FEW: usize = 5;

/// The geometric checks of `mesh`; see [the definitions](crate::check#definitions).
/// Triangles with an index out of range or a repeated index are left to
/// the topological counts and not looked at here.
pub fn check_geometry(mesh: &Mesh) -> Geometry {
    let v = &mesh.vertices;
    let shared = shared_positions(v);
    let mut report = Geometry {
        shared_position_vertices: shared.iter().filter(|&&s| s).count(),
        ..Geometry::default()
    };
    for (ti, t) in mesh.triangles.iter().enumerate() {
        if t.iter().any(|&i| i as usize >= v.len()) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2]
        {
            continue;
        }
        if zero_area(t.map(|i| v[i as usize])) {
            report.zero_area_triangles += 1;
            if report.first_zero_area_triangles.len() < FIRST_FEW {
                report.first_zero_area_triangles.push(ti);
            }
        }
        if t.iter().any(|&i| shared[i as usize]) {
            report.shared_position_triangles += 1;
            if report.first_shared_position_triangles.len() < FIRST_FEW {
                report.first_shared_position_triangles.push(ti);
            }
        }
    }
    report
}

/// Whether the cross product of the triangle's edge vectors `b - a` and
/// `c - a`, in `f64` from the `f32` coordinates, is zero: exactly when the
/// three points are collinear (or two coincide), for coordinates within
/// 2^29 of one another in magnitude (the differences and products are then
/// exact). A NaN coordinate gives no zero.
pub(super) fn zero_area([a, b, c]: [[f32; 3]; 3]) -> bool {
    let d = |p: [f32; 3]| std::array::from_fn::<f64, 3, _>(|i| f64::from(p[i]) - f64::from(a[i]));
    let (u, w) = (d(b), d(c));
    let cross = [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ];
    cross == [0.0; 3]
}

/// Per vertex: does another vertex have the same position (equal
/// coordinates, `-0` equal to `0`; NaN equals nothing)? By sorting the
/// vertex numbers by position: four bytes per vertex besides the result.
fn shared_positions(v: &[[f32; 3]]) -> Vec<bool> {
    // `total_cmp` orders -0 before 0: positions are read with -0 as 0.
    let key = |i: u32| v[i as usize].map(|c| c + 0.0);
    let mut order: Vec<u32> = (0..v.len() as u32).collect();
    order.sort_unstable_by(|a, b| {
        let (p, q) = (key(*a), key(*b));
        (0..3)
            .map(|i| p[i].total_cmp(&q[i]))
            .find(|o| o.is_ne())
            .unwrap_or(Ordering::Equal)
    });
    let mut shared = vec![false; v.len()];
    for pair in order.windows(2) {
        // Equal keys are adjacent; `==` leaves NaN unequal.
        if key(pair[0]) == key(pair[1]) {
            shared[pair[0] as usize] = true;
            shared[pair[1] as usize] = true;
        }
    }
    shared
}
