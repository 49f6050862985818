//! Atomic file output: write a temporary file beside the target, flush and
//! sync it, then rename it onto the target.

use super::fatal_cleanup::{self, Registered};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// A file being written under a temporary name beside its target; it
/// appears at the target only on [`AtomicFile::commit`]. Dropped without a
/// commit, it removes the temporary file and leaves the target as it was.
pub struct AtomicFile {
    /// Dropped first, so the path leaves the fatal-signal table before the
    /// file is removed or renamed.
    _registered: Option<Registered>,
    temp: tempfile::NamedTempFile,
    path: std::path::PathBuf,
    /// Synced to disk before the rename: false for an intermediate file
    /// that is read and removed within the run ([`AtomicFile::scratch`]).
    durable: bool,
}

impl AtomicFile {
    /// Creates the temporary file in the directory of `path`.
    pub fn create(path: &Path) -> Result<AtomicFile> {
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
        let temp = builder
            .tempfile_in(dir)
            .map_err(|e| Error::io(path, without_temp_path(e)))?;
        Ok(AtomicFile {
            _registered: fatal_cleanup::register(temp.path()),
            temp,
            path: path.to_path_buf(),
            durable: true,
        })
    }

    /// [`AtomicFile::create`] for an intermediate file, read and removed
    /// by the same run (a label's `.tmesh` before one file of every label
    /// is written from them): its commit renames it without syncing it to
    /// disk, which for thousands of labels cost most of the run (the
    /// blocks written, then discarded on removal).
    pub fn scratch(path: &Path) -> Result<AtomicFile> {
        Ok(AtomicFile {
            durable: false,
            ..AtomicFile::create(path)?
        })
    }

    /// The temporary file, to write to.
    pub fn file(&mut self) -> &mut File {
        self.temp.as_file_mut()
    }

    /// The target path (for error messages).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The directory the file will appear in (where temporary files of the
    /// same output belong).
    pub fn dir(&self) -> &Path {
        parent_dir(&self.path)
    }

    /// Syncs the data to disk (unless the file is a
    /// [`scratch`](AtomicFile::scratch) one) and renames the file onto its
    /// target.
    pub fn commit(self) -> Result<()> {
        let AtomicFile {
            _registered: registered,
            temp,
            path,
            durable,
        } = self;
        drop(registered);
        if durable {
            temp.as_file().sync_all().map_err(|e| Error::io(&path, e))?;
        }
        temp.persist(&path)
            .map_err(|e| Error::io(&path, without_temp_path(e.error)))?;
        Ok(())
    }
}

/// Writes go to the temporary file, unbuffered (wrap it in a
/// [`BufWriter`] for small writes).
impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.temp.as_file_mut().write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.temp.as_file_mut().write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.temp.as_file_mut().flush()
    }
}

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
    let mut file = AtomicFile::create(path)?;
    let result = (|| {
        let mut writer = BufWriter::new(file.file());
        write(&mut writer)?;
        writer.flush()
    })();
    // On error, dropping `file` deletes the temporary file.
    result.map_err(|e| Error::io(path, e))?;
    file.commit()
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
