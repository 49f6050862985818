//! The PNG file, written with the `png` crate through
//! [`crate::files::write_atomically`]: nothing appears at the path unless
//! the whole file was written.

use crate::{Error, Result};
use std::path::Path;

/// Writes `rgb` (8-bit RGB, row by row) as a `width` x `height` PNG at
/// `path`, atomically. The bytes depend on the pixels only.
pub fn write_png(path: &Path, width: usize, height: usize, rgb: &[u8]) -> Result<()> {
    let (w, h) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) if rgb.len() == width * height * 3 => (w, h),
        _ => {
            return Err(Error::Invalid(format!(
                "{}: bad picture size",
                path.display()
            )))
        }
    };
    crate::files::write_atomically(path, |out| {
        let mut encoder = png::Encoder::new(out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        // Each row against the one above: cheap, and good on flat areas.
        encoder.set_filter(png::Filter::Up);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer
            .write_image_data(rgb)
            .map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
}

/// Refuses an output path that does not end in `.png` (any case).
pub fn check_png_path(path: &Path) -> Result<()> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("png") => crate::files::check_output_file(path),
        _ => Err(Error::Invalid(format!(
            "{}: a preview is a PNG picture, so its path must end in .png",
            path.display()
        ))),
    }
}
