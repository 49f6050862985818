//! `tmc extract --labels`: every label's mesh is byte for byte what a
//! separate extraction of that label's 0/1 indicator volume (u8, iso 0.5)
//! writes, with and without `--close`; closed label surfaces match the
//! topology oracle of the indicator; any threads and slab depth give the
//! same bytes; whole-number floats are accepted and the first fraction is
//! refused by position; one PLY holds every label with a per-face label;
//! the frog's tissues when `../shared/data/frog_tissues.nrrd` is there.

mod common;

use common::cli::{assert_one_line, s, tmc};
use common::oracle;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::{Path, PathBuf};
use tmc::volume::{write_volume, ArrayVolume, ScalarType};
use tmc::Grid;

/// `tmc extract input --labels all --close --json -o dir/{label}.tmesh`:
/// the JSON report.
fn closed_labels_json(input: &Path, dir: &Path) -> serde_json::Value {
    let out = dir.join("{label}.tmesh");
    let args = [
        "extract",
        s(input),
        "--labels",
        "all",
        "--close",
        "-o",
        s(&out),
        "-q",
        "--json",
    ];
    serde_json::from_slice(&ok(&args)).unwrap()
}

/// A closed label surface encloses its voxels' volume to within the
/// half-voxel shell: half the largest voxel side (1.5 here and in the
/// frog) times the area.
fn assert_volume_within_the_shell(r: &serde_json::Value) {
    let (v, n, area) = (
        r["enclosed_volume"].as_f64().unwrap(),
        r["voxel_volume"].as_f64().unwrap(),
        r["area"].as_f64().unwrap(),
    );
    assert!(v > 0.0 && (v - n).abs() <= 0.75 * area, "{r}");
}

/// Runs `tmc` with `args`, asserting success; returns stdout.
fn ok(args: &[&str]) -> Vec<u8> {
    let out = tmc(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
    out.stdout
}

/// Writes `values` on a grid of `dims` (spacing 1, 1, 1.5, so that the
/// world map is not the identity) as an NRRD of `scalar`.
fn write(path: &Path, dims: [usize; 3], values: Vec<f64>, scalar: ScalarType) {
    let grid = Grid {
        spacing: [1.0, 1.0, 1.5],
        ..Grid::unit(dims)
    };
    let volume = ArrayVolume::new(grid, values).unwrap();
    write_volume(path, &volume, scalar, None).unwrap();
}

/// A label map: Voronoi regions of random seeds (labels 1..=regions,
/// touching each other and the border), background 0 where a random
/// field is low, a few one-voxel labels, and a torus (a label with a
/// tunnel).
fn label_map(dims: [usize; 3], regions: usize, seed: u64) -> Vec<f64> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let seeds: Vec<[f64; 3]> = (0..regions)
        .map(|_| std::array::from_fn(|i| rng.gen_range(0.0..dims[i] as f64)))
        .collect();
    let mut out = Vec::with_capacity(dims.iter().product());
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let p = [x as f64, y as f64, z as f64];
                let d2 = |c: &[f64; 3]| (0..3).map(|i| (p[i] - c[i]).powi(2)).sum::<f64>();
                let (k, _) = seeds
                    .iter()
                    .enumerate()
                    .map(|(k, c)| (k, d2(c)))
                    .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
                let background = rng.gen_bool(0.08);
                out.push(if background { 0.0 } else { (k + 1) as f64 });
            }
        }
    }
    let at = |x: usize, y: usize, z: usize| x + dims[0] * (y + dims[1] * z);
    // One-voxel labels, one on the border.
    for (i, p) in [[3, 4, 5], [0, 7, 2], [dims[0] - 2, 2, dims[2] / 2]]
        .iter()
        .enumerate()
    {
        out[at(p[0], p[1], p[2])] = (200 + i) as f64;
    }
    // A torus around the z axis through the grid's centre.
    let c = dims.map(|n| n as f64 / 2.0);
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let (dx, dy, dz) = (x as f64 - c[0], y as f64 - c[1], z as f64 - c[2]);
                let ring = ((dx * dx + dy * dy).sqrt() - 5.0).powi(2) + dz * dz;
                if ring < 2.3 {
                    out[at(x, y, z)] = 150.0;
                }
            }
        }
    }
    out
}

/// The values present, but 0.
fn labels_of(values: &[f64]) -> Vec<i64> {
    let mut l: Vec<i64> = values
        .iter()
        .map(|&v| v as i64)
        .filter(|&v| v != 0)
        .collect();
    l.sort_unstable();
    l.dedup();
    l
}

/// Extracts each of `labels` from `values` as its own u8 indicator volume
/// at 0.5 (with `extra`) and asserts that `dir/{label}.EXT` has its bytes.
fn assert_indicators(
    dir: &Path,
    dims: [usize; 3],
    values: &[f64],
    labels: &[i64],
    ext: &str,
    extra: &[&str],
) {
    let volume = dir.join("indicator.nrrd");
    let mesh = dir.join(format!("indicator.{ext}"));
    for &l in labels {
        let indicator = values.iter().map(|&v| f64::from(v == l as f64)).collect();
        write(&volume, dims, indicator, ScalarType::U8);
        let mut args = vec!["extract", s(&volume), "--iso", "0.5", "-o", s(&mesh), "-q"];
        args.extend_from_slice(extra);
        ok(&args);
        let label = dir.join(format!("{l}.{ext}"));
        assert!(
            std::fs::read(&mesh).unwrap() == std::fs::read(&label).unwrap(),
            "label {l} ({ext}, {extra:?}) differs from its indicator's extraction"
        );
    }
}

#[test]
fn each_label_is_its_indicator_extraction() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [23, 19, 17];
    let values = label_map(dims, 9, 1);
    let labels = labels_of(&values);
    assert!(labels.len() >= 13, "{labels:?}");
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values.clone(), ScalarType::U8);
    for (ext, extra) in [("tmesh", vec![]), ("ply", vec!["--close"]), ("obj", vec![])] {
        let out = dir.path().join(format!("{{label}}.{ext}"));
        let mut args = vec!["extract", s(&input), "--labels", "all", "-o", s(&out), "-q"];
        args.extend_from_slice(&extra);
        ok(&args);
        assert_indicators(dir.path(), dims, &values, &labels, ext, &extra);
    }
}

#[test]
fn closed_label_surfaces_match_the_oracle() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [16, 14, 12];
    let values = label_map(dims, 6, 2);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values.clone(), ScalarType::U8);
    let json = closed_labels_json(&input, dir.path());
    let reports = json["labels"].as_array().unwrap();
    let labels = labels_of(&values);
    assert_eq!(reports.len(), labels.len());
    for (&l, r) in labels.iter().zip(reports) {
        let mesh = tmc::check::read_mesh(&dir.path().join(format!("{l}.tmesh"))).unwrap();
        let report = tmc::check::check_mesh(&mesh);
        // The indicator, padded by one tie (outside) on every side as --close does.
        let indicator: Vec<f64> = values.iter().map(|&v| f64::from(v == l as f64)).collect();
        let (pdims, g) = oracle::padded(dims, &oracle::scaled(&indicator, 0.5), 1, 0);
        let topo = oracle::topology(pdims, &g);
        common::compare_with_oracle(&report, &topo).unwrap_or_else(|e| panic!("label {l}: {e}"));
        assert_eq!(r["label"], l);
        assert_eq!(r["closed"], true, "{r}");
        assert_eq!(r["components"], report.components);
        assert_eq!(r["genus"], topo.surface_genus().unwrap());
        // The enclosed volume is within the half-voxel shell of the voxels.
        assert_volume_within_the_shell(r);
    }
    // The torus has a tunnel.
    let torus = reports.iter().find(|r| r["label"] == 150).unwrap();
    assert_eq!(torus["genus"], 1, "{torus}");
}

#[test]
fn any_threads_and_slab_depth_give_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [21, 18, 26];
    let values = label_map(dims, 11, 3);
    let labels = labels_of(&values);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U16);
    let run = |name: &str, extra: &[&str]| {
        let sub = dir.path().join(name);
        std::fs::create_dir(&sub).unwrap();
        let out = sub.join("{label}.tmesh");
        let mut args = vec!["extract", s(&input), "--labels", "all", "-o", s(&out), "-q"];
        args.extend_from_slice(extra);
        ok(&args);
        labels
            .iter()
            .map(|l| std::fs::read(sub.join(format!("{l}.tmesh"))).unwrap())
            .collect::<Vec<_>>()
    };
    let first = run("a", &["--threads", "1", "--slab-depth", "64"]);
    for (i, extra) in [
        ["--threads", "2", "--slab-depth", "1"],
        ["--threads", "3", "--slab-depth", "2"],
        ["--threads", "2", "--slab-depth", "7"],
    ]
    .iter()
    .enumerate()
    {
        assert!(first == run(&format!("b{i}"), extra), "{extra:?}");
    }
}

#[test]
fn three_hundred_labels() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [40, 36, 30];
    let values = label_map(dims, 320, 4);
    let labels = labels_of(&values);
    assert!(labels.len() >= 300, "{}", labels.len());
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values.clone(), ScalarType::U16);
    let out = dir.path().join("{label}.tmesh");
    ok(&[
        "extract",
        s(&input),
        "--labels",
        "all",
        "-o",
        s(&out),
        "-q",
        "--close",
    ]);
    for l in &labels {
        assert!(dir.path().join(format!("{l}.tmesh")).exists(), "{l}");
    }
    let some: Vec<i64> = labels.iter().copied().step_by(23).collect();
    assert_indicators(dir.path(), dims, &values, &some, "tmesh", &["--close"]);
}

#[test]
fn whole_floats_are_labels_and_fractions_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [15, 13, 11];
    let mut values = label_map(dims, 5, 5);
    let labels = labels_of(&values);
    let float = dir.path().join("float.nrrd");
    write(&float, dims, values.clone(), ScalarType::F32);
    let out = dir.path().join("{label}.ply");
    ok(&["extract", s(&float), "--labels", "all", "-o", s(&out), "-q"]);
    assert_indicators(dir.path(), dims, &values, &labels, "ply", &[]);
    // Two fractions: the first in the file's order is named.
    values[4 + 15 * (6 + 13 * 7)] = 3.5;
    values[2 + 15 * (1 + 13 * 9)] = 0.25;
    write(&float, dims, values, ScalarType::F32);
    let fresh = dir.path().join("fresh");
    std::fs::create_dir(&fresh).unwrap();
    let out = fresh.join("{label}.ply");
    let err = assert_one_line(
        &tmc(&["extract", s(&float), "--labels", "all", "-o", s(&out), "-q"]),
        1,
    );
    assert!(err.contains("(x 4, y 6, z 7) is 3.5"), "{err}");
    assert_eq!(std::fs::read_dir(&fresh).unwrap().count(), 0);
}

#[test]
fn one_ply_holds_every_label_with_its_faces_labelled() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [17, 15, 13];
    let values = label_map(dims, 7, 6);
    let labels = labels_of(&values);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U8);
    let union = dir.path().join("all.ply");
    ok(&[
        "extract",
        s(&input),
        "--labels",
        "all",
        "--close",
        "-o",
        s(&union),
        "-q",
    ]);
    let each = dir.path().join("{label}.ply");
    ok(&[
        "extract",
        s(&input),
        "--labels",
        "all",
        "--close",
        "-o",
        s(&each),
        "-q",
    ]);
    let (vertices, faces) = parse_labelled_ply(&std::fs::read(&union).unwrap());
    let (mut v_at, mut f_at) = (0, 0);
    for &l in &labels {
        let one = std::fs::read(dir.path().join(format!("{l}.ply"))).unwrap();
        let (v, f) = parse_plain_ply(&one);
        assert_eq!(&vertices[v_at..v_at + v.len()], &v[..], "label {l}");
        for (i, face) in f.iter().enumerate() {
            let (got, label) = faces[f_at + i];
            assert_eq!(got, face.map(|k| k + v_at as u32), "label {l}");
            assert_eq!(label, l as u32);
        }
        v_at += v.len();
        f_at += f.len();
    }
    assert_eq!((v_at, f_at), (vertices.len(), faces.len()));
    // Touching labels share positions, so only the union's topology is
    // checked; each label alone is sound too.
    assert!(tmc(&["check", s(&union)]).status.success());
    for l in &labels {
        let one = dir.path().join(format!("{l}.ply"));
        let out = tmc(&["check", s(&one), "--strict"]);
        assert!(out.status.success(), "label {l}: {out:?}");
    }
}

/// The body of a binary PLY after `end_header\n`, and the header.
fn split_ply(bytes: &[u8]) -> (String, &[u8]) {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    (
        String::from_utf8_lossy(&bytes[..end]).into_owned(),
        &bytes[end..],
    )
}

fn count(header: &str, element: &str) -> usize {
    let line = header
        .lines()
        .find(|l| l.starts_with(&format!("element {element} ")))
        .unwrap();
    line.rsplit(' ').next().unwrap().parse().unwrap()
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// Vertices (12 bytes each) and faces of tmc's PLY.
fn parse_plain_ply(bytes: &[u8]) -> (Vec<[u8; 12]>, Vec<[u32; 3]>) {
    let (header, body) = split_ply(bytes);
    let (nv, nf) = (count(&header, "vertex"), count(&header, "face"));
    let v = (0..nv)
        .map(|i| body[i * 12..i * 12 + 12].try_into().unwrap())
        .collect();
    let f = (0..nf)
        .map(|i| {
            let at = nv * 12 + i * 13;
            assert_eq!(body[at], 3);
            std::array::from_fn(|k| u32_at(body, at + 1 + 4 * k))
        })
        .collect();
    (v, f)
}

/// A face of the one-file PLY and its label.
type LabelledFace = ([u32; 3], u32);

/// Vertices and (face, label) of the one-file PLY.
fn parse_labelled_ply(bytes: &[u8]) -> (Vec<[u8; 12]>, Vec<LabelledFace>) {
    let (header, body) = split_ply(bytes);
    assert!(header.contains("property list uchar uint vertex_indices\nproperty uint label\n"));
    let (nv, nf) = (count(&header, "vertex"), count(&header, "face"));
    assert_eq!(body.len(), nv * 12 + nf * 17);
    let v = (0..nv)
        .map(|i| body[i * 12..i * 12 + 12].try_into().unwrap())
        .collect();
    let f = (0..nf)
        .map(|i| {
            let at = nv * 12 + i * 17;
            assert_eq!(body[at], 3);
            let face = std::array::from_fn(|k| u32_at(body, at + 1 + 4 * k));
            (face, u32_at(body, at + 13))
        })
        .collect();
    (v, f)
}

#[test]
fn bad_label_arguments_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("labels.nrrd");
    write(
        &input,
        [6, 6, 6],
        label_map([6, 6, 6], 2, 7),
        ScalarType::U8,
    );
    let each = dir.path().join("{label}.ply");
    let err = assert_one_line(
        &tmc(&["extract", s(&input), "--labels", "1,x", "-o", s(&each)]),
        1,
    );
    assert!(err.contains("'x' is not an integer"), "{err}");
    let obj = dir.path().join("all.obj");
    let err = assert_one_line(
        &tmc(&["extract", s(&input), "--labels", "all", "-o", s(&obj)]),
        1,
    );
    assert!(err.contains("{label}"), "{err}");
    let names: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(names, vec![input.clone()]);
}

#[test]
fn frog_tissues() {
    let frog = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/frog_tissues.nrrd");
    if !frog.exists() {
        eprintln!("skipped: {} is not there", frog.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let json = closed_labels_json(&frog, dir.path());
    let reports = json["labels"].as_array().unwrap();
    assert!(reports.len() >= 20, "{}", reports.len());
    for r in reports {
        assert_eq!(r["closed"], true, "{r}");
        assert_volume_within_the_shell(r);
    }
    // Two labels against their indicators (u8, read back from the file).
    let source = tmc::volume::open(&frog, None).unwrap();
    let values = common::formats::all_samples(source.as_ref());
    let grid = *source.grid();
    let volume = dir.path().join("indicator.nrrd");
    let mesh = dir.path().join("indicator.tmesh");
    for l in [1i64, 16] {
        let indicator = values.iter().map(|&v| f64::from(v == l as f64)).collect();
        write_volume(
            &volume,
            &ArrayVolume::new(grid, indicator).unwrap(),
            ScalarType::U8,
            None,
        )
        .unwrap();
        ok(&[
            "extract",
            s(&volume),
            "--iso",
            "0.5",
            "--close",
            "-o",
            s(&mesh),
            "-q",
        ]);
        let label = dir.path().join(format!("{l}.tmesh"));
        assert!(
            std::fs::read(&mesh).unwrap() == std::fs::read(&label).unwrap(),
            "frog label {l}"
        );
    }
}
