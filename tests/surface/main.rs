//! The surface itself: the kernel against the independent oracle, ties,
//! shapes, synthetic and real volumes, the mesh checker, streaming, normals
//! and label maps.
//!
//! One test binary per stage keeps `cargo test --release` from linking (and
//! LTO-optimising) the library once per test file.

#[path = "../common/mod.rs"]
mod common;

mod check_geometry;
mod check_meshes;
mod edge_values;
mod label_stats;
mod labels;
mod normals;
mod oracle_selftest;
mod real_data;
mod shapes;
mod soak;
mod streaming;
mod synth;
mod ties;
mod topology;
