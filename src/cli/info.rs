//! `tmc info`: what a volume holds, and which isovalues to try.
//!
//! Before extracting a surface one needs the grid (is the spacing right? is
//! the volume mirrored?) and the range of values (which isovalue?). This
//! command opens the input as `tmc extract` would, prints its header facts,
//! and streams the samples twice, plane by plane (never the whole volume in
//! memory), for the range, the NaN count, the mean and a histogram whose
//! Otsu thresholds are offered as isovalues.

use super::raw_input::RawArgs;
use super::report::human_bytes;
use clap::Args;
use std::io::{self, Write};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::params::number_text;
use tmc::stream::cancellable::Cancellable;
use tmc::volume::{volume_info, VolumeInfo, MAX_BINS, MIN_BINS};
use tmc::Result;

/// Text at the end of `tmc info --help`.
const INFO_HELP: &str = "\
Suggested isovalues:
  Otsu's method on a histogram of the finite samples (--bins bins between the
  minimum and the maximum, or one bin per integer for integer data of a
  narrower range). Two-level Otsu gives two isovalues that split the values
  into three classes (air / soft tissue / bone in CT); single-level Otsu gives
  one. Each lies in the middle of the gap of empty bins at its cut, strictly
  between the minimum and the maximum. For integer-valued data it is a
  half-integer (floor + 0.5): no sample equals it, so no sample ties with the
  isovalue (a tie would be legal, equal is outside, but a half-integer makes
  the result obvious). Otherwise it is rounded to a power of ten no larger
  than the bin width.

Cost:
  Two streamed passes over the samples, in parallel over planes: the range
  first, then the histogram. Volumes of more than 2^28 samples get a histogram
  of every k-th plane only (k reported; set it with --plane-step); the range,
  counts and mean are always exact.

JSON keys (--json; one object on one line):
  input, format          the path and the reader (NRRD, NIfTI-1, NIfTI-2,
                         MetaImage, VTK legacy, VTK ImageData, TIFF stack,
                         DICOM, Zarr, NumPy, raw)
  file_bytes             size of the input file and the data files it names
                         (all files of a directory, the files of a glob)
  data_bytes             samples * stored sample size; null if unknown
  dims, samples          samples along x, y, z and their product
  sample_type            stored type (u8 i8 u16 i16 u32 i32 i64 u64 f16 f32
                         f64; before any NIfTI scaling), or null
  spacing, origin        [x, y, z]
  spacing_from,          where each came from: {\"kind\": \"file\", \"what\":
    origin_from          WHERE} (the header, ImageJ metadata ...), {\"kind\":
                         \"default\"} (the file states none), or {\"kind\":
                         \"option\", \"file\": [x, y, z] or null} (--spacing,
                         --origin; file = the value they override)
  units                  the unit of the values where the file states one
                         (DICOM RT Dose: GY or RELATIVE), else null
  segments               DICOM Segmentation only: [{number, label, property,
                         algorithm, frames}], the values of its label map
  overlapping_segments   DICOM Segmentation only, when segments share
                         samples: [[a, b], ...] (--labels refuses these)
  chunks                 chunked formats (Zarr, HDF5): chunk_shape [x, y, z],
                         codec, stored_bytes, chunks, chunks_stored; else null
  direction              3x3, rows = world axes, column j = index axis j
  affine                 4x4 index-to-world matrix, rows:
                         world = affine * [i, j, k, 1]
  min, max, mean         over finite samples; null if there are none
  nan_count, infinite_count
  integer_valued         every finite sample is a whole number
  histogram_bins         bins used; null for fewer than 2 distinct values
  histogram_plane_step   k: the histogram counted planes 0, k, 2k, ...
  suggested_iso          [low, high] from two-level Otsu, or [] if none
                         (also for data of two values, e.g. a mask)
  suggested_iso_single   single-level Otsu, or null";

/// Describe a volume: format, grid, value range and suggested isovalues.
///
/// Opens the input as 'tmc extract' does (any input format, or raw samples
/// with --dims and --dtype), prints its grid and index-to-world map, and
/// streams the samples for the minimum, maximum, mean, NaN count and the
/// isovalues that Otsu's method suggests.
#[derive(Debug, Args)]
#[command(after_help = INFO_HELP)]
pub(crate) struct InfoArgs {
    /// Input volume: .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha,
    /// .vtk, .vti, .tif/.tiff, a directory or pattern of TIFFs, DICOM (.dcm
    /// or a directory of slices), a Zarr store (STORE or STORE/ARRAY), or
    /// headerless samples with --dims and
    /// --dtype.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,

    /// Print one JSON object on stdout instead of text (keys below).
    #[arg(long)]
    pub json: bool,

    /// Histogram bins between the minimum and the maximum (3 to 4096).
    #[arg(long, value_name = "N", default_value_t = 1024, value_parser = clap::value_parser!(u16).range(MIN_BINS as i64..=MAX_BINS as i64))]
    pub bins: u16,

    /// Build the histogram from every N-th plane only; 0 (the default)
    /// chooses 1 unless the volume has more than 2^28 samples.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub plane_step: usize,

    /// Print nothing on stderr but errors (no notes on --spacing or
    /// --origin overriding the file's); the report on stdout is printed
    /// all the same.
    #[arg(short, long)]
    pub quiet: bool,

    /// Headerless input: --dims, --dtype, --endian, ...
    #[command(flatten)]
    pub raw: RawArgs,
}

/// Runs `tmc info`; setting `cancel` (SIGINT, SIGTERM, SIGHUP) stops the
/// streamed passes at the next plane with [`tmc::Error::Interrupted`].
pub(crate) fn run(args: &InfoArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    if let Some(series) = super::dicom_series::several(&args.input, &args.raw)? {
        return super::output::to_stdout(|out| {
            if args.json {
                super::dicom_series::write_json(out, &args.input, &series)
            } else {
                super::dicom_series::write_text(out, &args.input, &series)
            }
        });
    }
    let raw = args.raw.options();
    let source = super::raw_input::open_input(&args.input, &args.raw, cancel, args.quiet)?;
    let never = AtomicBool::new(false);
    let source = Cancellable {
        inner: source.as_ref(),
        cancel: cancel.unwrap_or(&never),
    };
    let info = volume_info(
        &args.input,
        raw.as_ref(),
        &source,
        usize::from(args.bins),
        args.plane_step,
    )?;
    super::output::to_stdout(|out| {
        if args.json {
            serde_json::to_writer(&mut *out, &info)?;
            writeln!(out)
        } else {
            write_text(out, &info)
        }
    })
}

/// Numbers joined by spaces.
fn join(values: &[f64]) -> String {
    values
        .iter()
        .map(|&v| number_text(v))
        .collect::<Vec<_>>()
        .join("  ")
}

/// Rows of numbers as lines, columns aligned.
fn matrix<const N: usize>(rows: &[[f64; N]]) -> Vec<String> {
    let cells: Vec<Vec<String>> = rows
        .iter()
        .map(|r| r.iter().map(|&v| number_text(v)).collect())
        .collect();
    let width = cells.iter().flatten().map(String::len).max().unwrap_or(0);
    cells
        .iter()
        .map(|r| {
            r.iter()
                .map(|c| format!("{c:>width$}"))
                .collect::<Vec<_>>()
                .join("  ")
        })
        .collect()
}

/// Writes the report as aligned `label  value` lines.
fn write_text(w: &mut impl Write, info: &VolumeInfo) -> io::Result<()> {
    let optional = |v: Option<f64>| v.map_or_else(|| "none".to_string(), number_text);
    let mut rows: Vec<(&str, String)> = vec![
        ("input", info.input.clone()),
        ("format", info.format.to_string()),
    ];
    if let Some(bytes) = info.file_bytes {
        rows.push((
            "file size",
            format!("{} ({bytes} bytes)", human_bytes(bytes)),
        ));
    }
    let [x, y, z] = info.dims;
    rows.push((
        "dims",
        format!(
            "{x} x {y} x {z} ({} sample{})",
            info.samples,
            if info.samples == 1 { "" } else { "s" }
        ),
    ));
    rows.push((
        "sample type",
        info.sample_type.unwrap_or("unknown").to_string(),
    ));
    rows.push(("spacing", join(&info.spacing)));
    rows.push(("  from", info.spacing_from.to_string()));
    rows.push(("origin", join(&info.origin)));
    rows.push(("  from", info.origin_from.to_string()));
    if let Some(c) = &info.chunks {
        let [x, y, z] = c.chunk_shape;
        rows.push(("chunk shape", format!("{x} x {y} x {z}")));
        rows.push(("codec", c.codec.clone()));
        let stored = c
            .chunks_stored
            .map_or(String::new(), |n| format!(", {n} stored"));
        rows.push(("chunks", format!("{}{stored}", c.chunks)));
        if let Some(bytes) = c.stored_bytes {
            rows.push((
                "compressed size",
                format!("{} ({bytes} bytes)", human_bytes(bytes)),
            ));
        }
    }
    for (i, line) in matrix(&info.direction).into_iter().enumerate() {
        rows.push((if i == 0 { "direction" } else { "" }, line));
    }
    for (i, line) in matrix(&info.affine).into_iter().enumerate() {
        let label = match i {
            0 => "index to world",
            1 => "(4x4 affine)",
            _ => "",
        };
        rows.push((label, line));
    }
    if let Some(units) = &info.units {
        rows.push(("units", units.clone()));
    }
    for (i, s) in info.segments.iter().enumerate() {
        let mut what = vec![format!("{}", s.number)];
        if !s.label.is_empty() {
            what.push(format!("\"{}\"", s.label));
        }
        what.extend(s.property.clone());
        what.extend(s.algorithm.clone());
        what.push(format!("{} frame(s)", s.frames));
        rows.push((if i == 0 { "segments" } else { "" }, what.join("  ")));
    }
    if !info.overlapping_segments.is_empty() {
        let pairs: Vec<String> = info
            .overlapping_segments
            .iter()
            .map(|[a, b]| format!("{a} and {b}"))
            .collect();
        rows.push((
            "overlapping",
            format!(
                "{} (the label map keeps the higher; --labels refuses, --segment N reads each)",
                pairs.join(", ")
            ),
        ));
    }
    rows.push(("min", optional(info.min)));
    rows.push(("max", optional(info.max)));
    rows.push(("mean", optional(info.mean)));
    rows.push(("NaN samples", info.nan_count.to_string()));
    if info.infinite_count > 0 {
        rows.push(("infinite samples", info.infinite_count.to_string()));
    }
    if let Some(bins) = info.histogram_bins {
        let planes = match info.histogram_plane_step {
            1 => "every plane".to_string(),
            k => format!("planes 0, {k}, {}, ... (--plane-step {k})", 2 * k),
        };
        rows.push(("histogram", format!("{bins} bins, {planes}")));
    }
    rows.push((
        "suggested iso",
        match info.suggested_iso[..] {
            [a, b] => format!(
                "{}  {}  (two-level Otsu, 3 classes)",
                number_text(a),
                number_text(b)
            ),
            _ if info.suggested_iso_single.is_some() => {
                "none (the values form only two classes)".to_string()
            }
            _ => "none (fewer than two distinct values)".to_string(),
        },
    ));
    if let Some(t) = info.suggested_iso_single {
        rows.push((
            "single iso",
            format!("{}  (Otsu, 2 classes)", number_text(t)),
        ));
    }
    let width = rows.iter().map(|(l, _)| l.len()).max().unwrap_or(0);
    for (label, value) in &rows {
        writeln!(w, "{label:<width$}  {value}")?;
    }
    Ok(())
}
