//! How tmc touches the file system: outputs that appear whole or not at all,
//! temporary files removed even on a fatal signal, and paths checked before
//! any work is done.
//!
//! Every mesh and volume writer (volumes, `.tmesh`, PLY/OBJ/OFF/STL) goes
//! through [`AtomicFile`], so a failed or interrupted run never leaves a
//! partial file at the output path. (The one file written otherwise is the
//! `--report` JSON-lines file of a batch, appended to line by line.)

mod atomic;
pub mod fatal_cleanup;
mod open_files;
mod paths;
mod placeholders;
mod withdraw;

pub(crate) use atomic::without_temp_path;
pub use atomic::{output_error, write_atomically, AtomicFile};
pub use open_files::{check_open_files, raise_open_file_limit};
pub use paths::{
    check_distinct, check_input_kind, check_output_file, check_output_files, lowercase_extension,
};
pub use placeholders::{
    fill_placeholder, has_placeholder, insert_before_extension, unknown_placeholder,
};
pub use withdraw::withdraw;
