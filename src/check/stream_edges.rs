//! [`EdgeTable`]: the edges of a window of vertices, each kept at its
//! smaller end and counted, for the preview's streaming count
//! ([`StreamCheck::chunk`](super::StreamCheck::chunk) without the vertex
//! sweep).
//!
//! Each window vertex has [`SLOTS`] places, each the larger end of an edge
//! and how many triangles use it: adding an edge compares its larger end
//! with the few its smaller end has so far (a CT surface's vertex is the
//! smaller end of about three edges). A vertex with more distinct edges
//! than places sends the rest to a list, sorted once when the edges are
//! read: a run of equal edges is one edge and its length the edge's
//! triangles. Memory is [`SLOTS`] pairs of `u32` per window vertex.

/// Places per vertex for the edges it is the smaller end of.
pub(super) const SLOTS: usize = 6;

/// An empty place: no larger end is `u32::MAX`, an index past any window.
const EMPTY: u32 = u32::MAX;

/// The edges a vertex is the smaller end of: the larger ends (the places
/// in use first, then [`EMPTY`] ones), and how many triangles use each.
#[derive(Debug, Clone, Copy)]
struct Places {
    ends: [u32; SLOTS],
    counts: [u32; SLOTS],
}

/// The edges of one window, by smaller end ([`EdgeTable::start`], then
/// [`Window::add`] and [`Window::finish`]). Kept between windows for
/// its room.
#[derive(Debug, Default)]
pub(super) struct EdgeTable {
    /// Per window vertex (the first ones: the table keeps the room of the
    /// largest window).
    places: Vec<Places>,
    /// Edges past a full vertex's places, once per use.
    spill: Vec<[u32; 2]>,
    /// The window's edges in places of three or more triangles.
    over: Over,
}

/// Of the edges in places of three or more triangles: their counts past
/// two, summed, and how many they are (rare on a surface, so kept apart
/// from the counts each edge changes).
#[derive(Debug, Default)]
struct Over {
    excess: u64,
    edges: u64,
}

impl Over {
    /// An edge used `count` times and now `k` more, past two in all.
    #[cold]
    #[inline(never)]
    fn add(&mut self, count: u32, k: u32) {
        self.excess += u64::from(count + k - 2 - count.saturating_sub(2));
        self.edges += u64::from(count < 3);
    }
}

/// An [`EdgeTable`] being filled: its places, as many as the window has
/// vertices, its spill list, and sums over the edges in places from
/// which their tally follows ([`Window::finish`]).
pub(super) struct Window<'a> {
    places: &'a mut [Places],
    spill: &'a mut Vec<[u32; 2]>,
    /// Edges in places.
    edges: u64,
    /// Those of three or more triangles.
    over: &'a mut Over,
}

/// Edges counted: all of them, those of one triangle, those of three or
/// more.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct EdgeTally {
    pub edges: u64,
    pub boundary: u64,
    pub nonmanifold: u64,
}

impl EdgeTally {
    /// One more edge, used by `count` triangles.
    fn add(&mut self, count: u32) {
        self.edges += 1;
        self.boundary += u64::from(count == 1);
        self.nonmanifold += u64::from(count >= 3);
    }
}

impl EdgeTable {
    /// Empties the table for a window of `n` vertices (whose indices are
    /// below `u32::MAX`) and lends it to be filled.
    pub fn start(&mut self, n: usize) -> Window<'_> {
        let empty = Places {
            ends: [EMPTY; SLOTS],
            counts: [0; SLOTS],
        };
        if self.places.len() < n {
            self.places.resize(n, empty);
        }
        for p in &mut self.places[..n] {
            p.ends = [EMPTY; SLOTS];
        }
        self.spill.clear();
        self.over = Over::default();
        Window {
            places: &mut self.places[..n],
            spill: &mut self.spill,
            edges: 0,
            over: &mut self.over,
        }
    }
}

impl Window<'_> {
    /// One more use by `k` triangles of the edge `lo`-`hi` (`lo <= hi`,
    /// both below the window's size): its count in one of `lo`'s places,
    /// the first empty place, or, with every place taken by other edges,
    /// `k` entries in the spill list. Whether the edge may be new: `false`
    /// only when it was in the table already (a spilled edge is always
    /// "may be new").
    #[inline(always)]
    pub fn add(&mut self, lo: u32, hi: u32, k: u32) -> bool {
        let p = &mut self.places[lo as usize];
        for i in 0..SLOTS {
            let end = p.ends[i];
            if end == hi {
                let count = p.counts[i];
                p.counts[i] = count + k;
                if count + k > 2 {
                    self.over.add(count, k);
                }
                return false;
            }
            if end == EMPTY {
                p.ends[i] = hi;
                p.counts[i] = k;
                self.edges += 1;
                if k > 2 {
                    self.over.add(0, k);
                }
                return true;
            }
        }
        self.spill.extend(std::iter::repeat_n([lo, hi], k as usize));
        true
    }

    /// The tally of the window's edges but those whose smaller end is
    /// `own` or past it, which go to `carry` (smaller end, larger end,
    /// triangles), to be added to the next window; `uses` is the sum of
    /// the `k` of every [`Window::add`].
    ///
    /// Of the edges in places (counts `c`), the tally follows from sums:
    /// `Σ c = 2E - B + Σ max(c - 2, 0)` (`E` edges, `B` of them of count
    /// one), so that a count need not be looked at again.
    pub fn finish(self, own: u32, uses: u64, mut carry: impl FnMut(u32, u32, u32)) -> EdgeTally {
        let (mut edges, mut excess, mut nonmanifold) =
            (self.edges, self.over.excess, self.over.edges);
        let mut uses = uses - self.spill.len() as u64;
        let later = self.places.iter().enumerate().skip(own as usize);
        for (lo, p) in later {
            for (&hi, &count) in p.ends.iter().zip(&p.counts) {
                if hi == EMPTY {
                    break;
                }
                edges -= 1;
                uses -= u64::from(count);
                excess -= u64::from(count.saturating_sub(2));
                nonmanifold -= u64::from(count > 2);
                carry(lo as u32, hi, count);
            }
        }
        let mut tally = EdgeTally {
            edges,
            boundary: 2 * edges + excess - uses,
            nonmanifold,
        };
        // The spilled edges, each a run of equal entries once sorted.
        self.spill.sort_unstable();
        for run in self.spill.chunk_by(|a, b| a == b) {
            let (lo, hi, count) = (run[0][0], run[0][1], run.len() as u32);
            if lo < own {
                tally.add(count);
            } else {
                carry(lo, hi, count);
            }
        }
        tally
    }
}

#[cfg(test)]
mod tests {
    use super::{EdgeTable, EdgeTally, EMPTY};
    use std::collections::BTreeMap;

    /// The table's tally and carried edges against a map's, on edges at a
    /// few vertices, some with more larger ends than places, added once
    /// or several times, with counts of one to three; and whether `add`
    /// said "new" the first time only (or for a spilled edge).
    #[test]
    fn the_table_counts_every_edge_as_a_map_does() {
        let mut table = EdgeTable::default();
        let mut tallies = [0; 3];
        for round in 0..40u32 {
            let n = 40 + round % 3;
            let own = [5, 20, n][round as usize % 3];
            let mut window = table.start(n as usize);
            let mut map = BTreeMap::new();
            let mut uses = 0;
            let mut state = 0x9e37_79b9u32.wrapping_add(round);
            for _ in 0..100 + 20 * round {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                // Vertices 0 and 30 get many larger ends, the others few.
                let lo = [0, 30, state % 7, 21 + state % 5][(state >> 4) as usize % 4];
                let hi = lo + 1 + (state >> 8) % if lo % 30 == 0 { 9 } else { 3 };
                let k = 1 + (state >> 20) % 3;
                let before = map.get(&(lo, hi)).copied();
                *map.entry((lo, hi)).or_insert(0) += k;
                let new = window.add(lo, hi, k);
                uses += u64::from(k);
                if before.is_none() {
                    assert!(new, "{lo}-{hi} is new");
                }
                if !new {
                    assert!(before.is_some(), "{lo}-{hi} was not there");
                }
            }
            let mut carried = BTreeMap::new();
            let tally = window.finish(own, uses, |lo, hi, count| {
                assert!(carried.insert((lo, hi), count).is_none(), "{lo}-{hi} twice");
            });
            let mut expected = EdgeTally::default();
            for (&(lo, _), &count) in map.iter().filter(|e| e.0 .0 < own) {
                expected.edges += 1;
                expected.boundary += u64::from(count == 1);
                expected.nonmanifold += u64::from(count >= 3);
                assert!(lo < own);
            }
            map.retain(|e, _| e.0 >= own);
            assert_eq!((tally, carried), (expected, map), "round {round}");
            tallies[0] += tally.boundary;
            tallies[1] += tally.nonmanifold;
            // Vertex 0's places all taken: some of its edges were spilled.
            tallies[2] += u64::from(table.places[0].ends.iter().all(|&e| e != EMPTY));
        }
        assert!(tallies.iter().all(|&t| t > 0), "{tallies:?}");
    }
}
