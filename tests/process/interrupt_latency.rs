//! Interrupts that answer at any density: SIGINT, SIGTERM and SIGHUP stop
//! `tmc extract`, `merge`, `convert`, `synth`, `info` and a batch with
//! status 130, 143 or 129, one line on stderr and nothing left in the output
//! directory (no output, no temporary file), whatever the thread count and
//! slab depth, on the densest input there is: uniform noise cut at its
//! median, where every cell is crossed and most are ambiguous.
//!
//! The target is 0.5 s from the signal to the exit. A timed assertion on a
//! shared 2-core machine is fragile, so each test asserts a generous
//! [`BOUND`] and prints the measured times (`--nocapture`); the medians are
//! in docs/robustness.md, with the command that measured them.

use crate::common;

use common::cli::{s, tmc};
use common::signals::{
    interrupt_and_check, median, out_dir, signal, spawn, still_running_after, wait_for_temp,
};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

/// Seconds a run may take to exit after the signal, in these tests (the
/// target is 0.5 s; see the module documentation).
const BOUND: f64 = 2.0;

/// The dense case of issue 30: 768 x 768 x 256 `u16` samples.
const DENSE: &str = "768,768,256";

/// One run at a time: the timings must not compete for the cores.
static SERIAL: Mutex<()> = Mutex::new(());

/// Writes `planes` planes of 768 x 768 `u16` uniform noise in `[0, 1000)`
/// (a xorshift generator, so every run writes the same bytes) to `path`.
fn write_noise(path: &Path, planes: usize) {
    let mut out = BufWriter::new(File::create(path).unwrap());
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..768 * 768 * planes {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        out.write_all(&((state % 1000) as u16).to_le_bytes())
            .unwrap();
    }
    out.flush().unwrap();
}

/// The noise volumes, written once per test run into a directory under
/// cargo's scratch directory for integration tests (`target/tmp`), which
/// the next run empties first: a static `TempDir` is never dropped, and
/// left about 1 GB in the system's temporary directory after every run.
struct Volumes {
    dir: PathBuf,
    /// The dense case (288 MiB).
    dense: PathBuf,
    /// Its first 13 planes.
    thin: PathBuf,
}

/// The noise volumes (see [`Volumes`]).
fn volumes() -> &'static Volumes {
    static VOLUMES: OnceLock<Volumes> = OnceLock::new();
    VOLUMES.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("interrupt-latency");
        if dir.exists() {
            fs::remove_dir_all(&dir).unwrap();
        }
        fs::create_dir_all(&dir).unwrap();
        let (dense, thin) = (dir.join("dense.raw"), dir.join("thin.raw"));
        write_noise(&dense, 256);
        write_noise(&thin, 13);
        Volumes { dir, dense, thin }
    })
}

/// The arguments that read `path` as raw `u16` samples of `dims` at
/// isovalue 500 (the median: the densest surface).
fn noise_args<'a>(path: &'a Path, dims: &'a str) -> Vec<&'a str> {
    vec![s(path), "--dims", dims, "--dtype", "u16", "--iso", "500"]
}

/// The three signals and their exit statuses.
const SIGNALS: [(&str, i32); 3] = [("INT", 130), ("TERM", 143), ("HUP", 129)];

/// Runs `args` once per signal (output `output_name` in a fresh directory),
/// interrupts each run `after` seconds in, checks the clean end and
/// returns the times from signal to exit.
fn each_signal(args: &[&str], output_name: &str, after: f64) -> Vec<f64> {
    SIGNALS
        .iter()
        .map(|&(name, code)| {
            let (dir, output) = out_dir(output_name);
            let mut full = args.to_vec();
            full.extend(["-o", s(&output)]);
            let mut child = spawn(&full);
            still_running_after(&mut child, after);
            interrupt_and_check(child, (name, code), None, BOUND, (dir.path(), &[]))
        })
        .collect()
}

/// Prints the times of `what` and their median.
fn report(what: &str, times: &[f64]) {
    let list: Vec<String> = times.iter().map(|t| format!("{t:.3}")).collect();
    println!(
        "{what}: signal to exit {} s (median {:.3} s)",
        list.join(", "),
        median(times.to_vec())
    );
}

#[test]
fn the_dense_case_stops_at_one_thread() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut args = vec!["extract"];
    args.extend(noise_args(&volumes().dense, DENSE));
    args.extend(["--threads", "1"]);
    let times = each_signal(&args, "mesh.tmesh", 1.0);
    report("extract, dense, 1 thread, .tmesh", &times);
}

#[test]
fn the_dense_case_stops_at_two_threads_and_any_slab_depth() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    for (depth, output) in [("1", "mesh.obj"), ("64", "mesh.ply")] {
        let mut args = vec!["extract"];
        args.extend(noise_args(&volumes().dense, DENSE));
        args.extend(["--threads", "2", "--slab-depth", depth]);
        let times = each_signal(&args, output, 1.5);
        report(&format!("extract, dense, 2 threads, depth {depth}"), &times);
    }
}

#[test]
fn a_batch_of_several_isovalues_stops_within_its_item() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut args = vec!["extract"];
    args.extend(noise_args(&volumes().dense, DENSE));
    args.extend(["--iso", "300", "--threads", "1"]);
    let times = each_signal(&args, "{iso}.ply", 1.0);
    report("batch, dense, isovalues 500 and 300", &times);
}

#[test]
fn info_stops_within_its_passes() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dense = &volumes().dense;
    // The 288 MiB read as bytes: twice the samples, a few seconds of work.
    let args = ["info", s(dense), "--dims", "768,768,512", "--dtype", "u8"];
    let times: Vec<f64> = SIGNALS
        .iter()
        .map(|&(name, code)| {
            let dir = tempfile::tempdir().unwrap();
            let mut child = spawn(&args);
            still_running_after(&mut child, 0.3);
            interrupt_and_check(child, (name, code), None, BOUND, (dir.path(), &[]))
        })
        .collect();
    report("info, dense as u8", &times);
}

/// The mesh of the first 13 planes of the dense noise as one `.tmesh` and
/// as two part files (about 250 MB each way).
fn thin_meshes() -> &'static (PathBuf, [PathBuf; 2]) {
    static MESHES: OnceLock<(PathBuf, [PathBuf; 2])> = OnceLock::new();
    MESHES.get_or_init(|| {
        let dir = &volumes().dir;
        let whole = dir.join("thin.tmesh");
        let parts = [dir.join("part1.tmesh"), dir.join("part2.tmesh")];
        let jobs = [
            (&whole, None),
            (&parts[0], Some("1/2")),
            (&parts[1], Some("2/2")),
        ];
        for (output, part) in jobs {
            let mut args = vec!["extract"];
            args.extend(noise_args(&volumes().thin, "768,768,13"));
            args.extend(["-o", s(output), "--quiet"]);
            if let Some(part) = part {
                args.extend(["--part", part]);
            }
            let out = tmc(&args);
            assert!(out.status.success(), "{out:?}");
        }
        (whole, parts)
    })
}

#[test]
fn convert_and_merge_of_a_dense_mesh_stop() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (whole, [one, two]) = thin_meshes();
    for output in ["mesh.obj", "mesh.ply"] {
        let times = each_signal(&["convert", s(whole)], output, 1.0);
        report(&format!("convert, dense, to {output}"), &times);
        let times = each_signal(&["merge", s(two), s(one)], output, 1.0);
        report(&format!("merge, dense, to {output}"), &times);
    }
}

#[test]
fn synth_stops_within_its_planes() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut times = Vec::new();
    for (name, code) in SIGNALS {
        let (dir, output) = out_dir("head.nrrd");
        // 1 GiB of f64 head phantom in planes of 8 MiB.
        let mut child = spawn(&[
            "synth",
            "head",
            "--dims",
            "1024,1024,128",
            "--dtype",
            "f64",
            "-q",
            "-o",
            s(&output),
        ]);
        wait_for_temp(&mut child, dir.path(), 16 << 20);
        times.push(interrupt_and_check(
            child,
            (name, code),
            None,
            BOUND,
            (dir.path(), &[]),
        ));
    }
    report("synth head 1024x1024x128 f64", &times);
}

/// A second signal while the first is being answered exits at once, and
/// still leaves nothing behind (the temporary output is removed by the
/// handler if the run has not removed it yet).
#[test]
fn a_second_signal_stops_at_once_and_leaves_nothing() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, output) = out_dir("mesh.ply");
    let mut args = vec!["extract"];
    args.extend(noise_args(&volumes().dense, DENSE));
    args.extend(["--threads", "1", "-o", s(&output)]);
    let mut child = spawn(&args);
    wait_for_temp(&mut child, dir.path(), 0);
    still_running_after(&mut child, 0.5);
    let sent = Instant::now();
    signal(&child, "INT");
    signal(&child, "INT");
    let out = child.wait_with_output().unwrap();
    let took = sent.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("two SIGINTs -> exit after {took:.3} s: {stderr}");
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    // Whichever came first: the run's own clean stop, or the handler's.
    assert!(
        [
            "tmc: error: interrupted by SIGINT; no output was written",
            "tmc: error: interrupted twice; stopped at once, the output in progress was removed",
        ]
        .contains(&stderr.trim_end()),
        "{stderr}"
    );
    assert!(took < BOUND, "took {took:.3} s");
    assert_eq!(common::cli::names(dir.path()), Vec::<String>::new());
}
