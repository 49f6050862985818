//! [`StreamGeometry`]: the geometric counts of
//! [`check_geometry`](super::check_geometry) (zero-area triangles,
//! vertices sharing a position) while a `.tmesh` file's chunks stream.
//!
//! A triangle's corners are in its chunk and the next one, so its area is
//! known once the next chunk has come. Vertices sharing a position are
//! looked for among the vertices of each two consecutive chunks, where
//! they are in every file tmc writes: a chunk holds the vertices of one
//! grid plane (on the plane's edges and on the edges up to the next plane)
//! and those inside the cells between the two planes, so the vertices of
//! chunks more than one apart lie between different planes. (A file made
//! otherwise, with such vertices further apart, has them counted by the
//! in-memory check only: see docs/usage.md.) A vertex's verdict is final
//! once the chunk after its own has come, and so a triangle's once the
//! chunk after its next has: three chunks are held.

use super::geometry::{zero_area, FIRST_FEW};
use super::report::Geometry;
use std::collections::VecDeque;

/// One chunk held until its triangles are counted.
#[derive(Debug)]
struct Held {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    /// Per vertex: does another vertex have its position?
    shared: Vec<bool>,
    /// The number in the mesh of the chunk's first triangle.
    first_triangle: usize,
}

/// The geometric counts of a mesh fed chunk by chunk, in file order
/// ([`StreamGeometry::chunk`], then [`StreamGeometry::finish`]).
#[derive(Debug, Default)]
pub(super) struct StreamGeometry {
    report: Geometry,
    held: VecDeque<Held>,
    triangles: usize,
    /// The positions of the last two chunks sorted, with the chunk (0 or
    /// 1 of the two) and vertex of each (working space).
    order: Vec<([u32; 3], u8, u32)>,
}

impl StreamGeometry {
    /// Takes the next chunk: its vertices, and its triangles indexing them
    /// and then the next chunk's first vertices.
    pub fn chunk(&mut self, vertices: Vec<[f32; 3]>, triangles: Vec<[u32; 3]>) {
        let shared = vec![false; vertices.len()];
        let first_triangle = self.triangles;
        self.triangles += triangles.len();
        self.held.push_back(Held {
            vertices,
            triangles,
            shared,
            first_triangle,
        });
        self.mark_shared();
        if self.held.len() == 3 {
            self.count_first();
        }
    }

    /// The counts once the last chunk has been given.
    pub fn finish(mut self) -> Geometry {
        while !self.held.is_empty() {
            self.count_first();
        }
        self.report
    }

    /// Marks the vertices of the last chunk that share a position with
    /// another of its own or of the chunk before (whose verdicts are then
    /// final): the positions of both, sorted, equal ones adjacent.
    fn mark_shared(&mut self) {
        let n = self.held.len();
        let pair = self.held.range(n.saturating_sub(2)..);
        let key = |p: &[f32; 3]| p.map(|c| (c + 0.0).to_bits());
        self.order.clear();
        for (c, h) in pair.enumerate() {
            let at = h.vertices.iter().enumerate();
            self.order
                .extend(at.map(|(i, p)| (key(p), c as u8, i as u32)));
        }
        self.order.sort_unstable();
        let last = (n - 1).min(1) as u8;
        for run in self.order.chunk_by(|a, b| a.0 == b.0) {
            // Only runs with a vertex of the new chunk are new.
            if run.len() < 2 || run.iter().all(|e| e.1 != last) {
                continue;
            }
            for &(_, c, i) in run {
                let h = &mut self.held[n - 1 - usize::from(last - c)];
                h.shared[i as usize] = true;
            }
        }
    }

    /// Counts the triangles of the first chunk held (whose corners'
    /// verdicts are final) and lets it go.
    fn count_first(&mut self) {
        let Some(h) = self.held.pop_front() else {
            return;
        };
        let own = h.vertices.len();
        let next = self.held.front();
        let corner = |i: u32| -> Option<([f32; 3], bool)> {
            let i = i as usize;
            if i < own {
                Some((h.vertices[i], h.shared[i]))
            } else {
                let n = next?;
                let j = i - own;
                Some((*n.vertices.get(j)?, n.shared[j]))
            }
        };
        let r = &mut self.report;
        for (k, t) in h.triangles.iter().enumerate() {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                continue;
            }
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                continue;
            };
            let number = h.first_triangle + k;
            if zero_area([a.0, b.0, c.0]) {
                r.zero_area_triangles += 1;
                if r.first_zero_area_triangles.len() < FIRST_FEW {
                    r.first_zero_area_triangles.push(number);
                }
            }
            if a.1 || b.1 || c.1 {
                r.shared_position_triangles += 1;
                if r.first_shared_position_triangles.len() < FIRST_FEW {
                    r.first_shared_position_triangles.push(number);
                }
            }
        }
        r.shared_position_vertices += h.shared.iter().filter(|&&s| s).count();
    }
}

#[cfg(test)]
mod tests {
    use super::super::check_geometry;
    use super::StreamGeometry;
    use crate::mesh::Mesh;

    #[test]
    fn the_counts_are_those_of_the_whole_mesh() {
        // Three chunks of four vertices; triangles reaching into the next
        // chunk; a zero-area triangle; positions shared within a chunk and
        // across two consecutive ones (-0 as 0).
        let vertices: Vec<[f32; 3]> = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
            [1.0, 1.0, 2.0],
            [-0.0, 1.0, 1.0],
            [5.0, 1.0, 2.0],
            [1.0, 5.0, 2.0],
        ];
        let chunks: [Vec<[u32; 3]>; 3] = [
            vec![[0, 1, 2], [0, 1, 3], [1, 3, 4], [3, 2, 2]],
            vec![[0, 1, 2], [2, 3, 4], [1, 2, 5]],
            vec![[0, 2, 3], [1, 2, 3]],
        ];
        let mut triangles = Vec::new();
        let mut stream = StreamGeometry::default();
        for (c, tris) in chunks.iter().enumerate() {
            let base = 4 * c as u32;
            triangles.extend(tris.iter().map(|t| t.map(|i| i + base)));
            stream.chunk(vertices[4 * c..4 * c + 4].to_vec(), tris.clone());
        }
        let whole = check_geometry(&Mesh {
            vertices,
            triangles,
            ..Mesh::default()
        });
        assert_eq!(whole.zero_area_triangles, 3);
        assert_eq!(whole.shared_position_vertices, 3);
        assert_eq!(stream.finish(), whole);
    }
}
