//! The closed/genus verdict a preview writes under its picture, counted
//! while the chunks stream, in plane order, without holding the mesh.
//!
//! A chunk's triangles use its own vertices and a prefix of the next
//! chunk's ([`crate::Chunk`]), so the count needs a window of two chunks:
//! * **components**: a union-find over the classes the current chunk's
//!   vertices belong to (carried from the chunks before) and the next
//!   chunk's prefix; a class none of whose members reaches the next chunk
//!   is a finished component;
//! * **edges**: a chunk's edges kept at their smaller end and counted; an edge with both ends
//!   in the next chunk may also be used by that chunk's triangles and is
//!   carried to it, one with both ends in the chunk's own vertices may have
//!   been carried from the chunk before and is matched against that list.
//!
//! The mesh is **closed** when every edge has two triangles; its genus is
//! then `C - χ/2` summed over its `C` components (`χ = V - E + F`), as
//! `tmc check` reports for a closed orientable mesh. Memory is that of two
//! chunks.

/// Places per vertex for the edges it is the smaller end of
/// ([`Topology::edges`]).
const SLOTS: usize = 6;

/// What the preview says about the topology of the mesh.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Verdict {
    /// Connected components (through shared vertices).
    pub components: u64,
    /// Distinct edges.
    pub edges: u64,
    /// Edges of one triangle.
    pub boundary_edges: u64,
    /// Edges of three or more triangles.
    pub nonmanifold_edges: u64,
    /// Vertices seen.
    pub vertices: u64,
    /// Triangles seen.
    pub triangles: u64,
}

impl Verdict {
    /// Euler characteristic `V - E + F`.
    pub fn euler(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.triangles as i64
    }

    /// Whether every edge has exactly two triangles.
    pub fn closed(&self) -> bool {
        self.boundary_edges == 0 && self.nonmanifold_edges == 0
    }

    /// Total genus of a closed mesh (`None` for an open one).
    pub fn genus(&self) -> Option<i64> {
        self.closed()
            .then(|| self.components as i64 - self.euler() / 2)
    }

    /// One more distinct edge, used by `count` triangles.
    fn tally(&mut self, count: u32) {
        self.edges += 1;
        match count {
            1 => self.boundary_edges += 1,
            2 => {}
            _ => self.nonmanifold_edges += 1,
        }
    }

    /// The verdict in a few words, as the caption shows it ("empty" for a
    /// mesh without triangles: no surface at that isovalue).
    pub fn describe(&self) -> String {
        if self.triangles == 0 {
            return "empty: no surface".into();
        }
        let parts = format!(
            "{} component{}",
            self.components,
            if self.components == 1 { "" } else { "s" }
        );
        match self.genus() {
            Some(g) => format!("closed, genus {g}, {parts}"),
            None if self.nonmanifold_edges > 0 => {
                format!("NOT MANIFOLD ({} edges), {parts}", self.nonmanifold_edges)
            }
            None => format!("open ({} boundary edges), {parts}", self.boundary_edges),
        }
    }
}

/// The streaming count: feed it each chunk's window in plane order
/// ([`Topology::chunk`]), then [`Topology::finish`].
#[derive(Debug, Default)]
pub struct Topology {
    verdict: Verdict,
    /// Class of each vertex of the chunk being counted (a prefix; vertices
    /// past it have classes of their own).
    carry: Vec<u32>,
    /// Classes in use by `carry`.
    classes: u32,
    /// Edges with both ends in the next chunk's vertices: smaller and
    /// larger end relative to that chunk, and the triangles seen so far.
    carried_edges: Vec<[u32; 3]>,
    /// Scratch: the union-find parents and the roots reaching the next
    /// chunk; per root, a mark (reaching, finished) and its new class.
    parent: Vec<u32>,
    roots: Vec<u32>,
    mark: Vec<u32>,
    /// Scratch: the edges by smaller end, [`SLOTS`] places each: how many
    /// are in use, the larger ends and their triangles; edges past a full
    /// vertex's places go to `spill`, once per triangle.
    used: Vec<u8>,
    places: Vec<Places>,
    spill: Vec<[u32; 2]>,
}

impl Topology {
    /// Counts one chunk: `own` vertices of its own, triangles indexing them
    /// and then the first `next` vertices of the next chunk. A triangle
    /// with an index past those is left out.
    pub fn chunk(&mut self, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let n = own.saturating_add(next);
        self.verdict.vertices += u64::from(own);
        if triangles.iter().any(|t| t[0].max(t[1]).max(t[2]) >= n) {
            let valid: Vec<[u32; 3]> = triangles
                .iter()
                .copied()
                .filter(|t| t[0].max(t[1]).max(t[2]) < n)
                .collect();
            self.count(own, next, &valid);
        } else {
            self.count(own, next, triangles);
        }
    }

    /// [`Topology::chunk`] of triangles whose indices are all below
    /// `own + next`.
    fn count(&mut self, own: u32, next: u32, triangles: &[[u32; 3]]) {
        self.verdict.triangles += triangles.len() as u64;
        self.components(own, next, triangles);
        self.edges(own, next, triangles);
    }

    /// The verdict once the last chunk has been counted.
    pub fn finish(mut self) -> Verdict {
        self.verdict.components += u64::from(self.classes);
        for [_, _, count] in std::mem::take(&mut self.carried_edges) {
            self.verdict.tally(count);
        }
        self.verdict
    }

    /// Union-find over the carried classes and the next chunk's prefix.
    fn components(&mut self, own: u32, next: u32, triangles: &[[u32; 3]]) {
        // Vertices past the carried prefix start classes of their own.
        while (self.carry.len() as u32) < own {
            self.carry.push(self.classes);
            self.classes += 1;
        }
        let k = self.classes;
        let size = (k + next) as usize;
        self.parent.clear();
        self.parent.extend(0..k + next);
        let carry = &self.carry[..own as usize];
        let element = |v: u32| match carry.get(v as usize) {
            Some(&class) => class,
            None => k + v - own,
        };
        let parent = &mut self.parent[..];
        for t in triangles {
            let ra = find(parent, element(t[0]));
            let rb = find(parent, element(t[1]));
            let r = if ra != rb {
                let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
                parent[hi as usize] = lo;
                lo
            } else {
                ra
            };
            let rc = find(parent, element(t[2]));
            if rc != r {
                let (lo, hi) = if r < rc { (r, rc) } else { (rc, r) };
                parent[hi as usize] = lo;
            }
        }
        // Roots reaching the next chunk (mark 1), and the classes that
        // finish here (counted, mark 2).
        self.roots.clear();
        self.mark.clear();
        self.mark.resize(size, 0);
        for j in 0..next {
            let r = find(parent, k + j);
            self.roots.push(r);
            self.mark[r as usize] = 1;
        }
        for class in 0..k {
            let r = find(parent, class) as usize;
            if self.mark[r] == 0 {
                self.mark[r] = 2;
                self.verdict.components += 1;
            }
        }
        // Classes for the next chunk's prefix, numbered by first use (the
        // mark of a reaching root becomes its class plus 3).
        self.carry.clear();
        self.classes = 0;
        for &r in &self.roots {
            let m = &mut self.mark[r as usize];
            if *m == 1 {
                *m = self.classes + 3;
                self.classes += 1;
            }
            self.carry.push(*m - 3);
        }
    }

    /// Counts the chunk's edges, matching those shared with its neighbours.
    ///
    /// Each edge is kept at its smaller end, in one of [`SLOTS`] places
    /// (its larger end and how many triangles use it; an edge carried from
    /// the chunk before comes in with its count): one pass over the
    /// triangles, each edge matched against the few its smaller end has
    /// so far. A vertex with more distinct edges than places (rare: a CT
    /// surface's vertex is the smaller end of about three) sends the rest
    /// to a list, sorted once: a run of equal edges is one edge and its
    /// length the edge's triangles. Then every edge is counted, or carried
    /// when both its ends are in the next chunk.
    fn edges(&mut self, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let n = (own + next) as usize;
        let mut carried = std::mem::take(&mut self.carried_edges);
        self.used.clear();
        self.used.resize(n, 0);
        if self.places.len() < n {
            self.places.resize(n, Places::default());
        }
        self.spill.clear();
        let (used, places, spill) = (&mut self.used[..], &mut self.places[..], &mut self.spill);
        for t in triangles {
            add_edge(used, places, spill, [t[0], t[1]], 1);
            add_edge(used, places, spill, [t[1], t[2]], 1);
            add_edge(used, places, spill, [t[2], t[0]], 1);
        }
        for &[lo, hi, count] in &carried {
            add_edge(used, places, spill, [lo, hi], count);
        }
        carried.clear();
        let mut edge = |lo: u32, hi: u32, count: u32| {
            if lo >= own {
                carried.push([lo - own, hi - own, count]);
            } else {
                self.verdict.tally(count);
            }
        };
        for (lo, &in_use) in self.used.iter().enumerate() {
            let p = &self.places[lo];
            for (&hi, &count) in p.ends.iter().zip(&p.counts).take(usize::from(in_use)) {
                edge(lo as u32, hi, count);
            }
        }
        self.spill.sort_unstable();
        for run in self.spill.chunk_by(|a, b| a == b) {
            edge(run[0][0], run[0][1], run.len() as u32);
        }
        self.carried_edges = carried;
    }
}

/// The edges a vertex is the smaller end of ([`Topology::edges`]): the
/// larger ends, and how many triangles use each.
#[derive(Debug, Clone, Copy, Default)]
struct Places {
    ends: [u32; SLOTS],
    counts: [u32; SLOTS],
}

/// One more use by `k` triangles of the edge `a`-`b` ([`Topology::edges`]):
/// its count in one of its smaller end's places, a new place, or, with
/// every place taken by other edges, `k` entries in `spill`.
#[inline(always)]
fn add_edge(
    used: &mut [u8],
    places: &mut [Places],
    spill: &mut Vec<[u32; 2]>,
    [a, b]: [u32; 2],
    k: u32,
) {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let lo = lo as usize;
    let in_use = usize::from(used[lo]);
    let p = &mut places[lo];
    for (end, c) in p.ends.iter().zip(p.counts.iter_mut()).take(in_use) {
        if *end == hi {
            *c += k;
            return;
        }
    }
    if in_use < SLOTS {
        p.ends[in_use] = hi;
        p.counts[in_use] = k;
        used[lo] += 1;
    } else {
        spill.extend(std::iter::repeat_n([lo as u32, hi], k as usize));
    }
}

/// The root of `x`, halving the path on the way.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = parent[x as usize];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An octahedron: 6 vertices, 8 triangles, split over two "chunks".
    #[test]
    fn an_octahedron_split_in_two_chunks_is_closed_with_genus_zero() {
        // Chunk 0 owns vertices 0..5 (the equator 1..4 and the bottom 0)...
        let tris: [[u32; 3]; 8] = [
            [0, 2, 1],
            [0, 3, 2],
            [0, 4, 3],
            [0, 1, 4],
            [5, 1, 2],
            [5, 2, 3],
            [5, 3, 4],
            [5, 4, 1],
        ];
        let mut whole = Topology::default();
        whole.chunk(6, 0, &tris);
        let v = whole.finish();
        assert_eq!((v.vertices, v.edges, v.triangles), (6, 12, 8));
        assert_eq!(v.genus(), Some(0));
        assert_eq!(v.components, 1);
        // Chunk 0: vertex 0 and its four triangles into the next chunk's
        // equator (next-relative 0..4 = old 1..4); chunk 1: equator and top.
        let lower: Vec<[u32; 3]> = tris[..4].iter().map(|t| t.map(|i| i)).collect();
        let upper: Vec<[u32; 3]> = tris[4..].iter().map(|t| t.map(|i| i - 1)).collect();
        let mut split = Topology::default();
        split.chunk(1, 4, &lower);
        split.chunk(5, 0, &upper);
        assert_eq!(split.finish(), v);
    }

    /// Edges, boundary and non-manifold edges of `triangles`, counted
    /// whole with a map.
    fn brute_edges(triangles: &[[u32; 3]]) -> (u64, u64, u64) {
        let mut map = std::collections::BTreeMap::new();
        for t in triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *map.entry((a.min(b), a.max(b))).or_insert(0u32) += 1;
            }
        }
        let count = |f: fn(u32) -> bool| map.values().filter(|&&c| f(c)).count() as u64;
        (map.len() as u64, count(|c| c == 1), count(|c| c >= 3))
    }

    #[test]
    fn a_vertex_of_many_edges_and_a_nonmanifold_edge_are_counted_whole_and_split() {
        // A closed wheel of 20 triangles round vertex 0 (more edges at
        // vertex 0 than it has places), a second wheel on the other side
        // (vertex 21) to close it, and one triangle more on an edge of the
        // rim: that edge has three triangles.
        let rim = 20u32;
        let mut tris = Vec::new();
        for i in 0..rim {
            let (a, b) = (1 + i, 1 + (i + 1) % rim);
            tris.push([0, a, b]);
            tris.push([rim + 1, b, a]);
        }
        tris.push([1, 2, rim + 2]);
        let whole_count = brute_edges(&tris);
        let mut whole = Topology::default();
        whole.chunk(rim + 3, 0, &tris);
        let v = whole.finish();
        assert_eq!(
            (v.edges, v.boundary_edges, v.nonmanifold_edges),
            whole_count
        );
        assert_eq!((v.edges, v.boundary_edges, v.nonmanifold_edges), (62, 2, 1));
        // Split: vertex 0 alone in the first chunk, its triangles reaching
        // into the second's (the rim edges are carried), the rest there.
        let (first, second): (Vec<[u32; 3]>, Vec<[u32; 3]>) =
            tris.iter().partition(|t| t.contains(&0));
        let second: Vec<[u32; 3]> = second.iter().map(|t| t.map(|i| i - 1)).collect();
        let mut split = Topology::default();
        split.chunk(1, rim, &first);
        split.chunk(rim + 2, 0, &second);
        assert_eq!(split.finish(), v);
    }

    #[test]
    fn two_open_triangles_are_two_components() {
        let mut t = Topology::default();
        t.chunk(6, 0, &[[0, 1, 2], [3, 4, 5]]);
        let v = t.finish();
        assert_eq!(v.components, 2);
        assert_eq!(v.boundary_edges, 6);
        assert!(!v.closed());
        assert!(v.describe().starts_with("open"));
    }

    #[test]
    fn a_mesh_without_triangles_is_described_as_empty() {
        let mut t = Topology::default();
        t.chunk(0, 0, &[]);
        assert_eq!(t.finish().describe(), "empty: no surface");
    }
}
