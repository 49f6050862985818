//! Lines on standard error that cannot fail the process.
//!
//! `eprintln!` panics when standard error cannot be written (`2>/dev/full`,
//! a pipe whose reader is gone), and the panic hook, printing in turn,
//! aborts the process (status 134) with no message at all. Errors, notes
//! and summaries go through [`say!`] instead: a line that cannot be written
//! is lost, and the exit status still tells what happened. (The `--stats`
//! table is a report, not a note: it fails the run when it cannot be
//! written; see `extract`.)

/// Writes one line to standard error like `eprintln!`, ignoring a failed
/// write instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}
