//! The reference cell: corners, edges and faces, numbered once for the crate.
//!
//! Corner `c` sits at `(c & 1, (c >> 1) & 1, (c >> 2) & 1)` (the paper's
//! `v0..v7`). Edges 0..4 run along x, 4..8 along y, 8..12 along z. Faces are
//! listed with their corners counter-clockwise seen from outside the cell.

/// Local coordinates of corner `c`.
pub const fn corner_pos(c: usize) -> [u8; 3] {
    [(c & 1) as u8, ((c >> 1) & 1) as u8, ((c >> 2) & 1) as u8]
}

/// The two corners of each edge, lower corner first.
pub const EDGE_CORNERS: [[usize; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7],
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// Axis (0 = x, 1 = y, 2 = z) along which edge `e` runs.
pub const fn edge_axis(e: usize) -> usize {
    e / 4
}

/// Corners of each face, counter-clockwise seen from outside.
/// Faces: 0: z=0, 1: z=1, 2: y=0, 3: y=1, 4: x=0, 5: x=1.
pub const FACE_CORNERS: [[usize; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

/// Index of the edge joining corners `a` and `b` (which must be neighbours).
pub const fn edge_between(a: usize, b: usize) -> usize {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let mut e = 0;
    while e < 12 {
        if EDGE_CORNERS[e][0] == lo && EDGE_CORNERS[e][1] == hi {
            return e;
        }
        e += 1;
    }
    panic!("corners are not neighbours")
}

/// The edges of each face in the cyclic order of [`FACE_CORNERS`]: edge `i`
/// joins corners `i` and `i + 1` (mod 4) of the face.
pub const fn face_edges(face: usize) -> [usize; 4] {
    FACE_EDGES[face]
}

/// [`face_edges`] of every face, computed at compile time.
const FACE_EDGES: [[usize; 4]; 6] = {
    let mut table = [[0; 4]; 6];
    let mut f = 0;
    while f < 6 {
        let q = FACE_CORNERS[f];
        let mut i = 0;
        while i < 4 {
            table[f][i] = edge_between(q[i], q[(i + 1) % 4]);
            i += 1;
        }
        f += 1;
    }
    table
};

/// The two faces that contain edge `e`.
pub fn edge_faces(e: usize) -> [usize; 2] {
    let mut out = [usize::MAX; 2];
    let mut n = 0;
    for f in 0..6 {
        if face_edges(f).contains(&e) {
            out[n] = f;
            n += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: [u8; 3], b: [u8; 3]) -> [i32; 3] {
        [0, 1, 2].map(|i| a[i] as i32 - b[i] as i32)
    }

    #[test]
    fn faces_are_counter_clockwise_from_outside() {
        for (f, q) in FACE_CORNERS.iter().enumerate() {
            let axis = 2 - f / 2;
            let outward = if f % 2 == 0 { -1 } else { 1 };
            for c in q {
                assert_eq!(corner_pos(*c)[axis] as i32, (outward + 1) / 2);
            }
            let a = sub(corner_pos(q[1]), corner_pos(q[0]));
            let b = sub(corner_pos(q[2]), corner_pos(q[1]));
            let cross = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            assert_eq!(cross[axis], outward, "face {f}");
        }
    }

    #[test]
    fn edges_run_along_their_axis() {
        for (e, [a, b]) in EDGE_CORNERS.iter().enumerate() {
            let d = sub(corner_pos(*b), corner_pos(*a));
            let mut expect = [0; 3];
            expect[edge_axis(e)] = 1;
            assert_eq!(d, expect);
            assert_eq!(edge_faces(e).iter().filter(|&&f| f < 6).count(), 2);
        }
    }
}
