//! Mesh writers: PLY (binary little-endian), OBJ, OFF and STL (binary),
//! for whole meshes and as streaming [`MeshSink`]s.
//!
//! [`create_sink`] picks a sink by the output extension (`.tmesh` too); the
//! pipeline streams chunks into it and it never holds the whole mesh. PLY
//! and OFF state their counts before the data, and all three shared-vertex
//! formats put every vertex before every face, so their sinks append
//! vertices and faces to two anonymous temporary files in the output's
//! directory and assemble the file at the end (disk use peaks at about twice
//! the output's size). The STL sink holds one chunk back, because a
//! triangle's corners may lie in the next chunk, and writes the facet count
//! into the header in place. Every sink writes exactly the bytes that
//! [`write_mesh`] writes for the same mesh.
//!
//! Every output is atomic (a temporary file in the same directory, renamed
//! onto the path once complete), so a failed run never leaves a partial
//! file. STL cannot share vertices: every facet stores its own three corners.

mod atomic;
pub mod fatal_cleanup;
mod numbering;
mod obj;
mod off;
mod ply;
mod replay;
mod spooled;
mod stl;

pub use atomic::{write_atomically, AtomicFile};
pub use obj::{write_obj, Obj, ObjSink};
pub use off::{write_off, Off, OffSink};
pub use ply::{write_ply, Ply, PlySink};
pub use replay::{replay, replay_cancellable};
pub use spooled::{write_whole, Layout, SpooledSink};
pub use stl::{write_stl, StlSink};

use crate::meshfile::TmeshWriter;
use crate::sink::MeshSink;
use crate::{Error, Mesh, Result};
use std::fs;
use std::path::Path;

/// An output mesh format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Stanford PLY, binary little-endian, shared vertices.
    Ply,
    /// Wavefront OBJ (text), shared vertices.
    Obj,
    /// Object File Format (text), shared vertices.
    Off,
    /// STL, binary, three unshared vertices per facet.
    Stl,
    /// tmc's chunked, compressed mesh file ([`crate::meshfile`]).
    Tmesh,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "ply" => Ok(Format::Ply),
            "obj" => Ok(Format::Obj),
            "off" => Ok(Format::Off),
            "stl" => Ok(Format::Stl),
            "tmesh" => Ok(Format::Tmesh),
            _ => Err(Error::Invalid(format!(
                "{}: unknown output format (expected .ply, .obj, .off, .stl or .tmesh)",
                path.display()
            ))),
        }
    }
}

/// A streaming writer for `path`, in the format named by its extension:
/// [`PlySink`], [`ObjSink`], [`OffSink`], [`StlSink`] or [`TmeshWriter`].
///
/// The file appears at `path` when the sink finishes; if anything fails
/// first, dropping the sink leaves nothing there (an existing file is kept).
pub fn create_sink(path: &Path) -> Result<Box<dyn MeshSink>> {
    Ok(match Format::from_path(path)? {
        Format::Ply => Box::new(PlySink::create(path)?),
        Format::Obj => Box::new(ObjSink::create(path)?),
        Format::Off => Box::new(OffSink::create(path)?),
        Format::Stl => Box::new(StlSink::create(path)?),
        Format::Tmesh => Box::new(TmeshWriter::create(path)?),
    })
}

/// Writes `mesh` to `path` in the format named by its extension (`.ply`,
/// `.obj`, `.off` or `.stl`), atomically: on error nothing is left at `path`
/// (an existing file there is kept).
///
/// A `.tmesh` file records the extraction that made it, which a [`Mesh`]
/// does not know: stream the extraction into [`create_sink`] instead.
pub fn write_mesh(path: &Path, mesh: &Mesh) -> Result<()> {
    let format = Format::from_path(path)?;
    if format == Format::Tmesh {
        return Err(Error::Invalid(format!(
            "{}: a .tmesh file records the extraction that made it; stream the extraction into tmc::export::create_sink instead",
            path.display()
        )));
    }
    check_mesh_indices(path, mesh)?;
    write_atomically(path, |w| match format {
        Format::Ply => write_ply(w, mesh),
        Format::Obj => write_obj(w, mesh),
        Format::Off => write_off(w, mesh),
        Format::Stl => write_stl(w, mesh),
        Format::Tmesh => unreachable!("refused above"),
    })
}

/// Checks, before any work is done, that a mesh could be written to `path`:
/// the extension is a known format, `path` is not a directory, and its parent
/// directory exists and accepts new files.
pub fn check_output_path(path: &Path) -> Result<()> {
    Format::from_path(path)?;
    check_output_file(path)
}

/// Checks, before any work is done, that a file of any kind could be
/// written to `path`: it is not a directory, and its parent directory exists
/// and accepts new files.
pub fn check_output_file(path: &Path) -> Result<()> {
    if path.is_dir() {
        return Err(Error::Invalid(format!(
            "{}: is a directory, not an output file",
            path.display()
        )));
    }
    let dir = atomic::parent_dir(path);
    match fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => {
            return Err(Error::Invalid(format!(
                "{}: output directory {} is not a directory",
                path.display(),
                dir.display()
            )))
        }
        Err(_) => {
            return Err(Error::Invalid(format!(
                "{}: output directory {} does not exist",
                path.display(),
                dir.display()
            )))
        }
    }
    // The only reliable test of writability is to create a file there.
    tempfile::Builder::new()
        .prefix(".tmc-probe-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map(drop)
        .map_err(|e| {
            Error::Invalid(format!(
                "{}: cannot write in directory {}: {}",
                path.display(),
                dir.display(),
                atomic::without_temp_path(e)
            ))
        })
}

/// Rejects triangles that name a vertex the mesh does not have.
fn check_mesh_indices(path: &Path, mesh: &Mesh) -> Result<()> {
    let n = mesh.vertices.len();
    if u32::try_from(n).is_err() || u32::try_from(mesh.triangles.len()).is_err() {
        return Err(Error::Invalid(format!(
            "{}: mesh too large ({} vertices, {} triangles; at most {} each)",
            path.display(),
            n,
            mesh.triangles.len(),
            u32::MAX
        )));
    }
    if let Some((i, t)) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
    {
        return Err(Error::Invalid(format!(
            "{}: triangle {i} {t:?} refers to a vertex past the {n} vertices",
            path.display()
        )));
    }
    Ok(())
}

/// The error of a sink used after it finished.
fn finished() -> Error {
    Error::Invalid("the mesh sink was used after it finished".into())
}
