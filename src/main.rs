//! The `tmc` command: extract isosurfaces from volumes, check meshes.
//!
//! Everything lives in the binary-only [`cli`] module; see `tmc --help`.

#![deny(clippy::undocumented_unsafe_blocks)]

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
