//! `tmc extract --labels all --json` (and `--stats`) counts each label's
//! figures while its chunks stream: they are those of the whole-mesh
//! check (`tmc::check::check_mesh`) of the label's file, and its area and
//! enclosed volume summed here triangle by triangle, to the last bit, with
//! and without `--close`, for any threads and slab depth.

use crate::common;

use common::cli::s;
use common::labels::{label_map, ok, write};
use std::path::Path;
use tmc::check::{check_mesh, read_mesh};
use tmc::volume::ScalarType;

/// Area and enclosed volume of `mesh`, summed in `f64` in the order of its
/// triangles (the divergence theorem: `a . (b x c) / 6` per triangle).
fn area_and_volume(mesh: &tmc::Mesh) -> (f64, f64) {
    let (mut area, mut volume) = (0.0f64, 0.0f64);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|k| mesh.vertices[k as usize].map(f64::from));
        let (u, v) = (sub(b, a), sub(c, a));
        let n = cross(u, v);
        area += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0;
        let bc = cross(b, c);
        volume += (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]) / 6.0;
    }
    (area, volume)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// Runs `--labels all --json` into `dir` with `extra` and asserts each
/// label's figures against its file's whole-mesh check; returns the JSON
/// labels.
fn assert_stats_are_the_files(input: &Path, dir: &Path, extra: &[&str]) -> Vec<serde_json::Value> {
    std::fs::create_dir_all(dir).unwrap();
    let out = dir.join("{label}.tmesh");
    let mut args = vec!["extract", s(input), "--labels", "all", "-o", s(&out), "-q"];
    args.push("--json");
    args.extend_from_slice(extra);
    let json: serde_json::Value = serde_json::from_slice(&ok(&args)).unwrap();
    let labels = json["labels"].as_array().unwrap().clone();
    for r in &labels {
        let l = r["label"].as_i64().unwrap();
        let mesh = read_mesh(&dir.join(format!("{l}.tmesh"))).unwrap();
        let report = check_mesh(&mesh);
        let (area, volume) = area_and_volume(&mesh);
        let what = format!("label {l} {extra:?}: {r}");
        assert_eq!(r["triangles"], mesh.triangles.len(), "{what}");
        assert_eq!(r["components"], report.components, "{what}");
        match report.total_genus() {
            Some(g) => assert_eq!(r["genus"], g, "{what}"),
            None => assert!(r.get("genus").is_none(), "{what}"),
        }
        assert_eq!(r["closed"], report.is_closed_manifold(), "{what}");
        assert_eq!(
            r["area"].as_f64().unwrap().to_bits(),
            area.to_bits(),
            "{what}"
        );
        // Only a closed surface encloses a volume; an open one's sum
        // would move with the origin.
        match report.is_closed_manifold() {
            true => assert_eq!(
                r["enclosed_volume"].as_f64().unwrap().to_bits(),
                volume.to_bits(),
                "{what}"
            ),
            false => assert!(r.get("enclosed_volume").is_none(), "{what}"),
        }
    }
    labels
}

/// A label map with touching labels, labels on the border, one-voxel
/// labels and a torus (`label_map`), and a hollow box of label 250 around
/// a block of 251: 250's surface has a cavity (two components).
fn map_with_a_cavity(dims: [usize; 3]) -> Vec<f64> {
    let mut values = label_map(dims, 12, 7);
    let at = |x: usize, y: usize, z: usize| x + dims[0] * (y + dims[1] * z);
    for z in 2..9 {
        for y in 2..9 {
            for x in 2..9 {
                let inner = (4..7).contains(&x) && (4..7).contains(&y) && (4..7).contains(&z);
                values[at(x, y, z)] = if inner { 251.0 } else { 250.0 };
            }
        }
    }
    values
}

#[test]
fn label_stats_are_the_whole_mesh_check_of_each_file() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [24, 21, 23];
    let values = map_with_a_cavity(dims);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U16);
    for close in [false, true] {
        let mut first: Option<Vec<serde_json::Value>> = None;
        for (threads, depth) in [("1", "1"), ("2", "5"), ("1", "5"), ("2", "1")] {
            let mut extra = vec!["--threads", threads, "--slab-depth", depth];
            if close {
                extra.push("--close");
            }
            let sub = dir.path().join(format!("{close}-{threads}-{depth}"));
            let mut labels = assert_stats_are_the_files(&input, &sub, &extra);
            for r in &mut labels {
                r.as_object_mut().unwrap().remove("output");
            }
            let cavity = labels.iter().find(|r| r["label"] == 250).unwrap();
            assert_eq!(cavity["components"], 2, "{cavity}");
            if close {
                assert!(labels.iter().all(|r| r["closed"] == true), "{labels:?}");
            } else {
                assert!(labels.iter().any(|r| r["closed"] == false));
            }
            match &first {
                None => first = Some(labels),
                Some(f) => assert!(*f == labels, "{extra:?} changed the figures"),
            }
        }
    }
}

#[test]
fn three_hundred_labels_stats_are_the_whole_mesh_checks() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [40, 36, 30];
    let values = label_map(dims, 320, 4);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U16);
    let extra = ["--threads", "2", "--slab-depth", "5"];
    let open = assert_stats_are_the_files(&input, &dir.path().join("open"), &extra);
    assert!(open.len() >= 300, "{}", open.len());
    let closed = [&extra[..], &["--close"]].concat();
    assert_stats_are_the_files(&input, &dir.path().join("closed"), &closed);
}
