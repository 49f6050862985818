//! The link test of one vertex, shared by [`check_mesh`](super::check_mesh)
//! and the streaming check ([`super::stream`]): do the vertex's triangles
//! form a single fan?

use super::union_find::UnionFind;

/// Scratch space for testing whether the link of a vertex (the edges
/// opposite to it in its triangles) is a single path or cycle. `T` names
/// the vertices: `u32` indices of a whole mesh, `u64` numbers of a stream.
#[derive(Debug)]
pub(super) struct LinkScratch<T> {
    edges: Vec<(T, T)>,
    nodes: Vec<T>,
    degree: Vec<u8>,
    parent: Vec<u8>,
}

impl<T> Default for LinkScratch<T> {
    fn default() -> Self {
        LinkScratch {
            edges: Vec::new(),
            nodes: Vec::new(),
            degree: Vec::new(),
            parent: Vec::new(),
        }
    }
}

impl<T: Copy + Ord> LinkScratch<T> {
    pub(super) fn clear(&mut self) {
        self.edges.clear();
    }

    pub(super) fn push(&mut self, a: T, b: T) {
        self.edges.push((a, b));
    }

    /// After [`LinkScratch::is_single_fan`]: whether the link has one node
    /// more than edges, i.e. a single fan is a path (the vertex is on the
    /// boundary) rather than a cycle.
    pub(super) fn is_path(&self) -> bool {
        self.nodes.len() == self.edges.len() + 1
    }

    /// A connected multigraph without loops whose degrees are at most 2 is
    /// a path or a cycle, i.e. the triangles form one fan.
    pub(super) fn is_single_fan(&mut self) -> bool {
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
        let index = |x: T| self.nodes.binary_search(&x).unwrap_or(0) as u32;
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
