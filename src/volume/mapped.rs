//! [`MappedFile`]: a read-only memory map of an input file, the one place
//! where tmc maps memory (and so the one place in `volume/` with `unsafe`).
//!
//! Readers that decode samples in place ([`super::RawVolume`],
//! [`super::StridedVolume`]) hold one: the page cache, not the process,
//! holds the file, and [`MappedFile::advise`] lets the slab loop read ahead
//! and drop the pages of planes it is done with, so that resident memory
//! stays bounded by the slab even for a file larger than memory.

use super::Access;
use crate::{Error, Result};
use memmap2::{Advice, Mmap, UncheckedAdvice};
use std::fs::File;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// A whole file mapped read-only, with the file kept open to notice when it
/// shrinks under the map.
pub(crate) struct MappedFile {
    map: Mmap,
    /// The same file, to look up its length (see
    /// [`MappedFile::check_unchanged`]); `None` for a map that keeps no
    /// file open ([`MappedFile::open_unheld`]), whose length is looked up
    /// by path.
    watch: Option<File>,
    path: PathBuf,
}

impl MappedFile {
    /// Maps `file` (opened from `path`), which must be a regular file.
    pub fn map(path: &Path, file: &File) -> Result<MappedFile> {
        let meta = file.metadata().map_err(|e| Error::io(path, e))?;
        if !meta.is_file() {
            return Err(Error::Format(format!(
                "{}: not a regular file",
                path.display()
            )));
        }
        // SAFETY: the map is read-only and private to its volume. Memory
        // mapping is sound as long as no other process truncates or rewrites
        // the file while it is mapped; like every mmap-based reader we accept
        // that an input file must not change during an extraction, and the
        // pipeline calls `check_unchanged` before each slab so that a file
        // that shrank gives an error. Callers check that the samples they
        // read lie inside `bytes()`, so every access stays inside the map.
        let map = unsafe { Mmap::map(file) }.map_err(|e| Error::io(path, e))?;
        let watch = Some(file.try_clone().map_err(|e| Error::io(path, e))?);
        Ok(MappedFile {
            map,
            watch,
            path: path.to_path_buf(),
        })
    }

    /// Opens and maps the file at `path`, keeping no file open (for a
    /// reader holding thousands of maps, one per slice of a stack, which
    /// must not run out of file descriptors): the file's length is then
    /// looked up by path. A file replaced under that path leaves the map
    /// on the old file, which stays whole; one truncated in place is seen.
    pub fn open_unheld(path: &Path) -> Result<MappedFile> {
        let mut mapped = MappedFile::open(path)?;
        mapped.watch = None;
        Ok(mapped)
    }

    /// Opens and maps the file at `path`.
    pub fn open(path: &Path) -> Result<MappedFile> {
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        MappedFile::map(path, &file)
    }

    /// The mapped bytes (as long as the file was when it was mapped).
    pub fn bytes(&self) -> &[u8] {
        &self.map
    }

    /// The mapped file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Read-ahead ([`Access::Soon`]) or release ([`Access::Done`]) advice
    /// for bytes `range` of the map; a hint that never changes what is read.
    pub fn advise(&self, range: Range<usize>, access: Access) {
        let end = range.end.min(self.map.len());
        if range.start >= end {
            return;
        }
        let len = end - range.start;
        // Advice is a hint: a kernel that refuses it changes nothing.
        let _ = match access {
            Access::Soon => self.map.advise_range(Advice::WillNeed, range.start, len),
            // SAFETY: the map is a read-only mapping of a file; dropping its
            // pages only makes the next access read them again from the file
            // (or the page cache), so no data the program sees can change.
            Access::Done => unsafe {
                self.map
                    .unchecked_advise_range(UncheckedAdvice::DontNeed, range.start, len)
            },
        };
    }

    /// Fails if the file is now shorter than the map (a read from the
    /// missing part would raise SIGBUS): one `fstat`.
    pub fn check_unchanged(&self) -> Result<()> {
        let path = &self.path;
        let meta = match &self.watch {
            Some(file) => file.metadata(),
            None => std::fs::metadata(path),
        };
        let len = meta.map_err(|e| Error::io(path, e))?.len();
        if len < self.map.len() as u64 {
            return Err(Error::Format(format!(
                "{}: the input file changed during the extraction: it shrank from {} to {len} bytes (truncated by another program?)",
                path.display(),
                self.map.len()
            )));
        }
        Ok(())
    }
}
