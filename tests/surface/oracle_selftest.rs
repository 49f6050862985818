//! Self-tests of the topology oracle (`tests/common/oracle.rs`): sweeps
//! along x, y and z agree, the cube formula agrees with Euler integration,
//! the 48 symmetries of the cube leave the answer unchanged, and known shapes
//! come out right.

use crate::common;

use common::fields::{self, Field};
use common::oracle::{self, Topology};
use common::{symmetries, transform};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

fn rng(seed: u64) -> Pcg64 {
    Pcg64::seed_from_u64(seed)
}

/// Canonical form of a partition given as class representatives.
fn canonical<const N: usize>(labels: [u8; N]) -> [u8; N] {
    let mut seen = [u8::MAX; N];
    let mut next = 0;
    labels.map(|l| {
        if seen[l as usize] == u8::MAX {
            seen[l as usize] = next;
            next += 1;
        }
        seen[l as usize]
    })
}

/// A random cell: small values with many ties, or large values.
fn random_cell(r: &mut Pcg64) -> [i64; 8] {
    match r.gen_range(0..4) {
        0 => std::array::from_fn(|_| r.gen_range(-3..=3)),
        1 => std::array::from_fn(|_| 2 * r.gen_range(0..=4) - r.gen_range(1..=8)),
        2 => std::array::from_fn(|_| r.gen_range(-1000..=1000)),
        _ => std::array::from_fn(|_| r.gen_range(-(1 << 19)..(1 << 19))),
    }
}

#[test]
fn face_rule_equals_interval_overlap() {
    let mut r = rng(1);
    for i in 0..40_000 {
        let h: [i64; 4] = if i % 2 == 0 {
            std::array::from_fn(|_| r.gen_range(-3..=3))
        } else {
            std::array::from_fn(|_| r.gen_range(-1000..=1000))
        };
        assert_eq!(
            canonical(oracle::face_partition(h)),
            canonical(oracle::face_partition_by_intervals(h)),
            "face {h:?}"
        );
    }
}

#[test]
fn cell_sweeps_agree_and_euler_matches_integration() {
    let mut r = rng(2);
    let mut tunnels = 0;
    for _ in 0..60_000 {
        let h = random_cell(&mut r);
        let sweeps = [0, 1, 2].map(|a| canonical(oracle::sweep_partition(&h, a)));
        assert_eq!(sweeps[0], sweeps[1], "cell {h:?}: x vs y sweep");
        assert_eq!(sweeps[0], sweeps[2], "cell {h:?}: x vs z sweep");
        // The surface partition refines the sweep's, which covers it.
        let surface = oracle::boundary_partition(&h);
        for c in 0..8 {
            assert_eq!(
                sweeps[0][c], sweeps[0][surface[c] as usize],
                "cell {h:?}: surface join missing from the sweep"
            );
        }
        let euler = oracle::cell_euler(&h, 0);
        for a in 0..3 {
            assert_eq!(euler, oracle::cell_euler(&h, a), "cell {h:?}");
            assert_eq!(
                euler,
                oracle::cell_euler_fubini(&h, a),
                "cell {h:?}: formula vs Euler integration along axis {a}"
            );
        }
        if euler == 0 && h.iter().any(|&v| v > 0) {
            tunnels += 1;
        }
    }
    // The random cells must exercise the tunnel (solid torus) configuration.
    assert!(tunnels > 0);
}

/// A random grid of `0..=max` values, `iso` integer or half-integer, padded
/// with one layer of zeros, as oracle integers.
fn random_grid(r: &mut Pcg64, max: i64) -> ([usize; 3], Vec<i64>) {
    let dims = [0; 3].map(|_| r.gen_range(1..=5));
    let values: Vec<f64> = (0..dims.iter().product::<usize>())
        .map(|_| r.gen_range(0..=max) as f64)
        .collect();
    let iso = r.gen_range(1..2 * max) as f64 / 2.0;
    oracle::padded(dims, &oracle::scaled(&values, iso), 1, -(2.0 * iso) as i64)
}

fn check_invariants(t: &Topology, what: &str) {
    assert!(t.closed, "{what}: padded grid must be closed");
    // Genus is never negative: χ(R) = b0 - b1 + b2 <= pos + neg - 1.
    let genus = t.surface_genus().unwrap();
    assert!(genus >= 0, "{what}: {t:?}");
    assert_eq!(t.surface_euler.unwrap() % 2, 0);
}

#[test]
fn random_grids_agree_along_all_axes() {
    let mut r = rng(3);
    let mut shapes = std::collections::BTreeSet::new();
    for i in 0..4000 {
        let max = if i % 3 == 2 { 1000 } else { 4 };
        let (dims, g) = random_grid(&mut r, max);
        let t = [0, 1, 2].map(|a| oracle::topology_along(dims, &g, a));
        assert_eq!(t[0], t[1], "grid {dims:?} {g:?}");
        assert_eq!(t[0], t[2], "grid {dims:?} {g:?}");
        check_invariants(&t[0], &format!("grid {dims:?} {g:?}"));
        shapes.insert((t[0].surface_components, t[0].surface_genus()));
    }
    // The random grids reach several components and positive genus.
    assert!(shapes.iter().any(|s| s.1 > Some(0)), "{shapes:?}");
    assert!(shapes.iter().any(|s| s.0 > Some(2)), "{shapes:?}");
}

fn assert_symmetric(dims: [usize; 3], g: &[i64]) {
    let base = oracle::topology(dims, g);
    for (perm, flip) in symmetries() {
        let (nd, ng) = transform(dims, g, perm, flip);
        let topo = oracle::topology(nd, &ng);
        assert_eq!(base, topo, "{dims:?} {g:?} {perm:?} {flip:?}");
    }
}

#[test]
fn cube_symmetries_preserve_topology() {
    let mut r = rng(4);
    for _ in 0..1500 {
        let cell = random_cell(&mut r);
        let (dims, g) = oracle::padded([2, 2, 2], &cell, 1, -1);
        assert_symmetric(dims, &g);
    }
    for i in 0..300 {
        let (dims, g) = random_grid(&mut r, if i % 2 == 0 { 4 } else { 1000 });
        assert_symmetric(dims, &g);
    }
}

fn assert_surface(t: Topology, components: usize, euler: i64, what: &str) {
    assert!(t.closed, "{what}: {t:?}");
    assert_eq!(
        (t.surface_components, t.surface_euler),
        (Some(components), Some(euler)),
        "{what}: {t:?}"
    );
}

#[test]
fn known_shapes() {
    let d = [20, 19, 18];
    let c = [9.3, 9.1, 8.6];
    assert_surface(fields::ball(d, c, 6.0).topology(0.0), 1, 2, "ball");
    assert_surface(
        fields::ball(d, c, 6.0).topology(50.5),
        1,
        2,
        "ball, iso 50.5",
    );
    assert_surface(
        fields::ball([9, 9, 9], [4.0; 3], 1.0).topology(0.0),
        1,
        2,
        "tiny ball",
    );
    for axis in 0..3 {
        let t = fields::torus([24, 24, 24], [11.6, 11.3, 11.8], 6.0, 2.5, axis).topology(0.0);
        assert_surface(t, 1, 0, "torus");
        assert_eq!((t.pos_components, t.neg_components, t.euler_r), (1, 1, 0));
    }
    let two = fields::ball(d, [5.0, 9.0, 9.0], 3.5).max(&fields::ball(d, [14.0, 9.0, 9.0], 3.5));
    assert_surface(two.topology(0.0), 2, 4, "two balls");
    let t = fields::shell(d, c, 6.0, 1.5).topology(0.0);
    assert_surface(t, 2, 4, "shell");
    assert_eq!((t.pos_components, t.neg_components), (1, 2));
    // Two tori fused along a short overlap: genus 2.
    let dd = [34, 20, 14];
    let left = fields::torus(dd, [10.5, 9.7, 6.6], 6.0, 2.2, 2);
    let right = fields::torus(dd, [22.5, 9.7, 6.6], 6.0, 2.2, 2);
    let t = left.max(&right).topology(0.0);
    assert_surface(t, 1, -2, "double torus");
    assert_surface(
        fields::single_vertex([5, 5, 5], [2, 2, 2]).topology(0.0),
        1,
        2,
        "vertex",
    );
    // Ties: a zero sample is outside, so an all-zero grid is empty.
    let zero = Field {
        dims: [4, 4, 4],
        values: vec![0.0; 64],
    };
    assert_surface(zero.topology(0.0), 0, 0, "zero grid");
}

#[test]
fn open_surfaces_report_no_surface_figures() {
    let f = fields::ball([10, 10, 10], [0.0, 4.5, 4.5], 3.0);
    let t = f.topology(0.0);
    assert!(!t.closed);
    assert_eq!((t.surface_components, t.surface_euler), (None, None));
    // Half a ball cut by the border is still a (contractible) ball.
    assert_eq!((t.pos_components, t.neg_components, t.euler_r), (1, 1, 1));
}

/// One cell (corners `c = x + 2y + 4z`) in a 4x4x4 grid padded with `pad`.
fn single_cell(corners: [i64; 8], pad: i64) -> Topology {
    let (dims, g) = oracle::padded([2, 2, 2], &corners, 1, pad);
    oracle::topology(dims, &g)
}

/// Marching cubes case 4: corners 0 and 7 on one side, the six others on
/// the other side.
#[test]
fn case_4_body_saddle() {
    let case4 = |diagonal: i64, others: i64| {
        std::array::from_fn(|c| if c == 0 || c == 7 { diagonal } else { others })
    };
    // Positive diagonal corners joined through the interior (body saddle
    // above the isovalue): one tube, a sphere.
    assert_surface(single_cell(case4(100, -1), -1), 1, 2, "positive tube");
    // Body saddle below the isovalue: two separate blobs.
    assert_surface(single_cell(case4(1, -100), -100), 2, 4, "separate blobs");
    // Along the diagonal the decider peaks at ((a - b) / 2)^2 - b^2: zero for
    // a = 3b (a tie separates the positive corners), positive for a = 4b.
    assert_surface(single_cell(case4(3, -1), -1), 2, 4, "tie");
    assert_surface(single_cell(case4(4, -1), -1), 1, 2, "just above the tie");
    // The complementary case: a non-positive tube through the cell, its two
    // ends joined outside through the padding, makes the six positive
    // corners a solid torus (χ(S) = 0).
    let t = single_cell(case4(-100, 1), -100);
    assert_surface(t, 1, 0, "negative tube");
    assert_eq!((t.pos_components, t.neg_components, t.euler_r), (1, 1, 0));
    // Without the tube the positive region fills the cell: a ball.
    assert_surface(single_cell(case4(-1, 100), -1), 1, 2, "no negative tube");
    // The tie joins the non-positive corners: still a torus.
    assert_surface(single_cell(case4(-3, 1), -3), 1, 0, "negative tie");
}
