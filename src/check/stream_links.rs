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
//!
//! The sweep also counts the edges, each at its smaller end (whose
//! triangles are all known when it is swept), and how many triangles use
//! each. Most vertices of a closed, consistently oriented surface are
//! told at once ([`one_cycle`]): following each corner to the one whose
//! previous corner is its next visits every corner once and comes back,
//! so the link is one cycle and every edge at the vertex has two
//! triangles, one each way; the others are looked at as above.

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
    /// Edges counted (each at its smaller end), of one triangle, and of
    /// three or more.
    edges: [u64; 3],
    /// The number in the mesh of the next chunk's first vertex.
    next_base: u64,
}

/// The sweep's working space ([`super::Scratch`]).
#[derive(Debug, Default)]
pub(super) struct SweepScratch {
    /// Where each vertex's corners start in `corners`, and a cursor.
    start: Vec<u32>,
    fill: Vec<u32>,
    /// Per corner: the corners after and before it, numbered in the mesh
    /// (the chunk's are the first `start[own]`; the room is that of the
    /// largest chunk so far).
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
        let start = &mut s.start[..];
        for c in carried.iter().filter(|c| c.at < own) {
            start[c.at as usize + 1] += 1;
        }
        for t in triangles {
            for k in 0..3 {
                let v = t[k];
                if v < own {
                    start[v as usize + 1] += 1;
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
            start[i + 1] += start[i];
        }
        s.fill.clear();
        s.fill.extend_from_slice(&start[..own as usize]);
        // Every corner is written below: the room is only grown.
        let total = start[own as usize] as usize;
        if s.corners.len() < total {
            s.corners.resize(total, (0, 0));
        }
        let (fill, corners) = (&mut s.fill[..], &mut s.corners[..total]);
        for c in carried.iter().filter(|c| c.at < own) {
            let f = &mut fill[c.at as usize];
            corners[*f as usize] = (c.next, c.prev);
            *f += 1;
        }
        for t in triangles {
            for k in 0..3 {
                let v = t[k];
                if v < own {
                    let f = &mut fill[v as usize];
                    corners[*f as usize] = (number(t[(k + 1) % 3]), number(t[(k + 2) % 3]));
                    *f += 1;
                }
            }
        }
        drop(carried);
        self.carried = onward;
        self.next_base = number(own);
        // Each own vertex, as check_mesh sweeps it.
        s.boundary.clear();
        let corners = std::mem::take(&mut s.corners);
        for v in 0..own {
            let around = &corners[s.start[v as usize] as usize..s.start[v as usize + 1] as usize];
            if around.is_empty() {
                self.counts.unreferenced_vertices += 1;
                continue;
            }
            let number_v = number(v);
            let mut tally = Tally {
                first: number_v,
                vertices: 1,
                ..Tally::default()
            };
            if one_cycle(around) {
                // Every edge at v has two triangles, one each way.
                tally.edges = around.iter().filter(|c| c.0 > number_v).count() as u64;
            } else {
                look_closer(s, v, base, own + next, around, &mut tally);
            }
            self.counts.non_manifold_vertices += tally.non_manifold_vertices;
            self.counts.inconsistent_edges += tally.inconsistent_edges;
            self.boundary_vertices += tally.boundary_vertices;
            self.edges[0] += tally.edges;
            self.edges[1] += tally.boundary_edges;
            self.edges[2] += tally.non_manifold_edges;
            if let Some(at) = &mut at {
                at[v as usize].add(&tally);
            }
        }
        s.corners = corners;
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

    /// The edges counted so far (each at its smaller end, once all its
    /// triangles are known): all, those of one triangle, those of three or
    /// more.
    pub(super) fn edges(&self) -> [u64; 3] {
        self.edges
    }

    /// The edges with both ends in the next chunk's first vertices, from
    /// the corners carried to it (which, after the last chunk, no sweep
    /// will count): smaller and larger end relative to that chunk, and how
    /// many triangles use each.
    pub(super) fn carried_edges(&self) -> Vec<[u32; 3]> {
        let mut ends: Vec<[u32; 2]> = Vec::new();
        for c in &self.carried {
            // The edges to later vertices, relative to that chunk.
            for other in [c.next, c.prev] {
                if other > self.next_base + u64::from(c.at) {
                    ends.push([c.at, (other - self.next_base) as u32]);
                }
            }
        }
        ends.sort_unstable();
        let runs = ends.chunk_by(|a, b| a == b);
        runs.map(|run| [run[0][0], run[0][1], run.len() as u32])
            .collect()
    }

    /// The counts once the last chunk has been swept.
    pub(super) fn finish(self) -> Links {
        Links {
            boundary_loops: self.boundary_vertices - self.merges,
            ..self.counts
        }
    }
}

/// The figures at own vertex `v` (numbered `base + v`, of a window of `n`
/// vertices) whose corners `around` are not [`one_cycle`]: its link
/// ([`LinkScratch`]), and its edges to later vertices sorted, a run of
/// one end being one edge and its length the edge's triangles (a boundary
/// edge is kept for the boundary loops).
fn look_closer(
    s: &mut SweepScratch,
    v: u32,
    base: u64,
    n: u32,
    around: &[(u64, u64)],
    tally: &mut Tally,
) {
    let number_v = base + u64::from(v);
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
    if !s.fan.is_single_fan() {
        tally.non_manifold_vertices = 1;
        // Its boundary edges, if any, are those of one triangle.
        tally.boundary_vertices = u64::from(has_lone_edge(&mut s.others, around));
    } else if s.fan.is_path() {
        tally.boundary_vertices = 1;
    }
    s.ends.sort_unstable();
    for group in s.ends.chunk_by(|a, b| a.0 == b.0) {
        tally.edge(group.len() as u32);
        match group {
            // A later vertex is in this chunk or the next's first.
            [(w, _)] if w - base < u64::from(n) => s.boundary.push([v, (w - base) as u32]),
            [(_, d1), (_, d2)] if d1 == d2 => tally.inconsistent_edges += 1,
            _ => {}
        }
    }
}

/// Whether a vertex's corners `around` (the corners after and before it
/// in each of its triangles, no two of a triangle the same) make one
/// cycle: from the first corner, the corner whose previous corner is this
/// one's next, again and again, is back at the first after visiting each
/// once. Then no two corners have the same previous corner (the first
/// corner with a given previous one is the one visited) nor the same
/// next, each neighbour is one corner's next and another's previous, and
/// so the link is one cycle (the vertex is manifold, not on the boundary)
/// and each edge at the vertex has two triangles, which traverse it in
/// opposite directions.
#[inline(never)]
fn one_cycle(around: &[(u64, u64)]) -> bool {
    let mut at = 0;
    for step in 0..around.len() {
        let want = around[at].0;
        let Some(j) = around.iter().position(|c| c.1 == want) else {
            return false;
        };
        if j == 0 {
            return step + 1 == around.len();
        }
        at = j;
    }
    false
}

/// Whether one of the edges round a vertex (its corners' `around`: the
/// corners after and before it) is used by one triangle only.
fn has_lone_edge(others: &mut Vec<u64>, around: &[(u64, u64)]) -> bool {
    others.clear();
    others.extend(around.iter().flat_map(|&(n, p)| [n, p]));
    others.sort_unstable();
    others.chunk_by(|a, b| a == b).any(|run| run.len() == 1)
}

#[cfg(test)]
mod tests {
    use super::super::link::LinkScratch;
    use super::one_cycle;

    /// The corners (next, previous) of the triangles `(v, a, b)` round a
    /// vertex `v`, rotated by `r`.
    fn corners(triangles: &[(u64, u64)], r: usize) -> Vec<(u64, u64)> {
        let mut c = triangles.to_vec();
        let n = c.len();
        c.rotate_left(r % n);
        c
    }

    /// Whether the link of those corners is one cycle, as `check_mesh`'s
    /// link test says, and, if so, whether every neighbour is one corner's
    /// next and another's previous (every edge at the vertex has two
    /// triangles, one each way).
    fn closed_and_oriented(around: &[(u64, u64)]) -> bool {
        let mut fan = LinkScratch::<u64>::default();
        for &(n, p) in around {
            fan.push(n, p);
        }
        let mut next: Vec<u64> = around.iter().map(|c| c.0).collect();
        let mut prev: Vec<u64> = around.iter().map(|c| c.1).collect();
        next.sort_unstable();
        prev.sort_unstable();
        let distinct = next.windows(2).all(|w| w[0] != w[1]);
        fan.is_single_fan() && !fan.is_path() && distinct && next == prev
    }

    #[test]
    fn one_cycle_is_a_closed_consistently_oriented_fan() {
        let fan: Vec<(u64, u64)> = (0..6).map(|i| (10 + i, 10 + (i + 1) % 6)).collect();
        let mut flipped = fan.clone();
        flipped[2] = (flipped[2].1, flipped[2].0);
        let open = fan[..5].to_vec();
        // Two fans meeting at the vertex: two cycles of the link.
        let bowtie = [(1, 2), (2, 3), (3, 1), (4, 5), (5, 6), (6, 4)];
        // One link node in both: a walk from corner to corner can pass
        // every corner, but the link is not one cycle.
        let eight = [(1, 2), (2, 3), (3, 1), (1, 5), (5, 6), (6, 1)];
        // Two triangles on the same three vertices, opposite ways.
        let pair = [(1, 2), (2, 1)];
        // The same triangle twice: its edges have three triangles each
        // with the one opposite.
        let doubled = [(1, 2), (2, 3), (3, 1), (3, 1)];
        let cases: [(&[(u64, u64)], bool); 7] = [
            (&fan, true),
            (&flipped, false),
            (&open, false),
            (&bowtie, false),
            (&eight, false),
            (&pair, true),
            (&doubled, false),
        ];
        for (i, (triangles, expected)) in cases.iter().enumerate() {
            for r in 0..triangles.len() {
                let mut around = corners(triangles, r);
                for reversed in [false, true] {
                    if reversed {
                        around.reverse();
                    }
                    let what = format!("case {i}, rotated {r}, reversed {reversed}");
                    assert_eq!(one_cycle(&around), *expected, "{what}");
                    assert_eq!(closed_and_oriented(&around), *expected, "{what}");
                }
            }
        }
    }
}
