//! The mesh vocabulary: what an extraction produces and how it is handed on.
//!
//! An extraction streams [`Chunk`]s, in plane order, into a [`MeshSink`];
//! [`MeshBuilder`] is the sink that assembles an in-memory [`Mesh`], and the
//! file writers (`meshfile`, `export`) are the others. This module knows
//! nothing of volumes, slabs or files.

mod builder;
mod chunk;
mod indexed;
mod room;
mod sink;

pub use builder::{Collector, MeshBuilder, Vertex};
pub use chunk::Chunk;
pub use indexed::Mesh;
pub use room::{fit, reserve_for_planes, FIRST_ROOM};
pub(crate) use sink::used_after_finish;
pub use sink::{ChunkEncoder, MeshInfo, MeshSink, Totals};
