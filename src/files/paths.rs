//! Checks of input and output paths, made before any work is done, so that
//! a run fails at once with a clear line instead of after the extraction.

use super::atomic::{missing_dir, parent_dir, without_temp_path};
use crate::{Error, Result};
use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::Path;

/// Refuses an input that is neither a regular file nor a directory (a FIFO,
/// a socket, a device) before anything opens it: opening a FIFO for reading
/// blocks until a writer comes. A path that cannot be looked up passes, for
/// the reader to report.
pub fn check_input_kind(path: &Path) -> Result<()> {
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(());
    };
    let kind = meta.file_type();
    if kind.is_file() || kind.is_dir() {
        return Ok(());
    }
    #[cfg(unix)]
    let what = {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            "a FIFO (named pipe)"
        } else if kind.is_socket() {
            "a socket"
        } else if kind.is_char_device() || kind.is_block_device() {
            "a device"
        } else {
            "a special file"
        }
    };
    #[cfg(not(unix))]
    let what = "a special file";
    Err(Error::Format(format!(
        "{}: is {what}, not a regular file or directory; inputs are memory-mapped or read by seeking and must be files",
        path.display()
    )))
}

/// Checks, before any work is done, that a file of any kind could be
/// written to `path`: it is not a directory, and its parent directory exists
/// and accepts new files.
pub fn check_output_file(path: &Path) -> Result<()> {
    check_output_files([path])
}

/// [`check_output_file`] for each of `paths`, each directory tried (a file
/// created in it and removed) once, however many of the outputs it is to
/// hold (one per label of a label map).
pub fn check_output_files<'p>(paths: impl IntoIterator<Item = &'p Path>) -> Result<()> {
    let mut tried = BTreeSet::new();
    for path in paths {
        let dir = output_dir(path)?;
        if tried.insert(dir) {
            try_writing(path, dir)?;
        }
    }
    Ok(())
}

/// The directory `path` is to be written in: refused when `path` is a
/// directory (or ends in a separator), or the directory does not exist.
fn output_dir(path: &Path) -> Result<&Path> {
    // `out.ply/` names a directory: its parent is taken as `.`, and the
    // rename at the end of the run would fail with ENOTDIR.
    let bytes = path.as_os_str().as_encoded_bytes();
    if bytes.len() > 1
        && bytes
            .last()
            .is_some_and(|&b| std::path::is_separator(b.into()))
    {
        return Err(Error::Invalid(format!(
            "{}: ends in a path separator, which names a directory; give the output file's name",
            path.display()
        )));
    }
    if path.is_dir() {
        let line = "is a directory, not an output file";
        return Err(Error::io(
            path,
            io::Error::new(io::ErrorKind::IsADirectory, line),
        ));
    }
    // The file system's errors keep their kind (`Error::Io`), as the
    // writers' do when a directory is missing at the write itself, so that
    // Python raises `FileNotFoundError` (`NotADirectoryError`,
    // `PermissionError`) whether the check or the write finds it.
    let dir = parent_dir(path);
    match fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => Ok(dir),
        Ok(_) => Err(Error::io(
            path,
            io::Error::new(
                io::ErrorKind::NotADirectory,
                format!("output directory {} is not a directory", dir.display()),
            ),
        )),
        Err(e) => Err(Error::io(path, io::Error::new(e.kind(), missing_dir(dir)))),
    }
}

/// Refuses `dir` (where `path` is to go) unless a file can be created in
/// it: the only reliable test of writability.
fn try_writing(path: &Path, dir: &Path) -> Result<()> {
    tempfile::Builder::new()
        .prefix(".tmc-probe-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map(drop)
        .map_err(|e| {
            let e = without_temp_path(e);
            let line = format!("cannot write in directory {}: {e}", dir.display());
            Error::io(path, io::Error::new(e.kind(), line))
        })
}

/// The extension of `path` in lower case, the way every format is chosen
/// (`scan.NRRD` is NRRD); empty when there is none or it is not UTF-8.
pub fn lowercase_extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default()
}

/// Refuses to write the output over the input (also through a symbolic or
/// hard link): the input is read while the output is written.
pub fn check_distinct(input: &Path, output: &Path) -> Result<()> {
    let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output)) else {
        return Ok(());
    };
    #[cfg(unix)]
    let same = {
        use std::os::unix::fs::MetadataExt;
        a.dev() == b.dev() && a.ino() == b.ino()
    };
    #[cfg(not(unix))]
    let same = {
        let _ = (a, b);
        matches!(
            (std::fs::canonicalize(input), std::fs::canonicalize(output)),
            (Ok(x), Ok(y)) if x == y
        )
    };
    if same {
        return Err(Error::Invalid(format!(
            "{}: the output is the input file {}; choose another output path",
            output.display(),
            input.display()
        )));
    }
    Ok(())
}
