//! The samples a part shares with its neighbours: part i's last plane is
//! part i+1's first, and `merge` checks that both read the same samples
//! there (parts of different inputs disagree).

use crate::volume::Padded;
use crate::{Result, SampleSource};
use std::ops::Range;

/// Samples hashed per update.
const BLOCK: usize = 1024;

/// CRC-32 of the samples (the little-endian bits of the `f64` values, as the
/// extraction reads them, padded with `close`) of the first and the last
/// plane of the cell layers `layers`.
pub fn seam_checksums(
    source: &dyn SampleSource,
    close: bool,
    layers: Range<usize>,
) -> Result<[u32; 2]> {
    let padded;
    let source: &dyn SampleSource = if close {
        padded = Padded::new(source);
        &padded
    } else {
        source
    };
    let len = source.grid().plane_len();
    let mut plane = crate::error::try_filled("a plane of samples", len, 0.0)?;
    let mut crc = |z: usize| -> Result<u32> {
        source.read_plane(z, &mut plane)?;
        let mut hasher = crc32fast::Hasher::new();
        let mut bytes = Vec::with_capacity(BLOCK * 8);
        for block in plane.chunks(BLOCK) {
            bytes.clear();
            bytes.extend(block.iter().flat_map(|v| v.to_bits().to_le_bytes()));
            hasher.update(&bytes);
        }
        Ok(hasher.finalize())
    };
    Ok([crc(layers.start)?, crc(layers.end)?])
}
