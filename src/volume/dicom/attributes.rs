//! Reading attributes of a parsed DICOM header: plain, per frame (the
//! functional groups of enhanced objects) and the geometry of a slice
//! orientation.

use super::lengths;
use dicom_core::VR;
use dicom_object::mem::InMemElement;
use dicom_object::{InMemDicomObject, Tag};

pub(super) fn element(obj: &InMemDicomObject, tag: Tag) -> Option<&InMemElement> {
    obj.element_opt(tag).ok().flatten()
}

/// A text attribute, unpadded; one stored with VR UN (some converters
/// write every element so) is read as the text of its bytes.
pub(super) fn text(obj: &InMemDicomObject, tag: Tag) -> Option<String> {
    let e = element(obj, tag)?;
    let s = if e.vr() == VR::UN {
        String::from_utf8_lossy(e.value().to_bytes().ok()?.as_ref()).into_owned()
    } else {
        e.to_str().ok()?.into_owned()
    };
    Some(lengths::unpadded(s.trim()).to_string()).filter(|s| !s.is_empty())
}

pub(super) fn floats(obj: &InMemDicomObject, tag: Tag) -> Option<Vec<f64>> {
    element(obj, tag).and_then(|e| e.to_multi_float64().ok())
}

pub(super) fn first_item(obj: &InMemDicomObject, seq: Tag) -> Option<&InMemDicomObject> {
    element(obj, seq)
        .and_then(|e| e.items())
        .and_then(|i| i.first())
}

/// Attribute `tag` of a frame: in its own functional group `seq`, in the
/// shared one, or at the top level.
pub(super) fn frame_floats(
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

pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    v.map(|x| x / n)
}

/// Row cosine, column cosine and normal of an `ImageOrientationPatient`.
pub(super) fn axes(o: &[f64; 6]) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let row = unit([o[0], o[1], o[2]]);
    let col = unit([o[3], o[4], o[5]]);
    (row, col, unit(cross(row, col)))
}

pub(super) fn vec3(v: Option<Vec<f64>>) -> Option<[f64; 3]> {
    v.filter(|v| v.len() >= 3 && v.iter().all(|x| x.is_finite()))
        .map(|v| [v[0], v[1], v[2]])
}
