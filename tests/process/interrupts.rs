//! Interrupting a long extraction: SIGINT and SIGTERM stop it within a
//! second or two with status 130 or 143 and leave nothing behind; SIGKILL
//! leaves at most a temporary file, never a file at the output path; an
//! input truncated under the memory map is one clean error, never a crash.
//! The library's cancel flag returns `Error::Interrupted`.

use crate::common;

use common::cli::{names, s, temp_files, tmc, tmc_path};
use common::signals::{
    interrupt_and_check, out_dir, signal, spawn, still_running_after, wait_for_temp, wait_until,
};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::AtomicBool;
use std::sync::{Mutex, OnceLock};
use std::thread::sleep;
use std::time::{Duration, Instant};

/// Samples per axis of the test volume: 600^3 u8 value noise takes several
/// seconds to extract on one thread (about 5 s on the 2-core test machine).
const N: usize = 600;

/// One extraction at a time: the timings must not compete for the cores.
static SERIAL: Mutex<()> = Mutex::new(());

/// A directory holding `noise.raw`, made once and kept under cargo's
/// scratch directory for integration tests (`target/tmp`), so that runs
/// reuse it and none leaves 216 MB behind in the system's temporary
/// directory (a static `TempDir` is never dropped). tmc writes its outputs
/// whole or not at all, so a file of the right size is a finished one.
fn volume() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("interrupts-noise-{N}"));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("noise.raw");
        let made = fs::metadata(&path).is_ok_and(|m| m.len() == (N * N * N) as u64);
        if !made {
            let dims = format!("{N},{N},{N}");
            let out = tmc(&[
                "synth",
                "noise",
                "--dims",
                &dims,
                "--dtype",
                "u8",
                "-o",
                s(&path),
                "--quiet",
            ]);
            assert!(out.status.success(), "{out:?}");
        }
        dir
    })
}

/// Starts `tmc extract` of `input` (the noise volume's layout) into
/// `output` on one thread.
fn start(input: &Path, output: &Path) -> Child {
    start_command("extract", input, &["-o", s(output)])
}

/// Starts `tmc COMMAND input` with the noise volume's layout, its
/// isovalue and one thread, then `extra`.
fn start_command(command: &str, input: &Path, extra: &[&str]) -> Child {
    let dims = format!("{N},{N},{N}");
    let mut args = vec![
        command,
        s(input),
        "--dims",
        &dims,
        "--dtype",
        "u8",
        "--iso",
        "127.5",
        "--threads",
        "1",
    ];
    args.extend(extra);
    spawn(&args)
}

/// Sends `name` to `child` and checks the clean end within 2 s, nothing
/// left in `dir` (see [`interrupt_and_check`]).
fn stop(child: Child, name: &str, code: i32, dir: &Path) {
    interrupt_and_check(child, (name, code), None, 2.0, (dir, &[]));
}

#[test]
fn sigint_and_sigterm_stop_the_extraction_and_remove_the_output() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    for (name, code, output_name) in [
        ("INT", 130, "mesh.ply"),
        ("TERM", 143, "mesh.ply"),
        ("INT", 130, "mesh.tmesh"),
    ] {
        let (dir, output) = out_dir(output_name);
        let mut child = start(&input, &output);
        still_running_after(&mut child, 0.5);
        stop(child, name, code, dir.path());
    }
}

#[test]
fn sigint_stops_an_extraction_with_a_preview_and_leaves_neither_file() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    let (dir, output) = out_dir("mesh.tmesh");
    let picture = dir.path().join("mesh.png");
    let mut child = start_command(
        "extract",
        &input,
        &["-o", s(&output), "--preview", s(&picture)],
    );
    still_running_after(&mut child, 0.5);
    stop(child, "INT", 130, dir.path());
}

#[test]
fn sigint_stops_compare() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    let dir = tempfile::tempdir().unwrap();
    let mut child = start_command("compare", &input, &["--runs", "1000", "-q"]);
    still_running_after(&mut child, 0.5);
    stop(child, "INT", 130, dir.path());
}

#[test]
fn sigkill_never_leaves_a_file_at_the_output_path() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    let (dir, output) = out_dir("mesh.ply");
    let mut child = start(&input, &output);
    still_running_after(&mut child, 0.5);
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!output.exists());
    // At most the temporary file of the atomic output.
    let left = names(dir.path());
    assert!(left.len() <= 1, "{left:?}");
    assert_eq!(temp_files(dir.path()), left);
}

#[test]
fn an_input_truncated_during_the_extraction_is_a_clean_error() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, output) = out_dir("mesh.tmesh");
    let input = dir.path().join("shrinking.raw");
    fs::copy(volume().join("noise.raw"), &input).unwrap();
    let child = start(&input, &output);
    truncate_while_running(child, &input, dir.path(), &output);
}

#[test]
fn a_metaimage_data_file_truncated_during_the_extraction_is_a_clean_error() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, output) = out_dir("mesh.ply");
    let data = dir.path().join("shrinking.raw");
    fs::copy(volume().join("noise.raw"), &data).unwrap();
    let header = dir.path().join("noise.mhd");
    fs::write(
        &header,
        format!(
            "ObjectType = Image\nNDims = 3\nDimSize = {N} {N} {N}\nElementType = MET_UCHAR\nElementDataFile = shrinking.raw\n"
        ),
    )
    .unwrap();
    let child = spawn(&[
        "extract",
        s(&header),
        "--iso",
        "127.5",
        "--threads",
        "1",
        "-o",
        s(&output),
    ]);
    truncate_while_running(child, &data, dir.path(), &output);
}

/// Truncates `data` to 1000 bytes 0.3 s into the extraction `child` (of
/// the noise volume into `output` in `dir`), then checks the clean end:
/// exit 1, one line (the per-slab check, or the SIGBUS handler), nothing
/// at the output path and no temporary file (both paths remove it).
fn truncate_while_running(mut child: Child, data: &Path, dir: &Path, output: &Path) {
    still_running_after(&mut child, 0.3);
    fs::OpenOptions::new()
        .write(true)
        .open(data)
        .unwrap()
        .set_len(1000)
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("truncated {}: {stderr}", data.display());
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let caught_by_check = stderr.starts_with(&format!(
        "tmc: error: {}: the input file changed during the extraction: it shrank from {} to 1000 bytes",
        data.display(),
        N * N * N
    ));
    let caught_by_sigbus =
        stderr.starts_with("tmc: error: input file changed under the memory map (SIGBUS)");
    assert!(caught_by_check || caught_by_sigbus, "{stderr}");
    assert!(!output.exists());
    assert!(temp_files(dir).is_empty(), "{:?}", names(dir));
}

#[test]
fn the_library_stops_when_its_cancel_flag_is_set() {
    let grid = tmc::Grid::unit([8, 8, 8]);
    let samples: Vec<f32> = (0..512).map(|i| (i % 7) as f32).collect();
    let source = tmc::ArrayVolume::new(grid, samples).unwrap();
    let params = tmc::ExtractParams {
        iso: 3.5,
        ..Default::default()
    };
    for (set, threads) in [(true, 1), (true, 2), (false, 2)] {
        let flag = AtomicBool::new(set);
        let options = tmc::PipelineOptions {
            cancel: Some(&flag),
            slab_depth: 2,
            ..Default::default()
        };
        let mut builder = tmc::MeshBuilder::default();
        let params = tmc::ExtractParams {
            threads,
            ..params.clone()
        };
        let result = tmc::extract_to(&source, &params, &options, &mut builder);
        if set {
            assert!(matches!(result, Err(tmc::Error::Interrupted)), "{result:?}");
        } else {
            assert!(result.unwrap().triangles > 0);
        }
    }
}

#[test]
fn a_mapped_input_that_shrank_is_noticed_before_the_next_slab() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("vol.raw");
    fs::write(&path, vec![7u8; 16 * 16 * 16]).unwrap();
    let options = tmc::volume::RawOptions {
        dims: [16, 16, 16],
        scalar: tmc::volume::ScalarType::U8,
        endian: tmc::volume::Endian::Little,
        header_bytes: 0,
        spacing: [1.0; 3],
        origin: [0.0; 3],
    };
    let source = tmc::volume::RawVolume::open(&path, &options).unwrap();
    use tmc::SampleSource;
    source.check_unchanged().unwrap();
    fs::OpenOptions::new()
        .write(true)
        .open(&path)
        .unwrap()
        .set_len(100)
        .unwrap();
    let expected = format!(
        "{}: the input file changed during the extraction: it shrank from 4096 to 100 bytes",
        path.display()
    );
    let err = source.check_unchanged().unwrap_err().to_string();
    assert!(err.starts_with(&expected), "{err}");
    // The pipeline asks before the first slab reads a plane.
    let mut builder = tmc::MeshBuilder::default();
    let params = tmc::ExtractParams {
        iso: 3.0,
        threads: 1,
        ..Default::default()
    };
    let result = tmc::extract_to(&source, &params, &Default::default(), &mut builder);
    let err = result.unwrap_err().to_string();
    assert!(err.starts_with(&expected), "{err}");
}

#[test]
fn sigint_and_sigterm_stop_a_conversion_or_a_merge_and_remove_the_output() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    // The mesh of 400^3 noise: about 70 MB of .tmesh, some seconds to
    // convert on the test machine.
    let dir = tempfile::tempdir().unwrap();
    let raw = dir.path().join("noise.raw");
    let tmesh = dir.path().join("noise.tmesh");
    for args in [
        &[
            "synth",
            "noise",
            "--dims",
            "400,400,400",
            "--dtype",
            "u8",
            "-o",
            s(&raw),
            "--quiet",
        ][..],
        &[
            "extract",
            s(&raw),
            "--dims",
            "400,400,400",
            "--dtype",
            "u8",
            "--iso",
            "127.5",
            "-o",
            s(&tmesh),
            "--quiet",
        ],
    ] {
        let out = tmc(args);
        assert!(out.status.success(), "{out:?}");
    }
    for (name, code, output_name) in [("INT", 130, "mesh.ply"), ("TERM", 143, "mesh.obj")] {
        let (out_dir, output) = out_dir(output_name);
        let mut child = spawn(&["convert", s(&tmesh), "-o", s(&output)]);
        still_running_after(&mut child, 0.3);
        stop(child, name, code, out_dir.path());
    }
    // The same mesh as two part files, merged.
    let parts: Vec<_> = (1..=2)
        .map(|i| {
            let part = dir.path().join(format!("part{i}.tmesh"));
            let spec = format!("{i}/2");
            let volume = ["--dims", "400,400,400", "--dtype", "u8", "--iso", "127.5"];
            let mut args = vec![
                "extract",
                s(&raw),
                "--part",
                &spec,
                "-o",
                s(&part),
                "--quiet",
            ];
            args.extend_from_slice(&volume);
            let out = tmc(&args);
            assert!(out.status.success(), "{out:?}");
            part
        })
        .collect();
    for (name, code, output_name) in [("INT", 130, "merged.ply"), ("TERM", 143, "merged.obj")] {
        let (out_dir, output) = out_dir(output_name);
        let mut child = spawn(&["merge", s(&parts[0]), s(&parts[1]), "-o", s(&output)]);
        still_running_after(&mut child, 0.3);
        stop(child, name, code, out_dir.path());
    }
}

#[test]
fn sighup_stops_the_extraction_like_sigterm() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    let (dir, output) = out_dir("mesh.ply");
    let mut child = start(&input, &output);
    wait_for_temp(&mut child, dir.path(), 0);
    still_running_after(&mut child, 0.2);
    stop(child, "HUP", 129, dir.path());
}

#[test]
fn signals_inherited_as_ignored_stay_ignored() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let input = volume().join("noise.raw");
    let (dir, output) = out_dir("mesh.tmesh");
    let dims = format!("{N},{N},{N}");
    // As `tmc ... &` in a script (SIGINT) and under nohup (SIGHUP): the
    // shell ignores them and exec keeps them ignored.
    let mut child = Command::new("sh")
        .args(["-c", "trap '' INT HUP; exec \"$0\" \"$@\""])
        .arg(tmc_path())
        .args(["extract", s(&input), "--dims", &dims, "--dtype", "u8"])
        .args(["--iso", "127.5", "--threads", "1", "-o", s(&output)])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sh");
    wait_for_temp(&mut child, dir.path(), 0);
    signal(&child, "INT");
    signal(&child, "HUP");
    // Still running: they were ignored; SIGTERM still stops it cleanly.
    still_running_after(&mut child, 0.3);
    stop(child, "TERM", 143, dir.path());
}

#[test]
fn sigint_and_sighup_stop_synth_and_remove_the_output() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    for (name, code) in [("INT", 130), ("HUP", 129)] {
        let (dir, output) = out_dir("s.nrrd");
        // 256 MiB of f32 noise: a few seconds on the test machine.
        let mut child = spawn(&[
            "synth",
            "noise",
            "--dims",
            "512,512,256",
            "--dtype",
            "f32",
            "-q",
            "-o",
            s(&output),
        ]);
        // The header and the first planes are written.
        wait_for_temp(&mut child, dir.path(), 1 << 20);
        stop(child, name, code, dir.path());
    }
}

/// A FIFO with nobody at the other end as `--manifest` (read) or
/// `--report` (written): the run waits, as a shell redirection would, but
/// SIGTERM and SIGINT stop it at once with the interrupted line, and no
/// output appears. (A FIFO as a `.tmesh` input is refused outright; see
/// `tests/formats/bad_inputs.rs`.)
#[cfg(unix)]
#[test]
fn a_fifo_manifest_or_report_waits_but_signals_stop_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = |name: &str| {
        let path = d.join(name);
        let made = Command::new("mkfifo").arg(&path).status().unwrap();
        assert!(made.success());
        path
    };
    let (manifest, report) = (fifo("manifest"), fifo("report"));
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd");
    let output = d.join("out.ply");
    let runs: [(Vec<&str>, &str, i32); 2] = [
        (vec!["extract", "--manifest", s(&manifest)], "TERM", 143),
        (
            vec![
                "extract",
                s(&input),
                "--iso",
                "500",
                "-o",
                s(&output),
                "--report",
                s(&report),
            ],
            "INT",
            130,
        ),
    ];
    for (args, name, code) in runs {
        let mut child = spawn(&args);
        still_running_after(&mut child, 0.5);
        let sent = Instant::now();
        signal(&child, name);
        let out = child.wait_with_output().unwrap();
        let took = sent.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert_eq!(
            stderr.trim_end(),
            format!("tmc: error: interrupted by SIG{name}; no output was written")
        );
        assert!(took < 2.0, "{args:?}: took {took:.3} s to exit");
        assert!(!output.exists());
        assert_eq!(names(d), ["manifest", "report"]);
    }
}

/// A batch stopped by SIGTERM during its second input keeps the first
/// input's finished output, writes nothing of the second, and its line says
/// so (not "no output was written").
#[cfg(unix)]
#[test]
fn a_batch_interrupted_after_an_input_keeps_that_output_and_says_so() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, _) = out_dir("unused");
    let d = dir.path();
    let input = volume().join("noise.raw");
    let second = d.join("again.raw");
    std::os::unix::fs::symlink(&input, &second).unwrap();
    let dims = format!("{N},{N},{N}");
    let template = d.join("{stem}.tmesh");
    let mut child = spawn(&[
        "extract",
        s(&input),
        s(&second),
        "--dims",
        &dims,
        "--dtype",
        "u8",
        "--iso",
        "127.5",
        "--threads",
        "1",
        "-o",
        s(&template),
    ]);
    let first = d.join("noise.tmesh");
    let started = Instant::now();
    while !first.exists() {
        assert!(child.try_wait().unwrap().is_none(), "the batch ended early");
        assert!(
            started.elapsed().as_secs() < 120,
            "the first input never finished"
        );
        sleep(Duration::from_millis(20));
    }
    still_running_after(&mut child, 0.3);
    signal(&child, "TERM");
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "{stderr}");
    assert_eq!(
        stderr.trim_end(),
        "tmc: error: interrupted by SIGTERM; the outputs of the 1 input(s) that finished before it are kept, nothing else was written"
    );
    assert_eq!(names(d), ["again.raw", "noise.tmesh"]);
}

/// A label map in `dir`, 256 x 256 x 400 `u8`. Label 1: a block in planes
/// 2 to 5, whose file is finished early in the pass. Label 2: noise (a
/// sample in two) in every plane from 8 on, whose surface takes the pass
/// seconds on one thread.
fn early_and_late_labels(dir: &Path) -> PathBuf {
    let map = dir.join("map.raw");
    let [nx, ny, nz] = [256usize, 256, 400];
    let mut bytes = vec![0u8; nx * ny * nz];
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for (i, b) in bytes.iter_mut().enumerate() {
        let [x, y, z] = [i % nx, i / nx % ny, i / (nx * ny)];
        if (2..6).contains(&z) && (10..30).contains(&x) && (10..30).contains(&y) {
            *b = 1;
        } else if z >= 8 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            *b = if state >> 63 == 1 { 2 } else { 0 };
        }
    }
    fs::write(&map, &bytes).unwrap();
    map
}

/// Starts a label pass of `map` (see [`early_and_late_labels`]) on one
/// thread and waits until label 1's file is in place while the pass goes
/// on; `earlier`, if given, is first written to `1.tmesh` and `2.tmesh`
/// (an earlier run's files, which the pass replaces).
fn start_labels_until_label_1(map: &Path, earlier: Option<&[u8]>) -> (tempfile::TempDir, Child) {
    let (dir, output) = out_dir("{label}.tmesh");
    for name in ["1.tmesh", "2.tmesh"] {
        if let Some(bytes) = earlier {
            fs::write(dir.path().join(name), bytes).unwrap();
        }
    }
    let mut child = spawn(&[
        "extract",
        s(map),
        "--dims",
        "256,256,400",
        "--dtype",
        "u8",
        "--labels",
        "all",
        "-o",
        s(&output),
        "--threads",
        "1",
    ]);
    let early = dir.path().join("1.tmesh");
    wait_until(&mut child, "label 1's file", || {
        fs::read(&early).is_ok_and(|b| Some(b.as_slice()) != earlier)
    });
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run finished before the test could interrupt it; use a larger input"
    );
    (dir, child)
}

/// A label pass finishes each label's file as soon as the pass is past the
/// label's last plane (`LabelFiles::finish_early`): interrupted after such
/// a file is in place, it removes it again, and leaves nothing.
#[test]
fn sigint_stops_a_label_pass_and_takes_back_the_files_finished_during_it() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let data = tempfile::tempdir().unwrap();
    let (dir, child) = start_labels_until_label_1(&early_and_late_labels(data.path()), None);
    interrupt_and_check(child, ("INT", 130), None, 2.0, (dir.path(), &[]));
}

/// The same, run into a directory holding an earlier run's files: label
/// 1's new file replaced the earlier one during the pass; interrupted, the
/// run puts the earlier file back (it removed it before: data lost).
#[test]
fn sigint_in_a_label_pass_puts_back_the_earlier_files_it_replaced() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let data = tempfile::tempdir().unwrap();
    let earlier = b"an earlier run's mesh";
    let map = early_and_late_labels(data.path());
    let (dir, child) = start_labels_until_label_1(&map, Some(earlier));
    let keep = ["1.tmesh", "2.tmesh"];
    interrupt_and_check(child, ("INT", 130), None, 2.0, (dir.path(), &keep));
    for name in keep {
        assert_eq!(fs::read(dir.path().join(name)).unwrap(), earlier, "{name}");
    }
}
