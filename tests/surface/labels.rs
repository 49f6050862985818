//! `tmc extract --labels`: every label's mesh is byte for byte what a
//! separate extraction of that label's 0/1 indicator volume (u8, iso 0.5)
//! writes, with and without `--close`; closed label surfaces match the
//! topology oracle of the indicator; any threads and slab depth give the
//! same bytes; whole-number floats are accepted and the first fraction is
//! refused by position; one PLY holds every label with a per-face label;
//! the frog's tissues when `../shared/data/frog_tissues.nrrd` is there.

use crate::common;

use common::cli::{assert_one_line, s, tmc};
use common::labels::{
    assert_indicators, label_map, labels_of, ok, parse_labelled_ply, parse_plain_ply, write,
};
use common::oracle;
use std::path::{Path, PathBuf};
use tmc::volume::{write_volume, ArrayVolume, ScalarType};

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

/// `tmc extract input --labels all EXTRA -o out`, quiet.
fn labels_run(input: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec!["extract", s(input), "--labels", "all", "-o", s(out), "-q"];
    args.extend_from_slice(extra);
    ok(&args);
}

#[test]
fn one_file_holds_every_label_with_its_faces_labelled() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [17, 15, 13];
    let values = label_map(dims, 7, 6);
    let labels = labels_of(&values);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U8);
    let union = dir.path().join("all.ply");
    let tmesh = dir.path().join("all.tmesh");
    let each = dir.path().join("{label}.ply");
    for out in [&union, &tmesh, &each] {
        labels_run(&input, out, &["--close"]);
    }
    let (vertices, faces) = parse_labelled_ply(&std::fs::read(&union).unwrap());
    let mut seen = 0;
    for &l in &labels {
        let one = std::fs::read(dir.path().join(format!("{l}.ply"))).unwrap();
        assert_eq!(
            label_part(&vertices, &faces, l as u32),
            parse_plain_ply(&one),
            "label {l}"
        );
        seen += faces.iter().filter(|f| f.1 == l as u32).count();
    }
    assert_eq!(seen, faces.len());
    // The .tmesh is the same mesh: converted, the PLY's bytes.
    let converted = dir.path().join("converted.ply");
    ok(&["convert", s(&tmesh), "-o", s(&converted)]);
    assert!(std::fs::read(&converted).unwrap() == std::fs::read(&union).unwrap());
    // Touching labels share positions, so only the union's topology is
    // checked; each label alone is sound too.
    assert!(tmc(&["check", s(&union)]).status.success());
    assert!(tmc(&["check", s(&tmesh)]).status.success());
    for l in &labels {
        let one = dir.path().join(format!("{l}.ply"));
        let out = tmc(&["check", s(&one), "--strict"]);
        assert!(out.status.success(), "label {l}: {out:?}");
    }
}

/// Label `l`'s vertices (in order) and faces (renumbered into them) of the
/// one-file mesh.
fn label_part(
    vertices: &[[u8; 12]],
    faces: &[([u32; 3], u32)],
    l: u32,
) -> (Vec<[u8; 12]>, Vec<[u32; 3]>) {
    let mine: Vec<[u32; 3]> = faces.iter().filter(|f| f.1 == l).map(|f| f.0).collect();
    let mut used: Vec<u32> = mine.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let at = |k: u32| used.binary_search(&k).unwrap() as u32;
    let v = used.iter().map(|&k| vertices[k as usize]).collect();
    (v, mine.iter().map(|f| f.map(at)).collect())
}

#[test]
fn read_tmesh_py_reads_the_labels() {
    if !common::cli::python_ready() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let dims = [16, 14, 12];
    let values = label_map(dims, 6, 8);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values.clone(), ScalarType::U8);
    labels_run(&input, &dir.path().join("all.tmesh"), &["--normals"]);
    labels_run(&input, &dir.path().join("{label}.tmesh"), &["--normals"]);
    // numpy: each label's triangles, vertices and normals in the one file
    // are those of the label's own file.
    let script = format!(
        "import sys, numpy as np; sys.path.insert(0, {scripts:?})\n\
         from read_tmesh import read_tmesh\n\
         v, t, info = read_tmesh({dir:?} + '/all.tmesh')\n\
         labels = info['labels']; assert labels.shape == (len(t),)\n\
         for l in np.unique(labels):\n\
         \x20   lv, lt, linfo = read_tmesh(f'{dir}/{{l}}.tmesh')\n\
         \x20   mine = t[labels == l]; used = np.unique(mine)\n\
         \x20   assert np.array_equal(v[used], lv) and np.array_equal(info['normals'][used], linfo['normals'])\n\
         \x20   assert np.array_equal(np.searchsorted(used, mine), lt)\n\
         \x20   assert linfo['labels'] is None\n\
         print(len(np.unique(labels)))",
        scripts = common::cli::read_tmesh_script().parent().unwrap().to_str().unwrap(),
        dir = s(dir.path()),
    );
    let out = std::process::Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let printed = String::from_utf8_lossy(&out.stdout);
    assert_eq!(printed.trim(), labels_of(&values).len().to_string());
}

#[test]
fn parts_merge_into_the_one_run_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [18, 16, 21];
    let values = label_map(dims, 8, 9);
    let labels = labels_of(&values);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values, ScalarType::U8);
    for extra in [vec![], vec!["--close", "--normals"]] {
        let [one, parts, merged] = ["one", "parts", "merged"].map(|d| dir.path().join(d));
        for d in [&one, &parts, &merged] {
            let _ = std::fs::remove_dir_all(d);
            std::fs::create_dir(d).unwrap();
        }
        labels_run(&input, &one.join("{label}.tmesh"), &extra);
        labels_run(&input, &one.join("all.ply"), &extra);
        for i in 1..=3 {
            let part = format!("{i}/3");
            let mut args = extra.clone();
            args.extend(["--part", &part, "--threads", "2"]);
            labels_run(&input, &parts.join("{label}.{part}.tmesh"), &args);
        }
        let mut files: Vec<PathBuf> = std::fs::read_dir(&parts)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        assert_eq!(files.len(), 3 * labels.len());
        files.reverse();
        let mut args: Vec<&str> = vec!["merge"];
        args.extend(files.iter().map(|p| s(p)));
        for out in [merged.join("{label}.tmesh"), merged.join("all.ply")] {
            ok(&[&args[..], &["-o", s(&out)][..]].concat());
        }
        for name in labels
            .iter()
            .map(|l| format!("{l}.tmesh"))
            .chain(["all.ply".into()])
        {
            let (a, b) = (one.join(&name), merged.join(&name));
            assert!(
                std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
                "{name} {extra:?}"
            );
        }
        // One label's parts missing: refused, nothing written.
        let out = merged.join("again.ply");
        let short = [&["merge"][..], &args[2..], &["-o", s(&out)][..]].concat();
        let err = assert_one_line(&tmc(&short), 1);
        assert!(err.contains("missing"), "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn normals_are_those_of_each_indicator() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [19, 17, 15];
    let values = label_map(dims, 6, 10);
    let labels = labels_of(&values);
    let input = dir.path().join("labels.nrrd");
    write(&input, dims, values.clone(), ScalarType::U8);
    let slabs = [
        "--normals",
        "--close",
        "--threads",
        "2",
        "--slab-depth",
        "3",
    ];
    for extra in [&["--normals"][..], &slabs[..]] {
        labels_run(&input, &dir.path().join("{label}.ply"), extra);
        assert_indicators(dir.path(), dims, &values, &labels, "ply", extra);
    }
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
        2,
    );
    assert!(err.contains("'x' is not an integer"), "{err}");
    let obj = dir.path().join("all.obj");
    let err = assert_one_line(
        &tmc(&["extract", s(&input), "--labels", "all", "-o", s(&obj)]),
        1,
    );
    assert!(err.contains("{label}"), "{err}");
    let err = assert_one_line(
        &tmc(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "--inside",
            "low",
            "-o",
            s(&each),
        ]),
        1,
    );
    assert!(err.contains("--inside low"), "{err}");
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
