//! Running the built `tmc` binary from integration tests: the command, the
//! one-line error check, small input files and directory listings.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Writes a volume with `tmc synth KIND --dims DIMS --dtype DTYPE` (seed 0)
/// at `dir/name` and returns its path.
pub fn synth(dir: &Path, kind: &str, dims: &str, dtype: &str, name: &str) -> PathBuf {
    let path = dir.join(name);
    let out = tmc(&[
        "synth",
        kind,
        "--dims",
        dims,
        "--dtype",
        dtype,
        "-o",
        s(&path),
        "-q",
    ]);
    assert!(out.status.success(), "{out:?}");
    path
}

/// Runs the built `tmc` with `args`.
pub fn tmc(args: &[&str]) -> Output {
    Command::new(tmc_path())
        .args(args)
        .output()
        .expect("run tmc")
}

/// Asserts exit status `code`, nothing on stdout and exactly one
/// `tmc: ...` line on stderr; returns that line.
pub fn assert_one_line(out: &Output, code: i32) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "stderr: {stderr}");
    assert!(out.stdout.is_empty(), "stdout not empty");
    assert_eq!(stderr.lines().count(), 1, "not one line: {stderr:?}");
    assert!(
        stderr.starts_with("tmc: error: "),
        "no 'tmc: error: ' prefix: {stderr:?}"
    );
    stderr.trim_end().to_string()
}

/// The bytes of a version 1.0 `.npy` header holding the dictionary `dict`
/// (padded so the data starts at a multiple of 64).
pub fn npy_header(dict: &str) -> Vec<u8> {
    let mut header = dict.to_string();
    while !(10 + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes
}

/// Writes a little-endian f32 `.npy` of a sphere's distance field (shape
/// `(nz, ny, nx)`), positive inside.
pub fn sphere_npy(dir: &Path, name: &str, dims: [usize; 3]) -> PathBuf {
    let [nx, ny, nz] = dims;
    let mut bytes = npy_header(&format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    let c = |n: usize| (n as f32 - 1.0) / 2.0;
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let d = ((x as f32 - c(nx)).powi(2)
                    + (y as f32 - c(ny)).powi(2)
                    + (z as f32 - c(nz)).powi(2))
                .sqrt();
                bytes.extend_from_slice(&(3.0 - d).to_le_bytes());
            }
        }
    }
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    path
}

/// The names in `dir`, sorted.
pub fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// `path` as a `&str`.
pub fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The repository's `scripts/read_tmesh.py`.
pub fn read_tmesh_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/read_tmesh.py")
}

/// Whether `python3` with numpy and zstandard is available; prints a
/// SKIPPED line when it is not.
pub fn python_ready() -> bool {
    let ready = Command::new("python3")
        .args(["-c", "import numpy, zstandard"])
        .output()
        .is_ok_and(|out| out.status.success());
    if !ready {
        println!(
            "SKIPPED: python3 with numpy and zstandard is not available \
             (python3 -m pip install numpy zstandard)"
        );
    }
    ready
}

/// Runs `python3 scripts/read_tmesh.py MESH`.
pub fn read_tmesh_py(mesh: &Path) -> Output {
    Command::new("python3")
        .arg(read_tmesh_script())
        .arg(mesh)
        .output()
        .expect("run python3")
}

/// Runs `scripts/read_tmesh.py` on `mesh`, asserts exit status 1 and one
/// line on stderr, and returns that line.
pub fn read_tmesh_py_error(mesh: &Path) -> String {
    let out = read_tmesh_py(mesh);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "read_tmesh.py: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "read_tmesh.py: {stderr}");
    stderr
}

/// The built `tmc` binary.
pub fn tmc_path() -> &'static str {
    env!("CARGO_BIN_EXE_tmc")
}

/// Runs the built `tmc` with `args`, killing it and failing the test if it
/// has not exited after `seconds` (a hang is a bug).
pub fn tmc_within(args: &[&str], seconds: u64) -> Output {
    use std::time::{Duration, Instant};
    let mut child = Command::new(tmc_path())
        .args(args)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start tmc");
    let deadline = Instant::now() + Duration::from_secs(seconds);
    while child.try_wait().expect("wait for tmc").is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("tmc {args:?} still running after {seconds} s: it hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("collect tmc output")
}

/// The names in `dir` that are temporary files of tmc's atomic output.
pub fn temp_files(dir: &Path) -> Vec<String> {
    names(dir)
        .into_iter()
        .filter(|n| n.starts_with(".tmc-") && n.ends_with(".tmp"))
        .collect()
}

/// A JSON number field of `--json` output.
pub fn json_number(json: &[u8], key: &str) -> f64 {
    let text = String::from_utf8_lossy(json);
    let needle = format!("\"{key}\":");
    let at = text.find(&needle).expect("key in JSON") + needle.len();
    let digits: String = text[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    digits.parse().unwrap()
}

/// Writes `uniform.npy` in `dir`: `dims` (x fastest) of uniform random
/// `f32` samples in [0, 1), the densest surface at 0.5 (about 3.8
/// triangles a cell).
pub fn uniform_npy(dir: &Path, dims: [usize; 3]) -> PathBuf {
    let [nx, ny, nz] = dims;
    let mut bytes = npy_header(&format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..nx * ny * nz {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        bytes.extend_from_slice(&((state >> 40) as f32 / (1u64 << 24) as f32).to_le_bytes());
    }
    let path = dir.join("uniform.npy");
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `tmc extract` of `input` (at iso 40, with `extra` options) fails with
/// one line holding `words`, and writes nothing.
pub fn refused(input: &Path, extra: &[&str], words: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.ply");
    let mut args = vec!["extract", s(input), "--iso", "40", "-o", s(&out)];
    args.extend_from_slice(extra);
    let line = assert_one_line(&tmc(&args), 1);
    assert!(line.contains(words), "{line}");
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
