//! Normals from the triangles, for the vertices where the field's gradient
//! says nothing.

use super::vector::{cross, dot, sub, unit};
use crate::error::try_filled;
use crate::mesh::Mesh;
use crate::Result;

/// Marks a vertex that has no normal yet (every other entry of the normals
/// is finite).
pub const PENDING: [f32; 3] = [f32::NAN; 3];

/// Gives every [`PENDING`] entry of `normals` (one per vertex of `mesh`)
/// the angle-weighted average of the unit normals of the vertex's
/// triangles, normalized; `[0, 0, 0]` where that is zero or undefined (no
/// triangle, or only degenerate ones).
///
/// Why: on a plateau or a tie (integer data at its isovalue, the NaN
/// border of `--close`) the interpolated gradient can vanish, while the
/// triangles around the vertex still show which way is out. Triangles are
/// counter-clockwise seen from outside in world coordinates (a mirroring
/// grid flips their winding, see [`Grid`](crate::grid::Grid)), so their
/// normals point outward as they are. Weighting by the angle at the vertex
/// makes the result independent of how the fan around it is cut.
///
/// Triangles with a vertex number out of range are skipped. One pass over
/// the triangles, in order, so the result is deterministic; it does nothing
/// (and allocates nothing) when no entry is pending.
pub fn fill_pending(mesh: &Mesh, normals: &mut [[f32; 3]]) -> Result<()> {
    let pending = |n: &[f32; 3]| n[0].is_nan();
    let count = normals.iter().filter(|n| pending(n)).count();
    if count == 0 {
        return Ok(());
    }
    // Slot of each pending vertex in `sums`; `usize::MAX` for the others.
    let mut slot = try_filled("the vertices without a gradient", normals.len(), usize::MAX)?;
    let mut sums = try_filled("the vertices without a gradient", count, [0.0f64; 3])?;
    for (s, i) in (0..normals.len())
        .filter(|&i| pending(&normals[i]))
        .enumerate()
    {
        slot[i] = s;
    }
    let n = normals.len();
    for tri in &mesh.triangles {
        let corners = tri.map(|v| v as usize);
        if corners.iter().any(|&v| v >= n) || corners.iter().all(|&v| slot[v] == usize::MAX) {
            continue;
        }
        let p = corners.map(|v| mesh.vertices[v].map(f64::from));
        let normal = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let twice_area = dot(normal, normal).sqrt();
        if !(twice_area > 0.0 && twice_area.is_finite()) {
            continue;
        }
        for k in 0..3 {
            let s = slot[corners[k]];
            if s == usize::MAX {
                continue;
            }
            let u = sub(p[(k + 1) % 3], p[k]);
            let v = sub(p[(k + 2) % 3], p[k]);
            // |u x v| is twice the area at every corner.
            let angle = twice_area.atan2(dot(u, v));
            for a in 0..3 {
                sums[s][a] += angle * normal[a] / twice_area;
            }
        }
    }
    for (i, normal) in normals.iter_mut().enumerate() {
        if slot[i] != usize::MAX {
            *normal = unit(sums[slot[i]]).unwrap_or([0.0; 3]);
        }
    }
    Ok(())
}
