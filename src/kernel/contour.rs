//! Closed contours on the cell boundary (the paper's Section 3).
//!
//! Each edge whose corners have different signs carries one vertex. On every
//! face these vertices are joined by segments: an unambiguous face has one
//! segment; an ambiguous face has two, paired by the asymptotic decider. The
//! segments close into up to four contours. A contour is oriented so that a
//! fan over it has its normal pointing to the outside (lower values).
//!
//! The surface of the cell is cut by the contours into regions; each region
//! holds the corners of one *surface component* (corners of one sign joined
//! along cell edges and across faces). The tunnel test needs these labels.

use super::cube::{face_edges, EDGE_CORNERS, FACE_CORNERS};
use super::sweep_pairs::may_join;

/// The contours of one cell configuration under one set of face decisions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ContourSet {
    /// Number of contours (0..=4).
    pub count: u8,
    /// Vertex count of each contour.
    pub len: [u8; 4],
    /// The edges of all contours, one after the other.
    pub edges: [u8; 12],
    /// Bit `i` set: contour `i` meets some face twice, so a fan over it would
    /// put an edge across that face (needs an interior vertex to stay manifold).
    pub meets_face_twice: u8,
    /// Surface component (a corner label) on the inside of each contour.
    pub inside_comp: [u8; 4],
    /// Surface component on the outside of each contour.
    pub outside_comp: [u8; 4],
    /// Surface component label of each corner (the smallest corner in it).
    pub corner_comp: [u8; 8],
    /// Which sweeps of the tunnel test could join two surface components
    /// (see [`may_join`]); 0: the test is skipped.
    pub tunnel_pairs: u8,
}

impl ContourSet {
    /// The edges of contour `i`.
    pub fn contour(&self, i: usize) -> &[u8] {
        let start: usize = self.len[..i].iter().map(|&l| l as usize).sum();
        &self.edges[start..start + self.len[i] as usize]
    }
}

/// Is face `f` ambiguous for configuration `config` (bit c set = corner c inside)?
pub fn face_is_ambiguous(config: u8, f: usize) -> bool {
    let q = FACE_CORNERS[f];
    let s = q.map(|c| config >> c & 1);
    s[0] == s[2] && s[1] == s[3] && s[0] != s[1]
}

/// Builds the contours of `config` where bit `f` of `joined` says that the
/// inside corners of ambiguous face `f` are joined across it.
pub fn build(config: u8, joined: u8) -> ContourSet {
    let inside = |c: usize| config >> c & 1 == 1;
    // Segments: on each face, from an "end" edge back to a "start" edge, so that
    // following them orients contours with the outside on the left.
    let mut next = [u8::MAX; 12];
    let mut seg_face = [u8::MAX; 12];
    for (f, &q) in FACE_CORNERS.iter().enumerate() {
        let e = face_edges(f);
        let ambiguous = face_is_ambiguous(config, f);
        for i in 0..4 {
            // Edge i of the face goes from corner q[i] to q[i+1]; a "start" is
            // an inside-to-outside step in counter-clockwise order.
            if !inside(q[i]) || inside(q[(i + 1) % 4]) {
                continue;
            }
            let end = if ambiguous {
                if joined >> f & 1 == 1 {
                    (i + 1) % 4
                } else {
                    (i + 3) % 4
                }
            } else {
                // The unique outside-to-inside step on this face.
                (0..4)
                    .find(|&k| !inside(q[k]) && inside(q[(k + 1) % 4]))
                    .expect("face with a start has an end")
            };
            next[e[end]] = e[i] as u8;
            seg_face[e[end]] = f as u8;
        }
    }

    let comp = surface_components(config, joined);
    let mut set = ContourSet {
        corner_comp: comp,
        tunnel_pairs: may_join(config, &comp),
        ..ContourSet::default()
    };
    let mut used = [false; 12];
    let mut total = 0;
    for first in 0..12 {
        if used[first] || next[first] == u8::MAX {
            continue;
        }
        let k = set.count as usize;
        let mut faces_seen = 0u8;
        let mut e = first;
        let mut len = 0;
        loop {
            used[e] = true;
            set.edges[total + len] = e as u8;
            len += 1;
            let bit = 1u8 << seg_face[e];
            if faces_seen & bit != 0 {
                set.meets_face_twice |= 1 << k;
            }
            faces_seen |= bit;
            e = next[e] as usize;
            if e == first {
                break;
            }
        }
        let [a, b] = EDGE_CORNERS[first];
        let (cin, cout) = if inside(a) { (a, b) } else { (b, a) };
        set.inside_comp[k] = comp[cin];
        set.outside_comp[k] = comp[cout];
        set.len[k] = len as u8;
        set.count += 1;
        total += len;
    }
    set
}

/// Labels every corner with its surface component: corners of equal sign
/// joined along cell edges, or across an ambiguous face by its decision.
pub fn surface_components(config: u8, joined: u8) -> [u8; 8] {
    let inside = |c: usize| config >> c & 1 == 1;
    let mut label: [u8; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    // At most 12 edges and 6 face diagonals; no allocation (the tables
    // build 16,384 contour sets when a process starts).
    let mut pairs = [(0usize, 0usize); 18];
    let mut count = 0;
    for &[a, b] in &EDGE_CORNERS {
        if inside(a) == inside(b) {
            pairs[count] = (a, b);
            count += 1;
        }
    }
    for (f, &q) in FACE_CORNERS.iter().enumerate() {
        if face_is_ambiguous(config, f) {
            let inside_diag = if inside(q[0]) { 0 } else { 1 };
            let diag = if joined >> f & 1 == 1 {
                inside_diag
            } else {
                1 - inside_diag
            };
            pairs[count] = (q[diag], q[diag + 2]);
            count += 1;
        }
    }
    // Tiny fixed-point union: propagate the smallest label.
    let mut changed = true;
    while changed {
        changed = false;
        for &(a, b) in &pairs[..count] {
            let m = label[a].min(label[b]);
            if label[a] != m || label[b] != m {
                label[a] = m;
                label[b] = m;
                changed = true;
            }
        }
    }
    label
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_corner_gives_a_triangle() {
        let s = build(1, 0);
        assert_eq!(s.count, 1);
        assert_eq!(s.len[0], 3);
        assert_eq!(s.meets_face_twice, 0);
        assert_eq!(s.inside_comp[0], 0);
        assert_eq!(s.outside_comp[0], 1);
    }

    #[test]
    fn every_crossing_edge_is_used_once() {
        for config in 0..=255u8 {
            for joined in 0..64u8 {
                let s = build(config, joined);
                let crossing = EDGE_CORNERS
                    .iter()
                    .filter(|[a, b]| (config >> a & 1) != (config >> b & 1))
                    .count();
                let total: usize = s.len.iter().map(|&l| l as usize).sum();
                assert_eq!(total, crossing);
                for i in 0..s.count as usize {
                    assert!(s.len[i] >= 3);
                    assert_ne!(s.inside_comp[i], s.outside_comp[i]);
                }
            }
        }
    }

    #[test]
    fn contours_plus_one_equal_surface_regions() {
        // Contours on a sphere: regions = contours + 1.
        for config in 1..255u8 {
            for joined in 0..64u8 {
                let s = build(config, joined);
                let mut labels = s.corner_comp.to_vec();
                labels.sort_unstable();
                labels.dedup();
                assert_eq!(
                    labels.len(),
                    s.count as usize + 1,
                    "config {config} joined {joined}"
                );
            }
        }
    }
}
