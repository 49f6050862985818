//! Ties (samples equal to the isovalue) keep their vertices apart on every
//! input the issue names (docs/conventions.md#ties): every sample type,
//! either side inside, `--close`, grids far from the origin (where `f32`
//! needs a larger offset) or turned, and parts merged. Each mesh is a
//! manifold (closed with `--close`, with the oracle's topology) without a
//! zero-area triangle or two vertices at one position, counted in its `f32`
//! coordinates by `tmc::check`.

mod common;

use common::cli::{npy_header, s, tmc};
use common::{compare_with_oracle, oracle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use tmc::check::check_mesh;
use tmc::{extract, ArrayVolume, ExtractParams, Grid, Inside, Mesh, SampleSource};

const DIMS: [usize; 3] = [13, 11, 9];
const ISO: f64 = 2.0;

/// Integers 0 to 4, a fifth of them ties at [`ISO`], in plateaus and
/// single samples (a random value or the one before it).
fn tie_field(seed: u64) -> Vec<u8> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut values: Vec<u8> = Vec::with_capacity(DIMS.iter().product());
    for _ in 0..DIMS.iter().product::<usize>() {
        let v = match values.last() {
            Some(&last) if rng.gen_bool(0.4) => last,
            _ => rng.gen_range(0..=4),
        };
        values.push(v);
    }
    assert!(values.iter().filter(|&&v| f64::from(v) == ISO).count() > values.len() / 8);
    values
}

fn params(inside: Inside, close: bool) -> ExtractParams {
    ExtractParams {
        iso: ISO,
        inside,
        close,
        ..Default::default()
    }
}

/// The mesh is an oriented manifold (closed with `--close`), sound in its
/// `f32` coordinates.
fn assert_sound(mesh: &Mesh, close: bool, case: &str) {
    let report = check_mesh(mesh);
    assert!(!mesh.triangles.is_empty(), "{case}: no surface");
    assert!(report.is_oriented_manifold(), "{case}: {report:?}");
    assert!(!close || report.is_closed_manifold(), "{case}: {report:?}");
    assert!(
        report.geometry.is_sound(),
        "{case}: {}",
        report.geometry.defects()
    );
}

/// Extracts `values` converted to each sample type: the same mesh as from
/// `f64`s, bit for bit (the classification compares in the samples' own
/// type, the vertices come from their values), and a sound one.
#[test]
fn every_sample_type_keeps_tie_vertices_apart() {
    for seed in 0..3 {
        let field = tie_field(seed);
        let grid = Grid::unit(DIMS);
        let as_f64: Vec<f64> = field.iter().map(|&v| f64::from(v)).collect();
        for inside in [Inside::High, Inside::Low] {
            for close in [false, true] {
                let p = params(inside, close);
                let run = |vol: &dyn SampleSource| extract(vol, &p).expect("extract").0;
                let expect = run(&ArrayVolume::new(grid, as_f64.clone()).unwrap());
                let case = format!("seed {seed} {inside:?} close {close}");
                assert_sound(&expect, close, &case);
                let meshes = [
                    ("u8", run(&ArrayVolume::new(grid, field.clone()).unwrap())),
                    (
                        "i8",
                        run(&ArrayVolume::new(grid, cast(&field, |v| v as i8)).unwrap()),
                    ),
                    (
                        "u16",
                        run(&ArrayVolume::new(grid, cast(&field, u16::from)).unwrap()),
                    ),
                    (
                        "i16",
                        run(&ArrayVolume::new(grid, cast(&field, i16::from)).unwrap()),
                    ),
                    (
                        "u32",
                        run(&ArrayVolume::new(grid, cast(&field, u32::from)).unwrap()),
                    ),
                    (
                        "i32",
                        run(&ArrayVolume::new(grid, cast(&field, i32::from)).unwrap()),
                    ),
                    (
                        "f32",
                        run(&ArrayVolume::new(grid, cast(&field, f32::from)).unwrap()),
                    ),
                ];
                for (name, mesh) in meshes {
                    assert!(mesh.vertices == expect.vertices, "{case} {name}: vertices");
                    assert!(
                        mesh.triangles == expect.triangles,
                        "{case} {name}: triangles"
                    );
                }
                if close && inside == Inside::High {
                    // The oracle's topology of {T > iso + ε}, the padding a tie.
                    let (dims, g) = oracle::padded(DIMS, &oracle::scaled(&as_f64, ISO), 1, 0);
                    let topo = oracle::topology(dims, &g);
                    compare_with_oracle(&check_mesh(&expect), &topo)
                        .unwrap_or_else(|e| panic!("{case}: {e}"));
                }
            }
        }
    }
}

fn cast<T>(field: &[u8], f: impl Fn(u8) -> T) -> Vec<T> {
    field.iter().map(|&v| f(v)).collect()
}

/// Grids whose `f32` coordinates cannot resolve the offset of 2^-10 of an
/// edge (about 2^13 spacings from the origin: the offset doubles until they
/// can), and turned or mirrored grids (the general index-to-world map):
/// sound too. (Farther out, beyond about 2^14 spacings, the interior vertices
/// that keep 2^-10 of a cell from its faces can round onto them: see the limits
/// in docs/conventions.md#ties.)
#[test]
fn far_and_turned_grids_keep_tie_vertices_apart() {
    let field: Vec<f64> = tie_field(7).iter().map(|&v| f64::from(v)).collect();
    let (c, s) = (0.6f64, 0.8f64);
    let turned = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    let mirrored = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
    let grids = [
        ("far", [1.0e4; 3], [1.0; 3], tmc::grid::IDENTITY),
        (
            "far, uneven",
            [5.0e3, -6.0e3, 4.0e3],
            [1.0, 2.0, 1.5],
            tmc::grid::IDENTITY,
        ),
        ("turned", [10.0, 20.0, 30.0], [0.5, 0.5, 2.0], turned),
        ("turned far", [3.0e4; 3], [1.0; 3], turned),
        ("mirrored", [0.0; 3], [1.0; 3], mirrored),
    ];
    for (name, origin, spacing, direction) in grids {
        let grid = Grid {
            dims: DIMS,
            spacing,
            origin,
            direction,
        };
        let vol = ArrayVolume::new(grid, field.clone()).unwrap();
        for inside in [Inside::High, Inside::Low] {
            for close in [false, true] {
                let (mesh, _) = extract(&vol, &params(inside, close)).expect("extract");
                assert_sound(&mesh, close, &format!("{name} {inside:?} close {close}"));
            }
        }
    }
}

/// `--part I/3` of a tie-heavy `u8` volume merged: `tmc check --strict`
/// (which fails on zero-area triangles and shared positions) passes, on
/// either side inside and with `--close`.
#[test]
fn merged_parts_keep_tie_vertices_apart() {
    let dir = tempfile::tempdir().unwrap();
    let [nx, ny, nz] = DIMS;
    let mut bytes = npy_header(&format!(
        "{{'descr': '|u1', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    bytes.extend(tie_field(11));
    let input = dir.path().join("ties.npy");
    std::fs::write(&input, bytes).unwrap();
    for opts in [
        &["--iso", "2"][..],
        &["--iso", "2", "--close"],
        &["--iso", "2", "--inside", "low", "--close"],
    ] {
        let mut parts = Vec::new();
        for i in 1..=3 {
            let part = dir.path().join(format!("part{i}.tmesh"));
            let part_arg = format!("{i}/3");
            let mut args = vec![
                "extract",
                s(&input),
                "-o",
                s(&part),
                "-q",
                "--part",
                &part_arg,
            ];
            args.extend_from_slice(opts);
            let out = tmc(&args);
            assert!(out.status.success(), "{args:?}: {out:?}");
            parts.push(part);
        }
        let merged = dir.path().join("merged.ply");
        let mut args = vec!["merge"];
        args.extend(parts.iter().map(|p| s(p)));
        args.extend_from_slice(&["-o", s(&merged)]);
        let out = tmc(&args);
        assert!(out.status.success(), "{args:?}: {out:?}");
        let out = tmc(&["check", s(&merged), "--strict", "--require-surface"]);
        assert!(out.status.success(), "{opts:?}: {out:?}");
    }
}
