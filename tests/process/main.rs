//! The process around a run: interrupts and their latency, memory and file
//! resources, a real (local) Slurm cluster and the Python package's pytest
//! suite.
//!
//! One test binary per stage keeps `cargo test --release` from linking (and
//! LTO-optimising) the library once per test file.

#[path = "../common/mod.rs"]
mod common;

mod interrupt_latency;
mod interrupts;
mod python_package;
mod resources;
mod slurm;
