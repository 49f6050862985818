//! (in progress) `.npy` reader.
use crate::{Error, Result};
/// Opens a `.npy` file.
pub fn open(path: &std::path::Path) -> Result<super::ArrayVolume> {
    Err(Error::Invalid(format!(
        "{}: npy not yet supported",
        path.display()
    )))
}
