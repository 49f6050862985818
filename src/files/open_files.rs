//! The limit on open files, raised for the runs that hold a file per
//! label at once (`extract --labels`, `merge` of label parts, the Python
//! package's `extract_labels_to`).

use crate::{Error, Result};
use rustix::process::{getrlimit, setrlimit, Resource};

/// Raises the soft limit on open files (`ulimit -n`, often 1024) to the
/// hard limit: a label pass keeps one to three files open per label until
/// all are committed together, so a few hundred labels would otherwise
/// fail with "Too many open files" on a default limit. Any user may raise
/// the soft limit up to the hard one. Best effort: where the hard limit is
/// unlimited the soft one goes to 2^20 (Linux's default `nr_open`), and a
/// refusal leaves the limit as it was (a run that needs more then fails
/// with the system's one-line error, leaving nothing).
pub fn raise_open_file_limit() {
    let limit = getrlimit(Resource::Nofile);
    let target = limit.maximum.unwrap_or(1 << 20);
    if limit.current.is_some_and(|current| current < target) {
        let raised = rustix::process::Rlimit {
            current: Some(target),
            maximum: limit.maximum,
        };
        let _ = setrlimit(Resource::Nofile, raised);
    }
}

/// Files the process may keep open besides a label pass's own: the
/// standard streams, the input and its data files, a run's temporary
/// files, with room to spare.
const OTHER_OPEN_FILES: u64 = 64;

/// Refuses, before any file is made, a label pass of `labels` labels
/// that keeps `per_label` files open for each when the limit on open
/// files (as [`raise_open_file_limit`] left it) cannot hold them: without
/// this the pass fails part way with the system's "Too many open files".
pub fn check_open_files(labels: usize, per_label: usize) -> Result<()> {
    let limit = getrlimit(Resource::Nofile);
    let Some(current) = limit.current else {
        return Ok(());
    };
    let needed = (labels as u64).saturating_mul(per_label as u64);
    if needed.saturating_add(OTHER_OPEN_FILES) <= current {
        return Ok(());
    }
    let fits = current.saturating_sub(OTHER_OPEN_FILES) / per_label.max(1) as u64;
    Err(Error::Invalid(format!(
        "{labels} labels keep {needed} files open at once ({per_label} per label), but this process may open {current} (ulimit -n, raised to the hard limit): extract at most {fits} labels per run (--labels with a list of them){}, or raise the hard limit on open files",
        match per_label {
            1 => "",
            _ => ", write .tmesh files (one open file per label)",
        }
    )))
}
