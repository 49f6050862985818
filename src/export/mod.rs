//! Mesh writers: PLY (binary little-endian), OBJ, OFF and STL (binary),
//! for whole meshes and as streaming [`MeshSink`](crate::MeshSink)s.
//!
//! [`create_sink`] picks a sink by the output extension (`.tmesh` too); the
//! pipeline ([`crate::stream`]) streams chunks into it and it never holds the whole mesh. PLY
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

mod by_extension;
mod early_finish;
mod label_files;
mod labelled;
mod numbering;
mod obj;
mod off;
mod ply;
mod replay;
mod set_aside;
mod spooled;
mod stl;

// Their home is `crate::files`; these paths are kept for the callers that
// used them when they lived here.
pub use crate::files::{check_output_file, fatal_cleanup, write_atomically, AtomicFile};
pub use by_extension::{
    check_normals_output, check_output_path, check_output_paths, create_sink, write_mesh, Format,
};
pub use label_files::{
    check_label_outputs, check_label_template, label_outputs, open_files_per_label, LabelFile,
    LabelFiles, LabelSink, FINISHING_THREADS,
};
pub use labelled::write_labelled;
pub use obj::{write_obj, Obj, ObjSink};
pub use off::{write_off, Off, OffSink};
pub use ply::{write_ply, Ply, PlySink};
pub use replay::{replay, replay_cancellable};
pub use spooled::{write_whole, Layout, SpooledSink};
pub use stl::{write_stl, StlSink};
