//! The process around a run: interrupts and their latency, memory and file
//! resources, a real (local) Slurm cluster and the Python package's pytest
//! suite.
//!
//! One test binary per stage keeps `cargo test --release` from linking (and
//! LTO-optimising) the library once per test file.

#[path = "../common/mod.rs"]
mod common;

/// Tests whose extractions load both cores (the memory bounds') hold this
/// for reading; the pytest suite, whose interrupt tests time how soon a
/// child answers SIGINT, holds it for writing, so it never runs beside
/// them (beside the streaming check's test it took 0.62-0.75 s, not 0.5).
pub static CORES: std::sync::RwLock<()> = std::sync::RwLock::new(());

mod budget;
mod interrupt_latency;
mod interrupts;
mod python_package;
mod resources;
mod slurm;
