//! DICOM Segmentation objects (SEG): what their header says of their
//! segments and where their frames lie.
//!
//! A SEG is a multi-frame file whose every frame is one slice of one
//! segment: its per-frame functional groups give the frame's position
//! (Plane Position), its segment (Segment Identification, a
//! `ReferencedSegmentNumber` of the Segment Sequence), and, per frame or
//! shared, its orientation and pixel measures. The frames of all segments
//! are placed on one grid here:
//!
//! * the slices are the distinct positions of the frames along the normal,
//!   stepped by `SpacingBetweenSlices` (else by the smallest gap between
//!   them); a slice no frame lies on (writers omit the frames of empty
//!   slices, highdicom by default) is empty, so the grid spans the first
//!   to the last slice any segment touches, and no further: the CT it was
//!   drawn on is not read;
//! * frames must share one orientation and lie on one line along the
//!   normal, each a whole number of steps from the first slice.
//!
//! BINARY segmentations store one bit per sample (BitsAllocated 1, frames
//! packed one after the other, least significant bit first); FRACTIONAL
//! ones 8 bits, a fraction of `MaximumFractionalValue`. How the frames
//! become samples is `seg_volume.rs`.

use super::attributes::{axes, dot, element, first_item, frame_floats, text, vec3};
use super::files::format_err;
use crate::volume::{Grid, SegmentNote};
use crate::Result;
use dicom_dictionary_std::tags;
use dicom_object::{InMemDicomObject, Tag};
use std::path::Path;

/// The SOP class of Segmentation Storage.
pub(super) const SEGMENTATION_STORAGE: &str = "1.2.840.10008.5.1.4.1.1.66.4";

/// Most slices a SEG's grid may have: a step far smaller than the span of
/// the frames (a damaged `SpacingBetweenSlices`) must not claim memory.
const MAX_SLICES: usize = 1 << 16;

/// How a SEG stores its samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// One bit per sample.
    Binary,
    /// 8 bits per sample, a fraction of this `MaximumFractionalValue`.
    Fractional(u8),
}

/// A SEG's header: its segments and frames on one grid.
#[derive(Debug)]
pub(super) struct SegHeader {
    pub(super) kind: Kind,
    pub(super) grid: Grid,
    pub(super) segments: Vec<SegmentNote>,
    /// `(frame, segment number)` of the frames of each slice, by slice.
    pub(super) slices: Vec<Vec<(usize, u32)>>,
    /// Frames in the file.
    pub(super) frames: usize,
}

/// Is the parsed header `obj` a Segmentation object (its SOP class, or
/// modality SEG)?
pub(super) fn is_segmentation(obj: &InMemDicomObject, sop_class: &str) -> bool {
    super::lengths::unpadded(sop_class) == SEGMENTATION_STORAGE
        || text(obj, tags::MODALITY).as_deref() == Some("SEG")
}

/// The segments of the Segment Sequence, with their frames not counted yet.
fn segments(path: &Path, obj: &InMemDicomObject) -> Result<Vec<SegmentNote>> {
    let items = element(obj, tags::SEGMENT_SEQUENCE)
        .and_then(|e| e.items())
        .filter(|i| !i.is_empty())
        .ok_or_else(|| format_err(path, "a Segmentation without a SegmentSequence"))?;
    let mut out: Vec<SegmentNote> = Vec::new();
    for item in items {
        let number = element(item, tags::SEGMENT_NUMBER)
            .and_then(|e| e.to_int::<u32>().ok())
            .filter(|&n| n > 0)
            .ok_or_else(|| format_err(path, "a segment without a SegmentNumber (1 or more)"))?;
        if out.iter().any(|s| s.number == number) {
            return Err(format_err(path, format!("two segments numbered {number}")));
        }
        out.push(SegmentNote {
            number,
            label: text(item, tags::SEGMENT_LABEL).unwrap_or_default(),
            property: first_item(item, tags::SEGMENTED_PROPERTY_TYPE_CODE_SEQUENCE)
                .and_then(|code| text(code, tags::CODE_MEANING)),
            algorithm: text(item, tags::SEGMENT_ALGORITHM_TYPE),
            frames: 0,
        });
    }
    out.sort_by_key(|s| s.number);
    Ok(out)
}

/// An unsigned attribute of the top level.
fn uint(obj: &InMemDicomObject, tag: Tag) -> Option<u32> {
    element(obj, tag).and_then(|e| e.to_int::<u32>().ok())
}

/// Reads the header of SEG `path`, parsed into `obj`. `stored_frames`:
/// the frames its pixel data holds, which count when the file states no
/// `NumberOfFrames`.
pub(super) fn read(
    path: &Path,
    obj: &InMemDicomObject,
    stored_frames: impl Fn(Kind, usize) -> usize,
) -> Result<SegHeader> {
    let fail = |msg: String| format_err(path, msg);
    let kind = match text(obj, tags::SEGMENTATION_TYPE).as_deref() {
        Some("BINARY") => Kind::Binary,
        Some("FRACTIONAL") => {
            let max = uint(obj, tags::MAXIMUM_FRACTIONAL_VALUE)
                .filter(|&m| (1..=255).contains(&m))
                .ok_or_else(|| {
                    fail(
                        "a FRACTIONAL Segmentation without a MaximumFractionalValue of 1 to 255"
                            .into(),
                    )
                })?;
            Kind::Fractional(max as u8)
        }
        other => {
            return Err(fail(format!(
                "SegmentationType {} is not supported (need BINARY or FRACTIONAL)",
                other.unwrap_or("(none)")
            )))
        }
    };
    let bits = uint(obj, tags::BITS_ALLOCATED).unwrap_or(0);
    let need = match kind {
        Kind::Binary => 1,
        Kind::Fractional(_) => 8,
    };
    if bits != need {
        return Err(fail(format!(
            "BitsAllocated {bits} in a {} Segmentation (need {need})",
            if need == 1 { "BINARY" } else { "FRACTIONAL" }
        )));
    }
    let (rows, columns) = match (uint(obj, tags::ROWS), uint(obj, tags::COLUMNS)) {
        (Some(r), Some(c)) if r > 0 && c > 0 => (r as usize, c as usize),
        _ => return Err(fail("no Rows or Columns: not a complete image".into())),
    };
    let frames = match uint(obj, tags::NUMBER_OF_FRAMES) {
        Some(n) => n.max(1) as usize,
        None => stored_frames(kind, rows * columns).max(1),
    };
    let mut segments = segments(path, obj)?;

    let shared = first_item(obj, tags::SHARED_FUNCTIONAL_GROUPS_SEQUENCE);
    // Groups beyond the frames (in a file cut down to fewer frames) are
    // not read.
    let per_frame = element(obj, tags::PER_FRAME_FUNCTIONAL_GROUPS_SEQUENCE)
        .and_then(|e| e.items())
        .filter(|items| items.len() >= frames)
        .ok_or_else(|| {
            fail(format!(
                "a Segmentation needs one per-frame functional group per frame ({frames}) to place its frames"
            ))
        })?;
    let lookup =
        |k: usize, seq: Tag, tag: Tag| frame_floats(obj, per_frame.get(k), shared, seq, tag);
    let orientation = |k: usize| {
        lookup(
            k,
            tags::PLANE_ORIENTATION_SEQUENCE,
            tags::IMAGE_ORIENTATION_PATIENT,
        )
        .filter(|v| v.len() >= 6 && v.iter().all(|x| x.is_finite()))
        .map(|v| [v[0], v[1], v[2], v[3], v[4], v[5]])
    };
    let o = orientation(0)
        .ok_or_else(|| fail("no ImageOrientationPatient: cannot place the frames".into()))?;
    let (row, col, normal) = axes(&o);
    if !normal.iter().all(|x| x.is_finite()) || dot(row, col).abs() > 1e-3 {
        return Err(fail(format!(
            "ImageOrientationPatient {o:?} is not two orthogonal directions"
        )));
    }
    let spacing = lookup(0, tags::PIXEL_MEASURES_SEQUENCE, tags::PIXEL_SPACING)
        .filter(|v| v.len() >= 2 && v[..2].iter().all(|s| s.is_finite() && *s > 0.0))
        .map_or([1.0, 1.0], |v| [v[0], v[1]]);
    let first_number = |tag| {
        lookup(0, tags::PIXEL_MEASURES_SEQUENCE, tag)
            .and_then(|v| v.first().copied())
            .filter(|s| s.is_finite() && *s > 0.0)
    };
    let between = first_number(tags::SPACING_BETWEEN_SLICES);
    let thickness = first_number(tags::SLICE_THICKNESS);

    // Each frame: its position, its distance along the normal, its segment.
    let mut placed = Vec::with_capacity(frames);
    for k in 0..frames {
        if let Some(ok) = orientation(k) {
            if ok.iter().zip(&o).any(|(a, b)| (a - b).abs() > 1e-4) {
                return Err(fail(format!(
                    "frame {} has another orientation {ok:?} than frame 1 {o:?}",
                    k + 1
                )));
            }
        }
        let position = vec3(lookup(
            k,
            tags::PLANE_POSITION_SEQUENCE,
            tags::IMAGE_POSITION_PATIENT,
        ))
        .ok_or_else(|| fail(format!("frame {} has no ImagePositionPatient", k + 1)))?;
        let segment = [per_frame.get(k), shared]
            .into_iter()
            .flatten()
            .filter_map(|g| first_item(g, tags::SEGMENT_IDENTIFICATION_SEQUENCE))
            .find_map(|item| uint(item, tags::REFERENCED_SEGMENT_NUMBER))
            .ok_or_else(|| {
                fail(format!(
                    "frame {} names no segment (ReferencedSegmentNumber)",
                    k + 1
                ))
            })?;
        let note = segments
            .iter_mut()
            .find(|s| s.number == segment)
            .ok_or_else(|| {
                fail(format!(
                    "frame {} is of segment {segment}, which the SegmentSequence does not describe",
                    k + 1
                ))
            })?;
        note.frames += 1;
        placed.push((position, dot(position, normal), segment));
    }

    // The distinct slices, ascending along the normal.
    let mut distances: Vec<f64> = placed.iter().map(|p| p.1).collect();
    distances.sort_by(f64::total_cmp);
    let extent = distances[distances.len() - 1] - distances[0];
    let same = 1e-3 * between.unwrap_or(1.0).min(1.0);
    distances.dedup_by(|a, b| (*a - *b).abs() <= same);
    let step = match between {
        Some(s) => s,
        None if distances.len() > 1 => distances
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min),
        None => thickness.unwrap_or(1.0),
    };
    let count = (extent / step).round() + 1.0;
    if count.is_nan() || count > MAX_SLICES as f64 {
        return Err(fail(format!(
            "frames spanning {extent} mm at a slice step of {step} mm make {count} slices, more than the {MAX_SLICES} tmc reads"
        )));
    }
    let start = distances[0];
    let first_position = placed
        .iter()
        .find(|p| (p.1 - start).abs() <= same)
        .map(|p| p.0)
        .unwrap_or(placed[0].0);
    let mut slices = vec![Vec::new(); count as usize];
    for (k, &(position, distance, segment)) in placed.iter().enumerate() {
        let steps = (distance - start) / step;
        let z = steps.round();
        let along = z * step;
        let off = [0, 1, 2].map(|i| position[i] - first_position[i] - normal[i] * along);
        if (steps - z).abs() > 1e-2 || dot(off, off).sqrt() > 1e-2 * step.max(1.0) {
            return Err(fail(format!(
                "frame {} at {position:?} is not on the grid of the other frames (slices {step} mm apart along {normal:?} from {first_position:?})",
                k + 1
            )));
        }
        slices[z as usize].push((k, segment));
    }
    let grid = Grid {
        dims: [columns, rows, slices.len()],
        spacing: [spacing[1], spacing[0], step],
        origin: first_position,
        direction: [0, 1, 2].map(|i| [row[i], col[i], normal[i]]),
    };
    Ok(SegHeader {
        kind,
        grid,
        segments,
        slices,
        frames,
    })
}
