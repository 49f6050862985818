//! Reading triangle meshes (PLY, OBJ, OFF, `.tmesh`) for the checker, and
//! STL for drawing ([`read_mesh_to_draw`]: the checker refuses STL, which
//! shares no vertices).
//!
//! The readers keep exactly the connectivity that the file states: vertices
//! are never welded, polygons are fan-triangulated (`v0 vi vi+1`). Every
//! malformed input is reported as one line, [`Error::Format`](crate::Error::Format), prefixed with
//! the file name. Malformed includes content that the format does not allow:
//! an OBJ line that is not an OBJ statement (or not UTF-8 text), an OFF
//! vertex line with other columns than its header keyword declares (see
//! [`OffLayout`](off::OffLayout)), an OFF face line with anything but 0, 1, 3 or 4 numbers
//! (a colour) after its vertex indices, anything but blank lines and
//! comments after the faces an
//! OFF header declares, anything after the last element a PLY header
//! declares, and vertex coordinates that are not finite `f32` numbers.
//! `.tmesh` files are read with [`TmeshReader`](crate::meshfile::TmeshReader), which verifies every
//! checksum and names a damaged chunk.

mod by_extension;
mod obj;
mod off;
mod ply;
mod source;
mod stl;

pub use by_extension::{is_tmesh, read_mesh, read_mesh_to_draw};
