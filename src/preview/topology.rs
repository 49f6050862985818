//! The closed/genus verdict a preview writes under its picture, counted
//! while the chunks stream, in plane order, without holding the mesh.
//!
//! A chunk's triangles use its own vertices and a prefix of the next
//! chunk's ([`crate::Chunk`]), so the count needs a window of two chunks:
//! * **components**: a union-find over the classes the current chunk's
//!   vertices belong to (carried from the chunks before) and the next
//!   chunk's prefix; a class none of whose members reaches the next chunk
//!   is a finished component;
//! * **edges**: a chunk's edges bucketed by smaller end and counted; an edge with both ends
//!   in the next chunk may also be used by that chunk's triangles and is
//!   carried to it, one with both ends in the chunk's own vertices may have
//!   been carried from the chunk before and is matched against that list.
//!
//! The mesh is **closed** when every edge has two triangles; its genus is
//! then `C - χ/2` summed over its `C` components (`χ = V - E + F`), as
//! `tmc check` reports for a closed orientable mesh. Memory is that of two
//! chunks.

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

    /// The verdict in a few words, as the caption shows it.
    pub fn describe(&self) -> String {
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
    /// Scratch: the edge buckets, by smaller end: where each starts in
    /// `larger`, and the larger ends.
    start: Vec<u32>,
    larger: Vec<u32>,
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
            self.tally(count);
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
    /// The edges are bucketed by their smaller end (a counting sort over
    /// the window's vertices, linear in the triangles; an edge carried from
    /// the chunk before goes in as many times as it had triangles), and
    /// each bucket, a few larger ends, sorted in place: equal ends are one
    /// edge, counted by its run.
    fn edges(&mut self, own: u32, next: u32, triangles: &[[u32; 3]]) {
        let n = (own + next) as usize;
        let carried = std::mem::take(&mut self.carried_edges);
        // Bucket ends by smaller end (prefix sums of the counts)...
        self.start.clear();
        self.start.resize(n + 1, 0);
        let start = &mut self.start[..];
        for t in triangles {
            start[t[0].min(t[1]) as usize] += 1;
            start[t[1].min(t[2]) as usize] += 1;
            start[t[2].min(t[0]) as usize] += 1;
        }
        for &[lo, _, count] in &carried {
            start[lo as usize] += count;
        }
        let mut total = 0;
        for s in start.iter_mut() {
            total += *s;
            *s = total;
        }
        // ... filled from the end, which leaves each bucket's start.
        self.larger.clear();
        self.larger.resize(total as usize, 0);
        let larger = &mut self.larger[..];
        let mut put = |a: u32, b: u32| {
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            let slot = &mut start[lo as usize];
            *slot -= 1;
            larger[*slot as usize] = hi;
        };
        for t in triangles {
            put(t[0], t[1]);
            put(t[1], t[2]);
            put(t[2], t[0]);
        }
        for &[lo, hi, count] in &carried {
            for _ in 0..count {
                put(lo, hi);
            }
        }
        let mut carried = carried;
        carried.clear();
        for lo in 0..n {
            let (s, e) = (start[lo] as usize, start[lo + 1] as usize);
            let bucket = &mut larger[s..e];
            insertion_sort(bucket);
            let mut i = 0;
            while i < bucket.len() {
                let hi = bucket[i];
                let mut j = i + 1;
                while j < bucket.len() && bucket[j] == hi {
                    j += 1;
                }
                let count = (j - i) as u32;
                if lo as u32 >= own {
                    carried.push([lo as u32 - own, hi - own, count]);
                } else {
                    self.verdict.edges += 1;
                    match count {
                        1 => self.verdict.boundary_edges += 1,
                        2 => {}
                        _ => self.verdict.nonmanifold_edges += 1,
                    }
                }
                i = j;
            }
        }
        self.carried_edges = carried;
    }

    /// One distinct edge used by `count` triangles.
    fn tally(&mut self, count: u32) {
        self.verdict.edges += 1;
        match count {
            1 => self.verdict.boundary_edges += 1,
            2 => {}
            _ => self.verdict.nonmanifold_edges += 1,
        }
    }
}

/// Sorts a few numbers in place (a bucket holds about six).
fn insertion_sort(v: &mut [u32]) {
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && v[j - 1] > x {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
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
}
