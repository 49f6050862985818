//! The vertex sweep of a [`StreamCheck::full`](super::StreamCheck::full):
//! what [`check_mesh`](super::check_mesh) finds at each vertex, found
//! while the chunks stream.
//!
//! A vertex's triangles are those of its own chunk and of the chunk before
//! (whose triangles reach into the first vertices of this one), so each
//! chunk hands the corners of its triangles at the next chunk's vertices on
//! to it, and a chunk's own vertices are swept once it is counted, as
//! `check_mesh` sweeps them: the link (the edges opposite the vertex) must
//! be one fan, an edge to a later vertex is traversed once in each
//! direction by its two triangles, and an edge of one triangle is a
//! boundary edge. Boundary loops (the components of the graph of boundary
//! edges) are counted as boundary vertices less the unions that joined two
//! of their classes, with a union-find over the window's vertices that
//! carries the classes of the next chunk's first vertices, as the
//! components do. A boundary vertex is one with an edge of one triangle:
//! at a manifold vertex, one whose link is a path; at a non-manifold one,
//! found among its edges (so that the count is `check_mesh`'s on any
//! mesh, which [`super::stream_components`] reports per component).

use super::link::LinkScratch;
use super::stream_components::Tally;
use super::union_find::find;

/// What a [`StreamCheck::full`](super::StreamCheck::full) counts beside
/// the preview's figures, with the definitions of
/// [`check_mesh`](super::check_mesh).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Links {
    /// Vertices no (proper) triangle uses.
    pub unreferenced_vertices: u64,
    /// Triangles that repeat a vertex (left out of everything else).
    pub degenerate_triangles: u64,
    /// Vertices whose triangles do not form a single fan.
    pub non_manifold_vertices: u64,
    /// Edges of two triangles that traverse them in the same direction.
    pub inconsistent_edges: u64,
    /// Components of the graph of boundary edges.
    pub boundary_loops: u64,
}

/// The figures of [`check_mesh`](super::check_mesh)'s report
/// ([`MeshReport`](super::MeshReport)) that a streaming check gives
/// ([`Verdict::checked`](super::Verdict::checked)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Checked {
    /// [`MeshReport::components`](super::MeshReport::components).
    pub components: u64,
    /// [`MeshReport::euler`](super::MeshReport::euler): referenced
    /// vertices, edges and proper triangles.
    pub euler: i64,
    /// [`MeshReport::total_genus`](super::MeshReport::total_genus): the
    /// sum of `(2 - χ - b) / 2` over the components, when no edge or
    /// vertex is non-manifold and no edge inconsistently oriented. (Where
    /// some edge is inconsistent, `check_mesh` still gives the genus of a
    /// component that could be oriented; telling that needs the whole
    /// component, so this gives none. Meshes tmc writes are consistently
    /// oriented.)
    pub genus: Option<i64>,
    /// [`MeshReport::is_closed_manifold`](super::MeshReport::is_closed_manifold).
    pub closed_manifold: bool,
}

/// A triangle's corner at a vertex of the next chunk: that vertex (from
/// the next chunk's first) and the corners after and before it, numbered
/// in the mesh.
#[derive(Debug, Clone, Copy)]
struct Corner {
    at: u32,
    next: u64,
    prev: u64,
}

/// What the sweep carries from chunk to chunk.
#[derive(Debug, Default)]
pub(super) struct LinkState {
    counts: Links,
    /// The corners at the next chunk's first vertices.
    carried: Vec<Corner>,
    /// Vertices with a boundary edge, and unions of two of their classes.
    boundary_vertices: u64,
    merges: u64,
    /// The class in the boundary graph of each of the current chunk's
    /// first vertices; empty when no two of them share one.
    loop_carry: Vec<u32>,
}

/// The sweep's working space ([`super::Scratch`]).
#[derive(Debug, Default)]
pub(super) struct SweepScratch {
    /// Where each vertex's corners start in `corners`, and a cursor.
    start: Vec<u32>,
    fill: Vec<u32>,
    /// Per corner: the corners after and before it, numbered in the mesh.
    corners: Vec<(u64, u64)>,
    fan: LinkScratch<u64>,
    /// A non-manifold vertex's neighbours, once per triangle edge.
    others: Vec<u64>,
    /// A vertex's edges to later vertices: the other end, and whether the
    /// triangle traverses it from the vertex.
    ends: Vec<(u64, bool)>,
    /// Boundary edges found, in window indices.
    boundary: Vec<[u32; 2]>,
    parent: Vec<u32>,
    class: Vec<u32>,
}

/// No class yet.
const NONE: u32 = u32::MAX;

impl LinkState {
    /// Triangles left out for repeating a vertex.
    pub(super) fn degenerate(&mut self, n: u64) {
        self.counts.degenerate_triangles += n;
    }

    /// Sweeps a chunk (as [`StreamCheck::chunk`](super::StreamCheck::chunk)
    /// is given it, proper triangles only) whose first vertex is `base`;
    /// with `at`, also tallies what it finds at each vertex of the window
    /// there.
    pub(super) fn chunk(
        &mut self,
        s: &mut SweepScratch,
        base: u64,
        own: u32,
        next: u32,
        triangles: &[[u32; 3]],
        mut at: Option<&mut [Tally]>,
    ) {
        let number = |i: u32| base + u64::from(i);
        let carried = std::mem::take(&mut self.carried);
        // Corners by vertex: a counting sort of the carried corners and
        // the chunk's, those at the next chunk's vertices carried on.
        let mut onward = Vec::new();
        s.start.clear();
        s.start.resize(own as usize + 1, 0);
        for c in carried.iter().filter(|c| c.at < own) {
            s.start[c.at as usize + 1] += 1;
        }
        for t in triangles {
            for k in 0..3 {
                let v = t[k];
                if v < own {
                    s.start[v as usize + 1] += 1;
                } else {
                    onward.push(Corner {
                        at: v - own,
                        next: number(t[(k + 1) % 3]),
                        prev: number(t[(k + 2) % 3]),
                    });
                }
            }
        }
        for i in 0..own as usize {
            s.start[i + 1] += s.start[i];
        }
        s.fill.clear();
        s.fill.extend_from_slice(&s.start[..own as usize]);
        s.corners.clear();
        s.corners.resize(s.start[own as usize] as usize, (0, 0));
        for c in carried.iter().filter(|c| c.at < own) {
            let f = &mut s.fill[c.at as usize];
            s.corners[*f as usize] = (c.next, c.prev);
            *f += 1;
        }
        for t in triangles {
            for k in 0..3 {
                let v = t[k];
                if v < own {
                    let f = &mut s.fill[v as usize];
                    s.corners[*f as usize] = (number(t[(k + 1) % 3]), number(t[(k + 2) % 3]));
                    *f += 1;
                }
            }
        }
        drop(carried);
        self.carried = onward;
        // Each own vertex, as check_mesh sweeps it.
        s.boundary.clear();
        for v in 0..own {
            let around = &s.corners[s.start[v as usize] as usize..s.start[v as usize + 1] as usize];
            if around.is_empty() {
                self.counts.unreferenced_vertices += 1;
                continue;
            }
            let number_v = number(v);
            s.fan.clear();
            s.ends.clear();
            for &(n, p) in around {
                s.fan.push(n, p);
                if n > number_v {
                    s.ends.push((n, true));
                }
                if p > number_v {
                    s.ends.push((p, false));
                }
            }
            let mut tally = Tally {
                first: number_v,
                vertices: 1,
                ..Tally::default()
            };
            if !s.fan.is_single_fan() {
                tally.non_manifold_vertices = 1;
                // Its boundary edges, if any, are those of one triangle.
                tally.boundary_vertices = u64::from(has_lone_edge(&mut s.others, around));
            } else if s.fan.is_path() {
                tally.boundary_vertices = 1;
            }
            s.ends.sort_unstable();
            for group in s.ends.chunk_by(|a, b| a.0 == b.0) {
                match group {
                    // A later vertex is in this chunk or the next's first.
                    [(w, _)] if w - base < u64::from(own + next) => {
                        s.boundary.push([v, (w - base) as u32])
                    }
                    [(_, d1), (_, d2)] if d1 == d2 => tally.inconsistent_edges += 1,
                    _ => {}
                }
            }
            self.counts.non_manifold_vertices += tally.non_manifold_vertices;
            self.counts.inconsistent_edges += tally.inconsistent_edges;
            self.boundary_vertices += tally.boundary_vertices;
            if let Some(at) = &mut at {
                at[v as usize].add(&tally);
            }
        }
        self.merges += self.unite(s, own, next, at);
    }

    /// Unites the ends of the boundary edges found, over the window's
    /// vertices with the carried classes; the unions that joined two
    /// classes. Leaves the classes of the next chunk's first vertices.
    fn unite(
        &mut self,
        s: &mut SweepScratch,
        own: u32,
        next: u32,
        mut at: Option<&mut [Tally]>,
    ) -> u64 {
        if s.boundary.is_empty() {
            // The next chunk's vertices are joined to nothing yet.
            self.loop_carry = Vec::new();
            return 0;
        }
        let n = (own + next) as usize;
        s.parent.clear();
        s.parent.extend(0..own + next);
        // Vertices of one carried class: one of them is its root.
        s.class.clear();
        s.class.resize(self.loop_carry.len(), NONE);
        for (j, &c) in self.loop_carry.iter().enumerate().take(own as usize) {
            match s.class[c as usize] {
                NONE => s.class[c as usize] = j as u32,
                root => s.parent[j] = root,
            }
        }
        let mut merges = 0;
        for &[a, b] in &s.boundary {
            let (ra, rb) = (find(&mut s.parent, a), find(&mut s.parent, b));
            if ra != rb {
                s.parent[ra.max(rb) as usize] = ra.min(rb);
                merges += 1;
                if let Some(at) = &mut at {
                    at[a as usize].boundary_merges += 1;
                }
            }
        }
        // Classes of the next chunk's first vertices, by first use.
        s.class.clear();
        s.class.resize(n, NONE);
        self.loop_carry.clear();
        let (mut classes, mut shared) = (0, false);
        for j in own..own + next {
            let r = find(&mut s.parent, j) as usize;
            if s.class[r] == NONE {
                s.class[r] = classes;
                classes += 1;
            } else {
                shared = true;
            }
            self.loop_carry.push(s.class[r]);
        }
        if !shared {
            self.loop_carry = Vec::new();
        }
        merges
    }

    /// The counts once the last chunk has been swept.
    pub(super) fn finish(self) -> Links {
        Links {
            boundary_loops: self.boundary_vertices - self.merges,
            ..self.counts
        }
    }
}

/// Whether one of the edges round a vertex (its corners' `around`: the
/// corners after and before it) is used by one triangle only.
fn has_lone_edge(others: &mut Vec<u64>, around: &[(u64, u64)]) -> bool {
    others.clear();
    others.extend(around.iter().flat_map(|&(n, p)| [n, p]));
    others.sort_unstable();
    others.chunk_by(|a, b| a == b).any(|run| run.len() == 1)
}
