//! Which files are DICOM, and the one-line errors that name them.

use crate::{Error, Result};
use std::fmt::Display;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Does `path` have the `DICM` magic at byte 128?
pub fn has_magic(path: &Path) -> bool {
    let mut head = [0u8; 132];
    File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && &head[128..] == b"DICM"
}

fn has_dcm_extension(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("dcm"))
}

/// Is `path` a file to read as DICOM (the magic, or a `.dcm` name)?
pub(super) fn is_dicom_file(path: &Path) -> bool {
    path.is_file() && (has_dcm_extension(path) || has_magic(path))
}

/// The files of directory `dir`, sorted by name.
pub(super) fn dir_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let path = entry.map_err(|e| Error::io(dir, e))?.path();
        if path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// Does directory `dir` hold at least one DICOM file?
pub fn dir_has_dicom(dir: &Path) -> bool {
    dir_files(dir).is_ok_and(|files| files.iter().any(|f| is_dicom_file(f)))
}

pub(super) fn format_err(path: &Path, msg: impl Display) -> Error {
    let msg = msg.to_string().replace(['\n', '\r'], " ");
    Error::Format(format!("{}: {msg}", path.display()))
}
