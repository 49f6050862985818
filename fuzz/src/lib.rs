//! Shared code of the fuzz targets: inputs become files in a temporary
//! directory, the reader opens them, and every opened volume is read and,
//! when small, meshed. Any panic is a bug; errors are fine.

use std::fs;
use std::path::{Path, PathBuf};
use tmc::volume::{self, RawOptions};
use tmc::{ExtractParams, SampleSource};

/// Samples a target reads at most (the harness's own buffers stay small).
const MAX_READ: usize = 1 << 22;
/// Samples a target meshes at most.
const MAX_EXTRACT: usize = 1 << 16;

/// A fresh temporary directory.
pub fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("temporary directory")
}

/// Writes `bytes` to `dir/name` and returns the path.
pub fn put(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, bytes).expect("write fuzz input");
    path
}

/// Splits `data` at every occurrence of `sep` (at most `max` parts; the
/// last one keeps the rest).
pub fn split<'a>(data: &'a [u8], sep: &[u8], max: usize) -> Vec<&'a [u8]> {
    let mut parts = Vec::new();
    let mut rest = data;
    while parts.len() + 1 < max {
        match rest.windows(sep.len()).position(|w| w == sep) {
            Some(at) => {
                parts.push(&rest[..at]);
                rest = &rest[at + sep.len()..];
            }
            None => break,
        }
    }
    parts.push(rest);
    parts
}

/// Lets a panic that a reader catches and reports as an error (a
/// third-party pixel decoder's, see `tmc::volume::in_guarded_call`) pass:
/// libFuzzer's panic hook aborts on every panic, caught or not, so it is
/// only called for the others.
fn pass_guarded_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let fuzzer_hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !tmc::volume::in_guarded_call() {
                fuzzer_hook(info);
            }
        }));
    });
}

/// Opens `path` with [`volume::open`] and exercises what opens.
pub fn open_and_read(path: &Path, raw: Option<&RawOptions>) {
    pass_guarded_panics();
    if let Ok(source) = volume::open(path, raw) {
        exercise(source.as_ref());
    }
}

/// Reads every plane of `source` (forward, then the first again), checks
/// the grid, and meshes it at the middle of its value range when it is
/// small. Read errors are fine (a truncated file may only show on reading).
pub fn exercise(source: &dyn SampleSource) {
    let grid = *source.grid();
    assert!(grid.dims.iter().all(|&d| d > 0), "empty grid {grid:?}");
    let plane = grid.plane_len();
    let total = plane.checked_mul(grid.dims[2]);
    let Some(total) = total.filter(|&t| t <= MAX_READ) else {
        return;
    };
    let mut buf = vec![0.0; plane];
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for z in 0..grid.dims[2] {
        if source.read_plane(z, &mut buf).is_err() {
            return;
        }
        for &v in &buf {
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    let _ = source.read_plane(0, &mut buf);
    if total > MAX_EXTRACT || lo > hi {
        return;
    }
    let iso = lo + (hi - lo) * 0.5;
    if !iso.is_finite() {
        return;
    }
    let params = ExtractParams {
        iso,
        threads: 1,
        ..ExtractParams::default()
    };
    if let Ok((mesh, _)) = tmc::extract(source, &params) {
        let _ = tmc::check::check_mesh(&mesh);
    }
}
