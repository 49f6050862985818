//! How tmc touches the file system: outputs that appear whole or not at all,
//! temporary files removed even on a fatal signal, and paths checked before
//! any work is done.
//!
//! Every writer (volumes, `.tmesh`, PLY/OBJ/OFF/STL, reports) goes through
//! [`AtomicFile`], so a failed or interrupted run never leaves a partial
//! file at the output path.

mod atomic;
pub mod fatal_cleanup;
mod paths;

pub(crate) use atomic::without_temp_path;
pub use atomic::{write_atomically, AtomicFile};
pub use paths::{check_input_kind, check_output_file};
