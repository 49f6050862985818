//! The output format named by a path's extension, and the writer for it.

use super::{write_obj, write_off, write_ply, write_stl, ObjSink, OffSink, PlySink, StlSink};
use crate::files::{check_output_file, lowercase_extension, write_atomically};
use crate::mesh::{Mesh, MeshSink};
use crate::meshfile::TmeshWriter;
use crate::{Error, Result};
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
        let ext = lowercase_extension(path);
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

impl Format {
    /// Whether the format holds vertex normals (PLY, OBJ, `.tmesh`); the
    /// others write the positions of a mesh with normals and drop them.
    pub fn holds_normals(self) -> bool {
        matches!(self, Format::Ply | Format::Obj | Format::Tmesh)
    }
}

/// With `normals`, fails unless `output`'s format holds vertex normals
/// (OFF and STL do not: the run would compute them for nothing), in the
/// words of `tmc extract --normals`; the CLI and the Python package ask
/// before the volume is read.
pub fn check_normals_output(output: &Path, normals: bool) -> Result<()> {
    if normals && !Format::from_path(output)?.holds_normals() {
        return Err(Error::Invalid(format!(
            "{}: --normals needs an output that holds vertex normals (.ply, .obj or .tmesh)",
            output.display()
        )));
    }
    Ok(())
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
    mesh.check_indices(path)?;
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

/// [`check_output_path`] for each of `paths`, each directory tried once
/// (see [`check_output_files`](crate::files::check_output_files)).
pub fn check_output_paths<'p>(paths: impl IntoIterator<Item = &'p Path> + Clone) -> Result<()> {
    for path in paths.clone() {
        Format::from_path(path)?;
    }
    crate::files::check_output_files(paths)
}
