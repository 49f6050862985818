//! The little vector arithmetic normals need, in `f64`.

/// `v` scaled to unit length as `f32`, or `None` when it is zero or not
/// finite. Scaled by its largest component first, so that neither tiny nor
/// huge vectors lose precision or overflow.
pub fn unit(v: [f64; 3]) -> Option<[f32; 3]> {
    let largest = v[0].abs().max(v[1].abs()).max(v[2].abs());
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let v = v.map(|c| c / largest);
    let length = dot(v, v).sqrt();
    Some(v.map(|c| (c / length) as f32))
}

/// `a - b`.
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product of `a` and `b`.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product `a x b` (right-handed).
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
