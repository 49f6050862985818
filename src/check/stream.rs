//! A streaming check: the topology of a mesh counted while its chunks
//! stream, in plane order, without holding the mesh. The preview's
//! closed/genus caption ([`crate::preview`]) and `tmc extract --labels
//! --stats` ([`StreamCheck::full`]) use it.
//!
//! A chunk's triangles use its own vertices and a prefix of the next
//! chunk's ([`crate::Chunk`]), so the count needs a window of two chunks:
//! * **components**: a union-find over the window's vertices, those of the
//!   chunk's first ones that share a class carried from the chunks before
//!   joined at the first of them; a set (whose root is its smallest
//!   vertex) none of whose members is in the next chunk is a finished
//!   component, found as a root among the chunk's own vertices;
//! * **edges**, in the default (the preview's) count: a chunk's edges kept
//!   at their smaller end and counted ([`EdgeTable`]); an edge with both
//!   ends in the next chunk may also be used by that chunk's triangles and
//!   is carried to it, with its count. A triangle's corners are taken in
//!   increasing order, so that its first corner is the smaller end of two
//!   of its edges: the union-find joins those two edges' ends when they
//!   are new (an edge met before had its ends joined then, and the third
//!   edge's ends are joined through the first corner);
//! * with [`StreamCheck::full`], **each vertex** once all its triangles
//!   are known (those of its own chunk and of the chunk before): its link,
//!   the orientation of its edges, the boundary loops through it and the
//!   edges it is the smaller end of ([`super::stream_links`]), so that the
//!   figures are those of [`check_mesh`](super::check_mesh)
//!   ([`Verdict::checked`]).
//!
//! The mesh is **closed** when every edge has two triangles; its genus is
//! then `C - χ/2` summed over its `C` components (`χ = V - E + F`), as
//! `tmc check` reports for a closed orientable mesh. Memory is that of two
//! chunks: the [`StreamCheck`] keeps what it carries to the next chunk
//! (nothing but a few counters when a chunk has no triangles), and the
//! working space of a chunk is a [`Scratch`] that several checks may share.

use super::stream_components::{ComponentScratch, ComponentState, Tally};
use super::stream_edges::EdgeTable;
use super::stream_links::{Checked, LinkState, Links, SweepScratch};
use super::union_find::{find, NONE};

/// What a [`StreamCheck`] found: what the preview says about the topology
/// of the mesh and, from [`StreamCheck::full`], the figures of
/// [`check_mesh`](super::check_mesh) ([`Verdict::checked`]).
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
    /// Triangles seen (but the left-out ones).
    pub triangles: u64,
    /// Triangles left out: an index past the next chunk's vertices.
    pub invalid_triangles: u64,
    /// What [`StreamCheck::full`] counts besides; `None` from
    /// [`StreamCheck::default`].
    pub links: Option<Links>,
}

impl Verdict {
    /// The counts of two meshes taken as one (components, edges and
    /// vertices add up, so the Euler characteristic and the genus do),
    /// without the links ([`StreamCheck::default`]'s counts, which the
    /// preview's verdict is).
    pub fn with(self, other: Verdict) -> Verdict {
        Verdict {
            components: self.components + other.components,
            edges: self.edges + other.edges,
            boundary_edges: self.boundary_edges + other.boundary_edges,
            nonmanifold_edges: self.nonmanifold_edges + other.nonmanifold_edges,
            vertices: self.vertices + other.vertices,
            triangles: self.triangles + other.triangles,
            invalid_triangles: self.invalid_triangles + other.invalid_triangles,
            links: None,
        }
    }

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
    pub(super) fn tally(&mut self, count: u32) {
        self.edges += 1;
        match count {
            1 => self.boundary_edges += 1,
            2 => {}
            _ => self.nonmanifold_edges += 1,
        }
    }

    /// The figures [`check_mesh`](super::check_mesh) gives the same mesh
    /// (`None` but from [`StreamCheck::full`]); see [`Checked`].
    pub fn checked(&self) -> Option<Checked> {
        let links = self.links?;
        let vertices = self.vertices.saturating_sub(links.unreferenced_vertices);
        // An unreferenced vertex is a class of its own, counted once.
        let components = self.components.saturating_sub(links.unreferenced_vertices);
        let euler = vertices as i64 - self.edges as i64 + self.triangles as i64;
        let manifold = self.nonmanifold_edges == 0 && links.non_manifold_vertices == 0;
        let oriented = links.inconsistent_edges == 0;
        // Per component, χ = 2 - 2g - b on an orientable manifold.
        let genus = (manifold && oriented)
            .then(|| (2 * components as i64 - euler - links.boundary_loops as i64) / 2);
        let closed_manifold = self.invalid_triangles == 0
            && links.degenerate_triangles == 0
            && self.boundary_edges == 0
            && manifold
            && oriented;
        Some(Checked {
            components,
            euler,
            genus,
            closed_manifold,
        })
    }

    /// The verdict in a few words, as the caption shows it ("empty" for a
    /// mesh without triangles: no surface at that isovalue).
    pub fn describe(&self) -> String {
        if self.triangles == 0 {
            return "empty: no surface".into();
        }
        let parts = format!("{} component{}", self.components, plural(self.components));
        match self.genus() {
            Some(g) => format!("closed, genus {g}, {parts}"),
            None if self.nonmanifold_edges > 0 => {
                let n = self.nonmanifold_edges;
                format!("NOT MANIFOLD ({n} edge{}), {parts}", plural(n))
            }
            None => {
                let n = self.boundary_edges;
                format!("open ({n} boundary edge{}), {parts}", plural(n))
            }
        }
    }
}

/// The plural ending of a count's noun: "" for one, "s" for any other.
pub(crate) fn plural(n: impl Into<u64>) -> &'static str {
    if n.into() == 1 {
        ""
    } else {
        "s"
    }
}

/// The streaming count: feed it each chunk's window in plane order
/// ([`StreamCheck::chunk`]), then [`StreamCheck::finish`].
#[derive(Debug, Default)]
pub struct StreamCheck {
    verdict: Verdict,
    /// Class of each vertex of the chunk being counted (a prefix; vertices
    /// past it have classes of their own), numbered from 0 by first use.
    carry: Vec<u32>,
    /// Classes in use by `carry`.
    classes: u32,
    /// Edges with both ends in the next chunk's vertices: smaller and
    /// larger end relative to that chunk, and the triangles seen so far
    /// (the default count only: a full one counts every edge at its
    /// smaller end once all its triangles are known).
    carried_edges: Vec<[u32; 3]>,
    /// The vertex sweep of [`StreamCheck::full`].
    links: Option<LinkState>,
    /// The per-component tallies of [`StreamCheck::per_component`].
    parts: Option<ComponentState>,
}

/// The working space of [`StreamCheck::chunk`], as large as the largest
/// window it was given; kept between chunks, and shared by any number of
/// checks that count one chunk at a time (one per label of a label map).
#[derive(Debug, Default)]
pub struct Scratch {
    /// The union-find parents over the window's vertices.
    parent: Vec<u32>,
    /// Per carried class, the first of the chunk's vertices in it (`NONE`
    /// when the class has none: it is finished).
    first: Vec<u32>,
    /// Per window vertex that is the root of a set reaching the next
    /// chunk, its class there plus one; 0 for the others.
    reach: Vec<u32>,
    /// The edges of the default count.
    edges: EdgeTable,
    /// The triangles kept when some are left out.
    valid: Vec<[u32; 3]>,
    /// The vertex sweep's.
    sweep: SweepScratch,
    /// The per-component tallies'.
    parts: ComponentScratch,
}

impl StreamCheck {
    /// A check that also looks at every vertex's link, the orientation of
    /// every edge and the boundary loops, and leaves out triangles that
    /// repeat a vertex, so that [`Verdict::checked`] gives the figures of
    /// [`check_mesh`](super::check_mesh). It costs more than the default
    /// (the preview's), which counts components and edges only.
    pub fn full() -> Self {
        StreamCheck {
            links: Some(LinkState::default()),
            ..StreamCheck::default()
        }
    }

    /// A [`StreamCheck::full`] that also counts every component's figures
    /// (`check_mesh`'s [`ComponentReport`](super::ComponentReport)s, from
    /// [`StreamCheck::finish_components`]): a tally more per vertex of the
    /// window and per component.
    pub(super) fn per_component() -> Self {
        StreamCheck {
            parts: Some(ComponentState::default()),
            ..StreamCheck::full()
        }
    }

    /// Counts one chunk: `own` vertices of its own, triangles indexing them
    /// and then the first `next` vertices of the next chunk (which must
    /// have at least `next` vertices). A triangle with an index past those
    /// is left out, and, in a [`StreamCheck::full`], one that repeats an
    /// index.
    pub fn chunk(&mut self, scratch: &mut Scratch, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let base = self.verdict.vertices;
        self.verdict.vertices += u64::from(own);
        if self.links.is_none() {
            self.start_classes(scratch, own, next);
            self.edges_and_unite(scratch, own, next, triangles);
            self.close(scratch, own, next);
        } else {
            self.check_chunk(scratch, base, own, next, triangles);
        }
        trim(&mut self.carry);
        trim(&mut self.carried_edges);
    }

    /// [`StreamCheck::chunk`] in a full check: the triangles that repeat
    /// an index or reach past the window left out.
    fn check_chunk(
        &mut self,
        scratch: &mut Scratch,
        base: u64,
        own: u32,
        next: u32,
        triangles: &[[u32; 3]],
    ) {
        let n = own.saturating_add(next);
        let past = |t: &[u32; 3]| t[0].max(t[1]).max(t[2]) >= n;
        let repeats = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        if triangles.iter().any(|t| past(t) || repeats(t)) {
            let mut valid = std::mem::take(&mut scratch.valid);
            valid.clear();
            for t in triangles {
                if past(t) {
                    self.verdict.invalid_triangles += 1;
                } else if let (Some(links), true) = (&mut self.links, repeats(t)) {
                    links.degenerate(1);
                } else {
                    valid.push(*t);
                }
            }
            self.count(scratch, base, own, next, &valid);
            scratch.valid = valid;
        } else {
            self.count(scratch, base, own, next, triangles);
        }
    }

    /// [`StreamCheck::check_chunk`] of triangles whose indices are all
    /// below `own + next` and distinct; `base` numbers the chunk's first
    /// vertex in the mesh.
    fn count(&mut self, s: &mut Scratch, base: u64, own: u32, next: u32, triangles: &[[u32; 3]]) {
        self.verdict.triangles += triangles.len() as u64;
        self.start_classes(s, own, next);
        let parent = &mut s.parent[..];
        for t in triangles {
            unite(parent, t[0], t[1]);
            unite(parent, t[0], t[2]);
        }
        let at = match self.parts {
            Some(_) => {
                let at = &mut s.parts.at;
                at.clear();
                at.resize((own + next) as usize, Tally::default());
                for t in triangles {
                    at[t[0] as usize].triangles += 1;
                }
                Some(&mut at[..])
            }
            None => None,
        };
        if let Some(links) = &mut self.links {
            links.chunk(&mut s.sweep, base, own, next, triangles, at);
        }
        self.close(s, own, next);
    }

    /// The verdict once the last chunk has been counted.
    pub fn finish(self) -> Verdict {
        self.finish_components().0
    }

    /// [`StreamCheck::finish`], with the finished components of a
    /// [`StreamCheck::per_component`] (`None` from any other check).
    pub(super) fn finish_components(mut self) -> (Verdict, Option<ComponentState>) {
        self.verdict.components += u64::from(self.classes);
        let mut carried = std::mem::take(&mut self.carried_edges);
        if let Some(links) = &mut self.links {
            // Only where the last chunk said its triangles reach past it.
            carried = links.carried_edges();
            let [edges, boundary, nonmanifold] = links.edges();
            self.verdict.edges += edges;
            self.verdict.boundary_edges += boundary;
            self.verdict.nonmanifold_edges += nonmanifold;
        }
        for [lo, _, count] in carried {
            self.verdict.tally(count);
            if let Some(parts) = &mut self.parts {
                if let Some(t) = parts.carried.get_mut(self.carry[lo as usize] as usize) {
                    t.edge(count);
                }
            }
        }
        if let Some(parts) = &mut self.parts {
            for t in std::mem::take(&mut parts.carried) {
                parts.finish(t);
            }
        }
        self.verdict.links = self.links.map(LinkState::finish);
        (self.verdict, self.parts)
    }

    /// The union-find over the window's vertices, each in a set of its
    /// own but those of the chunk's first vertices that share a carried
    /// class: joined at the first of them (so that a set's root is its
    /// smallest vertex, as [`unite`] keeps it).
    fn start_classes(&mut self, s: &mut Scratch, own: u32, next: u32) {
        s.parent.clear();
        s.parent.extend(0..own + next);
        s.first.clear();
        s.first.resize(self.classes as usize, NONE);
        for (j, &class) in self.carry.iter().take(own as usize).enumerate() {
            let first = &mut s.first[class as usize];
            if *first == NONE {
                *first = j as u32;
            } else {
                s.parent[j] = *first;
            }
        }
    }

    /// The default count's pass over the triangles: each one's edges in
    /// the [`EdgeTable`] (with those carried from the chunk before), the
    /// ends of its two edges at its smallest corner joined when new (one
    /// past the window is left out); then the edges counted, but those
    /// with both ends in the next chunk, carried to it.
    #[inline(never)]
    fn edges_and_unite(&mut self, s: &mut Scratch, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let n = own.saturating_add(next);
        let mut table = s.edges.start(n as usize);
        let mut carried = std::mem::take(&mut self.carried_edges);
        let mut uses = 0;
        for &[lo, hi, count] in &carried {
            table.add(lo, hi, count);
            uses += u64::from(count);
        }
        let parent = &mut s.parent[..];
        let mut invalid = 0;
        for t in triangles {
            let (a, b) = (t[0].min(t[1]), t[0].max(t[1]));
            let (b, c) = (b.min(t[2]), b.max(t[2]));
            let (a, b) = (a.min(b), a.max(b));
            if c >= n {
                invalid += 1;
                continue;
            }
            if table.add(a, b, 1) {
                unite(parent, a, b);
            }
            if table.add(a, c, 1) {
                unite(parent, a, c);
            }
            table.add(b, c, 1);
        }
        let valid = triangles.len() as u64 - invalid;
        self.verdict.invalid_triangles += invalid;
        self.verdict.triangles += valid;
        carried.clear();
        let tally = table.finish(own, uses + 3 * valid, |lo, hi, count| {
            carried.push([lo - own, hi - own, count]);
        });
        self.verdict.edges += tally.edges;
        self.verdict.boundary_edges += tally.boundary;
        self.verdict.nonmanifold_edges += tally.nonmanifold;
        self.carried_edges = carried;
    }

    /// After the triangles have joined the window's vertices: the sets
    /// that finish in this chunk (counted, and their tallies kept in a
    /// [`StreamCheck::per_component`]), and the classes of the next
    /// chunk's first vertices, carried on with their tallies.
    fn close(&mut self, s: &mut Scratch, own: u32, next: u32) {
        let n = (own + next) as usize;
        let parent = &mut s.parent[..n];
        // Every vertex straight under its root: a vertex's parent is never
        // after it ([`StreamCheck::start_classes`], [`unite`], `find`), so
        // in increasing order the parent's parent is already the root.
        for v in 0..n {
            let p = parent[v] as usize;
            parent[v] = parent[p];
        }
        // A carried class none of the chunk's vertices is in (they were
        // past its own: the chunk has fewer than the one before said).
        let gone = s.first.iter().filter(|&&f| f == NONE).count();
        self.verdict.components += gone as u64;
        if let Some(parts) = &mut self.parts {
            let root = &mut s.parts.root;
            root.clear();
            root.resize(n, Tally::default());
            let carried = std::mem::take(&mut parts.carried);
            for (t, &first) in carried.iter().zip(&s.first) {
                match first {
                    NONE => parts.finish(*t),
                    v => root[parent[v as usize] as usize].add(t),
                }
            }
            for (&r, t) in parent.iter().zip(&s.parts.at) {
                root[r as usize].add(t);
            }
            parts.carried = carried;
            parts.carried.clear();
        }
        // The roots reaching the next chunk, their classes numbered by
        // first use.
        s.reach.clear();
        s.reach.resize(n, 0);
        let reach = &mut s.reach[..];
        self.carry.clear();
        self.carry.resize(next as usize, 0);
        let mut classes = 0;
        for (&r, class) in parent[own as usize..].iter().zip(self.carry.iter_mut()) {
            let r = r as usize;
            if reach[r] == 0 {
                classes += 1;
                reach[r] = classes;
                if let Some(parts) = &mut self.parts {
                    parts.carried.push(s.parts.root[r]);
                }
            }
            *class = reach[r] - 1;
        }
        self.classes = classes;
        // The sets that finish here: a root among the own vertices (a
        // set's root is its smallest vertex) reaching no further.
        for (v, (&p, &reach)) in parent.iter().zip(&*reach).enumerate().take(own as usize) {
            if p == v as u32 && reach == 0 {
                self.verdict.components += 1;
                if let Some(parts) = &mut self.parts {
                    parts.finish(s.parts.root[v]);
                }
            }
        }
    }
}

/// Joins the sets of `a` and `b`, the larger root under the smaller one
/// (a set's root stays its smallest vertex).
#[inline(always)]
fn unite(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

/// Gives back the room of a vector that holds far less than it did (all
/// of it when it holds nothing): what a check carries from chunk to chunk
/// stays as small as the last window, so that a label absent from the
/// planes being written holds next to nothing.
fn trim<T>(v: &mut Vec<T>) {
    if v.capacity() > 2 * v.len() + 64 || (v.is_empty() && v.capacity() > 0) {
        v.shrink_to(v.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The verdict's words take the singular for a count of one (it said
    /// "1 boundary edges", "1 edges"), the plural for every other count.
    #[test]
    fn the_verdict_says_one_component_and_one_edge() {
        let one = Verdict {
            components: 1,
            edges: 3,
            boundary_edges: 1,
            vertices: 3,
            triangles: 1,
            ..Verdict::default()
        };
        assert_eq!(one.describe(), "open (1 boundary edge), 1 component");
        let many = Verdict {
            components: 2,
            boundary_edges: 6,
            ..one
        };
        assert_eq!(many.describe(), "open (6 boundary edges), 2 components");
        let bad = Verdict {
            nonmanifold_edges: 1,
            ..one
        };
        assert_eq!(bad.describe(), "NOT MANIFOLD (1 edge), 1 component");
        assert_eq!(plural(0u64), "s");
    }

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
        let mut whole = StreamCheck::default();
        whole.chunk(&mut Scratch::default(), 6, 0, &tris);
        let v = whole.finish();
        assert_eq!((v.vertices, v.edges, v.triangles), (6, 12, 8));
        assert_eq!(v.genus(), Some(0));
        assert_eq!(v.components, 1);
        // Chunk 0: vertex 0 and its four triangles into the next chunk's
        // equator (next-relative 0..4 = old 1..4); chunk 1: equator and top.
        let lower: Vec<[u32; 3]> = tris[..4].iter().map(|t| t.map(|i| i)).collect();
        let upper: Vec<[u32; 3]> = tris[4..].iter().map(|t| t.map(|i| i - 1)).collect();
        let mut split = StreamCheck::default();
        split.chunk(&mut Scratch::default(), 1, 4, &lower);
        split.chunk(&mut Scratch::default(), 5, 0, &upper);
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
        let mut whole = StreamCheck::default();
        whole.chunk(&mut Scratch::default(), rim + 3, 0, &tris);
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
        let mut split = StreamCheck::default();
        split.chunk(&mut Scratch::default(), 1, rim, &first);
        split.chunk(&mut Scratch::default(), rim + 2, 0, &second);
        assert_eq!(split.finish(), v);
    }

    #[test]
    fn two_open_triangles_are_two_components() {
        let mut t = StreamCheck::default();
        t.chunk(&mut Scratch::default(), 6, 0, &[[0, 1, 2], [3, 4, 5]]);
        let v = t.finish();
        assert_eq!(v.components, 2);
        assert_eq!(v.boundary_edges, 6);
        assert!(!v.closed());
        assert!(v.describe().starts_with("open"));
    }

    #[test]
    fn a_mesh_without_triangles_is_described_as_empty() {
        let mut t = StreamCheck::default();
        t.chunk(&mut Scratch::default(), 0, 0, &[]);
        assert_eq!(t.finish().describe(), "empty: no surface");
    }
}

#[cfg(test)]
mod full_tests {
    use super::super::checker::check_mesh;
    use super::super::report::MeshReport;
    use super::{Scratch, StreamCheck};
    use crate::mesh::Mesh;

    /// A small deterministic generator (xorshift64*).
    struct Rng(u64);

    impl Rng {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) % n
        }
    }

    /// A cylinder of `rows` rings of `ring` vertices, its quads split in
    /// two triangles, with random damage: triangles dropped, flipped,
    /// doubled, and degenerate ones added. Rows are the chunks: row `r`'s
    /// triangles end in row `r + 1`, as a chunk's end in the next one's
    /// first vertices. Returns the triangles of each chunk (indices in the
    /// mesh).
    fn damaged_cylinder(rows: u32, ring: u32, rng: &mut Rng, damage: u64) -> Vec<Vec<[u32; 3]>> {
        let id = |r: u32, i: u32| r * ring + i % ring;
        (0..rows)
            .map(|r| {
                let mut tris = Vec::new();
                if r + 1 == rows {
                    return tris;
                }
                for i in 0..ring {
                    let (a, b, c, d) = (id(r, i), id(r, i + 1), id(r + 1, i + 1), id(r + 1, i));
                    for mut t in [[a, b, c], [a, c, d]] {
                        match rng.below(100) {
                            x if x < damage => continue,
                            x if x < 2 * damage / 3 + damage => t.swap(0, 1),
                            x if x < damage + damage / 2 + damage / 3 => tris.push(t),
                            x if x < 2 * damage => tris.push([t[0], t[0], t[1]]),
                            _ => {}
                        }
                        tris.push(t);
                    }
                }
                tris
            })
            .collect()
    }

    #[test]
    fn the_full_stream_check_gives_check_meshs_figures() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut genus_seen = 0;
        for case in 0..300 {
            let (rows, ring) = (2 + rng.below(6) as u32, 3 + rng.below(6) as u32);
            let damage = [0, 2, 5, 10, 30][case % 5];
            let chunks = damaged_cylinder(rows, ring, &mut rng, damage);
            let mesh = Mesh {
                vertices: vec![[0.0; 3]; (rows * ring) as usize],
                triangles: chunks.concat(),
                ..Mesh::default()
            };
            let report = check_mesh(&mesh);
            let (mut check, mut scratch) = (StreamCheck::full(), Scratch::default());
            for (r, tris) in chunks.iter().enumerate() {
                let base = r as u32 * ring;
                let local: Vec<[u32; 3]> = tris.iter().map(|t| t.map(|i| i - base)).collect();
                let next = if r as u32 + 1 == rows { 0 } else { ring };
                check.chunk(&mut scratch, ring, next, &local);
            }
            let verdict = check.finish();
            let links = verdict.links.unwrap();
            let checked = verdict.checked().unwrap();
            let what = format!("case {case}: {verdict:?} against {report:?}");
            assert_eq!(checked.components, report.components as u64, "{what}");
            assert_eq!(checked.euler, report.euler, "{what}");
            assert_eq!(verdict.edges, report.edges as u64, "{what}");
            assert_eq!(
                verdict.boundary_edges, report.boundary_edges as u64,
                "{what}"
            );
            assert_eq!(
                verdict.nonmanifold_edges, report.non_manifold_edges as u64,
                "{what}"
            );
            assert_eq!(
                links.non_manifold_vertices, report.non_manifold_vertices as u64,
                "{what}"
            );
            assert_eq!(
                links.inconsistent_edges, report.inconsistent_edges as u64,
                "{what}"
            );
            assert_eq!(
                links.unreferenced_vertices, report.unreferenced_vertices as u64,
                "{what}"
            );
            assert_eq!(
                links.degenerate_triangles, report.degenerate_triangles as u64,
                "{what}"
            );
            assert_eq!(
                checked.closed_manifold,
                report.is_closed_manifold(),
                "{what}"
            );
            if links.inconsistent_edges == 0 {
                assert_eq!(checked.genus, report.total_genus(), "{what}");
                let loops: usize = report.per_component.iter().map(|c| c.boundary_loops).sum();
                if checked.genus.is_some() {
                    assert_eq!(links.boundary_loops, loops as u64, "{what}");
                    genus_seen += 1;
                }
            } else {
                assert_eq!(checked.genus, None, "{what}");
            }
        }
        assert!(genus_seen > 50, "{genus_seen} cases with a genus");
    }

    #[test]
    fn the_per_component_stream_check_gives_check_meshs_report() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut compared, mut several, mut broken) = (0, 0, 0);
        for case in 0..400 {
            let (rows, ring) = (2 + rng.below(7) as u32, 3 + rng.below(6) as u32);
            let damage = [0, 2, 5, 10, 30][case % 5];
            // Two cylinders side by side, each chunk holding a ring of
            // each (the second's vertices after the first's).
            let (a, b) = (
                damaged_cylinder(rows, ring, &mut rng, damage),
                damaged_cylinder(rows, ring, &mut rng, damage / 2),
            );
            let place = |v: u32, second: u32| (v / ring) * 2 * ring + v % ring + second * ring;
            let chunks: Vec<Vec<[u32; 3]>> = a
                .iter()
                .zip(&b)
                .map(|(ta, tb)| {
                    let ta = ta.iter().map(|t| t.map(|v| place(v, 0)));
                    ta.chain(tb.iter().map(|t| t.map(|v| place(v, 1))))
                        .collect()
                })
                .collect();
            let mesh = Mesh {
                vertices: vec![[0.0; 3]; (2 * rows * ring) as usize],
                triangles: chunks.concat(),
                ..Mesh::default()
            };
            let mut report = check_mesh(&mesh);
            let (mut check, mut scratch) = (StreamCheck::per_component(), Scratch::default());
            for (r, tris) in chunks.iter().enumerate() {
                let base = r as u32 * 2 * ring;
                let local: Vec<[u32; 3]> = tris.iter().map(|t| t.map(|i| i - base)).collect();
                let next = if r as u32 + 1 == rows { 0 } else { 2 * ring };
                check.chunk(&mut scratch, 2 * ring, next, &local);
            }
            let (_, parts) = check.finish_components();
            let streamed = parts.unwrap().reports();
            if report.inconsistent_edges > 0 {
                assert_eq!(streamed, None, "case {case}");
                continue;
            }
            let streamed = streamed.unwrap();
            report.geometry = Default::default();
            let mut from_stream = MeshReport {
                vertices: report.vertices,
                triangles: report.triangles,
                invalid_triangles: report.invalid_triangles,
                degenerate_triangles: report.degenerate_triangles,
                unreferenced_vertices: report.unreferenced_vertices,
                ..MeshReport::default()
            };
            from_stream.set_components(streamed);
            assert_eq!(from_stream, report, "case {case}");
            compared += 1;
            several += usize::from(report.components > 1);
            broken += usize::from(report.non_manifold_vertices > 0);
        }
        assert!(
            compared > 120 && several > 120 && broken > 20,
            "{compared} compared, {several} with several components, {broken} not manifold"
        );
    }

    #[test]
    fn a_closed_octahedron_and_an_empty_mesh_are_closed_of_genus_zero() {
        // As check_mesh: an empty mesh is vacuously a closed manifold.
        let empty = StreamCheck::full().finish().checked().unwrap();
        assert_eq!((empty.components, empty.genus), (0, Some(0)));
        assert!(empty.closed_manifold);
        let lower = [[0, 2, 1], [0, 3, 2], [0, 4, 3], [0, 1, 4]];
        let upper = [[4, 0, 1], [4, 1, 2], [4, 2, 3], [4, 3, 0]];
        let mut check = StreamCheck::full();
        let mut scratch = Scratch::default();
        check.chunk(&mut scratch, 1, 4, &lower);
        check.chunk(&mut scratch, 5, 0, &upper);
        let checked = check.finish().checked().unwrap();
        assert_eq!((checked.components, checked.euler), (1, 2));
        assert_eq!(checked.genus, Some(0));
        assert!(checked.closed_manifold);
    }
}
