//! tmc's errors as Python exceptions: the CLI's one line as the message,
//! the class chosen by what went wrong.

use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyKeyboardInterrupt, PyMemoryError,
    PyNotADirectoryError, PyOSError, PyPermissionError, PyValueError,
};
use pyo3::PyErr;
use std::io::ErrorKind;

/// `tmc::Error` to the Python exception a Python user expects:
/// `FileNotFoundError`/`PermissionError`/`NotADirectoryError`/
/// `IsADirectoryError`/`OSError` for files (the same class whether the
/// check before a run or the write itself finds a missing directory),
/// `ValueError` for bad input or options, `MemoryError`, and
/// `KeyboardInterrupt` for a cancelled run.
pub(crate) fn to_py(error: tmc::Error) -> PyErr {
    let text = error.to_string();
    match &error {
        tmc::Error::Io { source, .. } => match source.kind() {
            ErrorKind::NotFound => PyFileNotFoundError::new_err(text),
            ErrorKind::PermissionDenied => PyPermissionError::new_err(text),
            ErrorKind::NotADirectory => PyNotADirectoryError::new_err(text),
            ErrorKind::IsADirectory => PyIsADirectoryError::new_err(text),
            _ => PyOSError::new_err(text),
        },
        tmc::Error::Format(_) | tmc::Error::Invalid(_) => PyValueError::new_err(text),
        tmc::Error::OutOfMemory(_) => PyMemoryError::new_err(text),
        tmc::Error::Interrupted => PyKeyboardInterrupt::new_err(text),
    }
}

/// `Result` of the library to `PyResult`.
pub(crate) trait OrPyErr<T> {
    /// The value, or the error as a Python exception (see [`to_py`]).
    fn or_py(self) -> pyo3::PyResult<T>;
}

impl<T> OrPyErr<T> for tmc::Result<T> {
    fn or_py(self) -> pyo3::PyResult<T> {
        self.map_err(to_py)
    }
}
