//! [`MappedPages`]: the pages of a TIFF stack that are stored as plain
//! samples (uncompressed, in strips that follow one another, in the
//! machine's byte order), lent to the slab loop from a memory map of their
//! file instead of decoded into `f64`s: the page cache, not the process,
//! then holds them, as it does for a raw NRRD. Micro-CT stacks of 8192 x
//! 8192 slices are mostly stored so; before, each plane was decoded (2
//! bytes per sample for 16 bits), turned into `f64`s (8 more) and copied
//! into the slab loop's plane (8 more): some 2 GiB per worker.
//!
//! Compressed, tiled, predicted, inverted (`WhiteIsZero`) or foreign-order
//! pages are decoded as before.

use super::mapped::MappedFile;
use super::{Access, LentPlane, ScalarType};
use crate::Result;
use std::fs::File;
use std::io::BufReader;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use tiff::decoder::{ChunkType, Decoder};
use tiff::tags::{ByteOrder, Tag};

/// Where each plane's samples lie, for the pages stored as plain samples,
/// and the maps of their files, opened as their planes are first lent
/// (without holding the files open, so that a stack of many slices needs
/// no file descriptor per slice).
#[derive(Default)]
pub(super) struct MappedPages {
    /// Per plane: the index of its file in `files` and the bytes of its
    /// samples there, if the page is stored as plain samples.
    planes: Vec<Option<(usize, Range<usize>)>>,
    /// The stack's files, in order, with their maps once opened (`None`
    /// if mapping failed: then the planes are decoded).
    files: Vec<(PathBuf, OnceLock<Option<MappedFile>>)>,
}

impl std::fmt::Debug for MappedPages {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let lent = self.planes.iter().filter(|p| p.is_some()).count();
        write!(f, "MappedPages({lent} of {} planes)", self.planes.len())
    }
}

impl MappedPages {
    /// Notes the next plane: page of `file` (a file not seen before is
    /// added after the others), stored at `bytes` if plain samples.
    pub(super) fn push(&mut self, file: &Path, bytes: Option<Range<usize>>) {
        if self.files.last().is_none_or(|(f, _)| f != file) {
            self.files.push((file.to_path_buf(), OnceLock::new()));
        }
        let index = self.files.len() - 1;
        self.planes.push(bytes.map(|b| (index, b)));
    }

    /// Plane `z` from its file's map, if the page is stored as plain
    /// samples of `scalar` and its bytes lie in the file.
    pub(super) fn lend(&self, z: usize, scalar: ScalarType) -> Option<LentPlane<'_>> {
        let (file, bytes) = self.planes.get(z)?.as_ref()?;
        let (path, map) = &self.files[*file];
        let map = map
            .get_or_init(|| MappedFile::open_unheld(path).ok())
            .as_ref()?;
        LentPlane::from_bytes(scalar, map.bytes().get(bytes.clone())?)
    }

    /// Passes read-ahead or release advice for `planes` to the maps
    /// already open.
    pub(super) fn advise(&self, planes: Range<usize>, access: Access) {
        for (file, bytes) in self.planes.get(planes).into_iter().flatten().flatten() {
            if let Some(map) = self.files[*file].1.get().and_then(Option::as_ref) {
                map.advise(bytes.clone(), access);
            }
        }
    }

    /// Fails if a mapped file has shrunk below its map (one `stat` per
    /// map open).
    pub(super) fn check_unchanged(&self) -> Result<()> {
        for (_, map) in &self.files {
            if let Some(map) = map.get().and_then(Option::as_ref) {
                map.check_unchanged()?;
            }
        }
        Ok(())
    }
}

/// The bytes of the current page of `dec` (`dims` samples of `scalar`) in
/// its file, if the page is stored as plain samples: one sample per pixel,
/// black is zero, uncompressed, no predictor, in strips that follow one
/// another, in the machine's byte order. `None` when it is not (the page
/// is then decoded).
pub(super) fn plain_bytes(
    dec: &mut Decoder<BufReader<File>>,
    (w, h): (u32, u32),
    scalar: ScalarType,
) -> Option<Range<usize>> {
    let native = match dec.byte_order() {
        ByteOrder::LittleEndian => cfg!(target_endian = "little"),
        ByteOrder::BigEndian => cfg!(target_endian = "big"),
    };
    if !native || dec.get_chunk_type() != ChunkType::Strip {
        return None;
    }
    let mut tag = |tag, default: u64| match dec.find_tag_unsigned::<u64>(tag) {
        Ok(v) => Some(v.unwrap_or(default)),
        Err(_) => None,
    };
    // Compression 1 (none), predictor 1 (none), BlackIsZero, one sample.
    let plain = tag(Tag::Compression, 1)? == 1
        && tag(Tag::Predictor, 1)? == 1
        && tag(Tag::PhotometricInterpretation, 1)? == 1
        && tag(Tag::SamplesPerPixel, 1)? == 1;
    let rows_per_strip = tag(Tag::RowsPerStrip, u64::from(u32::MAX))?.min(u64::from(h));
    if !plain || rows_per_strip == 0 {
        return None;
    }
    let offsets = dec.get_tag_u64_vec(Tag::StripOffsets).ok()?;
    let counts = dec.get_tag_u64_vec(Tag::StripByteCounts).ok()?;
    let row = u64::from(w).checked_mul(scalar.size() as u64)?;
    let strips = u64::from(h).div_ceil(rows_per_strip);
    if offsets.len() as u64 != strips || counts.len() as u64 != strips {
        return None;
    }
    // Each strip holds exactly its rows and starts where the last ended.
    let start = *offsets.first()?;
    let mut end = start;
    for (k, (&offset, &count)) in offsets.iter().zip(&counts).enumerate() {
        let rows = rows_per_strip.min(u64::from(h) - k as u64 * rows_per_strip);
        if offset != end || count != rows.checked_mul(row)? {
            return None;
        }
        end = end.checked_add(count)?;
    }
    Some(usize::try_from(start).ok()?..usize::try_from(end).ok()?)
}
