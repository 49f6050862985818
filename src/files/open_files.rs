//! The limit on open files, raised for the runs that hold a file per
//! label at once (`extract --labels`, `merge` of label parts, the Python
//! package's `extract_labels_to`).

use rustix::process::{getrlimit, setrlimit, Resource};

/// Raises the soft limit on open files (`ulimit -n`, often 1024) to the
/// hard limit: a label pass keeps two or three files open per label until
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
