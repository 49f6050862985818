//! [`withdraw`]: outputs taken back when a run fails after committing them.

use crate::Error;
use std::path::Path;

/// The error of a run whose outputs were committed but which failed after
/// (a report that could not be written, another output that could not be
/// finished): the outputs are removed again, so that a failed run leaves
/// no new output (a file that was at an output path before the run was
/// replaced when the output was committed and is not restored). The
/// message names the files removed.
pub fn withdraw<'a>(outputs: impl IntoIterator<Item = &'a Path>, e: Error) -> Error {
    let removed: Vec<String> = outputs
        .into_iter()
        .filter(|o| std::fs::remove_file(o).is_ok())
        .map(|o| o.display().to_string())
        .collect();
    if removed.is_empty() {
        return e;
    }
    Error::Invalid(format!("{e}; removed the output {}", removed.join(", ")))
}
