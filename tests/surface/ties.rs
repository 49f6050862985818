//! Ties (samples equal to the isovalue) keep their vertices apart on every
//! input the issue names (docs/conventions.md#ties): every sample type,
//! either side inside, `--close`, grids far from the origin (where `f32`
//! needs a larger offset) or turned, and parts merged. Each mesh is a
//! manifold (closed with `--close`, with the oracle's topology) without a
//! zero-area triangle or two vertices at one position, counted in its `f32`
//! coordinates by `tmc::check`.

use crate::common;

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
/// sound too. (Farther out see [`far_grids_keep_interior_tie_vertices_apart`].)
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

/// Grids beyond 2^14 spacings from the origin, where `f32` cannot tell an
/// interior vertex 2^-10 of its cell from the cell's faces (the margin
/// widens, docs/conventions.md#ties): random fields and spacings, the
/// origin far on each axis alone and on all three, either sign, up to about
/// 2^18.8 spacings (where a quarter of the cell is what `f32` still
/// resolves); either side inside, with and without `--close`. The grid
/// issue 31 found two vertices at one position on comes first.
#[test]
fn far_grids_keep_interior_tie_vertices_apart() {
    let mut rng = Pcg64::seed_from_u64(31);
    let mut grids = vec![(3, [2.0e5, -3.0e5, 1.0e5], [1.0, 2.0, 1.5])];
    for round in 0..24 {
        let spacing: [f64; 3] = std::array::from_fn(|_| rng.gen_range(0.5..2.0));
        let least = spacing.iter().fold(f64::INFINITY, |m, &s| m.min(s));
        let mut far = || {
            let sign = if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
            sign * least * rng.gen_range(2.0f64.powi(14)..4.5e5)
        };
        // Far on axis `round % 4` alone (3: on all of them).
        let axis = round % 4;
        let origin: [f64; 3] =
            std::array::from_fn(|i| if axis == 3 || axis == i { far() } else { 0.0 });
        grids.push((round as u64 + 100, origin, spacing));
    }
    for (seed, origin, spacing) in grids {
        let grid = Grid {
            dims: DIMS,
            spacing,
            origin,
            direction: tmc::grid::IDENTITY,
        };
        // Plateaus of ties, and independent integers (as in the issue).
        let mut uniform = Pcg64::seed_from_u64(seed);
        let fields: [Vec<f64>; 2] = [
            tie_field(seed).iter().map(|&v| f64::from(v)).collect(),
            (0..DIMS.iter().product::<usize>())
                .map(|_| f64::from(uniform.gen_range(0..=4u8)))
                .collect(),
        ];
        for field in fields {
            let vol = ArrayVolume::new(grid, field).unwrap();
            for inside in [Inside::High, Inside::Low] {
                for close in [false, true] {
                    let (mesh, _) = extract(&vol, &params(inside, close)).expect("extract");
                    let case = format!("{seed}: {origin:?} {spacing:?} {inside:?} close {close}");
                    assert_sound(&mesh, close, &case);
                }
            }
        }
    }
}

/// Near ties: a crossing within `f32`'s rounding of its sample (a value a
/// hair above or below the isovalue next to one far from it) rounded onto
/// the sample, where all of that sample's crossings met (`tmc check` found
/// zero-area triangles and shared positions on `synth noise --dtype f32`
/// at 0: 4 on 256x256x128). Such vertices now go where a tie's would:
/// `tmc check --strict` passes on that noise, and for MC on samples of
/// 2^-30 and 1 in random signs (every edge vertex near a sample; TMC's
/// interior vertices of such cells can still meet, see
/// docs/conventions.md#ties), with the same bytes for 1 and 2 threads and
/// slabs of 3 planes.
#[test]
fn near_ties_keep_edge_vertices_apart() {
    let dir = tempfile::tempdir().unwrap();
    let noise = dir.path().join("noise.nrrd");
    let run = tmc(&[
        "synth",
        "noise",
        "--dims",
        "256,256,128",
        "--dtype",
        "f32",
        "-o",
        s(&noise),
        "-q",
    ]);
    assert!(run.status.success(), "{run:?}");
    let n = 40usize;
    let mut rng = Pcg64::seed_from_u64(7);
    let mut bytes = npy_header(&format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({n}, {n}, {n}), }}"
    ));
    for _ in 0..n * n * n {
        let size = if rng.gen_bool(0.5) {
            2f32.powi(-30)
        } else {
            1.0
        };
        let sign = if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
        bytes.extend((sign * size).to_le_bytes());
    }
    let near = dir.path().join("near.npy");
    std::fs::write(&near, bytes).unwrap();
    for (input, opts) in [
        (&noise, &["--iso", "0"][..]),
        (&near, &["--iso", "0", "--method", "mc"]),
        (&near, &["--iso", "0", "--method", "mc", "--close"]),
        (
            &near,
            &["--iso", "0", "--method", "mc", "--origin", "300,-200,100"],
        ),
    ] {
        let mut outputs = Vec::new();
        for (k, extra) in [
            &["--threads", "1"][..],
            &["--threads", "2", "--slab-depth", "3"],
        ]
        .into_iter()
        .enumerate()
        {
            let output = dir.path().join(format!("near{k}.ply"));
            let mut args = vec!["extract", s(input), "-o", s(&output), "-q"];
            args.extend_from_slice(opts);
            args.extend_from_slice(extra);
            let run = tmc(&args);
            assert!(run.status.success(), "{args:?}: {run:?}");
            let check = tmc(&["check", s(&output), "--strict", "--require-surface"]);
            assert!(check.status.success(), "{opts:?}: {check:?}");
            outputs.push(std::fs::read(&output).unwrap());
        }
        assert!(
            outputs[0] == outputs[1],
            "{opts:?}: threads and slabs differ"
        );
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

/// A volume without ties (random `f32`s at `--iso 2`: no sample, face
/// saddle or body saddle at the isovalue) gives the bytes the commit before
/// ties (db9cd6e) wrote for it: `tests/data/tie_free*.ply`, made by that
/// commit's `tmc extract tests/data/tie_free.nhdr --iso 2 -o tie_free.ply`,
/// and of `tie_free_far.nhdr` (the same samples, origin `(2e5, -3e5, 1e5)`,
/// spacing `(1, 2, 1.5)`: a grid far enough for both tie margins to widen,
/// which must not move a vertex that is not at a tie) with `--inside low`.
/// Far from the origin, `f32` rounded some crossings onto their samples,
/// where the vertices of the sample's other crossed edges met them
/// (db9cd6e's file has 18 vertices sharing positions): the edge vertices at
/// a sample's position, and no other edge vertex, now go where a tie's
/// vertex would; the interior vertices move inside their cells, away from
/// its faces, as on every grid this far (docs/conventions.md#ties); the
/// mesh passes `tmc check --strict`; the triangles are db9cd6e's.
#[test]
fn tie_free_volumes_keep_the_bytes_from_before_ties() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let dir = tempfile::tempdir().unwrap();
    for (name, extra) in [
        ("tie_free", &[][..]),
        ("tie_free_far", &["--inside", "low"]),
    ] {
        let input = data.join(format!("{name}.nhdr"));
        let out = dir.path().join(format!("{name}.ply"));
        let mut args = vec!["extract", s(&input), "--iso", "2", "-o", s(&out), "-q"];
        args.extend_from_slice(extra);
        let run = tmc(&args);
        assert!(run.status.success(), "{args:?}: {run:?}");
        let expect = std::fs::read(data.join(format!("{name}.ply"))).unwrap();
        let got = std::fs::read(&out).unwrap();
        assert!(
            expect.len() > 100_000,
            "{name}: a fixture too small to check"
        );
        let strict = tmc(&["check", s(&out), "--strict"]);
        assert!(strict.status.success(), "{name}: {strict:?}");
        if name == "tie_free" {
            assert!(got == expect, "{name}: the bytes differ from db9cd6e's");
            continue;
        }
        let (old_vertices, old_faces) = common::labels::parse_plain_ply(&expect);
        let (new_vertices, new_faces) = common::labels::parse_plain_ply(&got);
        assert_eq!(old_faces, new_faces, "{name}: the triangles differ");
        assert_eq!(old_vertices.len(), new_vertices.len());
        let mut seen = std::collections::HashMap::new();
        for v in &old_vertices {
            *seen.entry(*v).or_insert(0usize) += 1;
        }
        // The grid of tie_free_far.nhdr: a vertex whose f32 coordinates
        // are those of a sample.
        let (origin, spacing) = ([2e5, -3e5, 1e5], [1.0, 2.0, 1.5]);
        let coordinate = |v: &[u8; 12], j: usize| {
            f64::from(f32::from_le_bytes(v[4 * j..4 * j + 4].try_into().unwrap()))
        };
        // The axes on which the vertex is at a grid plane: all three for a
        // sample, two for an edge vertex, fewer for an interior vertex.
        let on_planes = |v: &[u8; 12]| {
            (0..3)
                .filter(|&j| {
                    let k = ((coordinate(v, j) - origin[j]) / spacing[j]).round();
                    (origin[j] + k * spacing[j]) as f32 as f64 == coordinate(v, j)
                })
                .count()
        };
        let index = |v: &[u8; 12], j: usize| (coordinate(v, j) - origin[j]) / spacing[j];
        // Whether `old` lies in the closed cell that holds `new` (a vertex
        // that had rounded onto a face is in the cells on both sides).
        let in_cell_of = |old: &[u8; 12], new: &[u8; 12]| {
            (0..3).all(|j| {
                let low = index(new, j).floor();
                (low..=low + 1.0).contains(&index(old, j))
            })
        };
        let (mut moved, mut interior) = (0, 0);
        for (i, (old, new)) in old_vertices.iter().zip(&new_vertices).enumerate() {
            if seen[old] > 1 {
                assert_ne!(old, new, "{name}: vertex {i} still shares a position");
            }
            if old == new {
                continue;
            }
            moved += 1;
            if on_planes(old) < 2 {
                // An interior vertex: on a grid this far, every one moves
                // inside its cell, away from the cell's faces.
                assert!(
                    on_planes(new) < 2,
                    "{name}: vertex {i} moved onto a grid line"
                );
                assert!(in_cell_of(old, new), "{name}: vertex {i} left its cell");
                interior += 1;
            } else {
                assert_eq!(
                    on_planes(old),
                    3,
                    "{name}: edge vertex {i} moved, but was not at a sample"
                );
            }
        }
        let shared: usize = seen.values().filter(|&&n| n > 1).sum();
        assert!(
            shared >= 18 && moved - interior >= shared && interior > 0,
            "{name}: {shared} shared, {moved} moved, {interior} of them interior"
        );
    }
}

/// Grids far from the origin keep apart the interior vertices of every
/// cell, not only of tie cells: on white noise (independent samples, no
/// ties: nearly every cell ambiguous), an interior vertex a hair inside a
/// face and the one the cell across puts a hair inside the same face, or
/// three vertices of a tunnel narrower than `f32` resolves there, fell on
/// one point (6 vertices sharing a position in the first case here before;
/// 40^3 white noise at these origins had 2 to 20, and some zero-area
/// triangles, through the command line). The surface is that of the same
/// samples at the origin: vertices, triangles, components and Euler
/// characteristic.
#[test]
fn far_grids_keep_every_interior_vertex_apart() {
    let dims = [32, 32, 32];
    let grids = [
        ([2.0e5, -3.0e5, 1.0e5], [1.0, 1.0, 1.0]),
        ([2.0e5, -3.0e5, 1.0e5], [1.0, 2.0, 1.5]),
        ([1.0e5, 1.0e5, 1.0e5], [1.0, 1.0, 1.0]),
        ([-4.0e5, 0.0, 4.0e5], [0.8, 1.25, 1.0]),
    ];
    for seed in 0..3u64 {
        let mut rng = Pcg64::seed_from_u64(seed);
        let n = dims.iter().product::<usize>();
        // Uniform reals, and integers at a half-integer isovalue.
        let fields: [(Vec<f64>, f64); 2] = [
            ((0..n).map(|_| rng.gen_range(-1.0..1.0)).collect(), 0.0),
            (
                (0..n).map(|_| f64::from(rng.gen_range(0..200u8))).collect(),
                99.5,
            ),
        ];
        for (field, iso) in fields {
            for close in [false, true] {
                let params = ExtractParams {
                    iso,
                    close,
                    ..Default::default()
                };
                let near = ArrayVolume::new(Grid::unit(dims), field.clone()).unwrap();
                let (at_origin, _) = extract(&near, &params).expect("extract");
                for (origin, spacing) in grids {
                    let grid = Grid {
                        dims,
                        spacing,
                        origin,
                        direction: tmc::grid::IDENTITY,
                    };
                    let vol = ArrayVolume::new(grid, field.clone()).unwrap();
                    let (mesh, _) = extract(&vol, &params).expect("extract");
                    let case =
                        format!("seed {seed} iso {iso} {origin:?} {spacing:?} close {close}");
                    assert_sound(&mesh, close, &case);
                    // The same surface: the cells' decisions do not look at
                    // positions (a tunnel's strips may pair its vertices
                    // otherwise, round a wider hexagon).
                    let (far, here) = (check_mesh(&mesh), check_mesh(&at_origin));
                    assert_eq!(
                        (far.vertices, far.triangles, far.components, far.euler),
                        (here.vertices, here.triangles, here.components, here.euler),
                        "{case}"
                    );
                }
            }
        }
    }
}
