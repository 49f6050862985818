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

use super::cell::{CellMesh, VertexRef};
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
    let step = dir.rem_euclid(3) as usize;
    let runs = std::array::from_fn(|i| (3 * i / n.max(1) * step % 3) as u8);
    let mut best = (f64::INFINITY, runs);
    // For a start k0 of vertex 0, the vertex after s steps sits at
    // `k0 + s step`: so dp[i][s], the best cost of vertices 0..=i with vertex
    // i after s steps, says where vertex i is. Each entry takes the better
    // of two candidates, stay (s steps before) or step (s - 1), by a select
    // rather than a branch; a tie goes to the candidate at the smaller k, as
    // if the candidates were offered in order of k. `stepped` records which.
    let mut dp = [[f64::INFINITY; 4]; 12];
    let mut stepped = [[false; 4]; 12];
    for k0 in 0..3 {
        let labels: [usize; 6] = std::array::from_fn(|s| (k0 + s * step) % 3);
        let at = |s: usize| labels[s];
        dp[0] = [cost[0][k0], f64::INFINITY, f64::INFINITY, f64::INFINITY];
        for i in 1..n {
            for s in 0..4 {
                let k = at(s);
                let stay = dp[i - 1][s] + cost[i][k];
                let moved = if s > 0 {
                    dp[i - 1][s - 1] + cost[i][k]
                } else {
                    f64::INFINITY
                };
                // at(s + 2) is where the step comes from: s - 1 steps, mod 3.
                let take = if at(s + 2) < k {
                    moved <= stay
                } else {
                    moved < stay
                };
                dp[i][s] = if take { moved } else { stay };
                stepped[i][s] = take && s > 0;
            }
        }
        // Closing edge back to vertex 0: a stay after three steps, or the
        // third step.
        for s in [3, 2] {
            let c = dp[n - 1][s];
            if c < best.0 {
                let mut asg = [0u8; 12];
                let mut s = s;
                for i in (0..n).rev() {
                    asg[i] = at(s) as u8;
                    if i > 0 && stepped[i][s] {
                        s -= 1;
                    }
                }
                best = (c, asg);
            }
        }
    }
    best
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
