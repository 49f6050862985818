//! Triangulation rules of Section 5 for the contours of one ambiguous cell.
//!
//! Every rule emits triangles only between contour vertices of one contour
//! and interior vertices of the cell; no triangle edge joins two vertices of
//! a face unless they are consecutive on a contour. That is what keeps the
//! mesh manifold across cell borders whatever the rules decide.
//!
//! * a contour meeting every face at most once: a fan (a flat polygon);
//! * a contour meeting some face twice (the paper's ambiguous contours with
//!   6 to 9 vertices): a fan around one interior vertex;
//! * a tunnel: each of its two contours is joined by a strip to a triangle of
//!   three interior vertices (the inner hexagon with consecutive vertices
//!   collapsed), the two strips winding round it in opposite directions;
//! * the 12-vertex contour: one such strip, closed by the inner triangle.

use super::cell_mesh::{CellMesh, VertexRef};
use glam::DVec3;

/// A fan over `contour` (edge indices), from its first vertex.
pub fn fan(contour: &[u8], out: &mut Vec<[VertexRef; 3]>) {
    for i in 1..contour.len() - 1 {
        out.push([contour[0], contour[i], contour[i + 1]]);
    }
}

/// A fan over `contour` around the interior vertex `centre` (a vertex ref).
pub fn fan_around(contour: &[u8], centre: u8, out: &mut Vec<[VertexRef; 3]>) {
    let n = contour.len();
    for i in 0..n {
        out.push([contour[i], contour[(i + 1) % n], centre]);
    }
}

/// Assignment of contour vertices to the three inner vertices: each step
/// along the contour stays or moves one place in direction `dir` (+1 or -1,
/// mod 3), one full turn in all, at the least total cost. Walking forward
/// round the ring keeps the fans of a strip from overlapping, which a
/// nearest-vertex assignment does not guarantee.
///
/// Should no cost compare (not a number), the result is still a valid
/// assignment: the contour split into three runs, one per inner vertex.
pub fn ring_assignment(cost: &[[f64; 3]], dir: i32) -> (f64, [u8; 12]) {
    let n = cost.len();
    assert!((1..=12).contains(&n), "contour of {n} vertices");
    let step = dir.rem_euclid(3) as usize;
    // A step known at compile time makes every label and tie rule below a
    // constant: no table lookups and no selects between `<` and `<=`.
    let ends = match step {
        0 => ring_starts::<0>(cost),
        1 => ring_starts::<1>(cost),
        _ => ring_starts::<2>(cost),
    };
    // Closing edge back to vertex 0: a stay after three steps, or the third
    // step; the first strictly cheapest, in order of k0 and then of these.
    let mut best = (f64::INFINITY, None);
    for (k0, closings) in ends.into_iter().enumerate() {
        for (c, path) in closings {
            if c < best.0 {
                best = (c, Some((k0, path)));
            }
        }
    }
    let Some((k0, path)) = best.1 else {
        let runs = std::array::from_fn(|i| (3 * i / n * step % 3) as u8);
        return (f64::INFINITY, runs);
    };
    // A cost below infinity comes from vertex 0 at k0 (a state not reached
    // yet stays infinite or not a number), so the path has its s steps.
    let mut asg = [0u8; 12];
    let mut steps = 0;
    for (i, a) in asg.iter_mut().enumerate().take(n) {
        steps += usize::from(path >> i & 1 == 1);
        *a = ((k0 + steps * step) % 3) as u8;
    }
    (best.0, asg)
}

/// The dynamic programme of [`ring_assignment`] for each start `k0` of
/// vertex 0: the cost and path of ending after three steps, then after two.
fn ring_starts<const STEP: usize>(cost: &[[f64; 3]]) -> [[(f64, u16); 2]; 3] {
    [
        ring_start::<STEP, 0>(cost),
        ring_start::<STEP, 1>(cost),
        ring_start::<STEP, 2>(cost),
    ]
}

/// For the start K0 of vertex 0, the vertex after s steps sits at
/// `K0 + s STEP`: so `d[s]`, the best cost so far with the current vertex
/// after s steps, says where that vertex is. Each entry takes the better of
/// two candidates, stay (s steps before) or step (s - 1); a tie goes to the
/// candidate whose previous vertex is at the smaller k, as if the candidates
/// were offered in order of k. The four states live in registers, and each
/// carries its path as a bit set of the vertices reached by a step (bit i: a
/// step from i - 1 to i), so there is no table to fill and no backtrack.
#[inline(always)]
fn ring_start<const STEP: usize, const K0: usize>(cost: &[[f64; 3]]) -> [(f64, u16); 2] {
    let at: [usize; 4] = std::array::from_fn(|s| (K0 + s * STEP) % 3);
    // Whether a tie takes the step into state s (s - 1 steps at a smaller k).
    let tie = |s: usize| at[s - 1] < at[s];
    // States not reached yet start at infinity, as in a table: an infinite
    // cost can make them not a number, which then loses every comparison.
    let mut d = [cost[0][K0], f64::INFINITY, f64::INFINITY, f64::INFINITY];
    let mut path = [0u16; 4];
    for (i, row) in cost.iter().enumerate().skip(1) {
        let bit = 1u16 << i;
        let c = at.map(|k| row[k]);
        let better = |s: usize| {
            let (stay, moved) = (d[s] + c[s], d[s - 1] + c[s]);
            let take = if tie(s) { moved <= stay } else { moved < stay };
            if take {
                (moved, path[s - 1] | bit)
            } else {
                (stay, path[s])
            }
        };
        let ((d1, p1), (d2, p2), (d3, p3)) = (better(1), better(2), better(3));
        d = [d[0] + c[0], d1, d2, d3];
        path = [0, p1, p2, p3];
    }
    [(d[3], path[3]), (d[2], path[2])]
}

/// The strip joining `contour` to the inner vertices `inner` (vertex refs)
/// along assignment `asg` (from [`ring_assignment`]).
pub fn strip(contour: &[u8], asg: &[u8], inner: [u8; 3], out: &mut CellMesh) {
    let n = contour.len();
    for i in 0..n {
        let (c, cn) = (contour[i], contour[(i + 1) % n]);
        let (a, b) = (asg[i] as usize, asg[(i + 1) % n] as usize);
        out.push_triangle([c, cn, inner[b]]);
        if a != b {
            out.push_triangle([c, inner[b], inner[a]]);
        }
    }
}

/// Cost of assigning each contour vertex, at `points` in contour order, to
/// each of the three inner vertices, `cost(point, k)`; entries past the
/// contour's length are unused.
pub fn costs(
    points: impl Iterator<Item = DVec3>,
    cost: impl Fn(DVec3, usize) -> f64,
) -> [[f64; 3]; 12] {
    let mut out = [[0.0; 3]; 12];
    for (row, p) in out.iter_mut().zip(points) {
        *row = [0, 1, 2].map(|k| cost(p, k));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_assignment_makes_one_turn() {
        let cost = vec![[0.0, 1.0, 1.0]; 5];
        for dir in [1, -1] {
            let (_, asg) = ring_assignment(&cost, dir);
            let mut turns = 0;
            for i in 0..5 {
                let d = (asg[(i + 1) % 5] as i32 - asg[i] as i32).rem_euclid(3);
                assert!(d == 0 || d == dir.rem_euclid(3));
                turns += i32::from(d != 0);
            }
            assert_eq!(turns, 3);
        }
    }

    /// Costs that do not compare (not a number) still give an assignment
    /// that turns once round the ring, one step at a time.
    #[test]
    fn costs_that_do_not_compare_still_give_a_valid_ring() {
        for n in 3..=12 {
            for dir in [1, -1] {
                let (_, asg) = ring_assignment(&vec![[f64::NAN; 3]; n], dir);
                let step = dir.rem_euclid(3) as u8;
                let mut turns = 0;
                for i in 0..n {
                    let (a, b) = (asg[i], asg[(i + 1) % n]);
                    assert!(b == a || b == (a + step) % 3, "n {n} dir {dir}: {asg:?}");
                    turns += usize::from(a != b);
                }
                assert_eq!(turns, 3, "n {n} dir {dir}: {asg:?}");
            }
        }
    }

    #[test]
    fn ring_assignment_finds_the_cheapest_turn() {
        // Against every assignment of up to 9 vertices, on small integer
        // costs (many ties): the reported cost is the least, and the
        // assignment reported is a valid turn of that cost.
        let mut next = crate::kernel::xorshift(0x1234_5678_9abc_def1u64);
        for round in 0..3000 {
            let n = 3 + round % 7;
            let cost: Vec<[f64; 3]> = (0..n)
                .map(|_| [0, 1, 2].map(|_| (next() % 4) as f64))
                .collect();
            for dir in [1i32, -1] {
                let step = dir.rem_euclid(3) as usize;
                let turn_cost = |asg: &[usize]| {
                    let mut steps = 0;
                    for i in 0..n {
                        let d = (asg[(i + 1) % n] + 3 - asg[i]) % 3;
                        if d != 0 && d != step {
                            return None;
                        }
                        steps += usize::from(d != 0);
                    }
                    (steps == 3).then(|| (0..n).map(|i| cost[i][asg[i]]).sum::<f64>())
                };
                let mut least = f64::INFINITY;
                for code in 0..3usize.pow(n as u32) {
                    let asg: Vec<usize> = (0..n).map(|i| code / 3usize.pow(i as u32) % 3).collect();
                    if let Some(c) = turn_cost(&asg) {
                        least = least.min(c);
                    }
                }
                let (c, asg) = ring_assignment(&cost, dir);
                assert_eq!(c, least, "{cost:?} {dir}");
                let asg: Vec<usize> = asg[..n].iter().map(|&k| k as usize).collect();
                assert_eq!(turn_cost(&asg), Some(c), "{cost:?} {dir} {asg:?}");
            }
        }
    }
}
