//! Union-find structures of the checker: over vertices (components) and,
//! with parity, over triangles (orientability); [`find`] for the streaming
//! check's windows.

/// The root of `x`, halving the path on the way.
#[inline]
pub(super) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = parent[x as usize];
    }
    x
}

/// Marker for "no value" in the `u32` index arrays.
pub(super) const NONE: u32 = u32::MAX;

/// Union-find over `u32` ids with path halving and union by size.
pub(super) struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    pub(super) fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    pub(super) fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    pub(super) fn union(&mut self, a: u32, b: u32) {
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
pub(super) struct ParityUnionFind {
    parent: Vec<u32>,
    /// Bit 0: parity to the parent. Bit 1 (roots only): contradiction seen.
    /// Bits 2..: rank, saturating.
    bits: Vec<u8>,
}

impl ParityUnionFind {
    const PARITY: u8 = 1;
    const CONFLICT: u8 = 2;
    const RANK_ONE: u8 = 4;

    pub(super) fn new(n: usize) -> Self {
        ParityUnionFind {
            parent: (0..n as u32).collect(),
            bits: vec![0; n],
        }
    }

    /// Returns the root of `x` and the parity from `x` to it, compressing the
    /// path.
    pub(super) fn find(&mut self, x: u32) -> (u32, u8) {
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
    pub(super) fn relate(&mut self, a: u32, b: u32, relation: u8) {
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

    pub(super) fn has_conflict(&mut self, x: u32) -> bool {
        let (root, _) = self.find(x);
        self.bits[root as usize] & Self::CONFLICT != 0
    }
}
