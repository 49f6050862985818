//! [`read_mesh`]: the reader for a path, by its extension or first bytes.

use super::obj::read_obj;
use super::off::read_off;
use super::ply::read_ply;
use super::source::{binary_stl, not_stl, stl_error, Format, Source, MAX_TRIANGLES};
use super::stl::read_stl;
use crate::export::replay;
use crate::files::lowercase_extension;
use crate::mesh::{Mesh, MeshBuilder};
use crate::meshfile::TmeshReader;
use crate::{Error, Result};
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

/// Reads a mesh from a PLY (ASCII or binary), OBJ, OFF or `.tmesh` file,
/// chosen by the extension or, failing that, by the first bytes of the file.
///
/// Content that the format does not allow is refused: an OBJ line that is
/// not an OBJ statement, data after what an OFF or PLY header declares, a
/// vertex coordinate that is not a finite `f32` number. So are STL files:
/// STL repeats the corners of every triangle instead of sharing vertices,
/// so it carries no connectivity to check. A `.tmesh` file must fit a
/// [`Mesh`] (at most `u32::MAX` vertices).
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    match open(path)? {
        (Format::Stl(_), _) => Err(stl_error(path)),
        (format, src) => read_format(path, format, src),
    }
}

/// Reads a mesh as [`read_mesh`] does, and also STL files (binary or
/// ASCII), whose facets' corners at the same position become one vertex:
/// for what needs the triangles and not a proof of their connectivity
/// (`tmc preview`; `tmc check` of an STL file, which says so).
pub fn read_mesh_to_draw(path: &Path) -> Result<Mesh> {
    let (format, src) = open(path)?;
    read_format(path, format, src)
}

fn read_format(path: &Path, format: Format, src: Option<Source<'_>>) -> Result<Mesh> {
    match (format, src) {
        (Format::Ply, Some(mut src)) => read_ply(&mut src),
        (Format::Obj, Some(mut src)) => read_obj(&mut src),
        (Format::Off, Some(mut src)) => read_off(&mut src),
        (Format::Stl(binary), Some(mut src)) => read_stl(&mut src, binary),
        _ => read_tmesh(path),
    }
}

/// Whether [`read_mesh`] reads `path` as a `.tmesh` file (by its
/// extension or, failing that, its first bytes); an error where it
/// refuses the file for its extension or first bytes.
pub fn is_tmesh(path: &Path) -> Result<bool> {
    Ok(matches!(open(path)?.0, Format::Tmesh))
}

/// The format of `path` (by its extension or, failing that, its first
/// bytes), with the file opened for the text readers (not for a file
/// named `.tmesh`, which its own reader opens).
fn open(path: &Path) -> Result<(Format, Option<Source<'_>>)> {
    let ext = lowercase_extension(path);
    if ext == "tmesh" {
        return Ok((Format::Tmesh, None));
    }
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut src = Source {
        path,
        reader: BufReader::with_capacity(1 << 20, file),
        buf: Vec::new(),
        pos: 0,
        line: 0,
        complete: false,
    };
    let format = match ext.as_str() {
        "ply" => Format::Ply,
        "obj" => Format::Obj,
        "off" => Format::Off,
        "stl" => stl_kind(&mut src)?,
        _ => src.sniff()?,
    };
    Ok((format, Some(src)))
}

/// Whether the `.stl` file of `src` is binary or ASCII STL; an error when
/// it is neither.
fn stl_kind(src: &mut Source) -> Result<Format> {
    use std::io::BufRead;
    let head = src.reader.fill_buf().map_err(|e| Error::io(src.path, e))?;
    if binary_stl(src.path, head) {
        Ok(Format::Stl(true))
    } else if head.trim_ascii_start().starts_with(b"solid") {
        Ok(Format::Stl(false))
    } else {
        Err(not_stl(src.path))
    }
}

/// Reads a whole `.tmesh` file, chunk by chunk, into a [`Mesh`].
fn read_tmesh(path: &Path) -> Result<Mesh> {
    crate::part::PartRecord::refuse_part(path)?;
    let mut reader = TmeshReader::open(path)?;
    let (vertices, triangles) = (reader.vertices(), reader.triangles());
    if vertices > u64::from(u32::MAX) || triangles > MAX_TRIANGLES as u64 {
        return Err(Error::Format(format!(
            "{}: {vertices} vertices and {triangles} triangles are more than a mesh in memory holds (at most {} vertices and {MAX_TRIANGLES} triangles)",
            path.display(),
            u32::MAX
        )));
    }
    let mut builder = MeshBuilder::with_room(vertices as usize, triangles as usize)?;
    replay(&mut reader, &mut builder)?;
    Ok(builder.into_mesh())
}
