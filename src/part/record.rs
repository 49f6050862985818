//! What a part file records about its run, and the input's identity.

use super::{seam_checksums, PartSpec};
use crate::{Error, Result, SampleSource};
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::Path;

/// Bytes at the start of the input that the identity checksums.
const HEAD_BYTES: u64 = 1 << 20;

/// Identifies an input across copies: its size and a checksum of its first
/// MiB (for a directory, of its file names and sizes); a detached header
/// (`.mhd`, `.nhdr`) adds its data files' sizes and the first one's MiB.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputId {
    /// Bytes in the input (summed over a directory's files).
    pub size: u64,
    /// CRC-32 of the first MiB (or of a directory's listing).
    pub crc: u32,
}

/// The part's own facts, beside the `.tmesh` header's grid and options.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PartRecord {
    /// The tmc version that wrote the part.
    pub tmc_version: String,
    /// Which part, 1 to `count`.
    pub index: usize,
    /// How many parts.
    pub count: usize,
    /// The part's cell layers (of the padded grid with `--close`).
    pub layers: [usize; 2],
    /// Cell layers of the whole run.
    pub total_layers: usize,
    /// The input's identity.
    pub input: InputId,
    /// How headerless samples were read (`--dtype`, `--dims`, `--endian`,
    /// `--header-bytes`, ...), `None` for inputs with a header.
    pub reading: Option<String>,
    /// What the run read of the input beyond the file or directory itself
    /// (an HDF5 dataset; a Zarr array, level or entry; a DICOM series or
    /// segment), as the options that choose it (`--dataset /scans --at
    /// 0=2`); `None` when nothing is chosen (and absent from its JSON). Two
    /// datasets of one file, or two channels of one image, have the input's
    /// identity and may agree at a seam.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub selection: Option<String>,
    /// CRC-32 of the samples of the part's first and last planes, which it
    /// shares with the parts before and after it (see [`seam_checksums`]).
    pub seam_crc: [u32; 2],
    /// The input's path as given (for messages only).
    pub input_name: String,
    /// The label whose surface the part holds (`tmc extract --labels`),
    /// `None` for an isosurface (and absent from its JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<i64>,
    /// How many labels the run made parts of (each label's part files hold
    /// the same count), so that a merge missing every part of a label
    /// says so; `None` for an isosurface and for parts of older versions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_count: Option<usize>,
}

impl PartRecord {
    /// The record of part `spec` of the extraction of `source` (read from
    /// `input`, headerless with `reading`), padded with `close`.
    pub fn new(
        spec: PartSpec,
        input: &Path,
        source: &dyn SampleSource,
        close: bool,
        reading: Option<String>,
    ) -> Result<PartRecord> {
        let pad = if close { 2 } else { 0 };
        let total = (source.grid().dims[2] + pad).saturating_sub(1);
        let range = super::layer_range(total, spec.index, spec.count)?;
        Ok(PartRecord {
            tmc_version: env!("CARGO_PKG_VERSION").to_string(),
            index: spec.index,
            count: spec.count,
            layers: [range.start, range.end],
            total_layers: total,
            input: identify(input, &source.data_files())?,
            reading,
            selection: None,
            seam_crc: seam_checksums(source, close, range)?,
            input_name: input.display().to_string(),
            label: None,
            label_count: None,
        })
    }
}

/// The identity of the input at `path` whose samples are read from
/// `data_files` (see [`SampleSource::data_files`]). An HDF5 dataset named
/// in the path (`scan.h5:/exchange/data`, no file of that name) is
/// identified by its file.
pub fn identify(path: &Path, data_files: &[&Path]) -> Result<InputId> {
    if let Some((file, _)) = crate::volume::hdf5::split_path(path) {
        return identify(&file, data_files);
    }
    let io = |e| Error::io(path, e);
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() {
        let mut names = Vec::new();
        for entry in std::fs::read_dir(path).map_err(io)? {
            let entry = entry.map_err(io)?;
            // Through links, as a copy that follows them sees the files. A
            // directory's own size is its file system's (4096 on ext4, by
            // entry on tmpfs and xfs), so a store copied to another node's
            // file system had another identity: a subdirectory (a Zarr
            // store's `c`) counts by its name alone.
            let meta = std::fs::metadata(entry.path()).map_err(io)?;
            let len = if meta.is_dir() { DIRECTORY } else { meta.len() };
            names.push((entry.file_name().to_string_lossy().into_owned(), len));
        }
        names.sort();
        let mut hasher = crc32fast::Hasher::new();
        for (name, len) in &names {
            hasher.update(name.as_bytes());
            hasher.update(&len.to_le_bytes());
        }
        let size = names.iter().map(|n| n.1).filter(|&n| n != DIRECTORY).sum();
        return Ok(InputId {
            size,
            crc: hasher.finalize(),
        });
    }
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&head(path)?);
    let mut size = meta.len();
    let detached: Vec<&&Path> = data_files.iter().filter(|d| **d != path).collect();
    for (k, data) in detached.iter().enumerate() {
        let len = std::fs::metadata(data)
            .map_err(|e| Error::io(data, e))?
            .len();
        size += len;
        hasher.update(&len.to_le_bytes());
        if k == 0 {
            hasher.update(&head(data)?);
        }
    }
    Ok(InputId {
        size,
        crc: hasher.finalize(),
    })
}

/// What a subdirectory of a directory input counts as, in place of a size.
const DIRECTORY: u64 = u64::MAX;

/// The first MiB of the file at `path`.
fn head(path: &Path) -> Result<Vec<u8>> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(HEAD_BYTES).read_to_end(&mut head))
        .map_err(|e| Error::io(path, e))?;
    Ok(head)
}

/// The section's footer: JSON length u64, CRC-32 of the JSON, tag.
pub(crate) const FOOTER_BYTES: usize = 16;
const TAG: &[u8; 4] = b"TPRT";

impl PartRecord {
    /// The section written between the last chunk and the index.
    pub(crate) fn encode(&self) -> Vec<u8> {
        let mut out = serde_json::to_vec(self).expect("a record serializes");
        let len = out.len() as u64;
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&crc.to_le_bytes());
        out.extend_from_slice(TAG);
        out
    }

    /// Reads the record of the part file at `path`.
    pub(crate) fn read(path: &Path) -> Result<PartRecord> {
        let json = PartRecord::read_json(path)?;
        serde_json::from_slice(&json).map_err(|_| {
            Error::Format(format!(
                "{}: the part record is not one this tmc ({}) reads (written by another version?); extract the parts again",
                path.display(),
                env!("CARGO_PKG_VERSION")
            ))
        })
    }

    /// The checked JSON of the record of the part file at `path`.
    fn read_json(path: &Path) -> Result<Vec<u8>> {
        use std::io::{Seek, SeekFrom};
        let io = |e| Error::io(path, e);
        let not_part = || {
            Error::Format(format!(
                "{}: not a part file (write parts with 'tmc extract --part I/N')",
                path.display()
            ))
        };
        // A FIFO would block the open below, and cannot seek.
        crate::files::check_input_kind(path)?;
        let mut file = std::fs::File::open(path).map_err(io)?;
        let mut magic = [0u8; 8];
        if file.read_exact(&mut magic).is_err() || magic != crate::meshfile::MAGIC {
            return Err(not_part());
        }
        let mut trailer = [0u8; crate::meshfile::TRAILER_BYTES];
        file.seek(SeekFrom::End(-(trailer.len() as i64)))
            .map_err(|_| not_part())?;
        file.read_exact(&mut trailer).map_err(io)?;
        if trailer[24..] != crate::meshfile::END_MAGIC {
            return Err(Error::Format(format!(
                "{}: the part file is truncated or damaged (its end marker is missing); extract this part again",
                path.display()
            )));
        }
        let index = u64::from_le_bytes(trailer[..8].try_into().expect("8 bytes"));
        let footer_at = index
            .checked_sub(FOOTER_BYTES as u64)
            .ok_or_else(not_part)?;
        file.seek(SeekFrom::Start(footer_at))
            .map_err(|_| not_part())?;
        let mut footer = [0u8; FOOTER_BYTES];
        file.read_exact(&mut footer).map_err(|_| not_part())?;
        if &footer[12..] != TAG {
            return Err(not_part());
        }
        let len = u64::from_le_bytes(footer[..8].try_into().expect("8 bytes"));
        let start = footer_at.checked_sub(len).ok_or_else(not_part)?;
        if len > 1 << 20 {
            return Err(not_part());
        }
        file.seek(SeekFrom::Start(start)).map_err(|_| not_part())?;
        let mut json = vec![0u8; len as usize];
        file.read_exact(&mut json).map_err(io)?;
        if crc32fast::hash(&json).to_le_bytes() != footer[8..12] {
            return Err(Error::Format(format!(
                "{}: the part record is damaged",
                path.display()
            )));
        }
        Ok(json)
    }

    /// Refuses the file at `path` if it is one part of several: such a file
    /// is not a whole mesh (its last chunk points into the next part).
    pub fn refuse_part(path: &Path) -> Result<()> {
        let Ok(json) = PartRecord::read_json(path) else {
            return Ok(());
        };
        match serde_json::from_slice::<PartRecord>(&json) {
            Ok(r) if r.count == 1 => Ok(()),
            _ => Err(Error::Format(format!(
                "{}: this is a part file of 'tmc extract --part I/N', not a whole mesh; stitch all the parts with 'tmc merge' first",
                path.display()
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// A directory input (a Zarr store, with its chunks under `c/`) copied
    /// to another file system has the same identity, though its
    /// subdirectory's size differs: ext4 reports 4096 for a new directory
    /// and does not shrink one whose entries were removed (as here), tmpfs
    /// and xfs count entries. The merge refused parts of a copy on another
    /// node ("inputs differ").
    #[test]
    fn a_directory_copy_with_other_subdirectory_sizes_is_the_same_input() {
        let dir = tempfile::tempdir().unwrap();
        let store = |name: &str, churn: usize| {
            let root = dir.path().join(name);
            std::fs::create_dir_all(root.join("c/0")).unwrap();
            std::fs::write(root.join("zarr.json"), b"{}").unwrap();
            std::fs::write(root.join("c/0/0"), b"chunk").unwrap();
            let churn: Vec<PathBuf> = (0..churn)
                .map(|k| root.join(format!("c/a-file-name-long-enough-to-fill-blocks-{k:05}")))
                .collect();
            for f in &churn {
                std::fs::write(f, b"").unwrap();
            }
            for f in &churn {
                std::fs::remove_file(f).unwrap();
            }
            root
        };
        let (a, b) = (store("a.zarr", 0), store("b.zarr", 2000));
        let size = |p: &Path| std::fs::metadata(p.join("c")).unwrap().len();
        if size(&a) == size(&b) {
            eprintln!("skipped: this file system gives both subdirectories one size");
            return;
        }
        assert_eq!(identify(&a, &[]).unwrap(), identify(&b, &[]).unwrap());
        // The files themselves still count.
        std::fs::write(b.join("zarr.json"), b"{ }").unwrap();
        assert_ne!(identify(&a, &[]).unwrap(), identify(&b, &[]).unwrap());
    }
}
