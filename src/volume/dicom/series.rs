//! One DICOM series as a [`SampleSource`]: the planes of the files
//! [`super::series_index`] chose, sorted along their normal, evenly
//! spaced, decoded one at a time when the slab loop asks for them.

use super::attributes::{axes, dot, element};
use super::files::format_err;
use super::header::{Format, Header, Plane};
use super::{lengths, syntax, unknown_vr};
use crate::volume::{guarded, Grid, PlaneView, SampleSource, ScalarType, SharedPlane, SourceNotes};
use crate::{Error, Result};
use dicom_dictionary_std::tags;
use dicom_object::{DefaultDicomObject, InMemDicomObject, OpenFileOptions};
use dicom_pixeldata::PixelDecoder;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

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
    /// Files of the directory not read, and why (one line each).
    pub(super) skipped: Vec<String>,
    /// `DoseUnits` of an RT Dose.
    dose_units: Option<String>,
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

    /// The files of the directory that were not read, and why, one line
    /// each: other series, non-image objects, files that do not parse,
    /// copies of one image and slices left out of this series.
    pub fn skipped(&self) -> &[String] {
        &self.skipped
    }

    /// Samples along x, y, z.
    pub(super) fn grid_dims(&self) -> [usize; 3] {
        self.grid.dims
    }

    /// The unit of the values, where the file states one: `DoseUnits` of
    /// an RT Dose (GY, RELATIVE).
    pub fn units(&self) -> Option<&str> {
        self.dose_units.as_deref()
    }

    /// `RescaleSlope` and `RescaleIntercept` of plane `z`.
    pub fn rescale(&self, z: usize) -> Option<(f64, f64)> {
        self.planes.get(z).map(|p| (p.slope, p.intercept))
    }
}

/// Builds the grid of one series from the headers of its files, which
/// agree ([`Header::differs`] says nothing of any two; the caller chose
/// them so): sorts the planes by position and checks that they are evenly
/// spaced along their normal. `left_out` (the files of the series the
/// caller left out, and why) is added to an error, which their absence may
/// explain (a gap), and kept for [`DicomSeries::skipped`].
pub(super) fn assemble(
    dir: &Path,
    series_uid: String,
    headers: Vec<Header>,
    left_out: Vec<String>,
) -> Result<DicomSeries> {
    let skipped = left_out.clone();
    let mut series = stack(dir, series_uid, headers).map_err(|e| {
        if left_out.is_empty() {
            e
        } else {
            Error::Format(format!(
                "{e} (left out of the series: {})",
                left_out.join("; ")
            ))
        }
    })?;
    series.skipped = skipped;
    Ok(series)
}

/// [`assemble`] without the files left out.
fn stack(dir: &Path, series_uid: String, headers: Vec<Header>) -> Result<DicomSeries> {
    let first = &headers[0];
    let dose_units = first.dose_units.clone();
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
        skipped: Vec::new(),
        dose_units,
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
        if lengths::unpadded(syntax) == lengths::DEFLATED_FRAMES {
            self.check_deflated_frame(&obj, plane)?;
        }
        let cannot = |e: String| {
            format_err(
                &plane.path,
                syntax::undecodable(lengths::unpadded(syntax), &e),
            )
        };
        let decoded = guarded::guarded(|| obj.decode_pixel_data_frame(plane.frame))
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
        lengths::check(path).map_err(|e| format_err(path, e))?;
        let mut obj = OpenFileOptions::new()
            .open_file(path)
            .map_err(|e| format_err(path, format!("not a readable DICOM file: {e}")))?;
        unknown_vr::resolve(&mut obj);
        let obj = Arc::new(obj);
        *last() = Some((path.to_path_buf(), Arc::clone(&obj)));
        Ok(obj)
    }

    /// Refuses a frame of deflated pixel data ([`lengths::DEFLATED_FRAMES`])
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
            Some(fragment) if lengths::inflates_beyond(fragment, frame_bytes) => {
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

impl DicomSeries {
    /// Plane `z` decoded, its samples kept to their `BitsStored` low bits
    /// (sign-extended when signed) in the type of `BitsAllocated`, with
    /// the plane's `RescaleSlope` and `RescaleIntercept`.
    fn decoded_plane(&self, z: usize) -> Result<SharedPlane> {
        let plane = self.planes.get(z).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: plane {z} is beyond the {} slices",
                self.source.display(),
                self.planes.len()
            ))
        })?;
        let mut bytes = self.decode(plane)?;
        let f = self.format;
        let scalar = self.stored_type().ok_or_else(|| {
            format_err(
                &plane.path,
                format!("{} bits allocated are not read", f.bits_allocated),
            )
        })?;
        let need = f.columns * f.rows * scalar.size();
        if bytes.len() < need {
            return Err(format_err(
                &plane.path,
                format!(
                    "{} bytes of pixel data in frame {}, need {need}",
                    bytes.len(),
                    plane.frame + 1
                ),
            ));
        }
        bytes.truncate(need);
        keep_stored_bits(&mut bytes, scalar.size(), f.bits_stored, f.signed);
        let rescale = (plane.slope, plane.intercept);
        Ok(SharedPlane {
            rescale: (rescale != (1.0, 0.0)).then_some(rescale),
            ..SharedPlane::new(Arc::new(bytes), 0..need, scalar)
        })
    }
}

/// Keeps the low `bits` bits of each `width`-byte sample of `bytes`
/// (native byte order), sign-extended from bit `bits - 1` when `signed`:
/// the values DICOM's `BitsStored` and `PixelRepresentation` give them.
fn keep_stored_bits(bytes: &mut [u8], width: usize, bits: u16, signed: bool) {
    let bits = u32::from(bits);
    if bits >= 8 * width as u32 {
        // Every bit is stored: the samples are their values already.
        return;
    }
    let shift = 64 - bits;
    let keep = |raw: u64| -> u64 {
        if signed {
            (((raw << shift) as i64) >> shift) as u64
        } else {
            (raw << shift) >> shift
        }
    };
    for s in bytes.chunks_exact_mut(width) {
        match width {
            1 => s[0] = keep(u64::from(s[0])) as u8,
            2 => {
                let v = keep(u64::from(u16::from_ne_bytes([s[0], s[1]])));
                s.copy_from_slice(&(v as u16).to_ne_bytes());
            }
            _ => {
                let v = keep(u64::from(u32::from_ne_bytes([s[0], s[1], s[2], s[3]])));
                s.copy_from_slice(&(v as u32).to_ne_bytes());
            }
        }
    }
}

impl SampleSource for DicomSeries {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The decoded plane with its rescale: the slab loop reads the
    /// samples as they are stored (`BitsStored` of them, sign-extended)
    /// and computes `stored * slope + intercept` as it goes, so the plane
    /// is held in its own type rather than as `f64`s.
    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        if out.len() != self.format.columns * self.format.rows {
            return Err(Error::Invalid(format!(
                "plane buffer holds {} samples, a plane has {}",
                out.len(),
                self.format.columns * self.format.rows
            )));
        }
        self.decoded_plane(z)?.rows(0, out.len(), out);
        Ok(())
    }

    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        self.decoded_plane(z).ok()
    }

    fn data_files(&self) -> Vec<&Path> {
        self.planes.iter().map(|p| p.path.as_path()).collect()
    }

    /// The unit of the values (an RT Dose's `DoseUnits`) and the files of
    /// the directory that were not read.
    fn notes(&self) -> SourceNotes {
        SourceNotes {
            units: self.dose_units.clone(),
            skipped: self.skipped.clone(),
            ..SourceNotes::default()
        }
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
