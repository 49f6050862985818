//! Lookup tables, derived once at start-up from [`super::contour`].
//!
//! Nothing here is typed in by hand: the standard marching-cubes table is the
//! triangulation of the contours of each configuration, so it agrees with the
//! contour code by construction.
//!
//! * `is_ambiguous[config]`: the paper's Definition 1 (corners of one sign
//!   not all joined along cell edges).
//! * `ambiguous_faces[config]`: bit `f` set when face `f` has alternating signs.
//! * `contours`: the contours of each configuration for each combination of
//!   decisions on its ambiguous faces, packed (656 sets of 35 bytes, so that the
//!   ones the data uses stay in cache); [`Tables::set_index`] finds them.
//! * `heads`: for each contour set, the few bytes most ambiguous cells need
//!   of it (see [`SetHead`]): whether a tunnel is possible and, unless a
//!   contour has 12 vertices or two meet a face twice, the fans over its
//!   contours (round interior vertex [`INTERIOR`] for the one that meets a
//!   face twice), so that a cell without a tunnel copies them as MC copies
//!   its triangles.
//! * `mc[config]`: standard MC triangles (edge triples) with the face rule
//!   "inside corners of an ambiguous face are separated". For unambiguous
//!   configurations this is the MC table both methods use.

use super::cell_mesh::INTERIOR;
use super::contour::{self, face_is_ambiguous, ContourSet};
use super::cube::{edge_faces, EDGE_CORNERS};
use super::triangulate::{fan, fan_around};
use std::hint::black_box;
use std::sync::OnceLock;

/// What the common path of an ambiguous cell reads of its contour set, in
/// 16 bytes instead of the set's 35, so that the heads a layer meets stay
/// in the nearest cache while the grid planes stream through it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SetHead {
    /// [`ContourSet::tunnel_pairs`], 0 when the set has fewer than two
    /// contours: 0 means no tunnel is possible.
    pub tunnel_pairs: u8,
    /// Triangles of the set's table fans, 0 if it has none (a contour of 12
    /// vertices, two contours that meet a face twice, or an unambiguous
    /// configuration).
    pub fan_len: u8,
    /// Where the table fans start in `table_fans`.
    pub fan_start: u16,
    /// Flat contours of 3, 4, 5 and 6 vertices (the paper's Table 1), four
    /// bits each from the lowest; only set with the table fans.
    pub flat_counts: u16,
    /// With the table fans: the number of vertices of the one contour that
    /// meets a face twice, whose fan goes round the interior vertex
    /// [`INTERIOR`]; 0 if all contours are flat.
    pub centred_len: u8,
    /// Which contour of the set that is (see `centred_len`).
    pub centred: u8,
    /// [`ContourSet::corner_comp`], the labels the tunnel test joins.
    pub labels: [u8; 8],
}

/// All tables of the kernel.
pub struct Tables {
    /// Definition 1 of the paper, per configuration.
    pub is_ambiguous: [bool; 256],
    /// Faces with alternating signs, per configuration.
    pub ambiguous_faces: [u8; 256],
    /// Contour sets, packed: at [`Tables::set_index`].
    pub contours: Vec<ContourSet>,
    /// Where the sets of each configuration start in `contours`, and (at
    /// 256) where the last one ends: the sets of `config` are
    /// `set_start[config]..set_start[config + 1]`.
    pub set_start: [u16; 257],
    /// `packed[mask][joined]`: the bits of `joined` on the faces of `mask`,
    /// moved down to the lowest bits in face order.
    pub packed: [[u8; 64]; 64],
    /// The head of each set of `contours`, at the same index.
    pub heads: Vec<SetHead>,
    /// The table fans of the sets that have them, one after the other (see
    /// [`SetHead::fan_start`]).
    pub table_fans: Vec<[u8; 3]>,
    /// Standard MC triangles per configuration: `mc_tris[mc_start[c]..mc_start[c + 1]]`.
    pub mc_tris: Vec<[u8; 3]>,
    /// Offsets into `mc_tris`.
    pub mc_start: [u16; 257],
    /// The most MC triangles of any configuration (room a row reserves).
    pub mc_most: usize,
}

impl Tables {
    /// Index into `contours` of the set of `config` under face decisions
    /// `joined` (bit `f`: inside corners of face `f` joined; bits of faces
    /// that are not ambiguous are ignored).
    #[inline]
    pub fn set_index(&self, config: u8, joined: u8) -> usize {
        let mask = self.ambiguous_faces[config as usize];
        let rank = self.packed[mask as usize][(joined & mask) as usize];
        usize::from(self.set_start[config as usize]) + usize::from(rank)
    }

    /// The contour set of `config` under face decisions `joined`.
    pub fn contour_set(&self, config: u8, joined: u8) -> &ContourSet {
        &self.contours[self.set_index(config, joined)]
    }

    /// The table fans of the set with head `head` (empty if it has none).
    #[inline]
    pub fn fans(&self, head: SetHead) -> &[[u8; 3]] {
        let start = usize::from(head.fan_start);
        &self.table_fans[start..start + usize::from(head.fan_len)]
    }

    /// Starts the loads an ambiguous cell of `config` will make after its
    /// face decisions (the row of `packed`; the heads, fans and sets of the
    /// configuration's first and last sets, between which its other sets
    /// lie), so that they overlap with reading its values and deciding its
    /// faces. The grid planes streaming through the cache evict the tables
    /// between layers; without this the cell waits on a chain of dependent
    /// misses.
    #[inline]
    pub fn touch_sets(&self, config: u8) {
        let c = usize::from(config);
        let mask = usize::from(self.ambiguous_faces[c]);
        // Every configuration has at least one set (`build` makes the set
        // of no face joined for each), so the one before the next
        // configuration's first is its last. Indexed directly, the four
        // reads cost a bounds check each and nothing else: cheaper than the
        // `first()` and `last()` of two slices, whose emptiness is checked
        // and whose heads are copied.
        let (first, last) = (
            usize::from(self.set_start[c]),
            usize::from(self.set_start[c + 1]) - 1,
        );
        let (head_first, head_last) = (&self.heads[first], &self.heads[last]);
        // A set without table fans has its `fan_start` at the next set's
        // fans, or at the end of them.
        let fan = |head: &SetHead| {
            self.table_fans
                .get(usize::from(head.fan_start))
                .map_or(0, |f| f[0])
        };
        // One byte of each, combined, handed to `black_box` once (each
        // `black_box` is a store).
        black_box(
            self.packed[mask & 63][0]
                ^ head_first.fan_len
                ^ head_last.fan_len
                ^ fan(head_first)
                ^ fan(head_last)
                ^ self.contours[first].count
                ^ self.contours[last].count,
        );
    }
}

/// The tables, built on first use.
pub fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(build)
}

fn build() -> Tables {
    let mut is_ambiguous = [false; 256];
    let mut ambiguous_faces = [0u8; 256];
    let mut contours = Vec::new();
    let mut set_start = [0u16; 257];
    let mut mc_tris = Vec::new();
    let mut mc_start = [0u16; 257];
    let mut table_fans = Vec::new();
    let mut heads = Vec::new();
    let mut packed = [[0u8; 64]; 64];
    for (mask, row) in packed.iter_mut().enumerate() {
        for (joined, rank) in row.iter_mut().enumerate() {
            *rank = pack_bits(joined as u8, mask as u8);
        }
    }
    for config in 0..256usize {
        let c = config as u8;
        is_ambiguous[config] = !signs_edge_connected(c);
        for f in 0..6 {
            if face_is_ambiguous(c, f) {
                ambiguous_faces[config] |= 1 << f;
            }
        }
        // One set per combination of decisions on the ambiguous faces, in
        // the order of their packed bits.
        let mask = ambiguous_faces[config];
        set_start[config] = contours.len() as u16;
        for joined in 0..64u8 {
            if joined & !mask == 0 {
                let rank = usize::from(packed[mask as usize][joined as usize]);
                debug_assert_eq!(contours.len(), set_start[config] as usize + rank);
                let set = contour::build(c, joined);
                heads.push(set_head(&set, is_ambiguous[config], &mut table_fans));
                contours.push(set);
            }
        }
        mc_start[config] = mc_tris.len() as u16;
        let set = contours[set_start[config] as usize];
        for i in 0..set.count as usize {
            triangulate_polygon(set.contour(i), &mut mc_tris);
        }
    }
    mc_start[256] = mc_tris.len() as u16;
    set_start[256] = contours.len() as u16;
    Tables {
        is_ambiguous,
        ambiguous_faces,
        contours,
        set_start,
        packed,
        heads,
        table_fans,
        mc_tris,
        mc_start,
        mc_most: mc_start
            .windows(2)
            .map(|w| usize::from(w[1] - w[0]))
            .max()
            .unwrap_or(0),
    }
}

/// The head of `set`. Its table fans, if it has them, are appended to
/// `table_fans`: an ambiguous configuration's set whose contours are flat
/// but for at most one that meets a face twice, and none of 12 vertices.
/// They are the triangles the cell's mesh path makes when there is no
/// tunnel, in the same order: a fan per flat contour, and a fan round
/// interior vertex [`INTERIOR`] for the other one.
fn set_head(set: &ContourSet, ambiguous: bool, table_fans: &mut Vec<[u8; 3]>) -> SetHead {
    let lens = &set.len[..set.count as usize];
    let mut head = SetHead {
        tunnel_pairs: if set.count >= 2 { set.tunnel_pairs } else { 0 },
        fan_start: u16::try_from(table_fans.len()).expect("table fans fit u16 offsets"),
        labels: set.corner_comp,
        ..SetHead::default()
    };
    if ambiguous && set.meets_face_twice.count_ones() <= 1 && !lens.contains(&12) {
        for (i, &n) in lens.iter().enumerate() {
            let contour = set.contour(i);
            if set.meets_face_twice >> i & 1 == 1 {
                (head.centred, head.centred_len) = (i as u8, n);
                fan_around(contour, INTERIOR, table_fans);
            } else {
                fan(contour, table_fans);
                if (3..=6).contains(&n) {
                    head.flat_counts += 1 << (4 * (n - 3));
                }
            }
        }
        head.fan_len = u8::try_from(table_fans.len() - usize::from(head.fan_start))
            .expect("at most 12 edges, so at most 12 fan triangles");
    }
    head
}

/// The bits of `bits` at the set bits of `mask`, moved down to bits
/// `0, 1, ...` in order (a parallel bit extract).
fn pack_bits(bits: u8, mask: u8) -> u8 {
    let mut out = 0;
    let mut rank = 0;
    for f in 0..8 {
        if mask >> f & 1 == 1 {
            out |= (bits >> f & 1) << rank;
            rank += 1;
        }
    }
    out
}

/// Definition 1: every two corners of the same sign are joined by a path
/// along cell edges through corners of that sign.
fn signs_edge_connected(config: u8) -> bool {
    for sign in [0u8, 1] {
        let members: Vec<usize> = (0..8).filter(|&c| config >> c & 1 == sign).collect();
        let Some(&first) = members.first() else {
            continue;
        };
        let mut reached = 1u8 << first;
        loop {
            let before = reached;
            for &[a, b] in &EDGE_CORNERS {
                let (ia, ib) = (config >> a & 1 == sign, config >> b & 1 == sign);
                if ia && ib && (reached >> a & 1 == 1 || reached >> b & 1 == 1) {
                    reached |= (1 << a) | (1 << b);
                }
            }
            if reached == before {
                break;
            }
        }
        if reached.count_ones() as usize != members.len() {
            return false;
        }
    }
    true
}

/// Do edges `a` and `b` lie on a common face of the cell?
pub fn share_face(a: usize, b: usize) -> bool {
    let fa = edge_faces(a);
    edge_faces(b).iter().any(|f| fa.contains(f))
}

/// Triangulates a contour without interior vertices, avoiding diagonals
/// between two vertices on a common face where possible (such a diagonal
/// would lie in the face, where the neighbouring cell may draw it too).
/// Triangles keep the contour's orientation.
#[allow(clippy::needless_range_loop)] // interval DP reads best by index
fn triangulate_polygon(poly: &[u8], out: &mut Vec<[u8; 3]>) {
    let n = poly.len();
    let bad = |i: usize, j: usize| -> u32 {
        let adjacent = j == i + 1 || (i == 0 && j == n - 1);
        u32::from(!adjacent && share_face(poly[i] as usize, poly[j] as usize))
    };
    // cost[i][j]: best triangulation of the sub-polygon i..=j (closed by chord i-j).
    let mut cost = vec![vec![0u32; n]; n];
    let mut split = vec![vec![0usize; n]; n];
    for span in 2..n {
        for i in 0..n - span {
            let j = i + span;
            let mut best = (u32::MAX, 0);
            for k in i + 1..j {
                let c = cost[i][k] + cost[k][j] + bad(i, k) + bad(k, j);
                if c < best.0 {
                    best = (c, k);
                }
            }
            cost[i][j] = best.0;
            split[i][j] = best.1;
        }
    }
    fn emit(i: usize, j: usize, split: &[Vec<usize>], poly: &[u8], out: &mut Vec<[u8; 3]>) {
        if j < i + 2 {
            return;
        }
        let k = split[i][j];
        out.push([poly[i], poly[k], poly[j]]);
        emit(i, k, split, poly, out);
        emit(k, j, split, poly, out);
    }
    emit(0, n - 1, &split, poly, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_contour_sets_equal_their_own_build() {
        let t = tables();
        for config in 0..=255u8 {
            for joined in 0..64u8 {
                let set = *t.contour_set(config, joined);
                assert_eq!(set, contour::build(config, joined), "{config} {joined}");
            }
        }
    }

    #[test]
    fn definition_one_counts() {
        let t = tables();
        let ambiguous = t.is_ambiguous.iter().filter(|&&a| a).count();
        // MC cases 3, 4, 6, 7 (12 + 4 + 24 + 8 configurations, and as many
        // complements) and 10, 12, 13 (6 + 24 + 2, closed under complement).
        assert_eq!(ambiguous, 2 * (12 + 4 + 24 + 8) + 6 + 24 + 2);
        // Unambiguous configurations never have an ambiguous face.
        for c in 0..256 {
            if !t.is_ambiguous[c] {
                assert_eq!(t.ambiguous_faces[c], 0, "config {c}");
            }
        }
    }

    #[test]
    fn heads_agree_with_their_sets_and_fans_cover_the_mesh_paths_triangles() {
        let t = tables();
        let mut centred = 0;
        for config in 0..256 {
            for joined in 0..64 {
                let i = t.set_index(config as u8, joined);
                let (set, head) = (t.contours[i], t.heads[i]);
                let lens = &set.len[..set.count as usize];
                let twice = set.meets_face_twice;
                let tabled = twice.count_ones() <= 1 && !lens.contains(&12);
                let fans = t.fans(head);
                assert_eq!(head.labels, set.corner_comp);
                let pairs = if set.count >= 2 { set.tunnel_pairs } else { 0 };
                assert_eq!(head.tunnel_pairs, pairs, "{config} {joined}");
                if !(t.is_ambiguous[config] && tabled) {
                    assert!(fans.is_empty(), "{config} {joined}");
                    assert_eq!(head.flat_counts, 0, "{config} {joined}");
                    assert_eq!(head.centred_len, 0, "{config} {joined}");
                    continue;
                }
                // Table 1's flat contours, by vertex count.
                let flat = |c: usize| twice >> c & 1 == 0;
                for n in 3..=6u8 {
                    let count = (0..lens.len()).filter(|&c| flat(c) && lens[c] == n);
                    let nibble = head.flat_counts >> (4 * (n - 3)) & 0xf;
                    assert_eq!(usize::from(nibble), count.count(), "{config} {joined}");
                }
                // The contour that meets a face twice, if any.
                if twice == 0 {
                    assert_eq!(head.centred_len, 0, "{config} {joined}");
                } else {
                    centred += 1;
                    let c = usize::from(head.centred);
                    assert_eq!(twice, 1 << c, "{config} {joined}");
                    assert_eq!(head.centred_len, lens[c], "{config} {joined}");
                }
                // The mesh path's triangles for the set, in its order: n - 2
                // per flat contour, n round the interior vertex.
                let mut expect = Vec::new();
                for c in 0..lens.len() {
                    let contour = set.contour(c);
                    if flat(c) {
                        fan(contour, &mut expect);
                    } else {
                        let n = contour.len();
                        let ring = (0..n).map(|k| [contour[k], contour[(k + 1) % n], INTERIOR]);
                        expect.extend(ring);
                    }
                }
                assert_eq!(fans, &expect[..], "{config} {joined}");
            }
        }
        assert!(centred > 100, "only {centred} sets with an interior vertex");
    }

    #[test]
    fn mc_table_sizes() {
        let t = tables();
        let count = |c: usize| (t.mc_start[c + 1] - t.mc_start[c]) as usize;
        assert_eq!(count(0), 0);
        assert_eq!(count(255), 0);
        assert_eq!(count(1), 1);
        assert_eq!(count(3), 2);
        // Each contour of n vertices gives n - 2 triangles.
        for c in 0..256 {
            let set = *t.contour_set(c as u8, 0);
            let expect: usize = (0..set.count as usize)
                .map(|i| set.len[i] as usize - 2)
                .sum();
            assert_eq!(count(c), expect);
        }
    }
}
