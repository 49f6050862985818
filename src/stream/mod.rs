//! The streaming machinery: a volume of any size becomes a stream of mesh
//! chunks in plane order, with memory set by the slab, not the volume.
//!
//! One extraction is one [`pass`] over the cell layers, told as its steps:
//! 1. **plan** ([`budget`], [`threads`]): the slab depth and how many slabs
//!    may be in flight, from the plane size, the threads and `--max-memory`;
//! 2. **schedule** ([`schedule`]): the writing thread cuts the next slab as
//!    soon as the window and the measured mesh in flight allow, only within
//!    the layers of the part asked for ([`parts`]);
//! 3. **triangulate** ([`crate::slab`]): a worker turns the slab's layers
//!    into one chunk per grid plane, for each isovalue while the planes are
//!    resident, and, with normals, gives the chunks their gradient normals
//!    as each block is finished ([`crate::normals::SlabNormals`]); then it
//!    encodes the chunks for a sink that has a
//!    [`MeshSink::encoder`](crate::mesh::MeshSink::encoder) (a `.tmesh`
//!    chunk's compressed payload), so that the one thread feeding the
//!    sinks only writes bytes;
//! 4. **stitch** ([`seam`]): finished slabs, in any order, are put back in
//!    plane order and handed to each isovalue's sink with global vertex
//!    numbers; nothing is matched by position. Each sink is wrapped in a
//!    [`crate::normals::FillPending`], which gives the vertices without a
//!    gradient their triangles' normal, one chunk behind, and, for a part
//!    with normals, drops the layer of context computed on each side.
//!
//! The output does not depend on the threads, the slab depth or the parts:
//! a chunk's content depends on its two planes only (see [`crate::slab`]).
//! A finished run is described by a [`RunSummary`] ([`report`]). A label
//! map is the same pass with one output per label ([`labels`]): only what a
//! worker does with a slab differs; [`label_report`] describes its run.

pub mod budget;
pub mod cancellable;
pub mod entry;
mod label_codes;
pub mod label_report;
pub mod labels;
pub mod parts;
pub mod pass;
pub mod preflight;
pub mod report;
pub mod schedule;
pub mod seam;
pub mod threads;

pub use entry::{extract, extract_part_to, extract_to};
pub use label_report::{LabelReport, LabelRun};
pub use labels::{
    extract_labels_to, extract_labels_with_runs_to, label_runs_room, last_label_chunks, MOST_LABELS,
};
pub use parts::layer_range;
pub use pass::{check_budget, extract_many_to};
pub use preflight::check_grid;
pub use report::RunSummary;
pub use seam::Seam;
