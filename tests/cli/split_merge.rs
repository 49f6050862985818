//! `tmc extract --part I/N` + `tmc merge`: the merged mesh is byte-identical
//! to a single run, for any N and any order; inconsistent parts are refused.

use crate::common;

use common::cli::{assert_one_line, npy_header, s, synth, tmc};
use std::path::{Path, PathBuf};

/// Runs `tmc extract input -o output` with `opts` (and `--part` if given).
fn extract(input: &Path, output: &Path, opts: &[&str], part: Option<String>) {
    let mut args = vec!["extract", s(input), "-o", s(output), "-q"];
    args.extend_from_slice(opts);
    let part = part.unwrap_or_default();
    if !part.is_empty() {
        args.extend_from_slice(&["--part", &part]);
    }
    let out = tmc(&args);
    assert!(out.status.success(), "{args:?}: {out:?}");
}

/// Writes the `n` parts of `input` into `dir`; returns their paths.
fn parts(input: &Path, dir: &Path, opts: &[&str], n: usize) -> Vec<PathBuf> {
    (1..=n)
        .map(|i| {
            let p = dir.join(format!("part-{i}-of-{n}.tmesh"));
            extract(input, &p, opts, Some(format!("{i}/{n}")));
            p
        })
        .collect()
}

/// Merges `parts` into `out` and asserts success.
fn merge(parts: &[PathBuf], out: &Path) {
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend_from_slice(&["-o", s(out)]);
    let o = tmc(&args);
    assert!(o.status.success(), "{o:?}");
}

/// Asserts that split/merge equals a single run in `.tmesh` and `.ply`, for
/// N = 1, 2, 3, 7, with the parts merged reversed and rotated.
fn assert_equivalent(input: &Path, opts: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["tmesh", "ply"] {
        let whole = dir.path().join(format!("whole.{ext}"));
        extract(input, &whole, opts, None);
        let expect = std::fs::read(&whole).unwrap();
        for n in [1, 2, 3, 7] {
            let sub = dir.path().join(format!("n{n}"));
            std::fs::create_dir_all(&sub).unwrap();
            let mut ps = parts(input, &sub, opts, n);
            ps.reverse();
            ps.rotate_left(n / 2);
            let merged = dir.path().join(format!("merged{n}.{ext}"));
            merge(&ps, &merged);
            let got = std::fs::read(&merged).unwrap();
            assert!(
                got == expect,
                "{opts:?} N={n} .{ext}: merged differs from a single run"
            );
        }
    }
}

#[test]
fn merged_noise_equals_a_single_run() {
    let dir = tempfile::tempdir().unwrap();
    let u8_noise = synth(dir.path(), "noise", "13,11,17", "u8", "n.npy");
    assert_equivalent(&u8_noise, &["--iso", "128"]);
    assert_equivalent(&u8_noise, &["--iso", "100", "--close", "--inside", "low"]);
    assert_equivalent(
        &u8_noise,
        &["--iso", "128", "--method", "mc", "--slab-depth", "2"],
    );
}

#[test]
fn more_parts_than_layers_merge_too() {
    let dir = tempfile::tempdir().unwrap();
    // 3 cell layers, 7 parts: some parts are empty.
    let thin = synth(dir.path(), "noise", "9,8,4", "u8", "t.npy");
    assert_equivalent(&thin, &["--iso", "128"]);
}

/// A mirroring index-to-world map (NRRD `space directions` with a negative
/// axis) reverses every triangle; the parts must reverse the triangles of
/// their seams alike, and place the --close caps where a single run does.
#[test]
fn merged_mirrored_volume_equals_a_single_run() {
    let path = common::formats::data_dir().join("nrrd_gzip_be_i16.nrrd");
    let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    assert!(text.contains("space directions: (0.5,0,0) (0,-1,0) (0,0,2)"));
    assert_equivalent(&path, &["--iso", "550.5"]);
    assert_equivalent(&path, &["--iso", "550.5", "--close", "--inside", "low"]);
}

#[test]
fn merged_real_volume_equals_a_single_run() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/fuel.nrrd");
    if !path.exists() {
        println!("skipped: {} is absent", path.display());
        return;
    }
    assert_equivalent(&path, &["--iso", "30"]);
}

/// An HDF5 dataset named in the input (`FILE:/dataset`): the part record
/// identifies the file, not the path with the dataset (which is no file).
#[test]
fn merged_hdf5_dataset_named_in_the_path_equals_a_single_run() {
    let file = common::formats::data_dir().join("h5_latest.h5");
    let input = PathBuf::from(format!("{}:/fixed", file.display()));
    assert_equivalent(&input, &["--iso", "41"]);
    assert_equivalent(&input, &["--iso", "41", "--close"]);
}

/// Merges `parts` expecting one error line containing `needle`, and no output.
fn refused(parts: &[&PathBuf], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.tmesh");
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend_from_slice(&["-o", s(&out)]);
    let line = assert_one_line(&tmc(&args), 1);
    assert!(line.contains(needle), "{line:?} lacks {needle:?}");
    assert!(!out.exists());
    assert!(common::cli::temp_files(dir.path()).is_empty());
}

#[test]
fn merge_refuses_inconsistent_parts() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "9,9,12", "u8", "a.npy");
    let b = synth(dir.path(), "sphere", "9,9,12", "u8", "b.npy");
    let d = |name: &str| {
        let p = dir.path().join(name);
        std::fs::create_dir_all(&p).unwrap();
        p
    };
    let p3 = parts(&a, &d("a3"), &["--iso", "128"], 3);
    let other_iso = parts(&a, &d("iso"), &["--iso", "129"], 3);
    let other_input = parts(&b, &d("b3"), &["--iso", "128"], 3);
    let p2 = parts(&a, &d("a2"), &["--iso", "128"], 2);
    let close = parts(&a, &d("cl"), &["--iso", "128", "--close"], 3);
    refused(&[&p3[0], &other_iso[1], &p3[2]], "isovalues");
    refused(&[&p3[0], &other_input[1], &p3[2]], "inputs");
    refused(&[&p3[0], &p2[1], &p3[2]], "part counts");
    refused(&[&p3[0], &close[1], &p3[2]], "options (--close: off vs on)");
    refused(&[&p3[0], &p3[2]], "part 2/3 is missing");
    refused(&[&p3[0], &p3[1]], "part 3/3 is missing");
    refused(&[&p3[0], &p3[1], &p3[1], &p3[2]], "part 2/3 is given twice");
    refused(&[&a], "not a part file");
    // A part from another tmc version: patch the recorded version.
    let bytes = std::fs::read(&p3[1]).unwrap();
    let text = format!("\"tmc_version\":\"{}\"", env!("CARGO_PKG_VERSION"));
    let at = bytes
        .windows(text.len())
        .position(|w| w == text.as_bytes())
        .expect("the record names the version");
    let mut patched = bytes.clone();
    let v = at + text.len() - 2;
    patched[v] = if patched[v] == b'9' { b'8' } else { b'9' };
    let old = dir.path().join("old.tmesh");
    std::fs::write(&old, &patched).unwrap();
    refused(&[&p3[0], &old, &p3[2]], "damaged");
    // The same with the record's checksum fixed: a version mismatch.
    let n = patched.len();
    let index = u64::from_le_bytes(patched[n - 32..n - 24].try_into().unwrap()) as usize;
    let len = u64::from_le_bytes(patched[index - 16..index - 8].try_into().unwrap()) as usize;
    let crc = crc32fast::hash(&patched[index - 16 - len..index - 16]);
    patched[index - 8..index - 4].copy_from_slice(&crc.to_le_bytes());
    std::fs::write(&old, &patched).unwrap();
    refused(&[&p3[0], &old, &p3[2]], "tmc versions");
    let x = dir.path().join("x.tmesh");
    let bad = tmc(&["extract", s(&a), "--iso", "1", "-o", s(&x), "--part", "4/3"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("4/3"));
    assert!(!x.exists());
}

/// `scripts/slurm/parts-local.sh`, or `None` (the test is skipped) where
/// xargs is absent.
fn parts_local() -> Option<PathBuf> {
    if std::process::Command::new("xargs")
        .arg("--version")
        .output()
        .is_err()
    {
        println!("skipped: xargs is absent");
        return None;
    }
    Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm/parts-local.sh"))
}

#[test]
fn the_shell_script_splits_and_merges() {
    let Some(script) = parts_local() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "noise", "12,10,15", "u8", "v.npy");
    let whole = dir.path().join("whole.tmesh");
    extract(&input, &whole, &["--iso", "128"], None);
    let merged = dir.path().join("merged.tmesh");
    let mut sh = std::process::Command::new("sh");
    sh.arg(&script)
        .args([s(&input), "3", s(&merged), "--iso", "128"])
        .env("TMC", common::cli::tmc_path());
    assert_merged_by(&mut sh, &merged, &whole);
}

/// `parts-local.sh` with a part count that is not one, or an output in a
/// directory that is not there: one line of its own, before any part runs,
/// nothing made. They were `seq`'s and `xargs`' lines, a `tmc merge` of
/// the glob of no parts for 0, and `mktemp`'s line.
#[test]
fn the_shell_script_says_what_is_wrong_with_its_arguments() {
    let Some(script) = parts_local() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = synth(d, "noise", "6,5,4", "u8", "v.npy");
    let (merged, lost) = (d.join("m.ply"), d.join("missing/m.ply"));
    let cases = [
        ("0", &merged, 2, "number of parts"),
        ("x", &merged, 2, "number of parts"),
        ("", &merged, 2, "number of parts"),
        ("2", &lost, 1, "does not exist"),
    ];
    for (n, output, code, says) in cases {
        let out = std::process::Command::new("sh")
            .arg(&script)
            .args([s(&input), n, s(output), "--iso", "128"])
            .env("TMC", common::cli::tmc_path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{n} {output:?}: {stderr}");
        assert!(
            stderr.lines().count() == 1 && stderr.contains(says),
            "{n} {output:?}: {stderr}"
        );
        assert_eq!(common::cli::names(d), ["v.npy"], "{n}");
    }
}

/// Runs `sh`, which merges into `merged`, and asserts it equals `whole`.
fn assert_merged_by(sh: &mut std::process::Command, merged: &Path, whole: &Path) {
    let out = sh.output().unwrap();
    assert!(out.status.success(), "{out:?}");
    assert_eq!(
        std::fs::read(merged).unwrap(),
        std::fs::read(whole).unwrap()
    );
}

/// Writes a u8 `.npy` of 64 x 64 x 600 samples whose planes from `from` on
/// are shifted by `shift`: beyond the first MiB, so the same input identity.
fn layered_npy(dir: &Path, name: &str, from: usize, shift: u8) -> PathBuf {
    let mut bytes =
        npy_header("{'descr': '|u1', 'fortran_order': False, 'shape': (600, 64, 64), }");
    for z in 0..600 {
        for i in 0..64 * 64 {
            let v = ((i * 7 + z * 13) % 256) as u8;
            bytes.push(if z >= from { v.wrapping_add(shift) } else { v });
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Parts of two inputs that agree on their size and first MiB (so on the
/// recorded identity) but not on the seam's samples are refused, naming
/// both parts and the plane; parts of one input still merge.
#[test]
fn merge_refuses_parts_that_disagree_at_the_seam() {
    let dir = tempfile::tempdir().unwrap();
    let a = layered_npy(dir.path(), "a.npy", 600, 0);
    let b = layered_npy(dir.path(), "b.npy", 290, 1);
    let a1 = dir.path().join("a1.tmesh");
    let a2 = dir.path().join("a2.tmesh");
    let b2 = dir.path().join("b2.tmesh");
    let opts = ["--iso", "128", "--close"];
    extract(&a, &a1, &opts, Some("1/2".into()));
    extract(&a, &a2, &opts, Some("2/2".into()));
    extract(&b, &b2, &opts, Some("2/2".into()));
    refused(&[&a1, &b2], "a1.tmesh and ");
    refused(
        &[&b2, &a1],
        "disagree on the samples of plane 300: they were made from different inputs",
    );
    merge(&[a1, a2], &dir.path().join("m.tmesh"));
}

/// Parts of one input read headerless with different options are refused.
#[test]
fn merge_refuses_parts_read_with_other_raw_options() {
    let dir = tempfile::tempdir().unwrap();
    let raw = dir.path().join("v.raw");
    std::fs::write(
        &raw,
        (0..8 * 8 * 8 * 2)
            .map(|i| (i * 37 % 251) as u8)
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let p1 = dir.path().join("p1.tmesh");
    let p2 = dir.path().join("p2.tmesh");
    let opts = ["--iso", "30000", "--dims", "8,8,8", "--dtype", "u16"];
    extract(&raw, &p1, &opts, Some("1/2".into()));
    let mut big = opts.to_vec();
    big.extend_from_slice(&["--endian", "big"]);
    extract(&raw, &p2, &big, Some("2/2".into()));
    refused(&[&p1, &p2], "--endian");
}

/// A Zarr v2 group store (uncompressed, written here) holding a 4-D array
/// `v` of two volumes (2 x 12 x 9 x 9 u8, a chunk per volume) and 3-D
/// arrays `a` and `b` holding those two volumes: the second volume differs
/// from the first only in its first three planes, so a part of the upper
/// layers cannot tell them apart by its seam.
fn two_volume_store(dir: &Path) -> PathBuf {
    let store = dir.join("two.zarr");
    let volume = |k: usize| -> Vec<u8> {
        (0..12 * 81)
            .map(|i| {
                let v = ((i * 37 + i / 81 * 11) % 251) as u8;
                if k == 1 && i < 3 * 81 {
                    255 - v
                } else {
                    v
                }
            })
            .collect()
    };
    let array = |path: &Path, shape: &str, chunks: &str, chunk_files: &[(&str, Vec<u8>)]| {
        std::fs::create_dir_all(path).unwrap();
        let meta = format!(
            r#"{{"zarr_format": 2, "shape": {shape}, "chunks": {chunks}, "dtype": "|u1", "compressor": null, "fill_value": 0, "order": "C", "filters": null}}"#
        );
        std::fs::write(path.join(".zarray"), meta).unwrap();
        for (name, bytes) in chunk_files {
            std::fs::write(path.join(name), bytes).unwrap();
        }
    };
    std::fs::create_dir_all(&store).unwrap();
    std::fs::write(store.join(".zgroup"), r#"{"zarr_format": 2}"#).unwrap();
    let (v0, v1) = (volume(0), volume(1));
    let four = [("0.0.0.0", v0.clone()), ("1.0.0.0", v1.clone())];
    array(&store.join("v"), "[2, 12, 9, 9]", "[1, 12, 9, 9]", &four);
    array(
        &store.join("a"),
        "[12, 9, 9]",
        "[12, 9, 9]",
        &[("0.0.0", v0)],
    );
    array(
        &store.join("b"),
        "[12, 9, 9]",
        "[12, 9, 9]",
        &[("0.0.0", v1)],
    );
    store
}

/// Parts that read different things of one input (two entries of a 4-D
/// array with `--at`, two arrays of a store with `--array`, two datasets
/// of an HDF5 file) are refused, naming what each read: the input's
/// identity is the same file or store, and the seam's samples agree, so
/// they were merged into a mesh of neither, without a word. Parts that
/// read the same thing still merge into the single run's bytes.
#[test]
fn merge_refuses_parts_that_read_other_things_of_one_input() {
    let dir = tempfile::tempdir().unwrap();
    let store = two_volume_store(dir.path());
    let part = |name: &str, opts: &[&str], i: usize| {
        let p = dir.path().join(name);
        let mut all = vec!["--iso", "100"];
        all.extend_from_slice(opts);
        extract(&store, &p, &all, Some(format!("{i}/2")));
        p
    };
    let first0 = part("at0-1.tmesh", &["--array", "v", "--at", "0=0"], 1);
    let second0 = part("at0-2.tmesh", &["--array", "v", "--at", "0=0"], 2);
    let first1 = part("at1-1.tmesh", &["--array", "v", "--at", "0=1"], 1);
    refused(
        &[&first1, &second0],
        "(--array v --at 0=1 vs --array v --at 0=0)",
    );
    let a2 = part("a-2.tmesh", &["--array", "a"], 2);
    let b1 = part("b-1.tmesh", &["--array", "b"], 1);
    refused(&[&b1, &a2], "(--array b vs --array a)");
    let merged = dir.path().join("m.ply");
    merge(&[first0, second0], &merged);
    let whole = dir.path().join("w.ply");
    let opts = ["--iso", "100", "--array", "v", "--at", "0=0"];
    extract(&store, &whole, &opts, None);
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(&whole).unwrap()
    );
    // Two datasets of one HDF5 file (twins: the same samples), named in
    // the path and with --dataset.
    let file = common::formats::data_dir().join("h5_latest.h5");
    let fixed = PathBuf::from(format!("{}:/fixed", file.display()));
    let btree = PathBuf::from(format!("{}:/btree2", file.display()));
    let f1 = dir.path().join("f1.tmesh");
    let t2 = dir.path().join("t2.tmesh");
    extract(&fixed, &f1, &["--iso", "41"], Some("1/2".into()));
    extract(&btree, &t2, &["--iso", "41"], Some("2/2".into()));
    refused(&[&f1, &t2], "(--dataset /fixed vs --dataset /btree2)");
    let d2 = dir.path().join("d2.tmesh");
    extract(
        &file,
        &d2,
        &["--iso", "41", "--dataset", "fixed"],
        Some("2/2".into()),
    );
    merge(&[f1, d2], &dir.path().join("f.ply"));
}

/// Misleading messages of the QA pass: a truncated part says so; a part
/// given to check or convert says to merge it; --report with --part says
/// why; isovalues 0 and -0 are the same.
#[test]
fn part_messages_name_the_real_problem() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "9,9,12", "u8", "a.npy");
    let p = parts(&a, dir.path(), &["--iso", "0"], 2);
    let bytes = std::fs::read(&p[1]).unwrap();
    let cut = dir.path().join("cut.tmesh");
    std::fs::write(&cut, &bytes[..bytes.len() - 100]).unwrap();
    refused(&[&p[0], &cut], "truncated");
    let line = assert_one_line(&tmc(&["check", s(&p[0])]), 1);
    assert!(
        line.contains("part file") && line.contains("tmc merge"),
        "{line}"
    );
    let ply = dir.path().join("c.ply");
    let line = assert_one_line(&tmc(&["convert", s(&p[0]), "-o", s(&ply)]), 1);
    assert!(line.contains("tmc merge"), "{line}");
    assert!(!ply.exists());
    let x = dir.path().join("x.tmesh");
    let r = dir.path().join("r.json");
    let args = [
        "extract",
        s(&a),
        "--iso",
        "0",
        "--part",
        "1/2",
        "-o",
        s(&x),
        "--report",
        s(&r),
    ];
    let line = assert_one_line(&tmc(&args), 1);
    assert!(
        line.contains("--json") && line.contains("not a batch"),
        "{line}"
    );
    let minus = dir.path().join("minus.tmesh");
    extract(&a, &minus, &["--iso", "-0"], Some("2/2".into()));
    merge(&[p[0].clone(), minus], &dir.path().join("m.tmesh"));
}

/// A part whose layers hold no surface says nothing about the volume, so
/// --part refuses --require-surface (it used to fail such a part with "every
/// sample is on the same side of the isovalue", which was false).
#[test]
fn a_part_takes_no_require_surface() {
    let dir = tempfile::tempdir().unwrap();
    // A ball in the middle: the bottom cell layer holds no surface.
    let ball = synth(dir.path(), "sphere", "12,12,12", "f32", "ball.npy");
    let whole = dir.path().join("whole.tmesh");
    extract(&ball, &whole, &["--iso", "0", "--require-surface"], None);
    let part = dir.path().join("p.tmesh");
    let args = [
        "extract",
        s(&ball),
        "--iso",
        "0",
        "--require-surface",
        "--part",
        "1/11",
        "-o",
        s(&part),
    ];
    let line = assert_one_line(&tmc(&args), 2);
    assert!(
        line.contains("--require-surface") && line.contains("--part"),
        "{line}"
    );
    assert!(!part.exists());
}

/// The merge holds one part file open at a time: 40 parts merge under a
/// limit of 16 open files.
#[test]
fn merge_opens_one_part_at_a_time() {
    let dir = tempfile::tempdir().unwrap();
    let a = synth(dir.path(), "noise", "9,9,50", "u8", "a.npy");
    let ps = parts(&a, dir.path(), &["--iso", "128"], 40);
    let whole = dir.path().join("whole.tmesh");
    extract(&a, &whole, &["--iso", "128"], None);
    let merged = dir.path().join("merged.tmesh");
    let list: Vec<&str> = ps.iter().map(|p| s(p)).collect();
    let mut sh = std::process::Command::new("sh");
    sh.arg("-c")
        .arg(format!(
            "ulimit -n 16 && exec \"$0\" merge \"$@\" -o {}",
            s(&merged)
        ))
        .arg(common::cli::tmc_path())
        .args(&list);
    assert_merged_by(&mut sh, &merged, &whole);
}

#[test]
fn the_shell_script_removes_its_parts_when_interrupted() {
    use std::os::unix::process::CommandExt;
    use std::time::{Duration, Instant};
    let Some(script) = parts_local() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Four parts of 400^3 noise, one at a time (JOBS=1), each about half
    // a second on one thread: the script is still running seconds after
    // the first part starts, even when this thread is late to see it.
    let input = synth(dir.path(), "noise", "400,400,400", "u8", "v.raw");
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let merged = out_dir.join("merged.tmesh");
    // In a process group of its own, signalled as a whole, as Ctrl-C does.
    // With SIGINT at its default: a test run started in the background by
    // a shell without job control (`cmd &` in a script, nohup) inherits
    // SIGINT ignored, and a shell cannot trap a signal ignored on entry, so
    // the script would run to its end (exit 0) whatever it does.
    let mut child = common::signals::default_signals("sh");
    let mut child = child
        .arg(&script)
        .args([s(&input), "4", s(&merged)])
        .args(["--dims", "400,400,400", "--dtype", "u8", "--iso", "127.5"])
        .env("TMC", common::cli::tmc_path())
        .env("JOBS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .process_group(0)
        .spawn()
        .unwrap();
    // Until a part is being written in the parts directory.
    let part_started = || {
        std::fs::read_dir(&out_dir).unwrap().flatten().any(|e| {
            e.file_name().to_string_lossy().starts_with(".tmc-parts.")
                && std::fs::read_dir(e.path())
                    .map(|d| d.count() > 0)
                    .unwrap_or(false)
        })
    };
    let start = Instant::now();
    while !part_started() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the script ended before a part was written"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no part started"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let group = format!("-{}", child.id());
    let status = std::process::Command::new("kill")
        .args(["-s", "INT", "--", &group])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{out:?}");
    let left: Vec<_> = std::fs::read_dir(&out_dir).unwrap().flatten().collect();
    assert!(left.is_empty(), "left {left:?}");
}

/// A u8 label map of `dims` (x, y, z) with four labels in blocks.
fn label_map(dir: &Path, [nx, ny, nz]: [usize; 3]) -> PathBuf {
    let mut bytes = npy_header(&format!(
        "{{'descr': '|u1', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                bytes.push(((x / 4 + 2 * (y / 3) + 3 * (z / 5)) % 4) as u8);
            }
        }
    }
    let path = dir.join("labels.npy");
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `parts-local.sh` with `--labels`: one mesh per label (`OUTPUT` with
/// `{label}`) and one file of every label, each byte for byte what one
/// run writes. Its part names had no `{label}` or `{part}`, so every
/// part was refused.
#[test]
fn the_shell_script_splits_and_merges_a_label_map() {
    let Some(script) = parts_local() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = label_map(d, [13, 11, 17]);
    for dir in ["one", "split"] {
        std::fs::create_dir(d.join(dir)).unwrap();
    }
    extract(
        &input,
        &d.join("one/{label}.ply"),
        &["--labels", "all"],
        None,
    );
    extract(&input, &d.join("one/all.ply"), &["--labels", "all"], None);
    for output in ["split/{label}.ply", "split/all.ply"] {
        let mut sh = std::process::Command::new("sh");
        sh.arg(&script)
            .args([s(&input), "3", s(&d.join(output)), "--labels", "all"])
            .env("TMC", common::cli::tmc_path());
        let out = sh.output().unwrap();
        assert!(out.status.success(), "{out:?}");
    }
    let one = common::cli::names(&d.join("one"));
    assert_eq!(one, ["1.ply", "2.ply", "3.ply", "all.ply"]);
    assert_eq!(common::cli::names(&d.join("split")), one);
    for name in one {
        assert_eq!(
            std::fs::read(d.join("split").join(&name)).unwrap(),
            std::fs::read(d.join("one").join(&name)).unwrap(),
            "{name}"
        );
    }
}

/// `{label}` in `tmc merge -o` for the parts of an isosurface (not of
/// `--labels`) is refused with nothing written, as `tmc extract --iso` with
/// it is: the merge wrote a file named `{label}.ply` and exited 0.
#[test]
fn label_placeholder_for_isosurface_parts_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = synth(dir.path(), "sphere", "10,9,12", "f32", "v.nrrd");
    let parts = parts(&input, dir.path(), &["--iso", "0.5"], 2);
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let output = out_dir.join("{label}.ply");
    let out = tmc(&["merge", s(&parts[0]), s(&parts[1]), "-o", s(&output)]);
    let line = assert_one_line(&out, 1);
    assert!(
        line.contains("{label} names the files of label parts"),
        "{line}"
    );
    assert!(common::cli::names(&out_dir).is_empty());
}
