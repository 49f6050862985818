//! [`check_mesh`]: one sweep over the triangles of each vertex finds every
//! edge once, checks the vertex links, and gathers the counts per component.

use super::geometry::check_geometry;
use super::link::LinkScratch;
use super::report::{ComponentReport, MeshReport};
use super::union_find::{ParityUnionFind, UnionFind, NONE};
use crate::mesh::Mesh;

/// Per-component counters accumulated during the sweep.
#[derive(Default, Clone)]
struct Counters {
    vertices: usize,
    edges: usize,
    triangles: usize,
    boundary_edges: usize,
    boundary_loops: usize,
    non_manifold_edges: usize,
    non_manifold_vertices: usize,
    inconsistent_edges: usize,
    non_orientable: bool,
}

/// Checks the combinatorial topology of `mesh`, and its geometry with
/// [`check_geometry`]; see [the definitions](crate::check#definitions).
///
/// # Panics
/// If the mesh has `u32::MAX` triangles or more (a `Mesh` that large cannot
/// be read or held by tmc anyway).
pub fn check_mesh(mesh: &Mesh) -> MeshReport {
    let nv = mesh.vertices.len();
    let tris = &mesh.triangles;
    assert!(
        tris.len() < NONE as usize,
        "check_mesh supports fewer than 2^32 - 1 triangles"
    );
    let mut report = MeshReport {
        vertices: nv,
        triangles: tris.len(),
        geometry: check_geometry(mesh),
        ..MeshReport::default()
    };

    let is_proper = |t: &[u32; 3]| {
        t.iter().all(|&i| (i as usize) < nv) && t[0] != t[1] && t[1] != t[2] && t[0] != t[2]
    };
    for t in tris {
        if t.iter().any(|&i| i as usize >= nv) {
            report.invalid_triangles += 1;
        } else if !is_proper(t) {
            report.degenerate_triangles += 1;
        }
    }

    // Incidence lists: the proper triangles of each vertex (counting sort).
    let mut offsets = vec![0usize; nv + 1];
    for t in tris.iter().filter(|t| is_proper(t)) {
        for &i in t {
            offsets[i as usize + 1] += 1;
        }
    }
    for i in 0..nv {
        offsets[i + 1] += offsets[i];
    }
    let mut incident = vec![0u32; offsets[nv]];
    let mut fill = offsets[..nv].to_vec();
    for (ti, t) in tris.iter().enumerate() {
        if is_proper(t) {
            for &i in t {
                incident[fill[i as usize]] = ti as u32;
                fill[i as usize] += 1;
            }
        }
    }
    drop(fill);

    // Components: union-find over vertices, then dense ids.
    let mut uf = UnionFind::new(nv);
    for t in tris.iter().filter(|t| is_proper(t)) {
        uf.union(t[0], t[1]);
        uf.union(t[0], t[2]);
    }
    let mut comp = vec![NONE; nv];
    let mut root_id = vec![NONE; nv];
    let mut ncomp = 0u32;
    for v in 0..nv {
        if offsets[v] == offsets[v + 1] {
            report.unreferenced_vertices += 1;
            continue;
        }
        let r = uf.find(v as u32) as usize;
        if root_id[r] == NONE {
            root_id[r] = ncomp;
            ncomp += 1;
        }
        comp[v] = root_id[r];
    }
    drop(uf);
    drop(root_id);
    let mut counters = vec![Counters::default(); ncomp as usize];
    for t in tris.iter().filter(|t| is_proper(t)) {
        counters[comp[t[0] as usize] as usize].triangles += 1;
    }

    // The sweep over vertices: edges {v, w} with v < w, and the link of v.
    let mut orient = ParityUnionFind::new(tris.len());
    let mut boundary: Vec<(u32, u32)> = Vec::new();
    let mut entries: Vec<(u32, bool, u32)> = Vec::new();
    let mut link = LinkScratch::<u32>::default();
    for v in 0..nv {
        let around = &incident[offsets[v]..offsets[v + 1]];
        if around.is_empty() {
            continue;
        }
        let c = &mut counters[comp[v] as usize];
        c.vertices += 1;
        let v32 = v as u32;
        entries.clear();
        link.clear();
        for &ti in around {
            let t = tris[ti as usize];
            let at = t.iter().position(|&i| i == v32).unwrap_or(0);
            let (next, prev) = (t[(at + 1) % 3], t[(at + 2) % 3]);
            link.push(next, prev);
            // `true`: the triangle traverses the edge from its smaller end.
            if next > v32 {
                entries.push((next, true, ti));
            }
            if prev > v32 {
                entries.push((prev, false, ti));
            }
        }
        if !link.is_single_fan() {
            c.non_manifold_vertices += 1;
        }
        entries.sort_unstable_by_key(|e| e.0);
        for group in entries.chunk_by(|a, b| a.0 == b.0) {
            c.edges += 1;
            match group {
                [(w, _, _)] => {
                    c.boundary_edges += 1;
                    boundary.push((v32, *w));
                }
                [(_, d1, t1), (_, d2, t2)] => {
                    let same = *d1 == *d2;
                    if same {
                        c.inconsistent_edges += 1;
                    }
                    orient.relate(*t1, *t2, u8::from(same));
                }
                _ => c.non_manifold_edges += 1,
            }
        }
    }
    drop(incident);

    for t in 0..tris.len() {
        if is_proper(&tris[t]) && orient.has_conflict(t as u32) {
            counters[comp[tris[t][0] as usize] as usize].non_orientable = true;
        }
    }
    drop(orient);

    // Boundary loops: components of the boundary-edge graph, per component.
    if !boundary.is_empty() {
        let mut ends: Vec<u32> = boundary.iter().flat_map(|&(a, b)| [a, b]).collect();
        ends.sort_unstable();
        ends.dedup();
        let local = |x: u32| ends.binary_search(&x).unwrap_or(0) as u32;
        let mut buf = UnionFind::new(ends.len());
        for &(a, b) in &boundary {
            buf.union(local(a), local(b));
        }
        for (i, &v) in ends.iter().enumerate() {
            if buf.find(i as u32) == i as u32 {
                counters[comp[v as usize] as usize].boundary_loops += 1;
            }
        }
    }

    let mut per_component: Vec<ComponentReport> = counters.iter().map(component_report).collect();
    per_component.sort_by_key(|c| std::cmp::Reverse((c.triangles, c.vertices)));
    report.set_components(per_component);
    report
}

fn component_report(c: &Counters) -> ComponentReport {
    let euler = c.vertices as i64 - c.edges as i64 + c.triangles as i64;
    let manifold = c.non_manifold_edges == 0 && c.non_manifold_vertices == 0;
    let twice_genus = 2 - euler - c.boundary_loops as i64;
    let genus = (manifold && !c.non_orientable && twice_genus >= 0 && twice_genus % 2 == 0)
        .then_some(twice_genus / 2);
    ComponentReport {
        vertices: c.vertices,
        edges: c.edges,
        triangles: c.triangles,
        euler,
        boundary_edges: c.boundary_edges,
        boundary_loops: c.boundary_loops,
        non_manifold_edges: c.non_manifold_edges,
        non_manifold_vertices: c.non_manifold_vertices,
        inconsistent_edges: c.inconsistent_edges,
        orientable: !c.non_orientable,
        consistently_oriented: c.inconsistent_edges == 0,
        genus,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(nv: usize, triangles: &[[u32; 3]]) -> Mesh {
        Mesh {
            vertices: vec![[0.0; 3]; nv],
            triangles: triangles.to_vec(),
            ..Mesh::default()
        }
    }

    /// A tetrahedron on vertices `o..o+4`, consistently oriented.
    fn tetrahedron(o: u32) -> Vec<[u32; 3]> {
        vec![
            [o, o + 2, o + 1],
            [o, o + 1, o + 3],
            [o + 1, o + 2, o + 3],
            [o, o + 3, o + 2],
        ]
    }

    /// The 12 triangles of a cube with corners `x + 2y + 4z`, oriented
    /// outward.
    fn cube() -> Vec<[u32; 3]> {
        let quads = [
            [0, 2, 3, 1], // z = 0
            [4, 5, 7, 6], // z = 1
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect()
    }

    /// An `n` x `m` grid with wrap-around in both directions.
    fn torus(n: u32, m: u32) -> Mesh {
        let id = |i: u32, j: u32| (i % n) + n * (j % m);
        let mut t = Vec::new();
        for j in 0..m {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
        mesh((n * m) as usize, &t)
    }

    #[test]
    fn tetrahedron_is_a_sphere() {
        let r = check_mesh(&mesh(4, &tetrahedron(0)));
        assert!(r.is_closed_manifold(), "{r:?}");
        assert_eq!((r.edges, r.euler, r.components), (6, 2, 1));
        assert_eq!(r.per_component[0].genus, Some(0));
        assert_eq!(r.total_genus(), Some(0));
    }

    #[test]
    fn cube_is_a_sphere_until_a_triangle_flips() {
        let mut t = cube();
        let r = check_mesh(&mesh(8, &t));
        assert!(r.is_closed_manifold(), "{r:?}");
        assert_eq!((r.vertices, r.edges, r.triangles, r.euler), (8, 18, 12, 2));
        t[5].swap(0, 1);
        let r = check_mesh(&mesh(8, &t));
        assert_eq!(r.inconsistent_edges, 3);
        assert!(!r.is_closed_manifold());
        let c = &r.per_component[0];
        assert!(c.orientable && !c.consistently_oriented);
        assert_eq!(c.genus, Some(0));
    }

    #[test]
    fn open_square_has_one_boundary_loop() {
        let r = check_mesh(&mesh(4, &[[0, 1, 2], [0, 2, 3]]));
        assert_eq!((r.boundary_edges, r.euler, r.components), (4, 1, 1));
        let c = &r.per_component[0];
        assert_eq!((c.boundary_loops, c.genus), (1, Some(0)));
        assert!(!r.is_closed_manifold());
        assert_eq!(r.non_manifold_vertices, 0);
    }

    #[test]
    fn grid_torus_has_genus_one() {
        let r = check_mesh(&torus(5, 4));
        assert!(r.is_closed_manifold(), "{r:?}");
        assert_eq!((r.euler, r.components), (0, 1));
        assert_eq!(r.per_component[0].genus, Some(1));
    }

    #[test]
    fn tetrahedra_sharing_an_edge() {
        let mut t = tetrahedron(0);
        // The second tetrahedron uses vertices 0, 1, 4, 5.
        t.extend(
            tetrahedron(2)
                .iter()
                .map(|t| t.map(|i| if i < 4 { i - 2 } else { i })),
        );
        let r = check_mesh(&mesh(6, &t));
        assert_eq!(r.non_manifold_edges, 1);
        assert_eq!(r.non_manifold_vertices, 2);
        assert_eq!(r.components, 1);
        assert_eq!(r.per_component[0].genus, None);
        assert!(!r.is_closed_manifold());
    }

    #[test]
    fn tetrahedra_sharing_a_vertex() {
        let mut t = tetrahedron(0);
        t.extend(
            tetrahedron(3)
                .iter()
                .map(|t| t.map(|i| if i == 3 { 0 } else { i })),
        );
        let r = check_mesh(&mesh(7, &t));
        assert_eq!((r.non_manifold_edges, r.non_manifold_vertices), (0, 1));
        assert_eq!((r.components, r.euler, r.boundary_edges), (1, 3, 0));
        assert!(!r.is_closed_manifold());
    }

    #[test]
    fn separate_tetrahedra_are_two_components() {
        let mut t = tetrahedron(0);
        t.extend(tetrahedron(4));
        let r = check_mesh(&mesh(9, &t));
        assert!(r.is_closed_manifold(), "{r:?}");
        assert_eq!((r.components, r.euler, r.unreferenced_vertices), (2, 4, 1));
        assert!(r.per_component.iter().all(|c| c.genus == Some(0)));
    }

    #[test]
    fn two_tori_make_genus_two_in_total() {
        let a = torus(4, 3);
        let mut t = a.triangles.clone();
        t.extend(a.triangles.iter().map(|t| t.map(|i| i + 12)));
        let r = check_mesh(&mesh(24, &t));
        assert_eq!((r.components, r.euler, r.total_genus()), (2, 0, Some(2)));
    }

    #[test]
    fn mobius_strip_is_not_orientable() {
        // A strip of 3 x 1 quads on 6 vertices glued with a half twist.
        let t = [
            [0, 1, 4],
            [0, 4, 3],
            [1, 2, 5],
            [1, 5, 4],
            [2, 3, 0],
            [2, 0, 5],
        ];
        let r = check_mesh(&mesh(6, &t));
        let c = &r.per_component[0];
        assert!(!c.orientable, "{r:?}");
        assert_eq!((c.boundary_loops, c.euler, c.genus), (1, 0, None));
    }

    #[test]
    fn bad_triangles_are_counted_and_ignored() {
        let mut t = tetrahedron(0);
        t.push([0, 0, 1]);
        t.push([0, 1, 9]);
        let r = check_mesh(&mesh(4, &t));
        assert_eq!((r.degenerate_triangles, r.invalid_triangles), (1, 1));
        assert_eq!((r.euler, r.boundary_edges), (2, 0));
        assert!(!r.is_closed_manifold());
    }

    #[test]
    fn empty_mesh() {
        let r = check_mesh(&Mesh::default());
        assert!(r.is_closed_manifold());
        assert_eq!((r.components, r.euler), (0, 0));
        let mut out = Vec::new();
        r.print_text(&mut out).unwrap();
        assert!(String::from_utf8(out).unwrap().contains("closed manifold"));
    }

    #[test]
    fn text_report_lists_components() {
        let mut t = tetrahedron(0);
        t.extend(tetrahedron(4));
        let r = check_mesh(&mesh(8, &t));
        let mut out = Vec::new();
        r.print_text(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("components"), "{text}");
        assert_eq!(
            text.lines()
                .filter(|l| l.trim_start().starts_with('1'))
                .count(),
            1
        );
    }
}
