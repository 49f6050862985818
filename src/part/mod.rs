//! Split and merge: `tmc extract --part I/N` writes the chunks of one z-range
//! of cell layers to a part file; [`merge()`] stitches the parts into the mesh
//! a single run writes, byte for byte.
//!
//! The seam between two parts needs no vertex matching: a chunk's vertices
//! are numbered the same way whichever slab computes them, and a triangle of
//! the last layer of a part points into the first vertices of the next
//! plane's chunk, which the next part owns. So a part is a `.tmesh` file
//! whose vertex bases start at 0 and whose last chunk may point into the
//! next part; the merge renumbers by adding the vertex counts of the parts
//! before. A [`PartRecord`] (JSON) between the last chunk and the index
//! records what the merge checks: tmc version, part I of N and its layers,
//! the input's identity (size and a checksum of its first bytes, which
//! survive copying the input to another node), how headerless samples were
//! read, and checksums of the samples of the planes shared with the
//! neighbouring parts, which must agree across every seam.

mod merge;
mod record;
mod seams;
mod writer;

pub use crate::stream::layer_range;
pub use merge::merge;
pub use record::{identify, InputId, PartRecord};
pub use seams::seam_checksums;
pub use writer::PartWriter;

/// Part `index` of `count` (1-based), as in `--part 3/7`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartSpec {
    /// Which part, 1 to `count`.
    pub index: usize,
    /// How many parts.
    pub count: usize,
}

impl PartSpec {
    /// Parses `I/N` with 1 <= I <= N.
    pub fn parse(text: &str) -> std::result::Result<PartSpec, String> {
        let bad = || format!("'{text}' is not a part I/N with 1 <= I <= N (e.g. 3/7)");
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(PartSpec { index, count })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn part_specs_parse() {
        assert!(PartSpec::parse("4/3").is_err());
        assert_eq!(PartSpec::parse("2/3"), Ok(PartSpec { index: 2, count: 3 }));
    }
}
