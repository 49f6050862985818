//! DICOM series: a directory of single-slice files, one slice file (its
//! series is read from its directory), or one multi-frame file.
//!
//! DICOM stores a volume as many files in no particular order, each with its
//! own position and value scaling, so the reader's job is assembling the
//! series: parsing and decoding one file is left to the dicom-rs crates
//! (`dicom-object`, `dicom-pixeldata`, pure-Rust codecs only).
//!
//! * Files are recognised by the `DICM` magic at byte 128 (any name) or a
//!   `.dcm` extension; other files (a README, a DICOMDIR) are skipped. A
//!   file that looks like DICOM but does not parse is an error naming it.
//! * Several `SeriesInstanceUID`s in one directory are an error listing
//!   them, unless one is chosen ([`open_series`], or by opening one file of
//!   the series).
//! * Slices are sorted by their position along the slice normal
//!   (`row cosine x column cosine` of `ImageOrientationPatient`, position =
//!   `ImagePositionPatient . normal`), never by file name or
//!   `InstanceNumber`. The slice spacing comes from the sorted positions;
//!   uneven gaps (a missing slice), duplicate positions, slices not stacked
//!   along their normal (gantry tilt) and slices that differ in size, sample
//!   type, orientation or pixel spacing are errors.
//! * The grid: dims = `[Columns, Rows, slices]`, spacing = `[column spacing,
//!   row spacing, slice spacing]` (`PixelSpacing` is `[row, column]`),
//!   origin = `ImagePositionPatient` of the first slice, direction columns =
//!   row cosine, column cosine and the normal. Coordinates stay in DICOM's
//!   patient system (LPS: x to the patient's left, y posterior, z head).
//!   A series without `PixelSpacing` gets 1 mm.
//! * `RescaleSlope`/`RescaleIntercept` are applied per slice, so CT values
//!   are Hounsfield units.
//! * Multi-frame files: frames are positioned by the per-frame
//!   `PlanePositionSequence` (enhanced objects; orientation, pixel measures
//!   and rescale from the per-frame or shared functional groups), else by
//!   one `ImagePositionPatient` stepped along the normal by
//!   `SpacingBetweenSlices` (or `SliceThickness`).
//! * Only the headers are read at open. A plane is decoded when it is asked
//!   for, by parsing its file again. The last file parsed is kept, so the
//!   frames of a multi-frame file come from one parse of it (parsed for
//!   each frame, a 256-frame file of 33 MB took 4.8 s to read, in 8.6 GB of
//!   reads); nothing else of the volume is kept.
//! * Transfer syntaxes: implicit/explicit VR little endian, explicit VR big
//!   endian, deflate, RLE lossless and JPEG baseline/extended/lossless. JPEG
//!   2000, JPEG-LS and JPEG XL need codecs tmc leaves out and are refused at
//!   open. Samples must be greyscale (1 sample per pixel) of 8, 16 or 32
//!   bits, unsigned or signed.

use super::{dicom_lengths, Grid, SampleSource, ScalarType};
use crate::{Error, Result};
use dicom_dictionary_std::tags;
use dicom_encoding::TransferSyntaxIndex;
use dicom_object::mem::InMemElement;
use dicom_object::{DefaultDicomObject, InMemDicomObject, OpenFileOptions, Tag};
use dicom_pixeldata::PixelDecoder;
use dicom_transfer_syntax_registry::TransferSyntaxRegistry;
use std::collections::BTreeMap;
use std::fmt::Display;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The SOP class of a DICOMDIR, which indexes files but holds no image.
const MEDIA_STORAGE_DIRECTORY: &str = "1.2.840.10008.1.3.10";

/// Largest relative deviation of one slice gap from the usual gap.
const GAP_TOLERANCE: f64 = 1e-3;

/// A DICOM series read one slice at a time.
#[derive(Debug)]
pub struct DicomSeries {
    /// The directory (or multi-frame file) the series was read from.
    source: PathBuf,
    grid: Grid,
    series_uid: String,
    format: Format,
    /// The planes in order of increasing position along the normal.
    planes: Vec<Plane>,
    /// The file a plane was last decoded from, parsed.
    last_file: Mutex<Option<(PathBuf, Arc<DefaultDicomObject>)>>,
}

/// Sample layout, which every slice of a series must share.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Format {
    columns: usize,
    rows: usize,
    bits_allocated: u16,
    bits_stored: u16,
    signed: bool,
}

impl Format {
    /// The bytes of one frame: `Columns x Rows x BitsAllocated / 8` (one
    /// sample per pixel), in `u128` so that no header overflows it.
    fn frame_bytes(&self) -> u128 {
        self.columns as u128 * self.rows as u128 * u128::from(self.bits_allocated / 8)
    }
}

/// Where one plane is stored and how its values are scaled.
#[derive(Debug, Clone)]
struct Plane {
    path: PathBuf,
    /// Frame index within the file (0 for single-frame files).
    frame: u32,
    position: [f64; 3],
    /// Position along the slice normal.
    distance: f64,
    slope: f64,
    intercept: f64,
}

impl DicomSeries {
    /// The `SeriesInstanceUID` of the series.
    pub fn series_uid(&self) -> &str {
        &self.series_uid
    }

    /// The file that holds plane `z` (sorted by position).
    pub fn plane_file(&self, z: usize) -> Option<&Path> {
        self.planes.get(z).map(|p| p.path.as_path())
    }

    /// `RescaleSlope` and `RescaleIntercept` of plane `z`.
    pub fn rescale(&self, z: usize) -> Option<(f64, f64)> {
        self.planes.get(z).map(|p| (p.slope, p.intercept))
    }
}

/// Does `path` have the `DICM` magic at byte 128?
pub fn has_magic(path: &Path) -> bool {
    let mut head = [0u8; 132];
    File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && &head[128..] == b"DICM"
}

fn has_dcm_extension(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("dcm"))
}

/// Is `path` a file to read as DICOM (the magic, or a `.dcm` name)?
fn is_dicom_file(path: &Path) -> bool {
    path.is_file() && (has_dcm_extension(path) || has_magic(path))
}

/// The files of directory `dir`, sorted by name.
fn dir_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let path = entry.map_err(|e| Error::io(dir, e))?.path();
        if path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// Does directory `dir` hold at least one DICOM file?
pub fn dir_has_dicom(dir: &Path) -> bool {
    dir_files(dir).is_ok_and(|files| files.iter().any(|f| is_dicom_file(f)))
}

fn format_err(path: &Path, msg: impl Display) -> Error {
    let msg = msg.to_string().replace(['\n', '\r'], " ");
    Error::Format(format!("{}: {msg}", path.display()))
}

/// Opens a DICOM directory, slice file or multi-frame file; a directory
/// must hold one series.
pub fn open(path: &Path) -> Result<DicomSeries> {
    open_series(path, None)
}

/// Opens the series `series` (a `SeriesInstanceUID`) of a directory, or the
/// only series there when `series` is `None`. A single-frame file stands
/// for its series in its directory; a multi-frame file for itself.
pub fn open_series(path: &Path, series: Option<&str>) -> Result<DicomSeries> {
    let (dir, headers, series) = if path.is_dir() {
        let mut headers = Vec::new();
        for file in dir_files(path)? {
            if is_dicom_file(&file) {
                headers.extend(Header::read(&file)?);
            }
        }
        (path.to_path_buf(), headers, series.map(str::to_string))
    } else {
        let header = Header::read(path)?
            .ok_or_else(|| format_err(path, "a DICOMDIR holds no image; open its directory"))?;
        if let Some(wanted) = series {
            if wanted != header.series_uid {
                return Err(format_err(
                    path,
                    format!("belongs to series {}, not {wanted}", header.series_uid),
                ));
            }
        }
        if header.frames > 1 {
            let uid = header.series_uid.clone();
            (path.to_path_buf(), vec![header], Some(uid))
        } else {
            let dir = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            let mut headers = Vec::new();
            for file in dir_files(&dir)? {
                if file == path || file.file_name() == path.file_name() {
                    continue;
                }
                if is_dicom_file(&file) {
                    headers.extend(Header::read(&file)?);
                }
            }
            let uid = header.series_uid.clone();
            headers.push(header);
            (dir, headers, Some(uid))
        }
    };
    if headers.is_empty() {
        return Err(format_err(&dir, "no DICOM image files found"));
    }
    let mut by_series: BTreeMap<String, Vec<Header>> = BTreeMap::new();
    for h in headers {
        by_series.entry(h.series_uid.clone()).or_default().push(h);
    }
    let (uid, chosen) = match series {
        Some(uid) => match by_series.remove(&uid) {
            Some(h) => (uid, h),
            None => {
                return Err(format_err(
                    &dir,
                    format!("no DICOM series {uid} (found {})", list_series(&by_series)),
                ))
            }
        },
        None if by_series.len() == 1 => by_series.pop_first().expect("one series"),
        None => {
            return Err(format_err(
                &dir,
                format!(
                    "{} DICOM series in one directory: {}; open one file of a series to read that series",
                    by_series.len(),
                    list_series(&by_series)
                ),
            ))
        }
    };
    assemble(&dir, uid, chosen)
}

fn list_series(by_series: &BTreeMap<String, Vec<Header>>) -> String {
    by_series
        .iter()
        .map(|(uid, h)| {
            let planes: usize = h.iter().map(|h| h.planes.len()).sum();
            format!("{uid} ({planes} slices)")
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// What the header of one file says.
struct Header {
    path: PathBuf,
    series_uid: String,
    format: Format,
    frames: u32,
    orientation: [f64; 6],
    /// `[row spacing, column spacing]`.
    pixel_spacing: Option<[f64; 2]>,
    /// SpacingBetweenSlices, else SliceThickness.
    slice_step: Option<f64>,
    planes: Vec<Plane>,
}

fn element(obj: &InMemDicomObject, tag: Tag) -> Option<&InMemElement> {
    obj.element_opt(tag).ok().flatten()
}

fn floats(obj: &InMemDicomObject, tag: Tag) -> Option<Vec<f64>> {
    element(obj, tag).and_then(|e| e.to_multi_float64().ok())
}

fn first_item(obj: &InMemDicomObject, seq: Tag) -> Option<&InMemDicomObject> {
    element(obj, seq)
        .and_then(|e| e.items())
        .and_then(|i| i.first())
}

/// Attribute `tag` of a frame: in its own functional group `seq`, in the
/// shared one, or at the top level.
fn frame_floats(
    top: &InMemDicomObject,
    per_frame: Option<&InMemDicomObject>,
    shared: Option<&InMemDicomObject>,
    seq: Tag,
    tag: Tag,
) -> Option<Vec<f64>> {
    [per_frame, shared]
        .into_iter()
        .flatten()
        .filter_map(|g| first_item(g, seq))
        .find_map(|item| floats(item, tag))
        .or_else(|| floats(top, tag))
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    v.map(|x| x / n)
}

/// Row cosine, column cosine and normal of an `ImageOrientationPatient`.
fn axes(o: &[f64; 6]) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let row = unit([o[0], o[1], o[2]]);
    let col = unit([o[3], o[4], o[5]]);
    (row, col, unit(cross(row, col)))
}

fn vec3(v: Option<Vec<f64>>) -> Option<[f64; 3]> {
    v.filter(|v| v.len() >= 3 && v.iter().all(|x| x.is_finite()))
        .map(|v| [v[0], v[1], v[2]])
}

impl Header {
    /// Reads the header of `path`; `None` for a DICOMDIR.
    fn read(path: &Path) -> Result<Option<Header>> {
        let pixels = dicom_lengths::check(path).map_err(|e| format_err(path, e))?;
        let obj = OpenFileOptions::new()
            .read_until(tags::PIXEL_DATA)
            .open_file(path)
            .map_err(|e| format_err(path, format!("not a readable DICOM file: {e}")))?;
        if obj.meta().media_storage_sop_class_uid() == MEDIA_STORAGE_DIRECTORY {
            return Ok(None);
        }
        let ts_uid = obj.meta().transfer_syntax();
        match TransferSyntaxRegistry.get(ts_uid) {
            None => {
                return Err(format_err(
                    path,
                    format!("unknown transfer syntax {ts_uid}"),
                ))
            }
            Some(ts) if !ts.can_decode_all() => {
                return Err(format_err(
                    path,
                    format!(
                        "transfer syntax {} ({ts_uid}) not supported (tmc decodes uncompressed, deflate, RLE and JPEG baseline/lossless data; JPEG 2000, JPEG-LS and JPEG XL need codecs it leaves out)",
                        ts.name()
                    ),
                ))
            }
            Some(_) => {}
        }
        let uint = |tag: Tag, name: &str| -> Result<u32> {
            element(&obj, tag)
                .and_then(|e| e.to_int::<u32>().ok())
                .ok_or_else(|| {
                    format_err(
                        path,
                        format!("no {name}: not an image (or not a complete one)"),
                    )
                })
        };
        let rows = uint(tags::ROWS, "Rows")?;
        let columns = uint(tags::COLUMNS, "Columns")?;
        let bits_allocated = uint(tags::BITS_ALLOCATED, "BitsAllocated")?;
        let bits_stored = element(&obj, tags::BITS_STORED)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(bits_allocated);
        let samples = element(&obj, tags::SAMPLES_PER_PIXEL)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(1);
        let signed = element(&obj, tags::PIXEL_REPRESENTATION)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(0)
            == 1;
        if samples != 1 {
            return Err(format_err(
                path,
                format!("{samples} samples per pixel (colour) are not supported: need greyscale"),
            ));
        }
        if ![8, 16, 32].contains(&bits_allocated) {
            return Err(format_err(
                path,
                format!("BitsAllocated {bits_allocated} is not supported (need 8, 16 or 32)"),
            ));
        }
        if rows == 0 || columns == 0 || bits_stored == 0 || bits_stored > bits_allocated {
            return Err(format_err(
                path,
                format!("bad image size {columns}x{rows} or BitsStored {bits_stored}"),
            ));
        }
        let format = Format {
            columns: columns as usize,
            rows: rows as usize,
            bits_allocated: bits_allocated as u16,
            bits_stored: bits_stored as u16,
            signed,
        };
        let series_uid = element(&obj, tags::SERIES_INSTANCE_UID)
            .and_then(|e| e.to_str().ok())
            .map(|s| dicom_lengths::unpadded(&s).to_string())
            .unwrap_or_default();
        let frames = element(&obj, tags::NUMBER_OF_FRAMES)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(1)
            .max(1);
        check_pixel_data(path, &format, frames, pixels)?;

        let shared = first_item(&obj, tags::SHARED_FUNCTIONAL_GROUPS_SEQUENCE);
        let per_frame_items =
            element(&obj, tags::PER_FRAME_FUNCTIONAL_GROUPS_SEQUENCE).and_then(|e| e.items());
        if let Some(items) = per_frame_items {
            if items.len() != frames as usize {
                return Err(format_err(
                    path,
                    format!(
                        "{} per-frame functional groups for {frames} frames",
                        items.len()
                    ),
                ));
            }
        }
        let group = |k: usize| per_frame_items.and_then(|items| items.get(k));
        let lookup = |k: usize, seq: Tag, tag: Tag| frame_floats(&obj, group(k), shared, seq, tag);

        let orientation = lookup(
            0,
            tags::PLANE_ORIENTATION_SEQUENCE,
            tags::IMAGE_ORIENTATION_PATIENT,
        )
        .filter(|v| v.len() >= 6 && v.iter().all(|x| x.is_finite()))
        .map(|v| [v[0], v[1], v[2], v[3], v[4], v[5]])
        .ok_or_else(|| format_err(path, "no ImageOrientationPatient: cannot place the slice"))?;
        let (row, col, normal) = axes(&orientation);
        if !normal.iter().all(|x| x.is_finite()) || dot(row, col).abs() > 1e-3 {
            return Err(format_err(
                path,
                format!("ImageOrientationPatient {orientation:?} is not two orthogonal directions"),
            ));
        }
        let pixel_spacing = lookup(0, tags::PIXEL_MEASURES_SEQUENCE, tags::PIXEL_SPACING)
            .filter(|v| v.len() >= 2)
            .map(|v| [v[0], v[1]]);
        if let Some(ps) = pixel_spacing {
            if !ps.iter().all(|&s| s.is_finite() && s > 0.0) {
                return Err(format_err(path, format!("bad PixelSpacing {ps:?}")));
            }
        }
        let slice_step = lookup(
            0,
            tags::PIXEL_MEASURES_SEQUENCE,
            tags::SPACING_BETWEEN_SLICES,
        )
        .or_else(|| lookup(0, tags::PIXEL_MEASURES_SEQUENCE, tags::SLICE_THICKNESS))
        .and_then(|v| v.first().copied())
        .filter(|s| s.is_finite() && *s > 0.0);

        let per_frame_positions = per_frame_items.is_some_and(|items| {
            items
                .iter()
                .all(|g| first_item(g, tags::PLANE_POSITION_SEQUENCE).is_some())
        });
        let mut planes = Vec::with_capacity(frames as usize);
        for k in 0..frames as usize {
            if k > 0 {
                let o = lookup(
                    k,
                    tags::PLANE_ORIENTATION_SEQUENCE,
                    tags::IMAGE_ORIENTATION_PATIENT,
                );
                if let Some(o) = o.filter(|o| o.len() >= 6) {
                    if o.iter()
                        .zip(&orientation)
                        .any(|(a, b)| (a - b).abs() > 1e-4)
                    {
                        return Err(format_err(
                            path,
                            format!("frame {} has another orientation {o:?} than frame 1 {orientation:?}", k + 1),
                        ));
                    }
                }
            }
            let position = if per_frame_positions || k == 0 {
                vec3(lookup(
                    k,
                    tags::PLANE_POSITION_SEQUENCE,
                    tags::IMAGE_POSITION_PATIENT,
                ))
                .ok_or_else(|| {
                    format_err(path, "no ImagePositionPatient: cannot place the slice")
                })?
            } else {
                let step = slice_step.ok_or_else(|| {
                    format_err(
                        path,
                        "multi-frame file with one ImagePositionPatient and no SpacingBetweenSlices or SliceThickness: cannot place its frames",
                    )
                })?;
                let first: [f64; 3] = planes
                    .first()
                    .map(|p: &Plane| p.position)
                    .unwrap_or_default();
                [0, 1, 2].map(|i| first[i] + normal[i] * step * k as f64)
            };
            let slope = lookup(
                k,
                tags::PIXEL_VALUE_TRANSFORMATION_SEQUENCE,
                tags::RESCALE_SLOPE,
            )
            .and_then(|v| v.first().copied())
            .unwrap_or(1.0);
            let intercept = lookup(
                k,
                tags::PIXEL_VALUE_TRANSFORMATION_SEQUENCE,
                tags::RESCALE_INTERCEPT,
            )
            .and_then(|v| v.first().copied())
            .unwrap_or(0.0);
            if !slope.is_finite() || !intercept.is_finite() {
                return Err(format_err(
                    path,
                    format!("bad RescaleSlope {slope} or RescaleIntercept {intercept}"),
                ));
            }
            planes.push(Plane {
                path: path.to_path_buf(),
                frame: k as u32,
                position,
                distance: dot(position, normal),
                slope,
                intercept,
            });
        }
        Ok(Some(Header {
            path: path.to_path_buf(),
            series_uid,
            format,
            frames,
            orientation,
            pixel_spacing,
            slice_step,
            planes,
        }))
    }
}

/// Checks the image size and frame count of a header against the pixel
/// data the length walk saw (`None`: it did not reach it), before anything
/// of that size is allocated: a damaged header must not claim gigabytes.
/// Native data must hold every frame; encapsulated data needs a fragment
/// per frame at least. Whatever the walk saw, every frame takes a byte of
/// the file at least.
fn check_pixel_data(
    path: &Path,
    format: &Format,
    frames: u32,
    pixels: Option<dicom_lengths::PixelData>,
) -> Result<()> {
    let size = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    let need = format.frame_bytes() * u128::from(frames);
    let problem = match pixels {
        Some(dicom_lengths::PixelData::Native(len)) if need > u128::from(len) => Some(format!(
            "{len} bytes of pixel data, but {frames} frame(s) of {}x{} at {} bits need {need}",
            format.columns, format.rows, format.bits_allocated
        )),
        Some(dicom_lengths::PixelData::Fragments(n)) if u64::from(frames) > n => Some(format!(
            "{n} fragment(s) of encapsulated pixel data for {frames} frame(s)"
        )),
        _ if u64::from(frames) > size => {
            Some(format!("NumberOfFrames {frames} in a file of {size} bytes"))
        }
        _ => None,
    };
    match problem {
        Some(p) => Err(format_err(path, format!("damaged image header: {p}"))),
        None => Ok(()),
    }
}

/// Checks that the files of one series agree and builds the grid.
fn assemble(dir: &Path, series_uid: String, headers: Vec<Header>) -> Result<DicomSeries> {
    let first = &headers[0];
    for h in &headers[1..] {
        let (a, b) = (first.format, h.format);
        if (a.columns, a.rows) != (b.columns, b.rows) {
            return Err(format_err(
                &h.path,
                format!(
                    "{}x{} slice (Columns x Rows) differs from the {}x{} of {}",
                    b.columns,
                    b.rows,
                    a.columns,
                    a.rows,
                    first.path.display()
                ),
            ));
        }
        if a != b {
            return Err(format_err(
                &h.path,
                format!(
                    "sample type ({} bits allocated, {} stored, {}) differs from that of {} ({}, {}, {})",
                    b.bits_allocated,
                    b.bits_stored,
                    if b.signed { "signed" } else { "unsigned" },
                    first.path.display(),
                    a.bits_allocated,
                    a.bits_stored,
                    if a.signed { "signed" } else { "unsigned" },
                ),
            ));
        }
        if h.orientation
            .iter()
            .zip(&first.orientation)
            .any(|(x, y)| (x - y).abs() > 1e-4)
        {
            return Err(format_err(
                &h.path,
                format!(
                    "ImageOrientationPatient {:?} differs from {:?} of {}",
                    h.orientation,
                    first.orientation,
                    first.path.display()
                ),
            ));
        }
        let same_spacing = match (h.pixel_spacing, first.pixel_spacing) {
            (Some(x), Some(y)) => (0..2).all(|i| (x[i] - y[i]).abs() <= 1e-4 * y[i].max(1.0)),
            (x, y) => x.is_none() && y.is_none(),
        };
        if !same_spacing {
            return Err(format_err(
                &h.path,
                format!(
                    "PixelSpacing {:?} differs from {:?} of {}",
                    h.pixel_spacing,
                    first.pixel_spacing,
                    first.path.display()
                ),
            ));
        }
    }
    let format = first.format;
    let (row, col, normal) = axes(&first.orientation);
    let [row_spacing, col_spacing] = first.pixel_spacing.unwrap_or([1.0, 1.0]);
    let single_step = first.slice_step;
    let mut planes: Vec<Plane> = headers.into_iter().flat_map(|h| h.planes).collect();
    planes.sort_by(|a, b| a.distance.total_cmp(&b.distance));

    let n = planes.len();
    let slice_spacing = if n == 1 {
        single_step.unwrap_or(1.0)
    } else {
        let gaps: Vec<f64> = planes
            .windows(2)
            .map(|w| w[1].distance - w[0].distance)
            .collect();
        let extent = planes[n - 1].distance - planes[0].distance;
        let tiny = 1e-6 * extent.abs().max(1.0);
        if let Some(w) = planes
            .windows(2)
            .find(|w| w[1].distance - w[0].distance <= tiny)
        {
            return Err(format_err(
                dir,
                format!(
                    "two slices at the same position {} ({} and {})",
                    w[0].distance,
                    describe(&w[0]),
                    describe(&w[1])
                ),
            ));
        }
        let mut sorted = gaps.clone();
        sorted.sort_by(f64::total_cmp);
        let usual = sorted[(sorted.len() - 1) / 2];
        for (k, &gap) in gaps.iter().enumerate() {
            if (gap - usual).abs() > GAP_TOLERANCE * usual {
                return Err(format_err(
                    dir,
                    format!(
                        "slice gap {gap} mm between positions {} and {} differs from the usual {usual} mm (missing slice?)",
                        planes[k].distance,
                        planes[k + 1].distance
                    ),
                ));
            }
        }
        extent / (n - 1) as f64
    };
    let origin = planes[0].position;
    let tolerance = (GAP_TOLERANCE * slice_spacing).max(1e-4);
    for p in &planes {
        let along = p.distance - planes[0].distance;
        let off = [0, 1, 2].map(|i| p.position[i] - origin[i] - normal[i] * along);
        if dot(off, off).sqrt() > tolerance {
            return Err(format_err(
                &p.path,
                format!(
                    "slice at {:?} is shifted {:?} across the slice normal from the first slice: slices are not stacked along their normal (gantry tilt?)",
                    p.position, off
                ),
            ));
        }
    }
    let grid = Grid {
        dims: [format.columns, format.rows, n],
        spacing: [col_spacing, row_spacing, slice_spacing],
        origin,
        direction: [0, 1, 2].map(|i| [row[i], col[i], normal[i]]),
    };
    Ok(DicomSeries {
        source: dir.to_path_buf(),
        grid,
        series_uid,
        format,
        planes,
        last_file: Mutex::new(None),
    })
}

fn describe(p: &Plane) -> String {
    if p.frame == 0 {
        p.path.display().to_string()
    } else {
        format!("{} frame {}", p.path.display(), p.frame + 1)
    }
}

impl DicomSeries {
    /// Decodes plane `z` into stored (unscaled) sample bytes, native order.
    fn decode(&self, plane: &Plane) -> Result<Vec<u8>> {
        let obj = self.parsed(&plane.path)?;
        let syntax = obj.meta().transfer_syntax();
        if dicom_lengths::unpadded(syntax) == dicom_lengths::DEFLATED_FRAMES {
            self.check_deflated_frame(&obj, plane)?;
        }
        let cannot =
            |e: String| format_err(&plane.path, format!("cannot decode the pixel data: {e}"));
        let decoded = super::guarded::guarded(|| obj.decode_pixel_data_frame(plane.frame))
            .map_err(|panic| cannot(format!("the decoder failed ({panic})")))?
            .map_err(|e| cannot(e.to_string()))?;
        Ok(decoded.data().to_vec())
    }

    /// The file at `path`, parsed whole: the last file parsed if it is the
    /// same, else parsed now (and kept in its place).
    fn parsed(&self, path: &Path) -> Result<Arc<DefaultDicomObject>> {
        let last = || self.last_file.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((p, obj)) = last().as_ref() {
            if p == path {
                return Ok(Arc::clone(obj));
            }
        }
        // Checked again: the file may have changed since the header.
        dicom_lengths::check(path).map_err(|e| format_err(path, e))?;
        let obj = OpenFileOptions::new()
            .open_file(path)
            .map_err(|e| format_err(path, format!("not a readable DICOM file: {e}")))?;
        let obj = Arc::new(obj);
        *last() = Some((path.to_path_buf(), Arc::clone(&obj)));
        Ok(obj)
    }

    /// Refuses a frame of deflated pixel data ([`dicom_lengths::DEFLATED_FRAMES`])
    /// that inflates beyond the size of a frame ([`Format::frame_bytes`]),
    /// inflating it in one
    /// streaming pass before the decoder, which inflates a frame without
    /// limit (a small file could claim gigabytes). A missing fragment or a
    /// stream that does not inflate is left to the decoder's error.
    fn check_deflated_frame(&self, obj: &InMemDicomObject, plane: &Plane) -> Result<()> {
        let f = self.format;
        let frame_bytes = u64::try_from(f.frame_bytes()).unwrap_or(u64::MAX);
        let fragment = element(obj, tags::PIXEL_DATA)
            .and_then(|e| e.value().fragments())
            .and_then(|fragments| fragments.get(plane.frame as usize));
        match fragment {
            Some(fragment) if dicom_lengths::inflates_beyond(fragment, frame_bytes) => {
                Err(format_err(
                    &plane.path,
                    format!(
                        "not a readable DICOM file: frame {} of its deflated pixel data inflates to more than the {frame_bytes} bytes of a {}x{} frame at {} bits (a decompression bomb or damaged)",
                        plane.frame + 1,
                        f.columns,
                        f.rows,
                        f.bits_allocated
                    ),
                ))
            }
            _ => Ok(()),
        }
    }
}

impl SampleSource for DicomSeries {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let plane = self.planes.get(z).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: plane {z} is beyond the {} slices",
                self.source.display(),
                self.planes.len()
            ))
        })?;
        let bytes = self.decode(plane)?;
        let f = self.format;
        let width = f.bits_allocated as usize / 8;
        let need = f.columns * f.rows * width;
        if bytes.len() < need || out.len() != f.columns * f.rows {
            return Err(format_err(
                &plane.path,
                format!(
                    "{} bytes of pixel data in frame {}, need {need}",
                    bytes.len(),
                    plane.frame + 1
                ),
            ));
        }
        let shift = 64 - u32::from(f.bits_stored);
        let stored = |raw: u64| -> f64 {
            // Keep the low `bits_stored` bits, sign-extended if signed.
            if f.signed {
                (((raw << shift) as i64) >> shift) as f64
            } else {
                ((raw << shift) >> shift) as f64
            }
        };
        let (slope, intercept) = (plane.slope, plane.intercept);
        for (o, s) in out.iter_mut().zip(bytes.chunks_exact(width)) {
            let raw = match width {
                1 => u64::from(s[0]),
                2 => u64::from(u16::from_ne_bytes([s[0], s[1]])),
                _ => u64::from(u32::from_ne_bytes([s[0], s[1], s[2], s[3]])),
            };
            *o = stored(raw) * slope + intercept;
        }
        Ok(())
    }

    fn data_files(&self) -> Vec<&Path> {
        self.planes.iter().map(|p| p.path.as_path()).collect()
    }

    fn sample_bytes(&self) -> usize {
        self.format.bits_allocated as usize / 8
    }

    /// The integer type of `BitsAllocated` and `PixelRepresentation`
    /// (before `RescaleSlope` and `RescaleIntercept`).
    fn stored_type(&self) -> Option<ScalarType> {
        Some(match (self.format.bits_allocated, self.format.signed) {
            (8, false) => ScalarType::U8,
            (8, true) => ScalarType::I8,
            (16, false) => ScalarType::U16,
            (16, true) => ScalarType::I16,
            (32, false) => ScalarType::U32,
            (32, true) => ScalarType::I32,
            _ => return None,
        })
    }
}
