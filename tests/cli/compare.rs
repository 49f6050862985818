//! `tmc compare` and the survey of differing cells behind it: the survey
//! counts what the extraction counts, a cell is called different exactly
//! when the two methods' meshes of it differ in more than how flat
//! polygons are cut into triangles, a tunnel volume's topology
//! differs between the methods with TMC's equal to the oracle's, the JSON
//! holds its fields, the topology step keeps to its bound, and SIGINT ends
//! it cleanly.

use crate::common;

use common::cli::{npy_header, s, synth, tmc};
use common::oracle;
use serde_json::Value;
use std::fs;
use std::path::Path;
use tmc::compare::survey;
use tmc::{ArrayVolume, ExtractParams, Grid, Inside, Method, Stats};

fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

/// Integer samples in `-spread..=spread` (ties with iso 0 included).
fn random_volume(dims: [usize; 3], spread: i64, seed: u64) -> ArrayVolume<f64> {
    let mut next = xorshift(seed);
    let data = (0..dims.iter().product::<usize>())
        .map(|_| (next() % (2 * spread as u64 + 1)) as i64 as f64 - spread as f64)
        .collect();
    ArrayVolume::new(Grid::unit(dims), data).unwrap()
}

fn params(method: Method, inside: Inside, close: bool) -> ExtractParams {
    ExtractParams {
        iso: 0.0,
        method,
        inside,
        close,
        threads: 1,
        ..Default::default()
    }
}

fn table_1(s: &Stats) -> (u64, [u64; 4], [u64; 4], u64, u64) {
    (
        s.ambiguous_cells,
        s.contours,
        s.ambiguous_contours,
        s.tunnels,
        s.contours_12,
    )
}

#[test]
fn the_survey_counts_the_extractions_table_1() {
    let mut any_tunnel = false;
    for seed in 1..=12u64 {
        let volume = random_volume([9, 8, 7], 1 + (seed % 4) as i64, seed);
        for inside in [Inside::High, Inside::Low] {
            for close in [false, true] {
                let p = params(Method::Tmc, inside, close);
                let (_, extracted) = tmc::extract(&volume, &p).unwrap();
                let (differing, surveyed) = survey(&volume, &p, 2, None).unwrap();
                let case = format!("seed {seed} {inside:?} close {close}");
                assert_eq!(table_1(&surveyed), table_1(&extracted), "{case}");
                assert_eq!(differing.tunnels, extracted.tunnels, "{case}");
                assert!(differing.contours_12 <= extracted.contours_12, "{case}");
                let kinds = [
                    differing.face_decisions,
                    differing.tunnels,
                    differing.contours_12,
                    differing.interior_vertices,
                ];
                assert!(kinds.iter().all(|&k| k <= differing.cells), "{case}");
                assert!(differing.cells <= kinds.iter().sum(), "{case}");
                assert!(differing.cells <= extracted.ambiguous_cells, "{case}");
                any_tunnel |= differing.tunnels > 0;
            }
        }
    }
    assert!(any_tunnel, "no volume had a tunnel: the test proves less");
}

/// What two triangulations of one cell share when they differ only in how
/// flat polygons are cut into triangles: their vertex positions and their
/// boundary edges (each contour's segments on the cell's faces), as sorted
/// lists of positions.
fn outline(mesh: &tmc::Mesh) -> (Vec<[u32; 3]>, Vec<[[u32; 3]; 2]>) {
    let at = |i: u32| mesh.vertices[i as usize].map(f32::to_bits);
    let mut vertices: Vec<[u32; 3]> = mesh.vertices.iter().map(|p| p.map(f32::to_bits)).collect();
    vertices.sort_unstable();
    let mut edges: Vec<[[u32; 3]; 2]> = mesh
        .triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| {
            let (a, b) = (at(a), at(b));
            if a < b {
                [a, b]
            } else {
                [b, a]
            }
        })
        .collect();
    edges.sort_unstable();
    // Keep the edges used once: the boundary.
    let mut boundary = Vec::new();
    let mut k = 0;
    while k < edges.len() {
        let run = edges[k..].iter().take_while(|e| **e == edges[k]).count();
        if run == 1 {
            boundary.push(edges[k]);
        }
        k += run;
    }
    (vertices, boundary)
}

#[test]
fn a_cell_differs_exactly_when_its_two_meshes_do() {
    let mut next = xorshift(0x5eed);
    let (mut differing_cells, mut ambiguous) = (0, 0);
    for _ in 0..20_000 {
        let spread = 1 + next() % 6;
        let data: Vec<f64> = (0..8)
            .map(|_| (next() % (2 * spread + 1)) as f64 - spread as f64)
            .collect();
        let volume = ArrayVolume::new(Grid::unit([2, 2, 2]), data.clone()).unwrap();
        let tmc_params = params(Method::Tmc, Inside::High, false);
        let (tmc_mesh, stats) = tmc::extract(&volume, &tmc_params).unwrap();
        let (mc_mesh, _) = tmc::extract(&volume, &params(Method::Mc, Inside::High, false)).unwrap();
        let (differing, _) = survey(&volume, &tmc_params, 1, None).unwrap();
        let meshes_differ = outline(&tmc_mesh) != outline(&mc_mesh);
        assert_eq!(
            differing.cells == 1,
            meshes_differ,
            "{data:?}: {differing:?}"
        );
        differing_cells += differing.cells;
        ambiguous += stats.ambiguous_cells;
    }
    println!("{differing_cells} of {ambiguous} ambiguous cells differ");
    assert!(differing_cells > 100 && differing_cells < ambiguous);
}

/// Writes `values` (x fastest) as a little-endian f64 `.npy` of `dims`.
fn write_npy(path: &Path, dims: [usize; 3], values: &[f64]) {
    let [nx, ny, nz] = dims;
    let mut bytes = npy_header(&format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    fs::write(path, bytes).unwrap();
}

fn compare_json(args: &[&str]) -> Value {
    let mut argv = vec!["compare"];
    argv.extend(args);
    argv.extend(["--json", "-q", "--runs", "3"]);
    let out = tmc(&argv);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn a_tunnel_changes_the_topology_and_tmc_agrees_with_the_oracle() {
    // One cell with two diagonally opposite inside corners whose body
    // centre is inside too (case 4 with a tunnel): TMC joins them in one
    // tube, MC leaves two blobs.
    let dims = [4, 4, 4];
    let mut values = vec![-1.0; 64];
    values[1 + 4 + 16] = 10.0;
    values[2 + 2 * 4 + 2 * 16] = 10.0;
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tunnel.npy");
    write_npy(&input, dims, &values);
    let json = compare_json(&[s(&input), "--iso", "0"]);
    let truth = oracle::topology(dims, &oracle::scaled(&values, 0.0));
    let components = truth.surface_components.unwrap() as u64;
    assert_eq!(components, 1);
    assert_eq!(json["tmc"]["components"], components);
    assert_eq!(json["tmc"]["euler"], truth.surface_euler.unwrap());
    assert_eq!(json["tmc"]["genus"], truth.surface_genus().unwrap());
    assert_eq!(json["mc"]["components"], 2);
    assert_eq!(json["tmc"]["tunnels"], 1);
    assert_eq!(json["differing_cells"]["tunnels"], 1);
    assert_eq!(json["differing_cells"]["cells"], 1);
}

/// Without `--threads`, `threads` in the JSON is the number of workers the
/// runs used, as in `tmc extract --json` (it said 0, the option's
/// default, which no run used).
#[test]
fn the_json_gives_the_threads_used() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "sphere", "9,9,9", "f32", "ball.npy");
    let json = compare_json(&[s(&input), "--iso", "0"]);
    let mesh = dir.path().join("b.ply");
    let mut args = vec!["extract", s(&input), "-o", s(&mesh)];
    args.extend(["--iso=0", "--json", "-q"]);
    let extract: Value = serde_json::from_slice(&tmc(&args).stdout).unwrap();
    assert!(extract["threads"].as_u64().unwrap() >= 1, "{extract}");
    assert_eq!(json["threads"], extract["threads"], "{json}");
}

#[test]
fn the_json_holds_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "noise", "20,18,16", "u8", "noise.npy");
    let json = compare_json(&[s(&input), "--iso", "127.5", "--threads", "2"]);
    for side in ["tmc", "mc"] {
        let o = &json[side];
        assert_eq!(o["seconds"].as_array().unwrap().len(), 3, "{side}");
        let median = o["median_seconds"].as_f64().unwrap();
        let (min, max) = (
            o["min_seconds"].as_f64().unwrap(),
            o["max_seconds"].as_f64().unwrap(),
        );
        assert!(0.0 < min && min <= median && median <= max, "{side}: {o}");
        for key in [
            "triangles",
            "vertices",
            "components",
            "euler",
            "genus",
            "ambiguous_cells",
            "contours",
            "ambiguous_contours",
            "tunnels",
            "contours_12",
        ] {
            assert!(!o[key].is_null(), "{side}.{key} missing: {o}");
        }
    }
    assert_eq!(json["threads"], 2, "the threads asked for");
    // The counts are those of 'tmc extract --json' of each method.
    for side in ["tmc", "mc"] {
        let mesh = dir.path().join(format!("{side}.tmesh"));
        let out = tmc(&[
            "extract",
            s(&input),
            "--iso",
            "127.5",
            "--method",
            side,
            "-o",
            s(&mesh),
            "--json",
            "-q",
        ]);
        let extract: Value = serde_json::from_slice(&out.stdout).unwrap();
        for key in [
            "triangles",
            "vertices",
            "ambiguous_cells",
            "contours",
            "tunnels",
        ] {
            assert_eq!(json[side][key], extract[key], "{side}.{key}");
        }
        let check = tmc(&["check", s(&mesh), "--json"]);
        let checked: Value = serde_json::from_slice(&check.stdout).unwrap();
        assert_eq!(json[side]["components"], checked["components"], "{side}");
        assert_eq!(json[side]["euler"], checked["euler"], "{side}");
    }
    let r = &json["ratio"];
    let (low, median, high) = (
        r["low"].as_f64().unwrap(),
        r["median"].as_f64().unwrap(),
        r["high"].as_f64().unwrap(),
    );
    assert!(0.0 < low && low <= median && median <= high, "{r}");
    let d = &json["differing_cells"];
    for key in [
        "cells",
        "face_decisions",
        "tunnels",
        "contours_12",
        "interior_vertices",
    ] {
        assert!(d[key].is_u64(), "differing_cells.{key}: {d}");
    }
    assert!(json["topology_note"].is_null());
    assert!(json["peak_rss_anon_bytes"].as_f64().unwrap() > 0.0);
}

#[test]
fn the_gyroid_has_the_same_topology_by_both_methods() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "gyroid", "64,64,64", "f32", "gyroid.npy");
    let json = compare_json(&[s(&input), "--iso", "0", "--close"]);
    // Not the same meshes: some cells differ, and the topology still agrees.
    assert!(
        json["differing_cells"]["cells"].as_u64().unwrap() > 10,
        "{json}"
    );
    for key in ["components", "euler", "genus"] {
        assert!(!json["tmc"][key].is_null(), "{key}: {json}");
        assert_eq!(json["tmc"][key], json["mc"][key], "{key}");
    }
}

#[test]
fn topology_beyond_its_bound_is_left_out_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "noise", "48,48,48", "u8", "noise.npy");
    let json = compare_json(&[s(&input), "--iso", "127.5", "--topology-memory", "64K"]);
    for side in ["tmc", "mc"] {
        for key in ["components", "euler", "genus"] {
            assert!(json[side][key].is_null(), "{side}.{key}: {json}");
        }
        assert!(json[side]["triangles"].as_u64().unwrap() > 10_000);
    }
    let note = json["topology_note"].as_str().unwrap();
    // The bound as given, not rounded down to whole MiB ("0 MiB").
    assert!(note.contains("over --topology-memory 64.0 KiB"), "{note}");
    assert!(!note.contains(" 0 MiB"), "{note}");
    // The table says so too.
    let out = tmc(&[
        "compare",
        s(&input),
        "--iso",
        "127.5",
        "--runs",
        "1",
        "-q",
        "--topology-memory",
        "64K",
    ]);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("note: components, Euler characteristic and genus left out"),
        "{table}"
    );
    assert!(table.contains("time TMC/MC"), "{table}");
}

#[test]
fn compare_keeps_to_max_memory_on_the_densest_surface() {
    // A mesh of some 240 MB in flight if nothing bounded it; the timed runs
    // keep to --max-memory, and the survey holds two planes per thread.
    let dir = tempfile::tempdir().unwrap();
    let input = common::cli::uniform_npy(dir.path(), [256, 256, 48]);
    let json = compare_json(&[
        s(&input),
        "--iso",
        "0.5",
        "--threads",
        "2",
        "--max-memory",
        "48M",
        "--topology-memory",
        "1K",
    ]);
    assert!(
        json["tmc"]["triangles"].as_u64().unwrap() > 10_000_000,
        "{json}"
    );
    let peak = json["peak_rss_anon_bytes"].as_f64().unwrap();
    assert!(
        peak <= 48.0 * (1 << 20) as f64,
        "peak {peak} bytes beyond --max-memory 48M"
    );
}

#[test]
fn a_set_cancel_flag_stops_the_survey() {
    let volume = random_volume([6, 6, 6], 2, 7);
    let cancel = std::sync::atomic::AtomicBool::new(true);
    let p = params(Method::Tmc, Inside::High, false);
    assert!(matches!(
        survey(&volume, &p, 2, Some(&cancel)),
        Err(tmc::Error::Interrupted)
    ));
}

#[test]
fn bad_input_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.npy");
    let line = common::cli::assert_one_line(&tmc(&["compare", s(&missing), "--iso", "1"]), 1);
    assert!(line.contains("missing.npy"), "{line}");
    let input = synth(dir.path(), "sphere", "8,8,8", "u8", "s.npy");
    common::cli::assert_one_line(
        &tmc(&["compare", s(&input), "--iso", "1", "--runs", "0"]),
        2,
    );
}

/// An isovalue that meets nothing (outside the data range) gives the
/// table of zeros with the note 'tmc extract' gives, not silently (the
/// note was missing); -q leaves it out.
#[test]
fn an_isovalue_outside_the_data_range_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "sphere", "8,8,8", "u8", "s.npy");
    let out = tmc(&["compare", s(&input), "--iso", "1000", "--runs", "1"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("tmc: note: no surface at isovalue 1000: every sample of"),
        "{stderr}"
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("triangles"), "{table}");
    let quiet = tmc(&["compare", s(&input), "--iso", "1000", "--runs", "1", "-q"]);
    assert_eq!(quiet.status.code(), Some(0), "{quiet:?}");
    assert!(quiet.stderr.is_empty(), "{quiet:?}");
    // A surface: no note.
    let out = tmc(&["compare", s(&input), "--iso", "100", "--runs", "1"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("no surface"));
}
