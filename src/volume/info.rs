//! What `tmc info` reports about a volume, as one value: [`VolumeInfo`],
//! the object `tmc info --json` prints.
//!
//! The library owns it so that every caller (the CLI, a language binding)
//! reports the same facts under the same names. [`volume_info`] opens
//! nothing: it summarizes a source the caller opened (see
//! [`open()`](super::open())) and gathers the header facts and the
//! streamed [`Summary`] with [`describe`].

use super::{format_name, summarize, RawOptions, SampleSource, Summary, SummaryOptions};
use super::{ChunkNotes, SegmentNote, ValueFrom};
use crate::grid::Grid;
use crate::{Error, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Samples the histogram pass reads at most when the plane step is
/// automatic (see [`automatic_plane_step`]).
pub const HISTOGRAM_BUDGET: u64 = 1 << 28;

/// The fewest histogram bins [`volume_info`] accepts.
pub const MIN_BINS: usize = 3;

/// The most histogram bins [`volume_info`] accepts.
pub const MAX_BINS: usize = 4096;

/// Everything `tmc info` reports about a volume; serialized (serde) it is
/// the JSON object of `tmc info --json`, keys in this order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VolumeInfo {
    /// The input path as given.
    pub input: String,
    /// The reader: "NRRD", "NIfTI-1", "TIFF stack", "raw", ... (see
    /// [`format_name`]), or "unknown".
    pub format: &'static str,
    /// Size of the input file and the data files it names (all regular
    /// files of a directory); `None` if one cannot be read.
    pub file_bytes: Option<u64>,
    /// Samples times the stored sample size; `None` if the stored type is
    /// unknown.
    pub data_bytes: Option<u64>,
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// The product of `dims`.
    pub samples: u64,
    /// The stored sample type ("u8", "i16", "f32", ...; before any NIfTI
    /// scaling), if known.
    pub sample_type: Option<&'static str>,
    /// Distance between samples along x, y, z.
    pub spacing: [f64; 3],
    /// World position of sample (0, 0, 0).
    pub origin: [f64; 3],
    /// Where the spacing came from: the file, the default, `--spacing`.
    pub spacing_from: ValueFrom,
    /// Where the origin came from: the file, the default, `--origin`.
    pub origin_from: ValueFrom,
    /// Chunk shape, codec and stored size of a chunked source (Zarr,
    /// HDF5), else `None`.
    pub chunks: Option<ChunkNotes>,
    /// The unit of the values, where the file states one (an RT Dose's
    /// `DoseUnits`, GY or RELATIVE); `null` otherwise.
    pub units: Option<String>,
    /// The segments of a DICOM Segmentation object (absent for any other
    /// input).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub segments: Vec<SegmentNote>,
    /// Pairs of its segments that share samples (absent when none do).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub overlapping_segments: Vec<[u32; 2]>,
    /// Direction cosines: rows are world axes, column `j` is index axis `j`.
    pub direction: [[f64; 3]; 3],
    /// The 4x4 index-to-world matrix: `world = affine * [i, j, k, 1]`.
    pub affine: [[f64; 4]; 4],
    /// Smallest finite sample, if any.
    pub min: Option<f64>,
    /// Largest finite sample, if any.
    pub max: Option<f64>,
    /// Mean of the finite samples, if any.
    pub mean: Option<f64>,
    /// NaN samples.
    pub nan_count: u64,
    /// Infinite samples.
    pub infinite_count: u64,
    /// Whether every finite sample is a whole number.
    pub integer_valued: bool,
    /// Bins of the histogram; `None` for fewer than two distinct values.
    pub histogram_bins: Option<usize>,
    /// The histogram counted planes `0, k, 2k, ...` for this `k`.
    pub histogram_plane_step: usize,
    /// `[low, high]` from two-level Otsu, or empty if none.
    pub suggested_iso: Vec<f64>,
    /// Single-level Otsu, if any.
    pub suggested_iso_single: Option<f64>,
}

/// The plane step of the histogram pass when none is asked for: 1, or
/// enough that it reads at most about [`HISTOGRAM_BUDGET`] of `samples`.
pub fn automatic_plane_step(samples: u64) -> usize {
    usize::try_from(samples.div_ceil(HISTOGRAM_BUDGET).max(1)).unwrap_or(usize::MAX)
}

/// Summarizes `source` (read from `input`, with `raw` if it is headerless)
/// and describes it: `bins` histogram bins ([`MIN_BINS`] to [`MAX_BINS`]),
/// every `plane_step`-th plane in the histogram, 0 for
/// [`automatic_plane_step`]. This is `tmc info` in one call.
pub fn volume_info(
    input: &Path,
    raw: Option<&RawOptions>,
    source: &dyn SampleSource,
    bins: usize,
    plane_step: usize,
) -> Result<VolumeInfo> {
    if !(MIN_BINS..=MAX_BINS).contains(&bins) {
        return Err(Error::Invalid(format!(
            "histogram bins must be {MIN_BINS} to {MAX_BINS}, not {bins}"
        )));
    }
    let samples = source.grid().dims.iter().map(|&n| n as u64).product();
    let options = SummaryOptions {
        bins,
        plane_step: match plane_step {
            0 => automatic_plane_step(samples),
            k => k,
        },
    };
    let summary = summarize(source, &options)?;
    Ok(describe(input, raw, source, &summary))
}

/// Gathers the header facts of `source` (read from `input`, with `raw` if
/// it is headerless) and its `summary` (see [`summarize`]).
pub fn describe(
    input: &Path,
    raw: Option<&RawOptions>,
    source: &dyn SampleSource,
    summary: &Summary,
) -> VolumeInfo {
    let grid = source.grid();
    let stored = source.stored_type();
    let suggestions = summary.suggestions();
    let notes = source.notes();
    VolumeInfo {
        input: input.display().to_string(),
        format: format_name(input, raw).unwrap_or("unknown"),
        file_bytes: file_bytes(input, source),
        data_bytes: stored.map(|t| summary.samples.saturating_mul(t.size() as u64)),
        dims: grid.dims,
        samples: summary.samples,
        sample_type: stored.map(|t| t.name()),
        spacing: grid.spacing,
        origin: grid.origin,
        spacing_from: notes.spacing_from,
        origin_from: notes.origin_from,
        chunks: notes.chunks,
        units: notes.units,
        segments: notes.segments,
        overlapping_segments: notes.overlapping_segments,
        direction: grid.direction,
        affine: affine(grid),
        min: summary.min,
        max: summary.max,
        mean: summary.mean,
        nan_count: summary.nan,
        infinite_count: summary.infinite,
        integer_valued: summary.integer_valued,
        histogram_bins: summary.histogram.as_ref().map(|h| h.counts.len()),
        histogram_plane_step: summary.plane_step,
        suggested_iso: suggestions.pair.map(Vec::from).unwrap_or_default(),
        suggested_iso_single: suggestions.single,
    }
}

/// The 4x4 index-to-world matrix: `world = A * [i, j, k, 1]`, with
/// `A[r][c] = direction[r][c] * spacing[c]` and the origin as last column.
fn affine(grid: &Grid) -> [[f64; 4]; 4] {
    let mut a = [[0.0; 4]; 4];
    for (r, row) in a.iter_mut().take(3).enumerate() {
        for (c, v) in row.iter_mut().take(3).enumerate() {
            *v = grid.direction[r][c] * grid.spacing[c];
        }
        row[3] = grid.origin[r];
    }
    a[3][3] = 1.0;
    a
}

/// Size of the input: the regular files directly in a directory, else the
/// file (if it is one) and the data files it names (a detached header's
/// data, the files of a glob), each once; `None` if one cannot be read.
fn file_bytes(path: &Path, source: &dyn SampleSource) -> Option<u64> {
    let meta = std::fs::metadata(path).ok();
    if meta.as_ref().is_some_and(|m| m.is_dir()) {
        let mut total = 0u64;
        for entry in std::fs::read_dir(path).ok()? {
            let meta = entry.ok()?.metadata().ok()?;
            if meta.is_file() {
                total += meta.len();
            }
        }
        return Some(total);
    }
    let mut files: Vec<PathBuf> = source
        .data_files()
        .into_iter()
        .chain(meta.filter(|m| m.is_file()).map(|_| path))
        .map(|f| std::fs::canonicalize(f).unwrap_or_else(|_| f.to_path_buf()))
        .collect();
    files.sort();
    files.dedup();
    files
        .iter()
        .map(|f| std::fs::metadata(f).ok().map(|m| m.len()))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::ArrayVolume;

    #[test]
    fn automatic_plane_step_keeps_the_histogram_within_budget() {
        assert_eq!(automatic_plane_step(0), 1);
        assert_eq!(automatic_plane_step(HISTOGRAM_BUDGET), 1);
        assert_eq!(automatic_plane_step(HISTOGRAM_BUDGET + 1), 2);
        assert_eq!(automatic_plane_step(5 * HISTOGRAM_BUDGET), 5);
    }

    #[test]
    fn volume_info_refuses_bins_out_of_range() {
        let source = ArrayVolume::new(Grid::unit([2, 2, 2]), vec![0.0; 8]).unwrap();
        let path = Path::new("memory");
        for bins in [0, MIN_BINS - 1, MAX_BINS + 1] {
            assert!(volume_info(path, None, &source, bins, 0).is_err());
        }
        let info = volume_info(path, None, &source, MIN_BINS, 0).unwrap();
        assert_eq!(info.samples, 8);
        assert_eq!(info.histogram_plane_step, 1);
        assert_eq!(info.affine[3], [0.0, 0.0, 0.0, 1.0]);
    }
}
