//! # tmc: topologically correct and manifold marching cubes
//!
//! tmc extracts isosurfaces of the piecewise trilinear interpolant of a
//! regular grid with R. Grosso's hybrid marching cubes ("Construction of
//! Topologically Correct and Manifold Isosurfaces", 2016): unambiguous cells
//! use the standard marching-cubes table, ambiguous cells are triangulated
//! from contours built with the asymptotic decider and classified by the
//! three quadratic equations of the paper.
//!
//! The pipeline, one folder per stage (see ARCHITECTURE.md for the map):
//! [`volume`] (sample sources) -> [`stream`] (slabs scheduled, in flight and
//! stitched) -> [`slab`] (layers of cells, per-row edge numbers) ->
//! [`kernel`] (one cell) -> [`mesh`] (chunks into a sink) -> [`meshfile`]
//! (`.tmesh`) and [`export`] (PLY, OBJ, OFF, STL); [`part`] splits and
//! merges runs, [`check`] validates meshes, [`normals`] gives a mesh's
//! vertices normals from the field's gradient, [`synth`] makes test volumes.
//! Beneath them all: [`params`], [`grid`], [`stats`], [`error`] and
//! [`files`], which import nothing above them.
//!
//! ## Conventions (invariants every module keeps)
//! * A sample is **inside** iff `value > iso`; a sample equal to the isovalue
//!   is outside, and NaN samples are outside. The mesh has the topology of
//!   `{T > iso + ε}` for an infinitesimal `ε > 0`, `T` the trilinear
//!   interpolant; face and body saddle ties follow from the same rule.
//! * Vertices are shared by topology: an edge vertex is numbered by the
//!   plane that owns its grid edge, an interior vertex belongs to its cell; nothing is welded by
//!   distance.
//! * Triangles are counter-clockwise seen from outside, so normals point
//!   toward lower values (`Inside::Low` flips the roles of high and low).
//! * Coordinates are physical: `origin + direction * (index * spacing)` (see
//!   [`Grid::world`]), x fastest.

#![warn(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

pub mod check;
pub mod compare;
pub mod error;
pub mod export;
pub mod fan_out;
pub mod files;
pub mod grid;
pub mod kernel;
pub mod mesh;
pub mod meshfile;
pub mod normals;
pub mod params;
pub mod part;
pub mod preview;
pub mod slab;
pub mod stats;
pub mod stream;
pub mod synth;
pub mod volume;

pub use error::{Error, Result};
pub use grid::Grid;
pub use mesh::{Chunk, ChunkEncoder, Mesh, MeshBuilder, MeshInfo, MeshSink, Totals};
pub use params::{ExtractParams, Inside, Method, PipelineOptions, Progress, VertexValues};
pub use stats::Stats;
pub use stream::{extract, extract_many_to, extract_part_to, extract_to};
pub use volume::{ArrayVolume, SampleSource};
