//! # tmc: topologically correct and manifold marching cubes
//!
//! tmc extracts isosurfaces of the piecewise trilinear interpolant of a
//! regular grid with R. Grosso's hybrid marching cubes ("Construction of
//! Topologically Correct and Manifold Isosurfaces", 2016): unambiguous cells
//! use the standard marching-cubes table, ambiguous cells are triangulated
//! from contours built with the asymptotic decider and classified by the
//! three quadratic equations of the paper.
//!
//! The pipeline, one module per stage:
//! `volume` (sample sources) -> `slab` (layers of cells, per-row edge numbers) ->
//! `kernel` (one cell) -> `seam` (global vertex numbering across slabs) ->
//! `mesh` -> `export` (PLY, OBJ, OFF, STL); `check` validates meshes.
//!
//! ## Conventions (invariants every module keeps)
//! * A sample is **inside** iff `value > iso`; a sample equal to the isovalue
//!   is outside, and NaN samples are outside. The mesh has the topology of
//!   `{T > iso + ε}` for an infinitesimal `ε > 0`, `T` the trilinear
//!   interpolant; face and body saddle ties follow from the same rule.
//! * Vertices are shared by topology: an edge vertex is keyed by its global
//!   grid edge, an interior vertex belongs to its cell; nothing is welded by
//!   distance.
//! * Triangles are counter-clockwise seen from outside, so normals point
//!   toward lower values (`Inside::Low` flips the roles of high and low).
//! * Coordinates are physical: `origin + index * spacing`, x fastest.

#![warn(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

pub mod budget;
pub mod check;
pub mod error;
pub mod export;
pub mod histogram;
pub mod kernel;
pub mod mesh;
pub mod meshfile;
pub mod multi;
pub mod part;
pub mod pipeline;
pub mod schedule;
pub mod seam;
pub mod sink;
pub mod slab;
pub mod stats;
pub mod synth;
pub mod volume;

pub use error::{Error, Result};
pub use mesh::Mesh;
pub use multi::extract_many_to;
pub use pipeline::{
    extract, extract_part_to, extract_to, ExtractParams, Inside, Method, PipelineOptions, Progress,
};
pub use sink::{Chunk, MeshBuilder, MeshInfo, MeshSink, Totals};
pub use stats::Stats;
pub use volume::{ArrayVolume, Grid, SampleSource};
