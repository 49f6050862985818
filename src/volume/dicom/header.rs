//! One file's header: what it says of its series (for listing and
//! choosing one), and, for an image tmc can read, its sample layout and
//! where each of its frames lies. Only the header is parsed (up to the
//! pixel data), never the samples.

use super::attributes::{axes, dot, element, first_item, frame_floats, text, vec3};
use super::files::format_err;
use super::{lengths, rt_dose, segmentation, syntax, unknown_vr};
use crate::{Error, Result};
use dicom_dictionary_std::tags;
use dicom_encoding::TransferSyntaxIndex;
use dicom_object::{InMemDicomObject, OpenFileOptions, Tag};
use dicom_transfer_syntax_registry::TransferSyntaxRegistry;
use std::path::{Path, PathBuf};

/// The SOP class of a DICOMDIR, which indexes files but holds no image.
const MEDIA_STORAGE_DIRECTORY: &str = "1.2.840.10008.1.3.10";

/// Sample layout, which every slice of a series must share.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Format {
    pub(super) columns: usize,
    pub(super) rows: usize,
    pub(super) bits_allocated: u16,
    pub(super) bits_stored: u16,
    pub(super) signed: bool,
}

impl Format {
    /// The bytes of one frame: `Columns x Rows x BitsAllocated / 8` (one
    /// sample per pixel), in `u128` so that no header overflows it.
    pub(super) fn frame_bytes(&self) -> u128 {
        self.columns as u128 * self.rows as u128 * u128::from(self.bits_allocated / 8)
    }
}

/// Where one plane is stored and how its values are scaled.
#[derive(Debug, Clone)]
pub(super) struct Plane {
    pub(super) path: PathBuf,
    /// Frame index within the file (0 for single-frame files).
    pub(super) frame: u32,
    pub(super) position: [f64; 3],
    /// Position along the slice normal.
    pub(super) distance: f64,
    pub(super) slope: f64,
    pub(super) intercept: f64,
}

/// What a file says of the series it belongs to: enough to list the
/// series of a directory and to choose one.
#[derive(Debug, Clone, Default)]
pub(super) struct SeriesMeta {
    /// `SeriesInstanceUID` (empty if the file states none).
    pub(super) uid: String,
    /// `SeriesNumber`, as written.
    pub(super) number: Option<String>,
    /// `Modality` (CT, MR, RTDOSE, SEG ...).
    pub(super) modality: Option<String>,
    /// `SeriesDescription`.
    pub(super) description: Option<String>,
    /// The transfer syntax's name (its UID if unknown).
    pub(super) transfer_syntax: String,
    /// Is the file a Segmentation object (read on its own, by
    /// `seg_volume.rs`, never stacked)?
    pub(super) segmentation: bool,
}

/// What the header of one image file says.
#[derive(Debug)]
pub(super) struct Header {
    pub(super) path: PathBuf,
    pub(super) series_uid: String,
    pub(super) format: Format,
    pub(super) frames: u32,
    pub(super) orientation: [f64; 6],
    /// `[row spacing, column spacing]`.
    pub(super) pixel_spacing: Option<[f64; 2]>,
    /// SpacingBetweenSlices, else SliceThickness.
    pub(super) slice_step: Option<f64>,
    /// `DoseUnits` of an RT Dose (GY, RELATIVE), whose values are scaled by
    /// `DoseGridScaling` into them.
    pub(super) dose_units: Option<String>,
    pub(super) planes: Vec<Plane>,
}

/// One file of a directory, as its header describes it.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)] // one per file, moved a few times
pub(super) enum Probe {
    /// Nothing tmc lists as an image: not DICOM, damaged, a DICOMDIR, a
    /// non-image object (a report, an RT plan, a presentation state); the
    /// error says which.
    Skip(Error),
    /// An image of the series `meta` says; `header` is the reason tmc
    /// cannot read it, if it cannot.
    Image {
        meta: SeriesMeta,
        /// `SOPInstanceUID`: copies of one image share it.
        sop_uid: String,
        header: Result<Header>,
    },
}

/// Reads the header of `path` (never its pixel data) and says what the
/// file is.
pub(super) fn probe(path: &Path) -> Probe {
    // A file whose pixel data runs past its end (truncated) still has a
    // header to parse: it is probed for its series, so that it is left out
    // of its own series by name rather than skipped as a stray. Any other
    // length that does not fit stops here (parsing it could allocate what
    // it claims).
    let pixels = lengths::check(path).map_err(|e| (e.contains("(7FE0,0010)"), format_err(path, e)));
    if let Err((false, e)) = pixels {
        return Probe::Skip(e);
    }
    let pixels = pixels.map_err(|(_, e)| e);
    let mut obj = match OpenFileOptions::new()
        .read_until(tags::PIXEL_DATA)
        .open_file(path)
    {
        Ok(obj) => obj,
        Err(e) => {
            return Probe::Skip(pixels.err().unwrap_or_else(|| {
                let why = syntax::unreadable(path).unwrap_or_else(|| e.to_string());
                format_err(path, format!("not a readable DICOM file: {why}"))
            }))
        }
    };
    unknown_vr::resolve(&mut obj);
    if obj.meta().media_storage_sop_class_uid() == MEDIA_STORAGE_DIRECTORY {
        return Probe::Skip(format_err(
            path,
            "a DICOMDIR indexes files but holds no image; open its directory",
        ));
    }
    let ts_uid = lengths::unpadded(obj.meta().transfer_syntax()).to_string();
    let segmentation =
        segmentation::is_segmentation(&obj, obj.meta().media_storage_sop_class_uid());
    let meta = SeriesMeta {
        segmentation,
        uid: text(&obj, tags::SERIES_INSTANCE_UID).unwrap_or_default(),
        number: text(&obj, tags::SERIES_NUMBER),
        modality: text(&obj, tags::MODALITY),
        description: text(&obj, tags::SERIES_DESCRIPTION),
        transfer_syntax: TransferSyntaxRegistry
            .get(&ts_uid)
            .map_or(ts_uid.clone(), |ts| ts.name().to_string()),
    };
    if element(&obj, tags::ROWS).is_none() {
        let what = meta.modality.clone().unwrap_or_else(|| {
            lengths::unpadded(obj.meta().media_storage_sop_class_uid()).to_string()
        });
        return Probe::Skip(format_err(
            path,
            format!("not an image ({what}, no Rows): nothing to read"),
        ));
    }
    let sop_uid = text(&obj, tags::SOP_INSTANCE_UID).unwrap_or_default();
    let header = if segmentation {
        Err(format_err(
            path,
            "a Segmentation object, read on its own (its segments as a label map)",
        ))
    } else {
        pixels.and_then(|pixels| Header::from_header(path, &obj, &ts_uid, pixels, &meta))
    };
    Probe::Image {
        meta,
        sop_uid,
        header,
    }
}

impl Header {
    /// The header of image file `path`, parsed into `obj` (transfer
    /// syntax `ts_uid`; `pixels`: what the length walk saw of its pixel
    /// data).
    fn from_header(
        path: &Path,
        obj: &InMemDicomObject,
        ts_uid: &str,
        pixels: Option<lengths::PixelData>,
        meta: &SeriesMeta,
    ) -> Result<Header> {
        if !TransferSyntaxRegistry
            .get(ts_uid)
            .is_some_and(|ts| ts.can_decode_all())
        {
            return Err(format_err(path, syntax::unsupported(ts_uid)));
        }
        let uint = |tag: Tag, name: &str| -> Result<u32> {
            element(obj, tag)
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
        let bits_stored = element(obj, tags::BITS_STORED)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(bits_allocated);
        let samples = element(obj, tags::SAMPLES_PER_PIXEL)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(1);
        let signed = element(obj, tags::PIXEL_REPRESENTATION)
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
        let series_uid = meta.uid.clone();
        let frames = element(obj, tags::NUMBER_OF_FRAMES)
            .and_then(|e| e.to_int::<u32>().ok())
            .unwrap_or(1)
            .max(1);
        check_pixel_data(path, &format, frames, pixels)?;

        let shared = first_item(obj, tags::SHARED_FUNCTIONAL_GROUPS_SEQUENCE);
        let per_frame_items =
            element(obj, tags::PER_FRAME_FUNCTIONAL_GROUPS_SEQUENCE).and_then(|e| e.items());
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
        let lookup = |k: usize, seq: Tag, tag: Tag| frame_floats(obj, group(k), shared, seq, tag);

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
        let first_position = vec3(lookup(
            0,
            tags::PLANE_POSITION_SEQUENCE,
            tags::IMAGE_POSITION_PATIENT,
        ));
        let grid_distances = match first_position {
            Some(first) if !per_frame_positions => {
                rt_dose::frame_distances(obj, frames as usize, first, normal)
                    .map_err(|e| format_err(path, e))?
            }
            _ => None,
        };
        let dose_scaling = rt_dose::dose_scaling(obj).map_err(|e| format_err(path, e))?;
        let dose_units = rt_dose::dose_units(obj);
        let mut planes: Vec<Plane> = Vec::with_capacity(frames as usize);
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
            } else if let Some(d) = &grid_distances {
                let first = planes[0].position;
                [0, 1, 2].map(|i| first[i] + normal[i] * d[k])
            } else {
                let step = slice_step.ok_or_else(|| {
                    format_err(
                        path,
                        "multi-frame file with one ImagePositionPatient and no GridFrameOffsetVector, SpacingBetweenSlices or SliceThickness: cannot place its frames",
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
            .unwrap_or(1.0)
                * dose_scaling.unwrap_or(1.0);
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
        Ok(Header {
            path: path.to_path_buf(),
            series_uid,
            format,
            frames,
            orientation,
            pixel_spacing,
            slice_step,
            dose_units,
            planes,
        })
    }
}

impl Header {
    /// Why the slices of `self` cannot stack with those of `first`:
    /// another size, sample type, orientation or pixel spacing; `None` if
    /// they can.
    pub(super) fn differs(&self, first: &Header) -> Option<String> {
        let h = self;
        let (a, b) = (first.format, h.format);
        if (a.columns, a.rows) != (b.columns, b.rows) {
            return Some(format!(
                "{}x{} slice (Columns x Rows) differs from the {}x{} of {}",
                b.columns,
                b.rows,
                a.columns,
                a.rows,
                first.path.display()
            ));
        }
        if a != b {
            return Some(
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
            );
        }
        if h.orientation
            .iter()
            .zip(&first.orientation)
            .any(|(x, y)| (x - y).abs() > 1e-4)
        {
            return Some(format!(
                "ImageOrientationPatient {:?} differs from {:?} of {}",
                h.orientation,
                first.orientation,
                first.path.display()
            ));
        }
        let same_spacing = match (h.pixel_spacing, first.pixel_spacing) {
            (Some(x), Some(y)) => (0..2).all(|i| (x[i] - y[i]).abs() <= 1e-4 * y[i].max(1.0)),
            (x, y) => x.is_none() && y.is_none(),
        };
        if !same_spacing {
            return Some(format!(
                "PixelSpacing {:?} differs from {:?} of {}",
                h.pixel_spacing,
                first.pixel_spacing,
                first.path.display()
            ));
        }
        None
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
    pixels: Option<lengths::PixelData>,
) -> Result<()> {
    let size = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    let need = format.frame_bytes() * u128::from(frames);
    let problem = match pixels {
        Some(lengths::PixelData::Native(len)) if need > u128::from(len) => Some(format!(
            "{len} bytes of pixel data, but {frames} frame(s) of {}x{} at {} bits need {need}",
            format.columns, format.rows, format.bits_allocated
        )),
        Some(lengths::PixelData::Fragments(n)) if u64::from(frames) > n => Some(format!(
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
