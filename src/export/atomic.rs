//! Atomic file output: write a temporary file beside the target, flush and
//! sync it, then rename it onto the target.

use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes a file at `path` through `write`, atomically.
///
/// The data goes to a temporary file in the same directory through a buffered
/// writer, which is flushed and synced to disk and then renamed onto `path`.
/// If `write` or any later step fails, the temporary file is removed and
/// `path` is left as it was.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<&mut File>) -> io::Result<()>,
{
    let dir = parent_dir(path);
    let mut builder = tempfile::Builder::new();
    builder.prefix(".tmc-").suffix(".tmp");
    #[cfg(unix)]
    {
        // Like a plain `File::create`: readable by others, subject to umask
        // (a temporary file is otherwise private to its owner).
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut temp = builder
        .tempfile_in(dir)
        .map_err(|e| Error::io(path, without_temp_path(e)))?;
    let result = (|| {
        let mut writer = BufWriter::new(temp.as_file_mut());
        write(&mut writer)?;
        writer.flush()?;
        drop(writer);
        temp.as_file().sync_all()
    })();
    // On error, dropping `temp` deletes the temporary file.
    result.map_err(|e| Error::io(path, e))?;
    temp.persist(path)
        .map_err(|e| Error::io(path, without_temp_path(e.error)))?;
    Ok(())
}

/// Drops the temporary file's name that `tempfile` adds to its errors (the
/// user never sees that file), keeping the OS error.
pub(crate) fn without_temp_path(e: io::Error) -> io::Error {
    match e.raw_os_error() {
        Some(code) => io::Error::from_raw_os_error(code),
        None => e,
    }
}

/// The directory that holds `path` (`.` for a bare file name).
pub(crate) fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}
