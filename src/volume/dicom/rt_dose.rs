//! RT Dose grids: where their frames lie and what their values mean.
//!
//! An RT Dose object (modality RTDOSE) is a multi-frame image with one
//! `ImagePositionPatient`; its frames are placed by Grid Frame Offset
//! Vector (3004,000C), one offset per frame, which the standard allows in
//! two forms:
//!
//! * relative: the first offset is 0 and each offset is the distance of
//!   its frame from the first along the slice normal;
//! * absolute: the first offset equals the z of `ImagePositionPatient`
//!   and each offset is its frame's z in patient coordinates (only for
//!   axial grids, normal along z).
//!
//! The stored integers times Dose Grid Scaling (3004,000E) are the dose in
//! Dose Units (3004,0002): GY, or RELATIVE to a reference dose. So with
//! `DoseUnits` GY `--iso 50` is the 50 Gy isodose surface.

use super::attributes::{element, floats};
use super::lengths;
use dicom_object::{InMemDicomObject, Tag};

/// Grid Frame Offset Vector.
const GRID_FRAME_OFFSET_VECTOR: Tag = Tag(0x3004, 0x000C);
/// Dose Grid Scaling.
const DOSE_GRID_SCALING: Tag = Tag(0x3004, 0x000E);
/// Dose Units.
const DOSE_UNITS: Tag = Tag(0x3004, 0x0002);

/// Largest difference (mm) between the first offset and 0 or the first
/// position's z for the offsets to count as relative or absolute.
const SAME_PLACE: f64 = 1e-3;

/// The distance of each of `frames` frames from the first along `normal`,
/// from Grid Frame Offset Vector; `Ok(None)` if the file has none.
/// `first` is the first frame's `ImagePositionPatient`. An error (a
/// sentence) for a vector with fewer values than frames, non-finite
/// values, or a first value that is neither 0 nor `first`'s z.
pub(super) fn frame_distances(
    obj: &InMemDicomObject,
    frames: usize,
    first: [f64; 3],
    normal: [f64; 3],
) -> Result<Option<Vec<f64>>, String> {
    let Some(offsets) = floats(obj, GRID_FRAME_OFFSET_VECTOR) else {
        return Ok(None);
    };
    if offsets.len() < frames {
        return Err(format!(
            "GridFrameOffsetVector has {} values for {frames} frames",
            offsets.len()
        ));
    }
    let offsets = &offsets[..frames];
    if offsets.iter().any(|o| !o.is_finite()) {
        return Err(format!(
            "GridFrameOffsetVector {offsets:?} holds a non-finite value"
        ));
    }
    let o0 = offsets[0];
    if o0.abs() <= SAME_PLACE {
        return Ok(Some(offsets.to_vec()));
    }
    if (o0 - first[2]).abs() <= SAME_PLACE * first[2].abs().max(1.0) {
        if (normal[2].abs() - 1.0).abs() > 1e-4 {
            return Err(format!(
                "GridFrameOffsetVector holds absolute z positions, but the frames' normal {normal:?} is not along z"
            ));
        }
        // position z = offset, and position = first + normal * distance.
        return Ok(Some(
            offsets.iter().map(|o| (o - first[2]) * normal[2]).collect(),
        ));
    }
    Err(format!(
        "GridFrameOffsetVector starts at {o0}: neither 0 (offsets relative to the first frame) nor the first frame's z {} (absolute positions)",
        first[2]
    ))
}

/// Dose Grid Scaling, the factor from stored values to dose; `None` if
/// the file has none. An error for a value that is not finite and positive.
pub(super) fn dose_scaling(obj: &InMemDicomObject) -> Result<Option<f64>, String> {
    match floats(obj, DOSE_GRID_SCALING).and_then(|v| v.first().copied()) {
        None => Ok(None),
        Some(s) if s.is_finite() && s > 0.0 => Ok(Some(s)),
        Some(s) => Err(format!("bad DoseGridScaling {s}")),
    }
}

/// Dose Units (GY, RELATIVE), if the file states them.
pub(super) fn dose_units(obj: &InMemDicomObject) -> Option<String> {
    element(obj, DOSE_UNITS)
        .and_then(|e| e.to_str().ok())
        .map(|s| lengths::unpadded(s.trim()).to_string())
        .filter(|s| !s.is_empty())
}
