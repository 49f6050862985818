//! `tmc extract --normals`: PLY `nx ny nz`, OBJ `vn` and `v//vn`, `.tmesh`
//! with the normals attribute; the same bytes for any threads,
//! slab depth and split into parts; kept by `tmc convert` and `tmc merge`;
//! refused for formats without vertex normals; `scripts/read_tmesh.py`
//! reads them.

use crate::common;

use common::cli::{assert_one_line, python_ready, read_tmesh_script, s, synth, tmc};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `tmc` with `args`, asserting success.
fn ok(args: &[&str]) {
    let out = tmc(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
}

/// `tmc extract input --iso 0.1 --normals -o output` with `extra`.
fn extract(input: &Path, output: &Path, extra: &[&str]) {
    let mut args = vec!["extract", s(input), "--iso", "0.1", "-o", s(output), "-q"];
    args.push("--normals");
    args.extend_from_slice(extra);
    ok(&args);
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

/// A gyroid with several surfaces crossing every slab and part boundary.
fn gyroid(dir: &Path) -> PathBuf {
    synth(dir, "gyroid", "40x36x50", "f32", "gyroid.nrrd")
}

/// The vertices and normals of a binary PLY written with normals.
fn ply_vertices(path: &Path) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let bytes = read(path);
    let end = b"end_header\n";
    let at = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = String::from_utf8_lossy(&bytes[..at]).into_owned();
    assert!(
        header.contains(
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
        ),
        "{header}"
    );
    let count: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    let f = |i: usize| f32::from_le_bytes(bytes[at + 4 * i..at + 4 * i + 4].try_into().unwrap());
    (0..count)
        .map(|v| {
            let r = |k: usize| [f(6 * v + k), f(6 * v + k + 1), f(6 * v + k + 2)];
            (r(0), r(3))
        })
        .unzip()
}

#[test]
fn normals_are_the_same_bytes_for_any_threads_slabs_and_parts() {
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    let one = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        extract(&input, &out, extra);
        out
    };
    for ext in ["ply", "obj", "tmesh"] {
        let reference = read(&one(&format!("ref.{ext}"), &["--threads", "1"]));
        for (threads, depth) in [("2", "1"), ("2", "3"), ("0", "64"), ("1", "7")] {
            let name = format!("t{threads}-d{depth}.{ext}");
            let other = one(&name, &["--threads", threads, "--slab-depth", depth]);
            assert!(read(&other) == reference, "{name} differs");
        }
    }
    let ply = read(&dir.path().join("ref.ply"));
    let tmesh = read(&dir.path().join("ref.tmesh"));
    for n in [2usize, 3, 5] {
        let parts: Vec<PathBuf> = (1..=n)
            .map(|i| one(&format!("p{i}-{n}.tmesh"), &["--part", &format!("{i}/{n}")]))
            .collect();
        for (ext, expected) in [("ply", &ply), ("tmesh", &tmesh)] {
            let merged = dir.path().join(format!("merged-{n}.{ext}"));
            let mut args = vec!["merge"];
            args.extend(parts.iter().map(|p| s(p)));
            args.extend_from_slice(&["-o", s(&merged)]);
            ok(&args);
            assert!(
                &read(&merged) == expected,
                "{n} parts merged to .{ext} differ"
            );
        }
    }
    // convert keeps the normals: the same bytes as a direct extraction.
    for ext in ["ply", "obj"] {
        let converted = dir.path().join(format!("converted.{ext}"));
        let from = dir.path().join("ref.tmesh");
        ok(&["convert", s(&from), "-o", s(&converted)]);
        let direct = read(&dir.path().join(format!("ref.{ext}")));
        assert!(read(&converted) == direct, "converted .{ext} differs");
    }
}

#[test]
fn ply_and_obj_carry_one_unit_normal_per_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    let ply = dir.path().join("g.ply");
    let obj = dir.path().join("g.obj");
    extract(&input, &ply, &[]);
    extract(&input, &obj, &[]);
    let (vertices, normals) = ply_vertices(&ply);
    assert!(vertices.len() > 1000);
    for n in &normals {
        let len = n.iter().map(|c| c * c).sum::<f32>().sqrt();
        assert!((len - 1.0).abs() < 1e-5, "{n:?}");
    }
    // OBJ: each `v` followed by its `vn`, the same numbers as the PLY's;
    // faces name each vertex's own normal.
    let text = std::fs::read_to_string(&obj).unwrap();
    let numbers = |prefix: &str| -> Vec<[f32; 3]> {
        text.lines()
            .filter_map(|l| l.strip_prefix(prefix))
            .map(|l| {
                let v: Vec<f32> = l.split(' ').map(|c| c.parse().unwrap()).collect();
                [v[0], v[1], v[2]]
            })
            .collect()
    };
    assert_eq!(numbers("v "), vertices);
    assert_eq!(numbers("vn "), normals);
    let faces: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
    assert!(!faces.is_empty());
    for f in faces {
        for corner in f[2..].split(' ') {
            let (v, n) = corner.split_once("//").unwrap();
            assert_eq!(v, n, "{f}");
        }
    }
}

#[test]
fn tmesh_is_version_2_only_with_normals() {
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    let with = dir.path().join("with.tmesh");
    let without = dir.path().join("without.tmesh");
    extract(&input, &with, &[]);
    ok(&[
        "extract",
        s(&input),
        "--iso",
        "0.1",
        "-o",
        s(&without),
        "-q",
    ]);
    let version = |p: &Path| u32::from_le_bytes(read(p)[8..12].try_into().unwrap());
    assert_eq!((version(&with), read(&with)[99]), (3, 1));
    assert_eq!((version(&without), read(&without)[99]), (3, 0));
    // Both are read (tmc check, and convert without normals to OFF).
    for p in [&with, &without] {
        ok(&["check", s(p)]);
    }
    let off = dir.path().join("positions.off");
    ok(&["convert", s(&with), "-o", s(&off)]);
    let direct = dir.path().join("direct.off");
    ok(&["convert", s(&without), "-o", s(&direct)]);
    assert!(
        read(&off) == read(&direct),
        "OFF from a file with normals differs"
    );
}

#[test]
fn normals_need_an_output_that_holds_them() {
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    for ext in ["off", "stl"] {
        let out = dir.path().join(format!("mesh.{ext}"));
        let o = tmc(&[
            "extract",
            s(&input),
            "--iso",
            "0.1",
            "--normals",
            "-o",
            s(&out),
        ]);
        let line = assert_one_line(&o, 1);
        assert!(line.contains("--normals needs an output"), "{line}");
        assert!(!out.exists());
    }
}

#[test]
fn merge_refuses_parts_with_and_without_normals() {
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    let a = dir.path().join("a.tmesh");
    let b = dir.path().join("b.tmesh");
    extract(&input, &a, &["--part", "1/2"]);
    let args = ["extract", s(&input), "--iso", "0.1", "-o", s(&b), "-q"];
    ok(&[&args[..], &["--part", "2/2"]].concat());
    let out = dir.path().join("m.ply");
    let o = tmc(&["merge", s(&a), s(&b), "-o", s(&out)]);
    let line = assert_one_line(&o, 1);
    assert!(line.contains("--normals: on vs off"), "{line}");
    assert!(!out.exists());
}

#[test]
fn read_tmesh_py_reads_the_normals() {
    if !python_ready() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let input = gyroid(dir.path());
    let tmesh = dir.path().join("g.tmesh");
    let ply = dir.path().join("g.ply");
    extract(&input, &tmesh, &[]);
    extract(&input, &ply, &[]);
    let (_, normals) = ply_vertices(&ply);
    let script = format!(
        "import sys; sys.path.insert(0, {dir:?}); from read_tmesh import read_tmesh\n\
         v, t, info = read_tmesh({mesh:?})\n\
         n = info['normals']\n\
         print(n.shape[0], repr(float(n[0][0])), repr(float(n[-1][2])))",
        dir = read_tmesh_script().parent().unwrap().to_str().unwrap(),
        mesh = s(&tmesh),
    );
    let out = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let printed = String::from_utf8_lossy(&out.stdout).into_owned();
    let fields: Vec<&str> = printed.split_whitespace().collect();
    assert_eq!(fields[0].parse::<usize>().unwrap(), normals.len());
    assert_eq!(fields[1].parse::<f32>().unwrap(), normals[0][0]);
    assert_eq!(
        fields[2].parse::<f32>().unwrap(),
        normals[normals.len() - 1][2]
    );
}

#[test]
fn a_batch_gives_every_output_normals() {
    let dir = tempfile::tempdir().unwrap();
    let a = gyroid(dir.path());
    let b = synth(dir.path(), "sphere", "20x22x24", "u8", "ball.nrrd");
    let template = dir.path().join("{stem}_{iso}.ply");
    let iso = ["--iso", "0.1,100"];
    ok(&[
        &[
            "extract",
            s(&a),
            s(&b),
            "-o",
            s(&template),
            "-q",
            "--normals",
        ][..],
        &iso,
    ]
    .concat());
    for name in [
        "gyroid_0.1.ply",
        "gyroid_100.ply",
        "ball_0.1.ply",
        "ball_100.ply",
    ] {
        let path = dir.path().join(name);
        let (vertices, normals) = ply_vertices(&path);
        assert_eq!(vertices.len(), normals.len(), "{name}");
    }
    // The one-input run writes the same bytes as the batch.
    let single = dir.path().join("single.ply");
    ok(&[
        "extract",
        s(&b),
        "--iso",
        "100",
        "-o",
        s(&single),
        "-q",
        "--normals",
    ]);
    assert!(read(&single) == read(&dir.path().join("ball_100.ply")));
}
