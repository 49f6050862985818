//! (in progress) raw reader.
use crate::{Error, Result};
/// A raw volume.
pub struct RawVolume;
impl RawVolume {
    /// Opens a raw file.
    pub fn open(path: &std::path::Path, _o: &super::RawOptions) -> Result<super::ArrayVolume> {
        Err(Error::Invalid(format!(
            "{}: raw not yet supported",
            path.display()
        )))
    }
}
