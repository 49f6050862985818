//! The crate's error type: every failure is one human-readable line.
//!
//! The messages quote what they found (a header line, a value, a path),
//! and a damaged or hostile file can hold control characters there: an
//! escape sequence would recolour or clear the user's terminal, a carriage
//! return hide the start of the line. So every message is shown through
//! [`escape_controls`], which writes them as visible escapes.

use std::borrow::Cow;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Errors reported by the library; the CLI prints them as one line.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An input or output file could not be accessed.
    #[error("{}: {source}", escape_controls(&path.display().to_string()))]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The input file is malformed or inconsistent with the options given.
    #[error("{}", escape_controls(.0))]
    Format(String),
    /// The options are invalid (bad isovalue, unknown extension, ...).
    #[error("{}", escape_controls(.0))]
    Invalid(String),
    /// The extraction was cancelled through
    /// [`PipelineOptions::cancel`](crate::PipelineOptions::cancel) (the CLI
    /// sets that flag on SIGINT or SIGTERM).
    #[error("interrupted")]
    Interrupted,
    /// Memory for the named purpose could not be had: `--max-memory` is too
    /// small for the pipeline, or an allocation proportional to the input or
    /// the output failed.
    #[error("{}", escape_controls(.0))]
    OutOfMemory(String),
}

/// `text` with every control character (C0, DEL, C1) written as a visible
/// escape: `\r`, `\n`, `\t`, `\0`, else `\xNN` (ASCII) or `\u{NN}`; other
/// text, backslashes included, as it is. Borrowed when there is nothing
/// to escape. Every [`Error`] message goes through it.
pub fn escape_controls(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\r' => out.push_str("\\r"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\0' => out.push_str("\\0"),
            c if c.is_ascii_control() => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c if c.is_control() => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// Result alias for the crate.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// An [`Error::OutOfMemory`] for a failed reservation of `count` items
    /// of `T` for `what`.
    pub fn alloc<T>(what: &str, count: usize) -> Self {
        let bytes = (count as u128) * (std::mem::size_of::<T>() as u128);
        Error::OutOfMemory(format!(
            "out of memory: cannot allocate {bytes} bytes for {what}"
        ))
    }

    /// This error, met reading `data` (a data file that the header file
    /// `header` names: MetaImage, a detached NRRD), as the user can follow
    /// it: naming the header they gave first, then the data file
    /// (`head.mhd: data file head.raw: ...`), the data file's own prefix
    /// dropped from the message.
    pub(crate) fn in_data_file(self, header: &Path, data: &Path) -> Error {
        let prefix = format!("{}: data file {}", header.display(), data.display());
        let own = format!("{}: ", data.display());
        match self {
            Error::Io { source, .. } => Error::Format(format!("{prefix}: {source}")),
            Error::Format(what) => {
                let what = what.strip_prefix(&own).unwrap_or(&what);
                Error::Format(format!("{prefix}: {what}"))
            }
            Error::Invalid(what) => {
                let what = what.strip_prefix(&own).unwrap_or(&what);
                Error::Invalid(format!("{prefix}: {what}"))
            }
            other => other,
        }
    }
}

/// A vector with room for `count` items of `T`, or [`Error::OutOfMemory`]
/// naming `what` when that much memory cannot be had (instead of an abort).
pub fn try_vec<T>(what: &str, count: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(count)
        .map_err(|_| Error::alloc::<T>(what, count))?;
    Ok(v)
}

/// A vector of `count` copies of `value`, or [`Error::OutOfMemory`] naming
/// `what` (a plane of samples from a header that claims a huge one must
/// give an error, not an abort).
pub fn try_filled<T: Clone>(what: &str, count: usize, value: T) -> Result<Vec<T>> {
    let mut v = try_vec(what, count)?;
    v.resize(count, value);
    Ok(v)
}

/// Makes room in `v` for `n` more items (growing as `push` would), or
/// fails with [`Error::OutOfMemory`] naming `what`: pushes of at most `n`
/// items after it cannot reallocate, so they cannot abort. One comparison
/// when there is room.
#[inline(always)]
pub(crate) fn make_room<T>(v: &mut Vec<T>, n: usize, what: &str) -> Result<()> {
    if v.capacity() - v.len() < n {
        grow(v, n, what)
    } else {
        Ok(())
    }
}

#[cold]
#[inline(never)]
fn grow<T>(v: &mut Vec<T>, n: usize, what: &str) -> Result<()> {
    v.try_reserve(n)
        .map_err(|_| Error::alloc::<T>(what, v.len().saturating_add(n)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_in_every_message() {
        assert!(matches!(
            escape_controls("plain 'text' \\ ok"),
            Cow::Borrowed(_)
        ));
        assert_eq!(
            escape_controls("a\x1b[31mb\rc\nd\te\0f\x7fg\u{9b}h"),
            "a\\x1b[31mb\\rc\\nd\\te\\0f\\x7fg\\u{9b}h"
        );
        let e = Error::Format("bad 'type' value 'uint8\x1b[2J\r'".into());
        assert_eq!(e.to_string(), "bad 'type' value 'uint8\\x1b[2J\\r'");
        let e = Error::io("out\x07.ply", std::io::Error::other("no"));
        assert_eq!(e.to_string(), "out\\x07.ply: no");
    }

    #[test]
    fn make_room_reserves_or_fails_cleanly() {
        let mut v: Vec<u64> = Vec::new();
        make_room(&mut v, 10, "the test").unwrap();
        assert!(v.capacity() >= 10);
        let err = make_room(&mut v, usize::MAX / 2, "the test").unwrap_err();
        assert!(matches!(err, Error::OutOfMemory(_)), "{err:?}");
    }

    #[test]
    fn an_impossible_allocation_is_an_error_not_an_abort() {
        // Beyond isize::MAX bytes, and 64 TiB (more than this machine has).
        for count in [usize::MAX / 2, 1 << 46] {
            let err = try_vec::<u64>("the test", count).unwrap_err();
            assert!(matches!(err, Error::OutOfMemory(_)), "{err:?}");
            let text = err.to_string();
            assert!(
                text.starts_with("out of memory: cannot allocate")
                    && text.ends_with("bytes for the test"),
                "{text}"
            );
        }
        assert_eq!(try_vec::<u8>("a little", 10).unwrap().capacity(), 10);
    }
}
