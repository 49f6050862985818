//! What the commands write besides their files: standard output that
//! tolerates a closed pipe, one-line error messages, and outputs taken
//! back when their report cannot be written.

use std::io::Write;

/// Writes to standard output through `write`, then flushes it. A closed
/// pipe (EPIPE: the reader, `head` say, has all it wanted) is not an error:
/// the rest of the output is dropped and the run ends as it would have
/// (the common convention, as ripgrep does); any other failure is.
pub(crate) fn to_stdout(
    write: impl FnOnce(&mut std::io::StdoutLock<'static>) -> std::io::Result<()>,
) -> tmc::Result<()> {
    let mut out = std::io::stdout().lock();
    match write(&mut out).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.map_err(|e| tmc::Error::io("standard output", e)),
    }
}

pub(crate) use tmc::files::withdraw;

/// Joins the lines of `text` into one.
pub(crate) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}
