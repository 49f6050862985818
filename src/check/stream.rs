//! A streaming check: the topology of a mesh counted while its chunks
//! stream, in plane order, without holding the mesh. The preview's
//! closed/genus caption ([`crate::preview`]) and `tmc extract --labels
//! --stats` ([`StreamCheck::full`]) use it.
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
//!   been carried from the chunk before and is matched against that list;
//! * with [`StreamCheck::full`], **each vertex** once all its triangles
//!   are known (those of its own chunk and of the chunk before): its link,
//!   the orientation of its edges and the boundary loops through it
//!   ([`super::stream_links`]), so that the figures are those of
//!   [`check_mesh`](super::check_mesh) ([`Verdict::checked`]).
//!
//! The mesh is **closed** when every edge has two triangles; its genus is
//! then `C - χ/2` summed over its `C` components (`χ = V - E + F`), as
//! `tmc check` reports for a closed orientable mesh. Memory is that of two
//! chunks: the [`StreamCheck`] keeps what it carries to the next chunk
//! (nothing but a few counters when a chunk has no triangles), and the
//! working space of a chunk is a [`Scratch`] that several checks may share.

use super::stream_components::{ComponentScratch, ComponentState, Tally};
use super::stream_links::{Checked, LinkState, Links, SweepScratch};
use super::union_find::find;

/// Places per vertex for the edges it is the smaller end of
/// ([`StreamCheck::edges`]).
const SLOTS: usize = 6;

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
/// ([`StreamCheck::chunk`]), then [`StreamCheck::finish`].
#[derive(Debug, Default)]
pub struct StreamCheck {
    verdict: Verdict,
    /// Class of each vertex of the chunk being counted (a prefix; vertices
    /// past it have classes of their own).
    carry: Vec<u32>,
    /// Classes in use by `carry`.
    classes: u32,
    /// Edges with both ends in the next chunk's vertices: smaller and
    /// larger end relative to that chunk, and the triangles seen so far.
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
    /// The union-find parents and the roots reaching the next chunk; per
    /// root, a mark (reaching, finished) and its new class.
    parent: Vec<u32>,
    roots: Vec<u32>,
    mark: Vec<u32>,
    /// The edges by smaller end, [`SLOTS`] places each: how many are in
    /// use, the larger ends and their triangles; edges past a full
    /// vertex's places go to `spill`, once per triangle.
    used: Vec<u8>,
    places: Vec<Places>,
    spill: Vec<[u32; 2]>,
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
        let n = own.saturating_add(next);
        let base = self.verdict.vertices;
        self.verdict.vertices += u64::from(own);
        let past = |t: &[u32; 3]| t[0].max(t[1]).max(t[2]) >= n;
        let repeats = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        let left_out = match self.links {
            None => triangles.iter().any(past),
            Some(_) => triangles.iter().any(|t| past(t) || repeats(t)),
        };
        if left_out {
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
        trim(&mut self.carry);
        trim(&mut self.carried_edges);
    }

    /// [`StreamCheck::chunk`] of triangles whose indices are all below
    /// `own + next` (and, in a full check, distinct); `base` numbers the
    /// chunk's first vertex in the mesh.
    fn count(&mut self, s: &mut Scratch, base: u64, own: u32, next: u32, triangles: &[[u32; 3]]) {
        self.verdict.triangles += triangles.len() as u64;
        let at = match self.parts {
            Some(_) => {
                let at = &mut s.parts.at;
                at.clear();
                at.resize((own + next) as usize, Tally::default());
                for t in triangles {
                    at[t[0] as usize].triangles += 1;
                }
                true
            }
            None => false,
        };
        self.unite(s, own, next, triangles);
        self.edges(s, own, next, triangles);
        if let Some(links) = &mut self.links {
            let at = at.then_some(&mut s.parts.at[..]);
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
        for [lo, _, count] in std::mem::take(&mut self.carried_edges) {
            self.verdict.tally(count);
            // Only where the last chunk said its triangles reach past it.
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

    /// Union-find over the carried classes and the next chunk's prefix:
    /// the chunk's triangles join them.
    fn unite(&mut self, s: &mut Scratch, own: u32, next: u32, triangles: &[[u32; 3]]) {
        // Vertices past the carried prefix start classes of their own.
        while (self.carry.len() as u32) < own {
            self.carry.push(self.classes);
            self.classes += 1;
        }
        let k = self.classes;
        s.parent.clear();
        s.parent.extend(0..k + next);
        let carry = &self.carry[..own as usize];
        let element = |v: u32| match carry.get(v as usize) {
            Some(&class) => class,
            None => k + v - own,
        };
        let parent = &mut s.parent[..];
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
    }

    /// After [`StreamCheck::unite`] and the counts: the classes that
    /// finish in this chunk, and those carried to the next one (with
    /// their tallies in a [`StreamCheck::per_component`]).
    fn close(&mut self, s: &mut Scratch, own: u32, next: u32) {
        let k = self.classes;
        let size = (k + next) as usize;
        let parent = &mut s.parent[..];
        if let Some(parts) = &mut self.parts {
            let root = &mut s.parts.root;
            root.clear();
            root.resize(size, Tally::default());
            for (class, t) in parts.carried.iter().enumerate() {
                root[find(parent, class as u32) as usize].add(t);
            }
            for (v, t) in s.parts.at.iter().enumerate() {
                let v = v as u32;
                let element = match self.carry.get(v as usize) {
                    Some(&class) if v < own => class,
                    _ => k + v - own,
                };
                root[find(parent, element) as usize].add(t);
            }
        }
        // Roots reaching the next chunk (mark 1), and the classes that
        // finish here (counted, mark 2).
        s.roots.clear();
        s.mark.clear();
        s.mark.resize(size, 0);
        for j in 0..next {
            let r = find(parent, k + j);
            s.roots.push(r);
            s.mark[r as usize] = 1;
        }
        for class in 0..k {
            let r = find(parent, class) as usize;
            if s.mark[r] == 0 {
                s.mark[r] = 2;
                self.verdict.components += 1;
                if let Some(parts) = &mut self.parts {
                    parts.finish(s.parts.root[r]);
                }
            }
        }
        // Classes for the next chunk's prefix, numbered by first use (the
        // mark of a reaching root becomes its class plus 3).
        self.carry.clear();
        self.classes = 0;
        if let Some(parts) = &mut self.parts {
            parts.carried.clear();
        }
        for &r in &s.roots {
            let m = &mut s.mark[r as usize];
            if *m == 1 {
                *m = self.classes + 3;
                self.classes += 1;
                if let Some(parts) = &mut self.parts {
                    parts.carried.push(s.parts.root[r as usize]);
                }
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
    fn edges(&mut self, s: &mut Scratch, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let n = (own + next) as usize;
        let mut carried = std::mem::take(&mut self.carried_edges);
        s.used.clear();
        s.used.resize(n, 0);
        if s.places.len() < n {
            s.places.resize(n, Places::default());
        }
        s.spill.clear();
        let (used, places, spill) = (&mut s.used[..], &mut s.places[..], &mut s.spill);
        for t in triangles {
            add_edge(used, places, spill, [t[0], t[1]], 1);
            add_edge(used, places, spill, [t[1], t[2]], 1);
            add_edge(used, places, spill, [t[2], t[0]], 1);
        }
        for &[lo, hi, count] in &carried {
            add_edge(used, places, spill, [lo, hi], count);
        }
        carried.clear();
        let mut at = self.parts.as_ref().map(|_| &mut s.parts.at[..]);
        let mut edge = |lo: u32, hi: u32, count: u32| {
            if lo >= own {
                carried.push([lo - own, hi - own, count]);
            } else {
                self.verdict.tally(count);
                if let Some(at) = &mut at {
                    at[lo as usize].edge(count);
                }
            }
        };
        for (lo, &in_use) in s.used.iter().enumerate() {
            let p = &s.places[lo];
            for (&hi, &count) in p.ends.iter().zip(&p.counts).take(usize::from(in_use)) {
                edge(lo as u32, hi, count);
            }
        }
        s.spill.sort_unstable();
        for run in s.spill.chunk_by(|a, b| a == b) {
            edge(run[0][0], run[0][1], run.len() as u32);
        }
        self.carried_edges = carried;
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

/// The edges a vertex is the smaller end of ([`StreamCheck::edges`]): the
/// larger ends, and how many triangles use each.
#[derive(Debug, Clone, Copy, Default)]
struct Places {
    ends: [u32; SLOTS],
    counts: [u32; SLOTS],
}

/// One more use by `k` triangles of the edge `a`-`b` ([`StreamCheck::edges`]):
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
                normals: Vec::new(),
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
                normals: Vec::new(),
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
