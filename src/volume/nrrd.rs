//! (in progress) `.nrrd` reader.
use crate::{Error, Result};
/// Opens a `.nrrd` file.
pub fn open(path: &std::path::Path) -> Result<super::ArrayVolume> {
    Err(Error::Invalid(format!(
        "{}: nrrd not yet supported",
        path.display()
    )))
}
