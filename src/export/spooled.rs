//! The streamed body of a shared-vertex mesh file (PLY, OBJ, OFF): a header
//! that may need the final counts, then every vertex, then every face.
//!
//! As chunks arrive, their vertices and faces are appended to two anonymous
//! temporary files ("spools") in the output's directory, on the output's own
//! file system (a spool the size of the mesh does not belong in a RAM-backed
//! `/tmp`). At the end the header goes into the output's [`AtomicFile`],
//! then the two spools, copied by the kernel where it can; then the output
//! is committed. Memory stays at a few buffers whatever the mesh size; disk
//! use peaks at about twice the output's size. Anonymous spools vanish with
//! the process, even if it is killed.

use super::atomic::without_temp_path;
use super::numbering::Numbering;
use super::AtomicFile;
use crate::sink::{Chunk, Totals};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

/// Buffer size of each spool.
const BUFFER_BYTES: usize = 1 << 20;

/// A shared-vertex mesh file being streamed.
pub(crate) struct Spooled {
    out: AtomicFile,
    vertices: BufWriter<File>,
    faces: BufWriter<File>,
    numbering: Numbering,
}

impl Spooled {
    /// Starts a file that will appear at `path` when finished.
    pub(crate) fn create(path: &Path) -> Result<Spooled> {
        let out = AtomicFile::create(path)?;
        let spool = || {
            tempfile::tempfile_in(out.dir())
                .map(|file| BufWriter::with_capacity(BUFFER_BYTES, file))
                .map_err(|e| Error::io(path, without_temp_path(e)))
        };
        Ok(Spooled {
            vertices: spool()?,
            faces: spool()?,
            numbering: Numbering::new(path),
            out,
        })
    }

    /// The counts and index checks of the chunks so far.
    pub(crate) fn numbering(&self) -> &Numbering {
        &self.numbering
    }

    /// Accepts the chunk starting at global vertex `base`; `write` then
    /// appends its vertices and its faces to the two spools.
    pub(crate) fn chunk<F>(&mut self, base: u64, chunk: &Chunk, write: F) -> Result<()>
    where
        F: FnOnce(&mut BufWriter<File>, &mut BufWriter<File>) -> io::Result<()>,
    {
        self.numbering.accept(base, chunk)?;
        write(&mut self.vertices, &mut self.faces).map_err(|e| Error::io(self.out.path(), e))
    }

    /// Checks the totals, writes the header (`header` gets the vertex and
    /// face counts), appends the vertices and the faces, and commits.
    pub(crate) fn finish<H>(self, totals: &Totals, header: H) -> Result<()>
    where
        H: FnOnce(&mut Vec<u8>, u64, u64) -> io::Result<()>,
    {
        self.numbering.finish(totals)?;
        let Spooled {
            mut out,
            vertices,
            faces,
            numbering,
        } = self;
        let path = out.path().to_path_buf();
        let result = (|| {
            let mut head = Vec::new();
            header(&mut head, numbering.vertices(), numbering.triangles())?;
            out.write_all(&head)?;
            for spool in [vertices, faces] {
                let mut file = spool.into_inner().map_err(|e| e.into_error())?;
                file.seek(SeekFrom::Start(0))?;
                io::copy(&mut file, out.file())?;
            }
            Ok(())
        })();
        result.map_err(|e| Error::io(&path, e))?;
        out.commit()
    }
}
