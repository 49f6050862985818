//! A DICOM Segmentation object as a [`SampleSource`]: its segments as a
//! label map (each sample the number of the segment that holds it, 0 for
//! none), or one segment alone as a volume of 0 to 1.
//!
//! * Label map: a sample belongs to a segment when its bit is set
//!   (BINARY) or its fraction is above one half (FRACTIONAL, the same
//!   sample that `--segment N --iso 0.5` puts inside). A label map holds
//!   one segment per sample; where segments overlap, the sample takes the
//!   highest number, and the pairs that overlap are found at open (one
//!   pass over the frames) and reported
//!   ([`SourceNotes::overlapping_segments`]), so that `--labels` can
//!   refuse the file by name rather than mesh a label map that is not the
//!   file's.
//! * One segment ([`DicomSegmentation::open`] with `segment`): 1 where
//!   its bit is set, or its fraction (stored value over
//!   `MaximumFractionalValue`, so that `--iso 0.5` is the half-way
//!   surface); 0 on the slices it has no frame on. Overlaps do not matter.
//!
//! The file is parsed whole at open and its pixel data kept (bit-packed
//! for BINARY, one byte a sample for FRACTIONAL, decoded once if it is
//! compressed): a SEG is a fraction of the size of the CT it was drawn on.

use super::files::format_err;
use super::segmentation::{self, Kind, SegHeader};
use super::{lengths, syntax, unknown_vr};
use crate::volume::{guarded, Grid, SampleSource, ScalarType, SegmentNote, SourceNotes};
use crate::{Error, Result};
use dicom_dictionary_std::tags;
use dicom_object::OpenFileOptions;
use dicom_pixeldata::PixelDecoder;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// A DICOM Segmentation object read as a label map or as one segment.
#[derive(Debug)]
pub struct DicomSegmentation {
    path: PathBuf,
    header: SegHeader,
    /// The pixel data: BINARY frames packed bit by bit, one after the
    /// other; FRACTIONAL frames a byte a sample.
    pixels: Vec<u8>,
    /// The segment read alone, or `None` for the label map.
    segment: Option<u32>,
    overlaps: Vec<[u32; 2]>,
}

impl DicomSegmentation {
    /// Opens SEG file `path`: the label map of its segments, or segment
    /// `segment` alone (an error naming the segments if it has no such
    /// segment).
    pub fn open(path: &Path, segment: Option<u32>) -> Result<DicomSegmentation> {
        lengths::check(path).map_err(|e| format_err(path, e))?;
        let mut obj = OpenFileOptions::new()
            .open_file(path)
            .map_err(|e| format_err(path, format!("not a readable DICOM file: {e}")))?;
        unknown_vr::resolve(&mut obj);
        let pixel_data = obj
            .element_opt(tags::PIXEL_DATA)
            .ok()
            .flatten()
            .ok_or_else(|| format_err(path, "a Segmentation without pixel data"))?;
        let stored_frames = |kind, frame: usize| match pixel_data.value().fragments() {
            Some(fragments) => fragments.len(),
            None => {
                let bytes = pixel_data.value().to_bytes().map_or(0, |b| b.len());
                match kind {
                    Kind::Binary => bytes.saturating_mul(8) / frame.max(1),
                    Kind::Fractional(_) => bytes / frame.max(1),
                }
            }
        };
        let header = segmentation::read(path, &obj, stored_frames)?;
        if let Some(n) = segment {
            if !header.segments.iter().any(|s| s.number == n) {
                return Err(format_err(
                    path,
                    format!("no segment {n} (it has {})", list(&header.segments)),
                ));
            }
        }
        let [columns, rows, _] = header.grid.dims;
        let frame = columns * rows;
        let pixels = if pixel_data.value().fragments().is_some() {
            if header.kind == Kind::Binary {
                return Err(format_err(
                    path,
                    format!(
                        "a BINARY Segmentation with compressed pixel data (transfer syntax {}) is not supported; store it uncompressed",
                        syntax::describe(lengths::unpadded(obj.meta().transfer_syntax()))
                    ),
                ));
            }
            let mut all = Vec::with_capacity(frame * header.frames);
            for k in 0..header.frames {
                let cannot = |e: String| {
                    let ts = lengths::unpadded(obj.meta().transfer_syntax());
                    format_err(
                        path,
                        format!("frame {}: {}", k + 1, syntax::undecodable(ts, &e)),
                    )
                };
                let decoded = guarded::guarded(|| obj.decode_pixel_data_frame(k as u32))
                    .map_err(|panic| cannot(format!("the decoder failed ({panic})")))?
                    .map_err(|e| cannot(e.to_string()))?;
                let data = decoded.data();
                if data.len() < frame {
                    return Err(cannot(format!("{} bytes, need {frame}", data.len())));
                }
                all.extend_from_slice(&data[..frame]);
            }
            all
        } else {
            let bytes = pixel_data
                .value()
                .to_bytes()
                .map_err(|e| format_err(path, format!("cannot read the pixel data: {e}")))?;
            let samples = frame as u128 * header.frames as u128;
            let need = match header.kind {
                Kind::Binary => samples.div_ceil(8),
                Kind::Fractional(_) => samples,
            };
            if (bytes.len() as u128) < need {
                return Err(format_err(
                    path,
                    format!(
                        "{} bytes of pixel data, but {} frame(s) of {columns}x{rows} need {need}",
                        bytes.len(),
                        header.frames
                    ),
                ));
            }
            bytes[..need as usize].to_vec()
        };
        let mut seg = DicomSegmentation {
            path: path.to_path_buf(),
            header,
            pixels,
            segment,
            overlaps: Vec::new(),
        };
        let mut plane = vec![0.0; frame];
        let mut overlaps = BTreeSet::new();
        for z in 0..seg.header.slices.len() {
            seg.label_plane(z, &mut plane, &mut overlaps);
        }
        seg.overlaps = overlaps.into_iter().collect();
        Ok(seg)
    }

    /// The segments of the file, by number.
    pub fn segments(&self) -> &[SegmentNote] {
        &self.header.segments
    }

    /// Pairs of segments that share samples, `[lower, higher]`, ascending.
    pub fn overlapping_segments(&self) -> &[[u32; 2]] {
        &self.overlaps
    }

    /// The segment read alone, if one was chosen.
    pub fn segment(&self) -> Option<u32> {
        self.segment
    }

    /// Is sample `i` of frame `k` inside its segment (set, or a fraction
    /// above one half)?
    fn inside(&self, k: usize, i: usize) -> bool {
        match self.header.kind {
            Kind::Binary => self.bit(k, i),
            Kind::Fractional(max) => 2 * u32::from(self.byte(k, i)) > u32::from(max),
        }
    }

    fn frame_len(&self) -> usize {
        self.header.grid.dims[0] * self.header.grid.dims[1]
    }

    fn bit(&self, k: usize, i: usize) -> bool {
        let at = k * self.frame_len() + i;
        (self.pixels[at >> 3] >> (at & 7)) & 1 == 1
    }

    fn byte(&self, k: usize, i: usize) -> u8 {
        self.pixels[k * self.frame_len() + i]
    }

    /// Slice `z` as a label map into `out`; pairs of segments found
    /// sharing a sample are added to `overlaps`.
    fn label_plane(&self, z: usize, out: &mut [f64], overlaps: &mut BTreeSet<[u32; 2]>) {
        out.fill(0.0);
        for &(k, segment) in &self.header.slices[z] {
            let label = f64::from(segment);
            for (i, o) in out.iter_mut().enumerate() {
                if self.inside(k, i) {
                    if *o != 0.0 && *o != label {
                        let other = *o as u32;
                        overlaps.insert([other.min(segment), other.max(segment)]);
                    }
                    *o = o.max(label);
                }
            }
        }
    }

    /// Slice `z` of segment `n` alone into `out`: 0/1, or fractions.
    fn segment_plane(&self, z: usize, n: u32, out: &mut [f64]) {
        out.fill(0.0);
        for &(k, _) in self.header.slices[z].iter().filter(|f| f.1 == n) {
            for (i, o) in out.iter_mut().enumerate() {
                let v = match self.header.kind {
                    Kind::Binary => f64::from(u8::from(self.bit(k, i))),
                    Kind::Fractional(max) => f64::from(self.byte(k, i)) / f64::from(max),
                };
                *o = o.max(v);
            }
        }
    }
}

/// The segments of a SEG as a phrase: "1 (ball), 2 (box)".
pub(super) fn list(segments: &[SegmentNote]) -> String {
    let named: Vec<String> = segments
        .iter()
        .map(|s| match s.label.as_str() {
            "" => s.number.to_string(),
            label => format!("{} ({label})", s.number),
        })
        .collect();
    format!("segments {}", named.join(", "))
}

impl SampleSource for DicomSegmentation {
    fn grid(&self) -> &Grid {
        &self.header.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        if z >= self.header.slices.len() || out.len() != self.frame_len() {
            return Err(Error::Invalid(format!(
                "{}: plane {z} of {} samples asked of {} slices of {}",
                self.path.display(),
                out.len(),
                self.header.slices.len(),
                self.frame_len()
            )));
        }
        match self.segment {
            Some(n) => self.segment_plane(z, n, out),
            None => self.label_plane(z, out, &mut BTreeSet::new()),
        }
        Ok(())
    }

    fn data_files(&self) -> Vec<&Path> {
        vec![self.path.as_path()]
    }

    fn sample_bytes(&self) -> usize {
        1
    }

    /// One byte for the fractions of one segment of a FRACTIONAL file;
    /// unknown otherwise (bits, or segment numbers).
    fn stored_type(&self) -> Option<ScalarType> {
        match (self.header.kind, self.segment) {
            (Kind::Fractional(_), Some(_)) => Some(ScalarType::U8),
            _ => None,
        }
    }

    /// The segments, and those that overlap.
    fn notes(&self) -> SourceNotes {
        SourceNotes {
            segments: self.header.segments.clone(),
            overlapping_segments: self.overlaps.clone(),
            ..SourceNotes::default()
        }
    }
}
