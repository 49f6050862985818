//! Reading volumes: every input format against fixtures written by third-party
//! writers, the readers' shared behaviour, planes too big to copy, and one
//! clear error for every kind of bad input.
//!
//! One test binary per stage keeps `cargo test --release` from linking (and
//! LTO-optimising) the library once per test file.

#[path = "../common/mod.rs"]
mod common;

mod bad_inputs;
mod big_planes;
mod dicom;
mod fuzz_regressions;
mod hdf5;
mod info;
mod label_runs;
mod nifti_mhd;
mod nrrd;
mod readers;
mod tiff_voxel;
mod vtk_tiff;
mod wide_types;
mod zarr;
