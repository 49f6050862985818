//! [`SourceNotes`]: what a reader knows about where its grid came from and
//! how its samples are stored, beyond the samples themselves. Only
//! reported (`tmc info`, the notes of `--spacing` and `--origin`), never
//! used to read.

use serde::Serialize;
use std::fmt;

/// Where the spacing or the origin of a grid came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ValueFrom {
    /// The file states none (a `.npy`, a TIFF without voxel size, raw
    /// samples): the default, unit spacing or zero origin.
    Default,
    /// The file states it; `what` names where ("header", "ImageJ
    /// metadata (micron, in mm)", "OME-Zarr scale", ...).
    File {
        /// Where in the file, and any unit conversion made.
        what: String,
    },
    /// `--spacing` or `--origin` set it; `file` is the value the file
    /// stated and the option overrode, if it stated one.
    Option {
        /// The overridden value of the file, if any.
        file: Option<[f64; 3]>,
    },
}

impl ValueFrom {
    /// The value stated in the file's header (what most readers say).
    pub fn header() -> ValueFrom {
        ValueFrom::File {
            what: "header".to_string(),
        }
    }
}

impl fmt::Display for ValueFrom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValueFrom::Default => write!(f, "default (the file states none)"),
            ValueFrom::File { what } => write!(f, "file ({what})"),
            ValueFrom::Option { file: None } => write!(f, "command line"),
            ValueFrom::Option {
                file: Some([x, y, z]),
            } => {
                write!(f, "command line (overrides the file's {x} {y} {z})")
            }
        }
    }
}

/// How a chunked source stores its samples (Zarr, chunked HDF5).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChunkNotes {
    /// Samples of one chunk along x, y, z (the inner chunk of a shard).
    pub chunk_shape: [usize; 3],
    /// The codecs or filters, in the order they were applied when writing
    /// ("bytes(little) > blosc(zstd, shuffle)", ...).
    pub codec: String,
    /// Bytes the stored chunks take on disk (compressed), if known.
    pub stored_bytes: Option<u64>,
    /// Chunks in the array, and how many of them are stored (a missing
    /// chunk reads as the fill value).
    pub chunks: u64,
    /// Chunks present on disk, if counted.
    pub chunks_stored: Option<u64>,
}

/// One segment of a DICOM Segmentation object, as `tmc info` lists it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentNote {
    /// `SegmentNumber`: the label its samples have in the label map, and
    /// what `--segment` takes.
    pub number: u32,
    /// `SegmentLabel` (empty if the file states none).
    pub label: String,
    /// The code meaning of its Segmented Property Type (what it is:
    /// "Liver", "Tissue" ...), if stated.
    pub property: Option<String>,
    /// `SegmentAlgorithmType`: AUTOMATIC, SEMIAUTOMATIC or MANUAL.
    pub algorithm: Option<String>,
    /// Frames of the file that hold it (a frame per slice it touches, for
    /// most writers).
    pub frames: usize,
}

/// What a source tells about itself beyond its grid and samples (see
/// [`super::SampleSource::notes`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SourceNotes {
    /// Where the spacing came from.
    pub spacing_from: ValueFrom,
    /// Where the origin came from.
    pub origin_from: ValueFrom,
    /// How the samples are chunked and compressed, for chunked formats.
    pub chunks: Option<ChunkNotes>,
    /// The unit of the values, where the file states one (an RT Dose's
    /// `DoseUnits`: GY or RELATIVE).
    pub units: Option<String>,
    /// Files of the input that were not read, and why, one line each (a
    /// DICOM directory's other series, non-image objects, strays); printed
    /// by `--verbose`, not part of `tmc info --json`.
    #[serde(skip)]
    pub skipped: Vec<String>,
    /// The segments of a DICOM Segmentation object (empty for any other
    /// source).
    pub segments: Vec<SegmentNote>,
    /// Pairs of segments of a DICOM Segmentation that share samples,
    /// `[lower, higher]` ascending: a label map holds one segment per
    /// sample (the higher number), so `--labels` refuses such a file.
    pub overlapping_segments: Vec<[u32; 2]>,
    /// What the reader read otherwise than the file wrote it, because as
    /// written it was unusable (a NIfTI's zero `pixdim` read as spacing 1),
    /// one line each: the CLI prints them as notes on stderr (unless
    /// `-q`), so that a default stands in for a value silently nowhere.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

impl Default for SourceNotes {
    /// Spacing and origin from the file's header; not chunked.
    fn default() -> Self {
        SourceNotes {
            spacing_from: ValueFrom::header(),
            origin_from: ValueFrom::header(),
            chunks: None,
            units: None,
            skipped: Vec::new(),
            segments: Vec::new(),
            overlapping_segments: Vec::new(),
            warnings: Vec::new(),
        }
    }
}

impl SourceNotes {
    /// Notes of a source whose file states neither spacing nor origin.
    pub fn no_grid() -> SourceNotes {
        SourceNotes {
            spacing_from: ValueFrom::Default,
            origin_from: ValueFrom::Default,
            chunks: None,
            units: None,
            skipped: Vec::new(),
            segments: Vec::new(),
            overlapping_segments: Vec::new(),
            warnings: Vec::new(),
        }
    }
}
