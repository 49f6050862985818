//! The `tmc` binary's behaviour: help and I/O errors, the mesh file and its
//! exports, split and merge, batch runs, compare, previews and the scripts
//! that read its outputs.
//!
//! One test binary per stage keeps `cargo test --release` from linking (and
//! LTO-optimising) the library once per test file.

#[path = "../common/mod.rs"]
mod common;

mod batch;
mod check_stream;
mod compare;
mod export_stream;
mod huge_dims;
mod io;
mod label_args;
mod label_names;
mod meshfile;
mod normals;
mod placeholders;
mod preview;
mod preview_frame;
mod preview_labels;
mod quiet;
mod scripts;
mod split_merge;
