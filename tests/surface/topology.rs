//! The kernel against the independent oracle (`tests/common/oracle.rs`) and
//! the independent mesh checker: every sign configuration, the 48 cube
//! symmetries, the configurations the paper names, and random volumes full
//! of ties. Extracted meshes must be closed, consistently oriented
//! 2-manifolds with the oracle's number of components and Euler characteristic.

use crate::common;

use common::{compare_with_oracle, oracle, symmetries, transform};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use tmc::check::{check_mesh, MeshReport};
use tmc::{extract, ArrayVolume, ExtractParams, Grid, Inside, Mesh, Method, Stats};

fn run(dims: [usize; 3], values: &[f64], iso: f64, close: bool, method: Method) -> (Mesh, Stats) {
    let vol = ArrayVolume::new(Grid::unit(dims), values.to_vec()).expect("volume");
    let params = ExtractParams {
        iso,
        close,
        method,
        threads: 1,
        ..Default::default()
    };
    extract(&vol, &params).expect("extract")
}

/// Extracts with `--close` and compares with the oracle on the grid padded
/// by one layer of ties (what `--close` means); the mesh must also have no
/// zero-area triangle and no two vertices at one position, ties or not.
fn check_closed(dims: [usize; 3], values: &[f64], iso: f64) -> Result<(MeshReport, Stats), String> {
    let (mesh, stats) = run(dims, values, iso, true, Method::Tmc);
    let report = check_mesh(&mesh);
    let (pdims, g) = oracle::padded(dims, &oracle::scaled(values, iso), 1, 0);
    let topo = oracle::topology(pdims, &g);
    let fail = |e: String| format!("{e}\n  dims {dims:?} iso {iso} values {values:?}");
    compare_with_oracle(&report, &topo).map_err(fail)?;
    if !report.geometry.is_sound() {
        return Err(fail(report.geometry.defects()));
    }
    Ok((report, stats))
}

fn random_cell(rng: &mut Pcg64, config: u32, ties: bool) -> [f64; 8] {
    std::array::from_fn(|c| {
        if config >> c & 1 == 1 {
            rng.gen_range(1..=1000) as f64
        } else if ties && rng.gen_bool(0.3) {
            0.0
        } else {
            -(rng.gen_range(1..=1000) as f64)
        }
    })
}

#[test]
fn every_configuration_with_random_magnitudes() {
    let mut rng = Pcg64::seed_from_u64(1);
    let mut tunnels = 0;
    for config in 0..256u32 {
        for k in 0..60 {
            let cell = random_cell(&mut rng, config, k % 2 == 1);
            let (_, stats) = check_closed([2, 2, 2], &cell, 0.0)
                .unwrap_or_else(|e| panic!("config {config}: {e}"));
            tunnels += stats.tunnels;
        }
    }
    assert!(tunnels > 0, "random cells should meet some tunnels");
}

/// Small magnitudes make exact ties of face and body saddles common.
#[test]
fn every_configuration_with_small_integers() {
    let mut rng = Pcg64::seed_from_u64(2);
    for config in 0..256u32 {
        for _ in 0..60 {
            let cell: Vec<f64> = (0..8)
                .map(|c| {
                    if config >> c & 1 == 1 {
                        rng.gen_range(1..=3) as f64
                    } else {
                        -(rng.gen_range(0..=3) as f64)
                    }
                })
                .collect();
            check_closed([2, 2, 2], &cell, 0.0).unwrap_or_else(|e| panic!("config {config}: {e}"));
        }
    }
}

/// Topology of the open patch in one cell: per component (euler, boundary
/// loops), sorted.
fn patch_topology(report: &MeshReport) -> Vec<(i64, usize)> {
    let mut v: Vec<(i64, usize)> = report
        .per_component
        .iter()
        .map(|c| (c.euler, c.boundary_loops))
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn cube_symmetries_and_complement_keep_the_topology() {
    let mut rng = Pcg64::seed_from_u64(3);
    let syms = symmetries();
    assert_eq!(syms.len(), 48);
    for trial in 0..1500 {
        let config = rng.gen_range(0..256u32);
        let cell = random_cell(&mut rng, config, trial % 3 == 0);
        let closed = check_closed([2, 2, 2], &cell, 0.0).expect("oracle").0;
        let open = check_mesh(&run([2, 2, 2], &cell, 0.0, false, Method::Tmc).0);
        assert_eq!(
            open.non_manifold_edges + open.non_manifold_vertices + open.inconsistent_edges,
            0
        );
        for &(perm, flip) in &syms {
            let s = (perm, flip);
            let t = transform([2, 2, 2], &cell, perm, flip).1;
            let r = check_closed([2, 2, 2], &t, 0.0)
                .unwrap_or_else(|e| panic!("symmetry {s:?}: {e}"))
                .0;
            assert_eq!((r.components, r.euler), (closed.components, closed.euler));
            let o = check_mesh(&run([2, 2, 2], &t, 0.0, false, Method::Tmc).0);
            assert_eq!(
                patch_topology(&o),
                patch_topology(&open),
                "symmetry {s:?} of {cell:?}"
            );
        }
        // The complement: without ties, {-g > 0} is bounded by the same surface.
        if !cell.contains(&0.0) {
            let neg: Vec<f64> = cell.iter().map(|v| -v).collect();
            let o = check_mesh(&run([2, 2, 2], &neg, 0.0, false, Method::Tmc).0);
            assert_eq!(
                patch_topology(&o),
                patch_topology(&open),
                "complement of {cell:?}"
            );
        }
    }
}

/// MC case number (Lorensen and Cline) of a configuration, from the number
/// of inside corners (after complementing to at most 4), the edge-connected
/// groups they form and the number of faces with alternating signs.
fn mc_case(config: u8) -> u8 {
    let config = if config.count_ones() > 4 {
        !config
    } else {
        config
    };
    let faces = [
        [0, 1, 3, 2],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 3, 7, 5],
    ];
    let ambiguous = faces
        .iter()
        .filter(|q| {
            let s = q.map(|c| config >> c & 1);
            s[0] == s[2] && s[1] == s[3] && s[0] != s[1]
        })
        .count();
    match (config.count_ones(), ambiguous) {
        (2, 1) => 3,
        (2, 0) => 4,
        (3, 1) => 6,
        (3, 3) => 7,
        (4, 6) => 13,
        (4, 2) => {
            // Case 10 (two opposite edges) or 12 (three corners and one apart).
            let edges = [
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
            let isolated = (0..8)
                .filter(|&c| config >> c & 1 == 1)
                .filter(|&c| {
                    !edges
                        .iter()
                        .any(|e| e.contains(&c) && e.iter().all(|&k| config >> k & 1 == 1))
                })
                .count();
            if isolated == 0 {
                10
            } else {
                12
            }
        }
        _ => 0,
    }
}

#[test]
fn the_configurations_the_paper_names() {
    let mut rng = Pcg64::seed_from_u64(4);
    let mut tunnel_cases = std::collections::BTreeSet::new();
    let (mut twelve, mut ambiguous) = (false, [false; 4]);
    for _ in 0..400_000 {
        let config = rng.gen_range(1..255u32);
        let cell = random_cell(&mut rng, config, false);
        let (mesh, stats) = run([2, 2, 2], &cell, 0.0, false, Method::Tmc);
        if stats.tunnels + stats.contours_12 + stats.ambiguous_contours.iter().sum::<u64>() == 0 {
            continue;
        }
        let report = check_mesh(&mesh);
        let patches = patch_topology(&report);
        if stats.tunnels == 1 {
            // The tunnel is an annulus: Euler characteristic 0, two boundary loops.
            assert!(patches.contains(&(0, 2)), "tunnel {cell:?}: {patches:?}");
            tunnel_cases.insert(mc_case(config as u8));
        }
        if stats.contours_12 == 1 {
            assert_eq!(patches, vec![(1, 1)], "12-vertex contour {cell:?}");
            twelve = true;
        }
        for (seen, &count) in ambiguous.iter_mut().zip(&stats.ambiguous_contours) {
            if count > 0 {
                let disks = patches.iter().all(|&(e, b)| e == 1 && b == 1);
                assert!(disks, "{cell:?}: {patches:?}");
                *seen = true;
            }
        }
        check_closed([2, 2, 2], &cell, 0.0).expect("oracle");
    }
    assert_eq!(
        tunnel_cases.into_iter().collect::<Vec<_>>(),
        vec![4, 6, 7, 10, 12, 13]
    );
    assert!(twelve, "no 12-vertex contour met");
    assert_eq!(
        ambiguous, [true; 4],
        "ambiguous contours with 6, 7, 8, 9 vertices"
    );
}

#[test]
fn random_volumes_match_the_oracle() {
    let mut rng = Pcg64::seed_from_u64(5);
    let mut cases = 0;
    for trial in 0..3000 {
        let n: [usize; 3] = if trial % 50 == 0 {
            [16, 16, 16]
        } else {
            std::array::from_fn(|_| rng.gen_range(2..=7))
        };
        let len = n.iter().product();
        let kind = trial % 5;
        let values: Vec<f64> = (0..len)
            .map(|i| {
                let (x, y, z) = (i % n[0], i / n[0] % n[1], i / (n[0] * n[1]));
                match kind {
                    // uniform noise, integers
                    0 => rng.gen_range(0..1000) as f64,
                    // near-binary
                    1 => f64::from(rng.gen_bool(0.5)),
                    // small integers, ties everywhere
                    2 => rng.gen_range(0..4) as f64,
                    // checkerboard with noise
                    3 => ((x + y + z) % 2) as f64 * 4.0 + rng.gen_range(-1..=1) as f64,
                    // labels
                    _ => rng.gen_range(0..3) as f64 * 10.0,
                }
            })
            .collect();
        let iso = match kind {
            0 => values[rng.gen_range(0..len)],
            1 => [0.0, 0.5, 1.0][trial % 3],
            2 => [0.0, 1.0, 1.5, 2.0, 3.0][trial % 5],
            3 => [0.0, 1.0, 2.0, 2.5][trial % 4],
            _ => [0.0, 5.0, 10.0, 20.0][trial % 4],
        };
        check_closed(n, &values, iso).unwrap_or_else(|e| panic!("trial {trial}: {e}"));
        cases += 1;
    }
    assert_eq!(cases, 3000);
}

/// Values of any magnitude: a grid scaled by a power of two, from the edge
/// of the subnormals up to near the largest double, gives the mesh of the
/// grid itself, vertex for vertex and triangle for triangle (the oracle
/// checks the unscaled grid). Face products underflow or overflow at these
/// scales, and the quadratics' discriminants long before.
#[test]
fn scaling_the_values_changes_nothing() {
    let mut rng = Pcg64::seed_from_u64(11);
    let mut tunnels = 0;
    for trial in 0..300 {
        let n: [usize; 3] = std::array::from_fn(|_| rng.gen_range(2..=6));
        let len = n.iter().product();
        let values: Vec<f64> = (0..len).map(|_| rng.gen_range(-3..=3) as f64).collect();
        let (_, stats) =
            check_closed(n, &values, 0.0).unwrap_or_else(|e| panic!("trial {trial}: {e}"));
        tunnels += stats.tunnels;
        let (reference, _) = run(n, &values, 0.0, true, Method::Tmc);
        for k in [-1020, -700, -300, -150, 150, 300, 700, 1020] {
            let scaled: Vec<f64> = values.iter().map(|v| v * 2f64.powi(k)).collect();
            let (mesh, _) = run(n, &scaled, 0.0, true, Method::Tmc);
            assert!(
                mesh.triangles == reference.triangles && mesh.vertices == reference.vertices,
                "trial {trial}, values x 2^{k}: {values:?}"
            );
        }
    }
    assert!(tunnels > 20, "only {tunnels} tunnels");
}

/// Exact ties at large magnitudes: a grid of small integers times a large
/// odd factor (QA's `134217729` and `100000007`, random ones up to 2^30 as
/// in int32 volumes and up to 2^50) or times `1 + 2^-51` is decided as the
/// small grid (every predicate is homogeneous), so the mesh must have the
/// oracle's topology of the small grid. Plain floating point took some of
/// these ties for tunnels.
#[test]
fn large_multiples_of_small_grids_match_the_oracle() {
    let mut rng = Pcg64::seed_from_u64(13);
    let mut tunnels = 0;
    for trial in 0..600 {
        let n: [usize; 3] = std::array::from_fn(|_| rng.gen_range(2..=6));
        let len = n.iter().product();
        let values: Vec<f64> = (0..len).map(|_| rng.gen_range(-3..=3) as f64).collect();
        let (pdims, g) = oracle::padded(n, &oracle::scaled(&values, 0.0), 1, 0);
        let topo = oracle::topology(pdims, &g);
        let odd =
            |rng: &mut Pcg64, bits: u32| (rng.gen_range(1u64 << (bits - 1)..1 << bits) | 1) as f64;
        let factors = [
            134_217_729.0,
            100_000_007.0,
            odd(&mut rng, 29),
            odd(&mut rng, 50),
            1.0 + f64::EPSILON / 2.0,
        ];
        for factor in factors {
            let scaled: Vec<f64> = values.iter().map(|v| v * factor).collect();
            let (mesh, stats) = run(n, &scaled, 0.0, true, Method::Tmc);
            compare_with_oracle(&check_mesh(&mesh), &topo).unwrap_or_else(|e| {
                panic!("trial {trial}, x {factor}: {e}\n  dims {n:?} values {values:?}")
            });
            tunnels += stats.tunnels;
        }
    }
    assert!(tunnels > 20, "only {tunnels} tunnels");
}

/// An isovalue no difference holds exactly: integer samples at
/// `iso = fl(1/3) = 1/3 - δ` (`δ = 2^-54 / 3`). With `h = 1 - 3v`, inside
/// low is `{iso - v > 0} = {h / 3 - δ > 0}`, and every predicate in the
/// integers `h` is a multiple of `3^-4` when not zero, far beyond what `δ`
/// moves: the region has the topology of `{h > ε}`, the oracle's on `h`.
/// Inside high is `{h / 3 - δ < 0}`, the closure of the complement of that
/// region (same surface: components `pos + neg - 1`, and Euler
/// characteristic `2 χ(R) = 2 (χ(complement) - 1)` in the box). The rounded
/// differences lose `δ`, and deciding on them took exact ties in `h` for
/// either side: tunnels inside low, faces inside high (QA found 44 of 3000
/// random cells wrong). A third of the grids are scaled by `2^-1010`, where
/// the residuals are subnormal, and a third by `2^900`.
#[test]
fn rounded_differences_are_decided_exactly() {
    let mut rng = Pcg64::seed_from_u64(17);
    let iso = 1.0 / 3.0;
    let mut tunnels = 0;
    for trial in 0..3000 {
        let inner: [usize; 3] = std::array::from_fn(|_| rng.gen_range(2..=5));
        // Small ranges for tunnels, wider ones for ties on faces.
        let r = [3, 7][trial % 2];
        let ints: Vec<i64> = (0..inner.iter().product::<usize>())
            .map(|_| rng.gen_range(-r..=r))
            .collect();
        let inside = [Inside::Low, Inside::High][trial / 2 % 2];
        // A border outside closes the surface.
        let border = if inside == Inside::Low { 8 } else { -8 };
        let (n, padded) = oracle::padded(inner, &ints, 1, border);
        // Scaled by a power of two (exact, and the same topology), down to
        // where the residuals are subnormal (a QA finding) and up.
        let scale = [1.0, 2f64.powi(-1010), 2f64.powi(900)][trial / 4 % 3];
        let values: Vec<f64> = padded.iter().map(|&v| v as f64 * scale).collect();
        let vol = ArrayVolume::new(Grid::unit(n), values).expect("volume");
        let params = ExtractParams {
            iso: iso * scale,
            inside,
            threads: 1,
            ..Default::default()
        };
        let (mesh, stats) = extract(&vol, &params).expect("extract");
        let h: Vec<i64> = padded.iter().map(|&v| 1 - 3 * v).collect();
        let mut topo = oracle::topology(n, &h);
        if inside == Inside::High {
            topo.surface_components = Some(topo.pos_components + topo.neg_components - 1);
            topo.surface_euler = Some(2 * (topo.euler_r - 1));
        }
        compare_with_oracle(&check_mesh(&mesh), &topo).unwrap_or_else(|e| {
            panic!("trial {trial}, {inside:?}: {e}\n  dims {inner:?} values {ints:?}")
        });
        tunnels += stats.tunnels;
    }
    assert!(tunnels > 20, "only {tunnels} tunnels");
}

/// A face whose exact values are too far apart for wide integers (a
/// clamped infinity next to ordinary values), or whose own corners are
/// exact while the rest of the cell is not, must be decided alike by the two
/// cells that share it (a review found both disagreeing, which cracked the
/// mesh). Three 3x2x2 volumes whose middle face is shared, then random ones.
#[test]
fn shared_faces_are_decided_alike_at_any_isovalue() {
    let inf = f64::INFINITY;
    // The shared face x = 1 in the order (y, z) = (0,0), (1,0), (1,1), (0,1),
    // and the other corners of the cells at x = 0 and x = 2.
    let volume = |face: [f64; 4], left: [f64; 4], right: [f64; 4]| {
        let mut v = [0.0; 12];
        for (k, (y, z)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
            v[1 + 3 * (y + 2 * z)] = face[k];
            v[3 * (y + 2 * z)] = left[k];
            v[2 + 3 * (y + 2 * z)] = right[k];
        }
        v
    };
    let cases = [
        (volume([1.0, -0.8, inf, -inf], [-1.0; 4], [-1.0; 4]), 0.1),
        (volume([2.0, -1.0, 2.0, -4.0], [-1.0; 4], [-1.0; 4]), 1e-300),
        (
            volume(
                [inf, -inf, 0.25 + 2f64.powi(-54), 0.25 - 2f64.powi(-55)],
                [2f64.powi(53), 0.0, 0.0, 0.0],
                [0.0; 4],
            ),
            0.25,
        ),
    ];
    for (values, iso) in cases {
        let (mesh, _) = run([3, 2, 2], &values, iso, true, Method::Tmc);
        let report = check_mesh(&mesh);
        assert!(
            report.is_closed_manifold(),
            "iso {iso} {values:?}: {report:?}"
        );
    }
    // As int32 samples (typed, so the residuals come from the type's test).
    let ints: Vec<i32> = cases[1].0.iter().map(|&v| v as i32).collect();
    let vol = ArrayVolume::new(Grid::unit([3, 2, 2]), ints).expect("volume");
    let params = ExtractParams {
        iso: 1e-300,
        close: true,
        threads: 1,
        ..Default::default()
    };
    let report = check_mesh(&extract(&vol, &params).expect("extract").0);
    assert!(report.is_closed_manifold(), "int32: {report:?}");
    let mut rng = Pcg64::seed_from_u64(19);
    for trial in 0..600 {
        let n: [usize; 3] = std::array::from_fn(|_| rng.gen_range(2..=5));
        let iso = [0.1, 0.25, 1e-300, 1.0 / 3.0][trial % 4];
        let values: Vec<f64> = (0..n.iter().product::<usize>())
            .map(|_| match rng.gen_range(0..8) {
                0 => inf,
                1 => -inf,
                2 => iso + rng.gen_range(-2..=2) as f64 * 2f64.powi(-54),
                3 => 2f64.powi(53) * rng.gen_range(-1..=1) as f64,
                _ => rng.gen_range(-4..=4) as f64 * 0.1,
            })
            .collect();
        let (mesh, _) = run(n, &values, iso, true, Method::Tmc);
        let report = check_mesh(&mesh);
        assert!(
            report.is_closed_manifold(),
            "trial {trial}, iso {iso}: {report:?}\n  dims {n:?} values {values:?}"
        );
    }
}

/// Infinite samples (and the largest doubles) next to ordinary ones: the
/// mesh stays a closed, consistently oriented manifold.
#[test]
fn infinite_samples_keep_the_mesh_manifold() {
    let mut rng = Pcg64::seed_from_u64(12);
    for trial in 0..200 {
        let n: [usize; 3] = std::array::from_fn(|_| rng.gen_range(2..=8));
        let len = n.iter().product();
        let values: Vec<f64> = (0..len)
            .map(|_| match rng.gen_range(0..10) {
                0 => f64::INFINITY,
                1 => f64::NEG_INFINITY,
                2 => f64::MAX * [1.0, -1.0][rng.gen_range(0..2)],
                _ => rng.gen_range(-1.0..1.0),
            })
            .collect();
        let (mesh, _) = run(n, &values, 0.0, true, Method::Tmc);
        let report = check_mesh(&mesh);
        assert!(
            report.is_closed_manifold() && report.degenerate_triangles == 0,
            "trial {trial}: {report:?}\n  dims {n:?} values {values:?}"
        );
    }
}

/// Rows whose length is near a multiple of 64: the slab loop classifies 64
/// samples to a word, so cells and edges at word ends must be seen too.
#[test]
fn rows_across_word_boundaries_match_the_oracle() {
    let mut rng = Pcg64::seed_from_u64(7);
    for (trial, nx) in [2, 3, 63, 64, 65, 66, 127, 128, 129, 130, 193]
        .into_iter()
        .enumerate()
    {
        let n = [nx, 4, 3];
        let len = n.iter().product();
        for kind in 0..2 {
            let values: Vec<f64> = (0..len)
                .map(|i| {
                    let x = i % nx;
                    match kind {
                        // crossings everywhere
                        0 => rng.gen_range(0..4) as f64,
                        // crossings only near the ends and the word seams
                        _ => f64::from(x == 0 || x == nx - 1 || x % 64 == 63 || x % 64 == 0) * 2.0,
                    }
                })
                .collect();
            for iso in [0.5, 1.0, 1.5] {
                check_closed(n, &values, iso)
                    .unwrap_or_else(|e| panic!("trial {trial} nx {nx} kind {kind} iso {iso}: {e}"));
            }
        }
    }
}

/// The inner hexagon of every tunnel met in random cells: consecutive
/// vertices differ in exactly one coordinate, and every vertex and every
/// edge midpoint lies on the level set.
#[test]
fn inner_hexagon_order() {
    use tmc::kernel::quadratic::{inner_hexagon, trilinear};
    let mut rng = Pcg64::seed_from_u64(6);
    let mut seen = 0;
    for _ in 0..200_000 {
        let g: [f64; 8] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
        let (_, stats) = run([2, 2, 2], &g, 0.0, false, Method::Tmc);
        if stats.tunnels + stats.contours_12 == 0 {
            continue;
        }
        seen += 1;
        let hex = inner_hexagon(&g);
        for i in 0..6 {
            let (a, b) = (hex[i], hex[(i + 1) % 6]);
            let differ = (0..3).filter(|&k| (a[k] - b[k]).abs() > 1e-12).count();
            assert!(differ <= 1, "hexagon {hex:?} of {g:?}");
            for p in [a, (a + b) * 0.5] {
                assert!(
                    trilinear(&g, p).abs() < 1e-9,
                    "{p:?} off the level set in {g:?}"
                );
            }
        }
    }
    assert!(seen > 10, "only {seen} tunnels met");
}

/// Cells of bonsai @ 40 whose geometry collapsed at ties without any sample
/// tie: a tunnel whose body saddle value is the isovalue (its hexagon was
/// a point, the inner triangle three vertices at one position), and two
/// cells sharing a face whose saddle value is the isovalue (both put their
/// interior vertex on that face saddle). With their oracle topology, no
/// zero-area triangle and no shared position (`check_closed`).
#[test]
fn saddle_ties_of_bonsai_keep_their_vertices_apart() {
    let tunnel = [2.0, -2.0, 2.0, 0.0, -1.0, 2.0, -5.0, 1.0];
    check_closed([2, 2, 2], &tunnel, 0.0).unwrap_or_else(|e| panic!("{e}"));
    // Planes z = 13, 14, 15 of bonsai at (127..129, 120..122), minus 40;
    // the face at z = 14 has 5 * 3 = (-15) * (-1).
    let stacked = [
        -1.0, 4.0, 4.0, 6.0, 5.0, -15.0, -1.0, 3.0, 37.0, 30.0, 28.0, 27.0,
    ];
    let (report, stats) = check_closed([2, 2, 3], &stacked, 0.0).unwrap_or_else(|e| panic!("{e}"));
    assert!(stats.ambiguous_cells >= 2, "{stats:?}");
    assert!(report.triangles > 0);
}
