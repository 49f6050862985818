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
            .map_err(|e| output_error(path, e))?;
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
            .map_err(|e| output_error(&path, e.error))?;
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

/// What to say of an output whose directory `dir` does not exist: that tmc
/// makes none, and the command that does.
pub(crate) fn missing_dir(dir: &Path) -> String {
    format!(
        "output directory {} does not exist (tmc makes no directories: \
         create it first, e.g. mkdir -p {})",
        dir.display(),
        dir.display()
    )
}

/// The error of a failed creation (or rename into place) of the output file
/// `path`, naming `path` (never a temporary file) and, when its directory
/// is missing, saying so and what to do, as [`check_output_file`](super::check_output_file) does
/// before a run. For the writers and for an output whose directory went
/// away during the run; the error's kind stays `source`'s (Python raises
/// `FileNotFoundError` for it as before).
pub fn output_error(path: &Path, source: io::Error) -> Error {
    let source = without_temp_path(source);
    let dir = parent_dir(path);
    if source.kind() == io::ErrorKind::NotFound && std::fs::metadata(dir).is_err() {
        return Error::io(path, io::Error::new(source.kind(), missing_dir(dir)));
    }
    Error::io(path, source)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer called without the CLI's check before the run (the
    /// library, Python's `Mesh.write`, or a directory removed during the
    /// run) names the path it was given and says what to do, never the
    /// temporary file.
    #[test]
    fn a_missing_directory_is_named_with_what_to_do() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no such/dir/out.ply");
        let error = write_atomically(&path, |_| Ok(())).unwrap_err();
        let line = error.to_string();
        assert!(line.starts_with(&path.display().to_string()), "{line}");
        assert!(line.contains("does not exist"), "{line}");
        assert!(line.contains("mkdir -p"), "{line}");
        assert!(!line.contains(".tmc-"), "{line}");
        // Still a not-found error (Python's FileNotFoundError).
        match error {
            Error::Io { source, .. } => assert_eq!(source.kind(), io::ErrorKind::NotFound),
            other => panic!("{other:?}"),
        }
    }

    /// The directory removed between creation and commit: the rename's
    /// error says the same.
    #[test]
    fn a_directory_removed_before_the_commit_is_named_with_what_to_do() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("gone");
        std::fs::create_dir(&sub).unwrap();
        let path = sub.join("out.tmesh");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"x").unwrap();
        std::fs::remove_dir_all(&sub).unwrap();
        let line = file.commit().unwrap_err().to_string();
        assert!(line.starts_with(&path.display().to_string()), "{line}");
        assert!(line.contains("does not exist"), "{line}");
        assert!(!line.contains(".tmc-"), "{line}");
    }
}
