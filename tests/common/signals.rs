//! Interrupting a running `tmc` from a test: start it, wait until it is
//! busy, send a signal with kill(1), and check the clean end (status, the
//! one line, nothing left) and how long it took.

use super::cli::{names, temp_files, tmc_path};
use std::ffi::OsStr;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::thread::sleep;
use std::time::{Duration, Instant};

/// A command running `program` with SIGINT, SIGTERM and SIGHUP at their
/// defaults, through GNU `env --default-signal` where it is there (without
/// it, as inherited, saying so once). A test suite started in the
/// background by a shell without job control (`cmd &`, nohup) hands every
/// process SIGINT ignored; tmc keeps a signal it inherits ignored (the
/// nohup convention, cli/signals.rs), and a shell cannot trap one, so the
/// interrupt tests would test nothing there.
pub fn default_signals(program: impl AsRef<OsStr>) -> Command {
    static ENV_RESETS: OnceLock<bool> = OnceLock::new();
    let env_resets = *ENV_RESETS.get_or_init(|| {
        let works = Command::new("env")
            .args(["--default-signal=INT,TERM,HUP", "true"])
            .status()
            .is_ok_and(|s| s.success());
        if !works {
            println!("note: env --default-signal is absent; signals as inherited");
        }
        works
    });
    if env_resets {
        let mut command = Command::new("env");
        command.arg("--default-signal=INT,TERM,HUP").arg(program);
        command
    } else {
        Command::new(program)
    }
}

/// Starts `tmc` with `args` (signals at their defaults, see
/// [`default_signals`]), its stderr captured.
pub fn spawn(args: &[&str]) -> Child {
    default_signals(tmc_path())
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start tmc")
}

/// Sleeps `seconds`, then fails unless `child` is still running (the test
/// would prove nothing if the run had already finished).
pub fn still_running_after(child: &mut Child, seconds: f64) {
    sleep(Duration::from_secs_f64(seconds));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run finished before the test could interrupt it; use a larger input"
    );
}

/// Sends `signal` (a name such as `INT`) to `child` with kill(1).
pub fn signal(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .expect("run kill");
    assert!(status.success());
}

/// Sends `name` (`INT`, `TERM`, `HUP`) to the running `child`, then checks
/// the clean end: exit status `code`, the one line `line` (the plain
/// "interrupted" line when `None`), within `bound` seconds, and nothing
/// left in `dir` but `keep` (no output, no temporary file). Returns the
/// seconds from the signal to the exit.
pub fn interrupt_and_check(
    child: Child,
    (name, code): (&str, i32),
    line: Option<&str>,
    bound: f64,
    (dir, keep): (&Path, &[&str]),
) -> f64 {
    let sent = Instant::now();
    signal(&child, name);
    let out = child.wait_with_output().unwrap();
    let took = sent.elapsed().as_secs_f64();
    println!("SIG{name} -> exit after {took:.3} s ({})", dir.display());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "SIG{name}: {stderr}");
    let plain = format!("tmc: error: interrupted by SIG{name}; no output was written");
    assert_eq!(stderr.trim_end(), line.unwrap_or(&plain));
    assert!(took < bound, "SIG{name}: took {took:.3} s to exit");
    assert_eq!(names(dir), keep, "left behind in {}", dir.display());
    took
}

/// A fresh, empty output directory and the path `name` in it.
pub fn out_dir(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join(name);
    (dir, output)
}

/// Waits until the run `child` has created its temporary output in `dir`
/// (of at least `min_bytes`): it has then installed its signal handlers
/// and is in the phase the caller wants to interrupt. Fails if the run
/// ends first.
pub fn wait_for_temp(child: &mut Child, dir: &Path, min_bytes: u64) {
    wait_until(child, "its temporary output", || {
        temp_files(dir)
            .iter()
            .any(|name| fs::metadata(dir.join(name)).is_ok_and(|m| m.len() >= min_bytes))
    });
}

/// Waits until `ready` says so while the run `child` goes on; fails if the
/// run ends first (without `what`) or after 120 s.
pub fn wait_until(child: &mut Child, what: &str, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it wrote {what}"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no {what} after 120 s"
        );
        sleep(Duration::from_millis(2));
    }
}

/// The median of `times` (not empty).
pub fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
