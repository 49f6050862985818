//! The crate's error type: every failure is one human-readable line.

use std::path::PathBuf;

/// Errors reported by the library; the CLI prints them as one line.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An input or output file could not be accessed.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The input file is malformed or inconsistent with the options given.
    #[error("{0}")]
    Format(String),
    /// The options are invalid (bad isovalue, unknown extension, ...).
    #[error("{0}")]
    Invalid(String),
}

/// Result alias for the crate.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
