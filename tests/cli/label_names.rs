//! The output names of `tmc extract --labels` and of `tmc merge` of label
//! parts: placeholders (`{stem}` filled in, `{iso}` refused), names that
//! are no UTF-8, and a merge that names the label whose parts are missing
//! and leaves no label's file when it fails.

use crate::common;

use common::cli::{assert_one_line, names, s, tmc};
use common::labels::{ok, write};
use std::fs;
use std::path::{Path, PathBuf};
use tmc::volume::ScalarType;

/// A 6x6x6 map of labels 3 (a 2x2x2 block) and 7 (a 2x2x3 block) on 0.
fn two_labels(dir: &Path) -> PathBuf {
    let mut values = vec![0.0; 216];
    for z in 1..3 {
        for y in 1..3 {
            for x in 1..3 {
                values[x + 6 * (y + 6 * z)] = 3.0;
            }
        }
    }
    for z in 2..5 {
        for y in 3..5 {
            for x in 3..5 {
                values[x + 6 * (y + 6 * z)] = 7.0;
            }
        }
    }
    let input = dir.join("map.nrrd");
    write(&input, [6, 6, 6], values, ScalarType::U8);
    input
}

#[test]
fn iso_in_a_label_output_is_refused_naming_label_instead() {
    let dir = tempfile::tempdir().unwrap();
    let input = two_labels(dir.path());
    for out in ["{stem}_{iso}.ply", "{label}_{iso}.ply", "{iso}/{label}.ply"] {
        let out = dir.path().join(out);
        let args = ["extract", s(&input), "--labels", "all", "-o", s(&out), "-q"];
        let err = assert_one_line(&tmc(&args), 1);
        assert!(err.contains("{iso}") && err.contains("{label}"), "{err}");
        assert_eq!(names(dir.path()), ["map.nrrd"]);
    }
}

#[test]
fn stem_is_the_input_name_in_one_file_and_in_a_file_per_label() {
    let dir = tempfile::tempdir().unwrap();
    let input = two_labels(dir.path());
    let d = dir.path();
    let run = |out: &str| {
        ok(&[
            "extract",
            s(&input),
            "--labels",
            "all",
            "-o",
            s(&d.join(out)),
            "-q",
        ])
    };
    run("{stem}.ply");
    run("plain.ply");
    run("{stem}_{label}.ply");
    run("{label}.ply");
    assert_eq!(
        names(d),
        [
            "3.ply",
            "7.ply",
            "map.nrrd",
            "map.ply",
            "map_3.ply",
            "map_7.ply",
            "plain.ply"
        ]
    );
    let read = |name: &str| fs::read(d.join(name)).unwrap();
    assert_eq!(read("map.ply"), read("plain.ply"));
    assert_eq!(read("map_3.ply"), read("3.ply"));
    assert_eq!(read("map_7.ply"), read("7.ply"));
}

/// The label parts of `input` in `parts`, `{label}.{i}.tmesh` for parts
/// 1 to 3 (the same `-o '{label}.{part}.tmesh'` for each).
fn label_parts(input: &Path, parts: &Path) {
    fs::create_dir(parts).unwrap();
    let out = parts.join("{label}.{part}.tmesh");
    for i in 1..=3 {
        let part = format!("{i}/3");
        ok(&[
            "extract",
            s(input),
            "--labels",
            "all",
            "--part",
            &part,
            "-o",
            s(&out),
            "-q",
        ]);
    }
}

/// A temporary directory with the map of [`two_labels`] and its label
/// parts in `parts/` (see [`label_parts`]).
fn parts_of_two_labels() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let input = two_labels(dir.path());
    let parts = dir.path().join("parts");
    label_parts(&input, &parts);
    (dir, parts)
}

/// `tmc merge` of the files of `parts` into `out`.
fn merge(parts: &Path, out: &Path) -> std::process::Output {
    let files: Vec<PathBuf> = names(parts).iter().map(|n| parts.join(n)).collect();
    let mut args = vec!["merge", "-o", s(out)];
    args.extend(files.iter().map(|f| s(f)));
    tmc(&args)
}

#[test]
fn a_merge_names_the_label_of_a_missing_part() {
    let (dir, parts) = parts_of_two_labels();
    fs::remove_file(parts.join("7.2.tmesh")).unwrap();
    assert_merge_refused(dir.path(), &parts, &["label 7: part 2/3 is missing"]);
    // Every part of label 7 missing: the records know the run had two.
    fs::remove_file(parts.join("7.1.tmesh")).unwrap();
    fs::remove_file(parts.join("7.3.tmesh")).unwrap();
    assert_merge_refused(dir.path(), &parts, &["2 labels", "labels 3)"]);
}

/// `tmc merge` of the files of `parts` into a file per label and into one
/// file, in a new directory `out` of `dir`, fails with one line saying
/// each of `says`, leaving `out` empty.
fn assert_merge_refused(dir: &Path, parts: &Path, says: &[&str]) {
    let out = dir.join("out");
    fs::create_dir_all(&out).unwrap();
    for target in ["{label}.ply", "all.ply"] {
        let err = assert_one_line(&merge(parts, &out.join(target)), 1);
        assert!(says.iter().all(|s| err.contains(s)), "{err}");
        assert!(names(&out).is_empty(), "{:?}", names(&out));
    }
}

/// Parts left in the directory by an earlier run with other labels (the
/// Slurm scripts' and `parts-local.sh`'s merge takes every label's file):
/// each run's records agree on all but the label, so only the number of
/// labels tells them apart. The merge refuses more labels than the run
/// had; it wrote a mesh of every stale label too.
#[test]
fn a_merge_refuses_the_labels_of_another_run() {
    let (dir, parts) = parts_of_two_labels();
    let input = dir.path().join("map.nrrd");
    // An earlier run of labels 0 and 5 (the background, and a label the
    // map does not hold) of the same map, two labels as the run of all.
    let earlier = dir.path().join("earlier");
    fs::create_dir(&earlier).unwrap();
    for i in 1..=3 {
        let part = format!("{i}/3");
        let out = earlier.join("{label}.{part}.tmesh");
        ok(&[
            "extract",
            s(&input),
            "--labels",
            "0,5",
            "--part",
            &part,
            "-o",
            s(&out),
            "-q",
        ]);
    }
    for name in names(&earlier) {
        fs::rename(earlier.join(&name), parts.join(&name)).unwrap();
    }
    assert_merge_refused(dir.path(), &parts, &["2 labels", "labels 0, 3, 5, 7"]);
}

#[test]
fn a_merge_into_a_file_per_label_that_fails_leaves_no_label_file() {
    let (dir, parts) = parts_of_two_labels();
    // A damaged chunk in label 7's last part, merged after label 3's
    // files are written: the merge fails there.
    let damaged = parts.join("7.3.tmesh");
    let entries = tmc::meshfile::TmeshReader::open(&damaged)
        .unwrap()
        .entries()
        .to_vec();
    let (k, _) = entries
        .iter()
        .enumerate()
        .find(|(k, e)| e.triangle_count > 0 && *k + 1 < entries.len())
        .expect("a chunk with triangles before another");
    let mut bytes = fs::read(&damaged).unwrap();
    bytes[entries[k + 1].offset as usize - 1] ^= 0xff;
    fs::write(&damaged, bytes).unwrap();
    let out = dir.path().join("out");
    fs::create_dir(&out).unwrap();
    let result = merge(&parts, &out.join("{label}.ply"));
    let err = assert_one_line(&result, 1);
    assert!(err.contains("7.3.tmesh"), "{err}");
    assert!(names(&out).is_empty(), "{:?}", names(&out));
}

/// Output directories whose names are no UTF-8 (tmc passes the bytes on).
#[cfg(unix)]
#[test]
fn names_that_are_no_utf8_are_kept_with_placeholders() {
    use std::ffi::{OsStr, OsString};
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let input = two_labels(dir.path());
    let odd = dir.path().join(OsStr::from_bytes(b"nu\xffd"));
    fs::create_dir(&odd).unwrap();
    let run = |args: Vec<OsString>| {
        let out = std::process::Command::new(common::cli::tmc_path())
            .args(&args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
    };
    let os = |a: &str| OsString::from(a);
    run(vec![
        os("extract"),
        input.clone().into_os_string(),
        os("--labels"),
        os("all"),
        os("-q"),
        os("-o"),
        odd.join("{stem}_{label}.ply").into_os_string(),
    ]);
    run(vec![
        os("extract"),
        input.into_os_string(),
        os("--iso"),
        os("2.5,5.5"),
        os("-q"),
        os("-o"),
        odd.join("m.ply").into_os_string(),
    ]);
    assert_eq!(
        names(&odd),
        ["m_iso2.5.ply", "m_iso5.5.ply", "map_3.ply", "map_7.ply"]
    );
}

#[test]
fn a_merge_into_a_file_per_label_does_not_write_over_a_part() {
    let (_dir, parts) = parts_of_two_labels();
    let before: Vec<Vec<u8>> = names(&parts)
        .iter()
        .map(|n| fs::read(parts.join(n)).unwrap())
        .collect();
    let err = assert_one_line(&merge(&parts, &parts.join("{label}.2.tmesh")), 1);
    assert!(err.contains("the output is the input file"), "{err}");
    let after: Vec<Vec<u8>> = names(&parts)
        .iter()
        .map(|n| fs::read(parts.join(n)).unwrap())
        .collect();
    assert_eq!(before, after);
}

#[test]
fn label_without_labels_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = two_labels(dir.path());
    for out in ["{label}.ply", "{stem}_{label}_{iso}.ply"] {
        let out = dir.path().join(out);
        let args = ["extract", s(&input), "--iso", "2.5", "-o", s(&out), "-q"];
        let err = assert_one_line(&tmc(&args), 1);
        assert!(err.contains("{label}") && err.contains("--labels"), "{err}");
        assert_eq!(names(dir.path()), ["map.nrrd"]);
    }
}

/// An output name no label's file could take (a missing directory, an
/// unknown format) is refused before the map is read: a map whose first
/// reading fails (a sample 1.5) gets the output's error, not the map's
/// (the labels are known only after that reading, and the name was
/// checked only then: minutes into a large map).
#[test]
fn a_label_output_that_cannot_be_written_is_refused_before_the_map_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut values = vec![0.0; 64];
    values[21] = 1.5;
    let input = d.join("bad.nrrd");
    write(&input, [4, 4, 4], values, ScalarType::F32);
    for (out, words) in [
        ("nodir/{label}.ply", "output directory"),
        ("{label}.xyz", "unknown output format"),
        ("{stem}_{label}.xyz", "unknown output format"),
    ] {
        let out = d.join(out);
        let args = ["extract", s(&input), "--labels", "all", "-o", s(&out), "-q"];
        let err = assert_one_line(&tmc(&args), 1);
        assert!(err.contains(words) && !err.contains("1.5"), "{err}");
    }
    // A listed label one file's uint32 'label' cannot hold: known from
    // the list, refused before the map is read too.
    for (list, out) in [
        ("--labels=-5", "one.ply"),
        ("--labels=3,4294967296", "one.tmesh"),
    ] {
        let out = d.join(out);
        let err = assert_one_line(&tmc(&["extract", s(&input), list, "-o", s(&out)]), 1);
        assert!(
            err.contains("does not fit the uint32") && !err.contains("1.5"),
            "{err}"
        );
    }
    // {label} in the directory: the directories are the labels'.
    let out = d.join("{label}/m.ply");
    let args = ["extract", s(&input), "--labels", "all", "-o", s(&out), "-q"];
    let err = assert_one_line(&tmc(&args), 1);
    assert!(err.contains("1.5"), "{err}");
    assert_eq!(names(d), ["bad.nrrd"]);
}
