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

use super::numbering::Numbering;
use crate::files::{without_temp_path, AtomicFile};
use crate::mesh::Mesh;
use crate::mesh::{used_after_finish, Chunk, MeshInfo, MeshSink, Totals};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::marker::PhantomData;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// How a shared-vertex format lays out its header, vertices and faces.
pub trait Layout {
    /// Most vertices the format can index.
    const MAX_VERTICES: u64 = u64::MAX;
    /// Why more vertices cannot be written (completes "the mesh has more
    /// than N vertices, ...").
    const TOO_MANY: &'static str = "";
    /// The header, given the final counts.
    fn header(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()>;
    /// One vertex.
    fn vertex(w: &mut impl Write, v: &[f32; 3]) -> io::Result<()>;
    /// One triangle, global indices.
    fn face(w: &mut impl Write, t: [u64; 3]) -> io::Result<()>;

    /// Whether the format holds vertex normals; a format that does not
    /// writes the positions of a mesh with normals and drops the normals.
    const NORMALS: bool = false;
    /// The header of a file whose vertices carry normals.
    fn header_with_normals(w: &mut impl Write, vertices: u64, faces: u64) -> io::Result<()> {
        Self::header(w, vertices, faces)
    }
    /// One vertex and its normal.
    fn vertex_with_normal(w: &mut impl Write, v: &[f32; 3], _normal: &[f32; 3]) -> io::Result<()> {
        Self::vertex(w, v)
    }
    /// One triangle of a file whose vertices carry normals.
    fn face_with_normals(w: &mut impl Write, t: [u64; 3]) -> io::Result<()> {
        Self::face(w, t)
    }

    /// Whether the format holds a label per face; a format that does not
    /// writes the faces of a labelled mesh and drops the labels.
    const LABELS: bool = false;
    /// The header of a file whose faces carry labels (and whose vertices
    /// carry normals when `normals`).
    fn header_with_labels(
        w: &mut impl Write,
        vertices: u64,
        faces: u64,
        normals: bool,
    ) -> io::Result<()> {
        match normals {
            true => Self::header_with_normals(w, vertices, faces),
            false => Self::header(w, vertices, faces),
        }
    }
    /// One triangle and its label.
    fn face_with_label(
        w: &mut impl Write,
        t: [u64; 3],
        normals: bool,
        _label: u32,
    ) -> io::Result<()> {
        match normals {
            true => Self::face_with_normals(w, t),
            false => Self::face(w, t),
        }
    }
}

/// Writes a whole mesh in layout `L`, with its normals when it has one per
/// vertex and `L` holds them, and its labels when it has one per triangle
/// and `L` holds them (an empty mesh with normals or labels declares them,
/// as the streamed file of the run that made it does).
pub fn write_whole<L: Layout>(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    let (vertices, faces) = (mesh.vertices.len() as u64, mesh.triangles.len() as u64);
    let normals =
        (mesh.normals.as_deref()).filter(|n| L::NORMALS && n.len() == mesh.vertices.len());
    let labels = (mesh.labels.as_deref()).filter(|l| L::LABELS && l.len() == mesh.triangles.len());
    let attributes = (normals.is_some(), labels.is_some());
    write_header::<L>(w, vertices, faces, attributes)?;
    if let Some(normals) = normals {
        for (v, n) in mesh.vertices.iter().zip(normals) {
            L::vertex_with_normal(w, v, n)?;
        }
    } else {
        mesh.vertices.iter().try_for_each(|v| L::vertex(w, v))?;
    }
    for (k, t) in mesh.triangles.iter().enumerate() {
        let t = t.map(u64::from);
        match (normals.is_some(), labels) {
            (normals, Some(labels)) => L::face_with_label(w, t, normals, labels[k])?,
            (true, None) => L::face_with_normals(w, t)?,
            (false, None) => L::face(w, t)?,
        }
    }
    Ok(())
}

/// The header of a file in layout `L` of `vertices` and `faces` with the
/// attributes `(normals, labels)`.
fn write_header<L: Layout>(
    w: &mut impl Write,
    vertices: u64,
    faces: u64,
    (normals, labels): (bool, bool),
) -> io::Result<()> {
    match (normals, labels) {
        (_, true) => L::header_with_labels(w, vertices, faces, normals),
        (true, false) => L::header_with_normals(w, vertices, faces),
        (false, false) => L::header(w, vertices, faces),
    }
}

/// Streams a file in layout `L` from chunks, byte-identical to
/// [`write_whole`] of the same mesh; memory stays small whatever the mesh
/// size (see [`super::create_sink`]).
pub struct SpooledSink<L> {
    body: Option<Spooled>,
    /// The chunks carry normals and `L` holds them.
    normals: bool,
    /// The chunks carry labels and `L` holds them.
    labels: bool,
    layout: PhantomData<L>,
}

impl<L: Layout> SpooledSink<L> {
    /// Starts a file that will appear at `path` when the sink finishes.
    pub fn create(path: &Path) -> Result<Self> {
        Ok(SpooledSink {
            body: Some(Spooled::create(path)?),
            normals: false,
            labels: false,
            layout: PhantomData,
        })
    }
}

impl<L: Layout> MeshSink for SpooledSink<L> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.normals = info.normals && L::NORMALS;
        self.labels = info.labels && L::LABELS;
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.chunk_cancellable(base, chunk, &AtomicBool::new(false))
    }

    /// Looks at `cancel` before every 65,536 vertices or faces
    /// formatted into the spools.
    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        let body = self.body.as_mut().ok_or_else(used_after_finish)?;
        if base + chunk.vertices.len() as u64 > L::MAX_VERTICES {
            return Err(body.numbering().error(format!(
                "the mesh has more than {} vertices, {}",
                L::MAX_VERTICES,
                L::TOO_MANY
            )));
        }
        if self.normals && chunk.normals.len() != chunk.vertices.len() {
            return Err(body.numbering().error(format!(
                "a chunk of {} vertices has {} normals",
                chunk.vertices.len(),
                chunk.normals.len()
            )));
        }
        if self.labels && chunk.labels.len() != chunk.triangles.len() {
            return Err(body.numbering().error(format!(
                "a chunk of {} triangles has {} labels",
                chunk.triangles.len(),
                chunk.labels.len()
            )));
        }
        let interrupted = || cancel.load(Ordering::Relaxed);
        let mut stopped = false;
        let (normals, labels) = (self.normals, self.labels);
        body.chunk(base, chunk, |vertices, faces| {
            if normals || labels {
                let attributes = (normals, labels);
                return write_with::<L>(chunk, base, attributes, vertices, faces, &interrupted)
                    .map(|done| stopped = !done);
            }
            for step in chunk.vertices.chunks(WRITE_STEP) {
                stopped |= interrupted();
                if stopped {
                    return Ok(());
                }
                for v in step {
                    L::vertex(vertices, v)?;
                }
            }
            for step in chunk.triangles.chunks(WRITE_STEP) {
                stopped |= interrupted();
                if stopped {
                    return Ok(());
                }
                for t in step {
                    L::face(faces, t.map(|i| base + u64::from(i)))?;
                }
            }
            Ok(())
        })?;
        match stopped {
            true => Err(Error::Interrupted),
            false => Ok(()),
        }
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.finish_cancellable(totals, &AtomicBool::new(false))
    }

    /// Looks at `cancel` before the header and every `COPY_STEP` (8 MiB) of
    /// the spools copied into the output.
    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        let body = self.body.take().ok_or_else(used_after_finish)?;
        let (normals, labels) = (self.normals, self.labels);
        body.finish(totals, cancel, |w, vertices, faces| {
            write_header::<L>(w, vertices, faces, (normals, labels))
        })
    }
}

/// Appends `chunk` (starting at global vertex `base`) to the spools with
/// its attributes `(normals, labels)`: the vertices with their normals,
/// the faces with their labels; false when `interrupted` stopped it
/// (asked before every [`WRITE_STEP`] vertices or faces).
fn write_with<L: Layout>(
    chunk: &Chunk,
    base: u64,
    (normals, labels): (bool, bool),
    vertices: &mut impl Write,
    faces: &mut impl Write,
    interrupted: &impl Fn() -> bool,
) -> io::Result<bool> {
    for (k, step) in chunk.vertices.chunks(WRITE_STEP).enumerate() {
        if interrupted() {
            return Ok(false);
        }
        match normals {
            true => {
                let n = &chunk.normals[k * WRITE_STEP..];
                for (v, n) in step.iter().zip(n) {
                    L::vertex_with_normal(vertices, v, n)?;
                }
            }
            false => step.iter().try_for_each(|v| L::vertex(vertices, v))?,
        }
    }
    for (k, step) in chunk.triangles.chunks(WRITE_STEP).enumerate() {
        if interrupted() {
            return Ok(false);
        }
        for (j, t) in step.iter().enumerate() {
            let t = t.map(|i| base + u64::from(i));
            match labels {
                true => L::face_with_label(faces, t, normals, chunk.labels[k * WRITE_STEP + j])?,
                false => L::face_with_normals(faces, t)?,
            }
        }
    }
    Ok(true)
}

/// Vertices or faces formatted between two looks at the cancel flag (a few
/// milliseconds of text).
const WRITE_STEP: usize = 1 << 16;

/// Buffer size of each spool.
const BUFFER_BYTES: usize = 1 << 20;

/// Bytes of spool copied into the output between two looks at the cancel
/// flag (a few milliseconds of copying).
const COPY_STEP: u64 = 8 << 20;

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
    /// face counts), appends the vertices and the faces, and commits; stops
    /// with [`Error::Interrupted`] (nothing committed) once `cancel` is set,
    /// which it looks at every [`COPY_STEP`] bytes.
    pub(crate) fn finish<H>(self, totals: &Totals, cancel: &AtomicBool, header: H) -> Result<()>
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
        let interrupted = || cancel.load(Ordering::Relaxed);
        let result = (|| {
            let mut head = Vec::new();
            header(&mut head, numbering.vertices(), numbering.triangles())?;
            if interrupted() {
                return Ok(false);
            }
            out.write_all(&head)?;
            for spool in [vertices, faces] {
                let mut file = spool.into_inner().map_err(|e| e.into_error())?;
                file.seek(SeekFrom::Start(0))?;
                // In steps, each still copied by the kernel where it can.
                loop {
                    if interrupted() {
                        return Ok(false);
                    }
                    if io::copy(&mut (&mut file).take(COPY_STEP), out.file())? == 0 {
                        break;
                    }
                }
            }
            Ok(!interrupted())
        })();
        // Dropping `out` uncommitted removes the temporary file.
        match result.map_err(|e| Error::io(&path, e))? {
            true => out.commit(),
            false => Err(Error::Interrupted),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::Ply;

    /// A spooled PLY file in `dir` holding one triangle.
    fn one_triangle(path: &Path) -> Spooled {
        let mut body = Spooled::create(path).unwrap();
        let chunk = Chunk {
            plane: 0,
            vertices: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            triangles: vec![[0, 1, 2]],
            normals: Vec::new(),
            labels: Vec::new(),
            values: Vec::new(),
            encoded: Vec::new(),
        };
        body.chunk(0, &chunk, |vertices, faces| {
            for v in &chunk.vertices {
                Ply::vertex(vertices, v)?;
            }
            Ply::face(faces, [0, 1, 2])
        })
        .unwrap();
        body
    }

    const TOTALS: Totals = Totals {
        vertices: 3,
        triangles: 1,
        chunks: 1,
    };

    #[test]
    fn a_cancel_during_the_final_copy_commits_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mesh.ply");
        let cancel = AtomicBool::new(false);
        // The flag is set once finishing has begun (here: while the header
        // is made, just before the spools are copied).
        let result = one_triangle(&path).finish(&TOTALS, &cancel, |w, v, f| {
            cancel.store(true, Ordering::Relaxed);
            Ply::header(w, v, f)
        });
        assert!(matches!(result, Err(Error::Interrupted)), "{result:?}");
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);

        let cancel = AtomicBool::new(false);
        one_triangle(&path)
            .finish(&TOTALS, &cancel, Ply::header)
            .unwrap();
        assert!(path.exists());
    }
}
