//! Helpers shared by the integration tests: the exact topology oracle, test
//! fields, and the comparison of a checked mesh with the oracle.
#![allow(dead_code)]

pub mod cli;
pub mod fields;
pub mod formats;
pub mod labels;
pub mod oracle;
pub mod signals;

use oracle::Topology;
use tmc::check::MeshReport;

/// Compares the report of an extracted mesh with the oracle's topology of
/// the same grid and isovalue (closed case: nothing positive on the grid
/// boundary). Returns a description of every disagreement.
pub fn compare_with_oracle(report: &MeshReport, topo: &Topology) -> Result<(), String> {
    let mut problems = Vec::new();
    if !report.is_closed_manifold() {
        problems.push(format!("mesh is not a closed manifold: {report:?}"));
    }
    match (topo.surface_components, topo.surface_euler) {
        (Some(components), Some(euler)) => {
            if report.components != components {
                problems.push(format!(
                    "components: mesh {} vs oracle {components}",
                    report.components
                ));
            }
            if report.euler != euler {
                problems.push(format!("euler: mesh {} vs oracle {euler}", report.euler));
            }
        }
        _ => problems.push("oracle: surface is not closed (positive sample on the border)".into()),
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("; "))
    }
}

/// The 48 symmetries of the cube: an axis permutation (new axis `i` is old
/// axis `perm[i]`) and a reflection per new axis.
pub fn symmetries() -> Vec<([usize; 3], [bool; 3])> {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut out = Vec::with_capacity(48);
    for perm in perms {
        for f in 0..8 {
            out.push((perm, [f & 1 != 0, f & 2 != 0, f & 4 != 0]));
        }
    }
    out
}

/// A grid (x fastest) under the symmetry `(perm, flip)`.
pub fn transform<T: Copy + Default>(
    dims: [usize; 3],
    g: &[T],
    perm: [usize; 3],
    flip: [bool; 3],
) -> ([usize; 3], Vec<T>) {
    let nd = perm.map(|a| dims[a]);
    let mut out = vec![T::default(); g.len()];
    for z in 0..nd[2] {
        for y in 0..nd[1] {
            for x in 0..nd[0] {
                let q = [x, y, z];
                let mut p = [0; 3];
                for i in 0..3 {
                    p[perm[i]] = if flip[i] { nd[i] - 1 - q[i] } else { q[i] };
                }
                out[x + nd[0] * (y + nd[1] * z)] = g[p[0] + dims[0] * (p[1] + dims[1] * p[2])];
            }
        }
    }
    (nd, out)
}

/// Parses an ASCII OFF file of triangles (an independent reader for the
/// writers' output).
pub fn parse_off(text: &str) -> tmc::Mesh {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("OFF"));
    let counts: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let mut mesh = tmc::Mesh::default();
    for _ in 0..counts[0] {
        let v: Vec<f32> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        mesh.vertices.push([v[0], v[1], v[2]]);
    }
    for _ in 0..counts[1] {
        let f: Vec<u32> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        assert_eq!(f[0], 3);
        mesh.triangles.push([f[1], f[2], f[3]]);
    }
    assert_eq!(lines.next(), None);
    mesh
}
