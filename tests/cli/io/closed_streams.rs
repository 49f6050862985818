//! A closed stdout pipe, a report that cannot be written, a full stderr:
//! what the binary does when its own streams fail.

use super::tmc_ok;
use crate::common;
use crate::common::cli::{names, s, sphere_npy};
use std::fs;
use std::path::Path;

/// Runs `tmc args` with its stdout a pipe whose reading end is already
/// closed, so that its first write fails with EPIPE (as under `| head -1`
/// once head has its line).
fn tmc_into_closed_pipe(args: &[&str]) -> std::process::Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    std::process::Command::new(common::cli::tmc_path())
        .args(args)
        .stdout(writer)
        .output()
        .unwrap()
}

#[test]
fn a_closed_stdout_pipe_ends_the_run_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [8, 8, 8]);
    let mesh = dir.path().join("m.tmesh");
    tmc_ok(&["extract", s(&input), "--iso", "0", "-q", "-o", s(&mesh)]);
    let json_mesh = dir.path().join("j.ply");
    for args in [
        &["check", s(&mesh)][..],
        &["check", s(&mesh), "--json"],
        &["info", s(&input)],
        &["info", s(&input), "--json"],
        &[
            "extract",
            s(&input),
            "--iso",
            "0",
            "-q",
            "--json",
            "-o",
            s(&json_mesh),
        ],
        &["--help"],
        &["--version"],
    ] {
        let out = tmc_into_closed_pipe(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
    }
    // The mesh of a run that succeeded stays.
    assert!(json_mesh.exists());
}

#[test]
fn a_report_that_cannot_be_written_fails_the_run_and_takes_the_mesh_back() {
    let Some(full) = dev_full() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [8, 8, 8]);
    let i = s(&input);
    for (name, args, to_full) in [
        ("jj.tmesh", vec!["--json"], true),
        ("jp.ply", vec!["--json"], true),
        ("kk.tmesh", vec!["--report", "/dev/full"], false),
        ("kb.tmesh", vec!["--report", "/dev/full", "--json"], false),
    ] {
        let output = dir.path().join(name);
        let mut command = std::process::Command::new(common::cli::tmc_path());
        command
            .args(["extract", i, "--iso", "0", "-q", "-o", s(&output)])
            .args(&args);
        if to_full {
            command.stdout(full.try_clone().unwrap());
        }
        let out = command.output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        assert!(
            stderr.starts_with("tmc: error: ") && stderr.contains("No space left on device"),
            "{name}: {stderr}"
        );
        assert!(
            stderr.contains(&format!("removed the output {}", output.display())),
            "{name}: {stderr}"
        );
        assert!(!output.exists(), "{name} stayed");
    }
    assert_eq!(names(dir.path()), vec!["in.npy".to_string()]);
}

/// `/dev/full` open for writing (every write fails with ENOSPC); `None`,
/// saying that the test is skipped, where there is none.
fn dev_full() -> Option<fs::File> {
    let full = fs::OpenOptions::new().write(true).open("/dev/full").ok();
    if full.is_none() {
        eprintln!("skipped: no /dev/full on this system");
    }
    full
}

/// Runs `tmc args` with its stderr on `/dev/full`, where every write fails
/// with ENOSPC; `None` where there is no `/dev/full`.
fn tmc_with_full_stderr(args: &[&str]) -> Option<std::process::Output> {
    let full = fs::OpenOptions::new().write(true).open("/dev/full").ok()?;
    let out = std::process::Command::new(common::cli::tmc_path())
        .args(args)
        .stderr(full)
        .output()
        .unwrap();
    Some(out)
}

#[test]
fn a_full_stderr_loses_lines_but_not_the_exit_status() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere_npy(dir.path(), "in.npy", [8, 8, 8]);
    let (i, missing) = (s(&input), dir.path().join("missing.npy"));
    let (mesh, empty, stats, volume) = (
        dir.path().join("m.ply"),
        dir.path().join("e.ply"),
        dir.path().join("s.ply"),
        dir.path().join("v.nrrd"),
    );
    // (arguments, exit status, the file that must exist afterwards)
    let lines = dir.path().join("l.ply");
    let cases: [(Vec<&str>, i32, Option<&Path>); 7] = [
        // An error line that cannot be written: still status 1.
        (
            vec!["extract", s(&missing), "--iso", "0", "-o", s(&mesh)],
            1,
            None,
        ),
        // A usage error: still status 2.
        (vec!["extract", i, "--iso", "x", "-o", s(&mesh)], 2, None),
        // The note of an empty mesh is lost; the mesh stays.
        (
            vec!["extract", i, "--iso", "1e9", "-o", s(&empty)],
            0,
            Some(&empty),
        ),
        // The summary of synth is lost; the volume stays.
        (
            vec![
                "synth",
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&volume),
            ],
            0,
            Some(&volume),
        ),
        // --stats is a report: it fails the run and takes the mesh back.
        (
            vec!["extract", i, "--iso", "0", "--stats", "-o", s(&stats)],
            1,
            None,
        ),
        // The note of tmc check on an empty mesh is lost.
        (vec!["check", s(&empty)], 0, None),
        // Progress lines are lost; the mesh stays.
        (
            vec![
                "extract",
                i,
                "--iso",
                "0",
                "--progress",
                "lines",
                "-o",
                s(&lines),
            ],
            0,
            Some(&lines),
        ),
    ];
    for (args, code, stays) in cases {
        let Some(out) = tmc_with_full_stderr(&args) else {
            eprintln!("skipped: no /dev/full on this system");
            return;
        };
        assert_eq!(out.status.code(), Some(code), "{args:?}");
        if let Some(path) = stays {
            assert!(path.exists(), "{args:?}: {} is missing", path.display());
        }
    }
    assert!(!stats.exists(), "the --stats run left its mesh");
    let mut left = names(dir.path());
    left.sort();
    assert_eq!(left, ["e.ply", "in.npy", "l.ply", "v.nrrd"]);
}

/// A `--preview` picture is an output too: a report that cannot be
/// written takes it back with the meshes (it stayed, for one input, a
/// label map and a batch).
#[test]
fn a_report_that_cannot_be_written_takes_the_picture_back_too() {
    let Some(full) = dev_full() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = sphere_npy(d, "in.npy", [8, 8, 8]);
    let other = sphere_npy(d, "other.npy", [9, 8, 7]);
    let seg = d.join("seg.nrrd");
    let dims = [12, 10, 9];
    let values = crate::common::labels::label_map(dims, 4, 3);
    crate::common::labels::write(&seg, dims, values, tmc::volume::ScalarType::U16);
    let before = names(d);
    let at = |name: &str| s(&d.join(name)).to_string();
    let (i, o, seg) = (s(&input), s(&other), s(&seg));
    let (mesh, labels, picture, pictures) = (
        at("{stem}.ply"),
        at("{label}.ply"),
        at("p.png"),
        at("{stem}.png"),
    );
    let one = ["--iso", "0", "-o", &mesh, "--preview", &picture];
    let map = ["--labels", "all", "-o", &labels, "--preview", &picture];
    let batch = ["--iso", "0", "-o", &mesh, "--preview", &pictures];
    // (arguments, the stream on /dev/full: stdout for --json, stderr for
    // --stats, none for --report /dev/full)
    let cases: [(Vec<&str>, Option<bool>); 6] = [
        ([&[i][..], &one, &["--json"]].concat(), Some(true)),
        ([&[i][..], &one, &["--stats"]].concat(), Some(false)),
        ([&[seg][..], &map, &["--json"]].concat(), Some(true)),
        ([&[seg][..], &map, &["--stats"]].concat(), Some(false)),
        ([&[i, o][..], &batch, &["--json"]].concat(), Some(true)),
        (
            [&[i, o][..], &batch, &["--report", "/dev/full"]].concat(),
            None,
        ),
    ];
    for (args, on_full) in cases {
        let mut command = std::process::Command::new(common::cli::tmc_path());
        command.arg("extract").args(&args);
        match on_full {
            Some(true) => command.stdout(full.try_clone().unwrap()),
            Some(false) => command.stderr(full.try_clone().unwrap()),
            None => &mut command,
        };
        let out = command.output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        if on_full != Some(false) {
            assert!(
                stderr.contains("removed the output") && stderr.contains(".png"),
                "{args:?}: {stderr}"
            );
        }
        assert_eq!(names(d), before, "{args:?} left files");
    }
}
