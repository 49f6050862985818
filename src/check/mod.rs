//! An independent, purely combinatorial mesh checker.
//!
//! [`check_mesh`] looks only at the triangle indices of a [`Mesh`] (positions
//! are never used) and reports whether the mesh is a closed, consistently
//! oriented 2-manifold, together with its Euler characteristic, connected
//! components and their genus. [`read_mesh`] loads PLY, OBJ, OFF and `.tmesh`
//! files so that meshes written by any tool can be checked. Nothing here
//! shares code with the extraction kernel: the checker is the referee of the
//! kernel's tests and of `tmc check`.
//!
//! ## Definitions
//! * A triangle is **invalid** when an index is out of range and
//!   **degenerate** when it repeats an index. Both kinds are counted and then
//!   ignored: every other quantity is computed over the remaining **proper**
//!   triangles.
//! * A vertex is **referenced** when a proper triangle uses it; the others are
//!   counted as unreferenced and ignored.
//! * An (undirected) edge is a **boundary** edge when one proper triangle uses
//!   it, **manifold** when two do, and **non-manifold** when more than two do.
//!   A manifold edge is **inconsistent** when both triangles traverse it in the
//!   same direction (their orientations disagree).
//! * A referenced vertex is **non-manifold** when its incident triangles do not
//!   form a single fan: its link (the edges opposite to it) is not one path
//!   or one cycle. The ends of a non-manifold edge are non-manifold vertices.
//! * **Components** are the classes of triangles connected through shared
//!   vertices (so two spheres touching at one vertex are one component, with
//!   one non-manifold vertex).
//! * The **Euler characteristic** is `V - E + F` over referenced vertices,
//!   edges of proper triangles and proper triangles.
//! * A component's **boundary loops** are the connected components of the
//!   graph of its boundary edges, and its **genus** is `(2 - χ - b) / 2` for
//!   `b` boundary loops, reported only for orientable components without
//!   non-manifold edges or vertices.
//!
//! ## Scaling
//! The checker never hashes edges. Triangles are bucketed by vertex (a
//! counting sort into a compressed incidence list); each undirected edge
//! `{v, w}` with `v < w` is then found exactly once among the triangles of
//! `v`, by sorting that vertex's few `(w, direction, triangle)` entries. The
//! same pass checks the vertex links. Components use a union-find over
//! vertices, orientability a union-find with parity over triangles. Memory is
//! a few words per vertex and per triangle.

mod read;

use std::io::Write;

use serde::Serialize;

use crate::Mesh;

pub use read::read_mesh;

/// Per-component figures of a [`MeshReport`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ComponentReport {
    /// Referenced vertices of the component.
    pub vertices: usize,
    /// Undirected edges of the component.
    pub edges: usize,
    /// Proper triangles of the component.
    pub triangles: usize,
    /// `vertices - edges + triangles`.
    pub euler: i64,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Connected components of the graph of the boundary edges.
    pub boundary_loops: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Vertices whose triangles do not form a single fan.
    pub non_manifold_vertices: usize,
    /// Manifold edges traversed twice in the same direction.
    pub inconsistent_edges: usize,
    /// Whether the triangles can be oriented so that every manifold edge is
    /// consistent (non-manifold edges are ignored).
    pub orientable: bool,
    /// Whether the triangles as given are consistently oriented
    /// (`inconsistent_edges == 0`).
    pub consistently_oriented: bool,
    /// `(2 - euler - boundary_loops) / 2` for an orientable component
    /// without non-manifold edges or vertices, `None` otherwise.
    pub genus: Option<i64>,
}

impl ComponentReport {
    /// True for a closed, consistently oriented 2-manifold component.
    pub fn is_closed_manifold(&self) -> bool {
        self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }
}

/// The result of [`check_mesh`]; see the module documentation for the
/// definitions.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct MeshReport {
    /// Vertices in the mesh (referenced or not).
    pub vertices: usize,
    /// Triangles in the mesh (proper or not).
    pub triangles: usize,
    /// Triangles with an index out of range (ignored otherwise).
    pub invalid_triangles: usize,
    /// Triangles repeating an index (ignored otherwise).
    pub degenerate_triangles: usize,
    /// Vertices used by no proper triangle.
    pub unreferenced_vertices: usize,
    /// Undirected edges of the proper triangles.
    pub edges: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Referenced vertices whose triangles do not form a single fan.
    pub non_manifold_vertices: usize,
    /// Manifold edges whose two triangles traverse them in the same
    /// direction.
    pub inconsistent_edges: usize,
    /// Connected components (triangles sharing a vertex are connected).
    pub components: usize,
    /// `V - E + F` over referenced vertices, edges and proper triangles.
    pub euler: i64,
    /// One entry per component, largest (by triangles) first.
    pub per_component: Vec<ComponentReport>,
}

impl MeshReport {
    /// True when the mesh is a closed, consistently oriented 2-manifold: no
    /// invalid or degenerate triangle, no boundary edge, no non-manifold edge
    /// or vertex and no inconsistent edge. Unreferenced vertices are allowed.
    /// An empty mesh is (vacuously) a closed manifold.
    pub fn is_closed_manifold(&self) -> bool {
        self.invalid_triangles == 0
            && self.degenerate_triangles == 0
            && self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }

    /// True when the mesh is a consistently oriented 2-manifold, possibly
    /// with boundary (an open surface): everything [`is_closed_manifold`]
    /// asks for except that boundary edges are allowed.
    ///
    /// [`is_closed_manifold`]: MeshReport::is_closed_manifold
    pub fn is_oriented_manifold(&self) -> bool {
        self.invalid_triangles == 0
            && self.degenerate_triangles == 0
            && self.non_manifold_edges == 0
            && self.non_manifold_vertices == 0
            && self.inconsistent_edges == 0
    }

    /// One line naming what keeps the mesh from being a consistently
    /// oriented manifold (empty when [`MeshReport::is_oriented_manifold`]).
    pub fn defects(&self) -> String {
        [
            (self.invalid_triangles, "invalid triangles"),
            (self.degenerate_triangles, "degenerate triangles"),
            (self.non_manifold_edges, "non-manifold edges"),
            (self.non_manifold_vertices, "non-manifold vertices"),
            (self.inconsistent_edges, "inconsistently oriented edges"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// Sum of the genera of the components, when every component has one.
    pub fn total_genus(&self) -> Option<i64> {
        self.per_component.iter().map(|c| c.genus).sum()
    }

    /// Writes a human-readable, aligned summary (at most 20 component rows).
    /// The verdict of a mesh without triangles reads `yes (empty)`: it is
    /// closed only vacuously.
    pub fn print_text(&self, w: &mut impl Write) -> std::io::Result<()> {
        const MAX_ROWS: usize = 20;
        let yes_no = |b: bool| if b { "yes" } else { "no" };
        let rows: [(&str, String); 14] = [
            ("vertices", self.vertices.to_string()),
            ("triangles", self.triangles.to_string()),
            ("edges", self.edges.to_string()),
            ("invalid triangles", self.invalid_triangles.to_string()),
            (
                "degenerate triangles",
                self.degenerate_triangles.to_string(),
            ),
            (
                "unreferenced vertices",
                self.unreferenced_vertices.to_string(),
            ),
            ("boundary edges", self.boundary_edges.to_string()),
            ("non-manifold edges", self.non_manifold_edges.to_string()),
            (
                "non-manifold vertices",
                self.non_manifold_vertices.to_string(),
            ),
            ("inconsistent edges", self.inconsistent_edges.to_string()),
            ("components", self.components.to_string()),
            ("euler characteristic", self.euler.to_string()),
            (
                "total genus",
                self.total_genus()
                    .map_or_else(|| "-".to_string(), |g| g.to_string()),
            ),
            (
                "closed manifold",
                if self.triangles == 0 {
                    "yes (empty)".into()
                } else {
                    yes_no(self.is_closed_manifold()).into()
                },
            ),
        ];
        for (label, value) in &rows {
            writeln!(w, "{label:<22} {value:>12}")?;
        }
        if self.per_component.is_empty() {
            return Ok(());
        }
        writeln!(w)?;
        writeln!(
            w,
            "{:>6} {:>12} {:>12} {:>12} {:>8} {:>6} {:>6} {:>8} {:>8}",
            "comp",
            "vertices",
            "edges",
            "triangles",
            "euler",
            "loops",
            "genus",
            "oriented",
            "manifold"
        )?;
        for (i, c) in self.per_component.iter().take(MAX_ROWS).enumerate() {
            let oriented = if c.consistently_oriented {
                "yes"
            } else if c.orientable {
                "fixable"
            } else {
                "no"
            };
            let manifold = c.non_manifold_edges == 0 && c.non_manifold_vertices == 0;
            writeln!(
                w,
                "{:>6} {:>12} {:>12} {:>12} {:>8} {:>6} {:>6} {:>8} {:>8}",
                i,
                c.vertices,
                c.edges,
                c.triangles,
                c.euler,
                c.boundary_loops,
                c.genus.map_or_else(|| "-".to_string(), |g| g.to_string()),
                oriented,
                yes_no(manifold),
            )?;
        }
        if self.per_component.len() > MAX_ROWS {
            writeln!(
                w,
                "{:>6} ... and {} more components",
                "",
                self.per_component.len() - MAX_ROWS
            )?;
        }
        Ok(())
    }
}

/// Marker for "no value" in the `u32` index arrays.
const NONE: u32 = u32::MAX;

/// Union-find over `u32` ids with path halving and union by size.
struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] = self.size[a as usize].saturating_add(self.size[b as usize]);
    }
}

/// Union-find with parity over triangles: `flip(t)` is the parity from `t`
/// to its root, and a root remembers whether its class met a contradiction
/// (an odd cycle of orientation constraints, i.e. a non-orientable class).
struct ParityUnionFind {
    parent: Vec<u32>,
    /// Bit 0: parity to the parent. Bit 1 (roots only): contradiction seen.
    /// Bits 2..: rank, saturating.
    bits: Vec<u8>,
}

impl ParityUnionFind {
    const PARITY: u8 = 1;
    const CONFLICT: u8 = 2;
    const RANK_ONE: u8 = 4;

    fn new(n: usize) -> Self {
        ParityUnionFind {
            parent: (0..n as u32).collect(),
            bits: vec![0; n],
        }
    }

    /// Returns the root of `x` and the parity from `x` to it, compressing the
    /// path.
    fn find(&mut self, x: u32) -> (u32, u8) {
        // First pass: find the root and the total parity.
        let mut root = x;
        let mut parity = 0;
        while self.parent[root as usize] != root {
            parity ^= self.bits[root as usize] & Self::PARITY;
            root = self.parent[root as usize];
        }
        // Second pass: point every node on the path straight at the root.
        let (mut node, mut node_parity) = (x, parity);
        while node != root {
            let next = self.parent[node as usize];
            let old = self.bits[node as usize] & Self::PARITY;
            self.parent[node as usize] = root;
            self.bits[node as usize] = (self.bits[node as usize] & !Self::PARITY) | node_parity;
            node_parity ^= old;
            node = next;
        }
        (root, parity)
    }

    /// Requires `flip(a) ^ flip(b) == relation`.
    fn relate(&mut self, a: u32, b: u32, relation: u8) {
        let (ra, pa) = self.find(a);
        let (rb, pb) = self.find(b);
        if ra == rb {
            if pa ^ pb != relation {
                self.bits[ra as usize] |= Self::CONFLICT;
            }
            return;
        }
        let rank = |bits: u8| bits >> 2;
        let (ra_bits, rb_bits) = (self.bits[ra as usize], self.bits[rb as usize]);
        let (child, root) = if rank(ra_bits) < rank(rb_bits) {
            (ra, rb)
        } else {
            (rb, ra)
        };
        let conflict = (ra_bits | rb_bits) & Self::CONFLICT;
        self.parent[child as usize] = root;
        // Only the parity bit matters for a non-root node.
        self.bits[child as usize] = pa ^ pb ^ relation;
        let mut root_bits = self.bits[root as usize] | conflict;
        if rank(ra_bits) == rank(rb_bits) && rank(root_bits) < 63 {
            root_bits += Self::RANK_ONE;
        }
        self.bits[root as usize] = root_bits;
    }

    fn has_conflict(&mut self, x: u32) -> bool {
        let (root, _) = self.find(x);
        self.bits[root as usize] & Self::CONFLICT != 0
    }
}

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

/// Checks the combinatorial topology of `mesh`; see the module
/// documentation for the definitions.
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
    let mut link = LinkScratch::default();
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

    report.components = counters.len();
    report.per_component = counters.iter().map(component_report).collect();
    report
        .per_component
        .sort_by_key(|c| std::cmp::Reverse((c.triangles, c.vertices)));
    for c in &report.per_component {
        report.edges += c.edges;
        report.boundary_edges += c.boundary_edges;
        report.non_manifold_edges += c.non_manifold_edges;
        report.non_manifold_vertices += c.non_manifold_vertices;
        report.inconsistent_edges += c.inconsistent_edges;
        report.euler += c.euler;
    }
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

/// Scratch space for testing whether the link of a vertex (the edges
/// opposite to it in its triangles) is a single path or cycle.
#[derive(Default)]
struct LinkScratch {
    edges: Vec<(u32, u32)>,
    nodes: Vec<u32>,
    degree: Vec<u8>,
    parent: Vec<u8>,
}

impl LinkScratch {
    fn clear(&mut self) {
        self.edges.clear();
    }

    fn push(&mut self, a: u32, b: u32) {
        self.edges.push((a, b));
    }

    /// A connected multigraph without loops whose degrees are at most 2 is
    /// a path or a cycle, i.e. the triangles form one fan.
    fn is_single_fan(&mut self) -> bool {
        self.nodes.clear();
        self.nodes
            .extend(self.edges.iter().flat_map(|&(a, b)| [a, b]));
        self.nodes.sort_unstable();
        self.nodes.dedup();
        let n = self.nodes.len();
        if n > 255 {
            // Too many neighbours for the compact scratch arrays.
            return self.is_single_fan_large();
        }
        self.degree.clear();
        self.degree.resize(n, 0);
        self.parent.clear();
        self.parent.extend(0..n as u8);
        let mut pieces = n;
        for &(a, b) in &self.edges {
            let ia = self.nodes.binary_search(&a).unwrap_or(0);
            let ib = self.nodes.binary_search(&b).unwrap_or(0);
            for i in [ia, ib] {
                self.degree[i] += 1;
                if self.degree[i] > 2 {
                    return false;
                }
            }
            let (ra, rb) = (find_u8(&mut self.parent, ia), find_u8(&mut self.parent, ib));
            if ra != rb {
                self.parent[ra] = rb as u8;
                pieces -= 1;
            }
        }
        pieces == 1
    }

    fn is_single_fan_large(&self) -> bool {
        let index = |x: u32| self.nodes.binary_search(&x).unwrap_or(0) as u32;
        let mut degree = vec![0u32; self.nodes.len()];
        let mut uf = UnionFind::new(self.nodes.len());
        for &(a, b) in &self.edges {
            let (ia, ib) = (index(a), index(b));
            degree[ia as usize] += 1;
            degree[ib as usize] += 1;
            uf.union(ia, ib);
        }
        let root = uf.find(0);
        degree.iter().all(|&d| d <= 2) && (0..self.nodes.len() as u32).all(|i| uf.find(i) == root)
    }
}

fn find_u8(parent: &mut [u8], mut x: usize) -> usize {
    while parent[x] as usize != x {
        parent[x] = parent[parent[x] as usize];
        x = parent[x] as usize;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(nv: usize, triangles: &[[u32; 3]]) -> Mesh {
        Mesh {
            vertices: vec![[0.0; 3]; nv],
            triangles: triangles.to_vec(),
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
