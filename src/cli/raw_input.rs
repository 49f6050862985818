//! The raw-input options (`--dims`, `--dtype`, ...), shared by every
//! subcommand that opens a volume, so that raw data is described the same
//! way everywhere.

use super::values;
use clap::{Args, ValueEnum};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use tmc::volume::{Endian, RawOptions, RawVolume, SampleSource, ScalarType};
use tmc::{Error, Result};

/// How to read headerless samples; all absent for a file with a header.
#[derive(Debug, Clone, Args)]
pub(crate) struct RawArgs {
    /// Raw input: samples along x, y, z (e.g. 256,256,128); needs --dtype.
    #[arg(long, value_name = "X,Y,Z", value_parser = values::dims, requires = "dtype", help_heading = "Raw input (headerless samples, x fastest)")]
    pub dims: Option<[usize; 3]>,

    /// Raw input: sample type, one of u8, i8, u16, i16, u32, i32, f32, f64,
    /// i64, u64, f16 (the last three read as f64: 64-bit integers exactly
    /// within ±2^53); needs --dims.
    #[arg(long, value_name = "T", value_parser = values::dtype, requires = "dims", help_heading = "Raw input (headerless samples, x fastest)")]
    pub dtype: Option<ScalarType>,

    /// Raw input: byte order of multi-byte samples [default: little].
    #[arg(
        long,
        value_enum,
        requires = "dims",
        help_heading = "Raw input (headerless samples, x fastest)"
    )]
    pub endian: Option<EndianArg>,

    /// Raw input: bytes to skip before the first sample [default: 0].
    #[arg(
        long,
        value_name = "N",
        requires = "dims",
        help_heading = "Raw input (headerless samples, x fastest)"
    )]
    pub header_bytes: Option<u64>,

    /// Distance between samples along x, y, z, finite and positive, for any
    /// input: sets it where the file states none (raw, .npy, a TIFF without
    /// voxel size; default 1,1,1), overrides the file's (with a note).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = values::spacing, help_heading = "Grid (any input)")]
    pub spacing: Option<[f64; 3]>,

    /// Position of the first sample, for any input: sets it where the file
    /// states none (default 0,0,0), overrides the file's (with a note).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = values::origin, help_heading = "Grid (any input)")]
    pub origin: Option<[f64; 3]>,

    /// Zarr: the array of a group to read (its path in the store), e.g.
    /// --array scans/ct; the same as giving STORE/scans/ct as the input.
    #[arg(long, value_name = "PATH", help_heading = "Zarr input")]
    pub array: Option<String>,

    /// OME-Zarr: the level of the multiscale pyramid to read (0, the
    /// finest, by default); its scale and translation give the grid.
    #[arg(
        long,
        value_name = "N",
        conflicts_with = "array",
        help_heading = "Zarr input"
    )]
    pub level: Option<usize>,

    /// Zarr and HDF5: the entry to read of each axis before z, y, x, e.g.
    /// --at c=1 for the second channel of an OME-Zarr image (t, c, z, y,
    /// x), or --at 0=3 by position (0 the slowest); axes of one entry need
    /// none; also a channel axis after x, as ilastik writes zyxc (--at
    /// 3=1). Only the chunks holding that entry are read.
    #[arg(long, value_name = "AXIS=I,...", value_delimiter = ',', value_parser = tmc::volume::leading_axes::parse_pick, help_heading = "Zarr and HDF5 input")]
    pub at: Vec<(String, u64)>,

    /// HDF5: the dataset to read (its path in the file), e.g.
    /// --dataset /exchange/data; the same as giving FILE:/exchange/data as
    /// the input.
    #[arg(long, value_name = "PATH", help_heading = "HDF5 input")]
    pub dataset: Option<String>,

    /// DICOM: the series of a directory to read, by its SeriesNumber or
    /// SeriesInstanceUID (tmc info DIR lists them).
    #[arg(long, value_name = "N|UID", help_heading = "DICOM input")]
    pub series: Option<String>,

    /// DICOM Segmentation: read segment N alone, as 0 (outside) to 1
    /// (inside; a FRACTIONAL segment's fraction), so --iso 0.5 is its
    /// surface; without it a SEG reads as a label map of its segments
    /// (for --labels).
    #[arg(long, value_name = "N", help_heading = "DICOM input")]
    pub segment: Option<u32>,

    /// Name the files of the input that were not read, and why (a DICOM
    /// directory's other series, non-image objects, unreadable files,
    /// copies and slices left out of the series).
    #[arg(long)]
    pub verbose: bool,
}

/// `--endian`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum EndianArg {
    /// Least significant byte first.
    Little,
    /// Most significant byte first.
    Big,
}

impl RawArgs {
    /// The raw-input options, if `--dims` was given.
    pub(crate) fn options(&self) -> Option<RawOptions> {
        let (dims, scalar) = (self.dims?, self.dtype?);
        Some(RawOptions {
            dims,
            scalar,
            endian: match self.endian {
                Some(EndianArg::Big) => Endian::Big,
                Some(EndianArg::Little) | None => Endian::Little,
            },
            header_bytes: self.header_bytes.unwrap_or(0),
            // `open_input` sets --spacing and --origin, as for any input.
            spacing: [1.0; 3],
            origin: [0.0; 3],
        })
    }

    /// What a run reads of `input` beyond the file or directory itself, as
    /// the options that choose it, spelled one way (the HDF5 dataset of
    /// `FILE:/dataset` or `--dataset`, `--array`, `--level`, `--at`,
    /// `--series`, `--segment`); `None` when nothing is chosen. A part
    /// file records it, so that `tmc merge` refuses parts that read other
    /// things of one input (`PartRecord::selection`).
    pub(crate) fn selection(&self, input: &Path) -> Option<String> {
        let dataset = tmc::volume::hdf5::split_path(input)
            .map(|(_, dataset)| dataset)
            .or_else(|| self.dataset.clone());
        let mut chosen = Vec::new();
        if let Some(dataset) = dataset {
            chosen.push(format!("--dataset /{}", dataset.trim_start_matches('/')));
        }
        if let Some(array) = &self.array {
            chosen.push(format!("--array {}", array.trim_matches('/')));
        }
        if let Some(level) = self.level.filter(|&level| level > 0) {
            chosen.push(format!("--level {level}"));
        }
        if !self.at.is_empty() {
            let mut at = self.at.clone();
            at.sort();
            let picks: Vec<String> = at.iter().map(|(axis, i)| format!("{axis}={i}")).collect();
            chosen.push(format!("--at {}", picks.join(",")));
        }
        if let Some(series) = &self.series {
            chosen.push(format!("--series {series}"));
        }
        if let Some(segment) = self.segment {
            chosen.push(format!("--segment {segment}"));
        }
        (!chosen.is_empty()).then(|| chosen.join(" "))
    }
}

/// Opens `input` as the command line describes it, on the grid that
/// `--spacing` and `--origin` set (a note on stderr for each value of the
/// file's they override, unless `quiet`). Headerless data must
/// fill the file exactly: extra bytes mean that `--dims` or `--dtype` are
/// wrong (the library reads such files and ignores what follows the
/// samples; a shorter file is refused there). Setting `cancel` stops the
/// decompression of compressed samples with [`tmc::Error::Interrupted`].
pub(crate) fn open_input(
    input: &Path,
    args: &RawArgs,
    cancel: Option<&AtomicBool>,
    quiet: bool,
) -> Result<Box<dyn SampleSource>> {
    let raw = args.options();
    let raw = raw.as_ref();
    let never = AtomicBool::new(false);
    let select = tmc::volume::zarr::ZarrSelect {
        array: args.array.clone(),
        level: args.level,
        dataset: args.dataset.clone(),
        series: args.series.clone(),
        segment: args.segment,
        at: args.at.clone(),
    };
    let source = tmc::volume::open_selected(input, raw, &select, cancel.unwrap_or(&never))?;
    let (source, notes) = tmc::volume::regrid(source, args.spacing, args.origin)?;
    if !quiet {
        for note in source.notes().warnings.into_iter().chain(notes) {
            say!("tmc: note: {}: {note}", input.display());
        }
    }
    if args.verbose {
        for skipped in source.notes().skipped {
            say!("tmc: skipped {skipped}");
        }
    }
    if let Some(options) = raw {
        let extra = RawVolume::trailing_bytes(input, options);
        if extra > 0 {
            let [x, y, z] = options.dims;
            return Err(Error::Format(format!(
                "{}: file has {extra} bytes more than dims {x}x{y}x{z} {} need after a {}-byte header; check --dims and --dtype (--header-bytes skips a header)",
                input.display(),
                options.scalar,
                options.header_bytes
            )));
        }
    }
    Ok(source)
}
