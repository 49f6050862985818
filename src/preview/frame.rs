//! [`Reach`]: the box of the vertices a preview drew, and whether the
//! frame fitted before the first triangle held them.
//!
//! The views are fitted to bounds known up front ([`super::views`]). For a
//! `.tmesh` those are its recorded grid's box, which is the mesh's only
//! when the grid had the identity direction: the format keeps no direction
//! cosines, so a mesh extracted on a rotated or mirrored grid may lie
//! partly or wholly outside the box its picture was framed by. The raster
//! workers grow a [`Reach`] each from the vertices they are handed (six
//! comparisons a vertex), merged at the end by the same minimum and
//! maximum (the same box for any threads or chunking); when it does not
//! fit the frame, [`super::PreviewSink`] draws the mesh again, framed by
//! it ([`super::PreviewSink::reframed`]).

use super::views::Bounds;
use glam::Vec4;

/// The box of the vertices seen so far (empty before the first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    min: [f32; 3],
    max: [f32; 3],
}

impl Default for Reach {
    fn default() -> Self {
        Reach {
            min: [f32::INFINITY; 3],
            max: [f32::NEG_INFINITY; 3],
        }
    }
}

impl Reach {
    /// Grows the box by `vertices` (a NaN coordinate is passed over).
    pub fn add(&mut self, vertices: &[[f32; 3]]) {
        // Four vertices at a time, as three vectors of lanes (x y z x,
        // y z x y, z x y z): a few instructions a vertex. A lane takes a
        // coordinate where the comparison holds, which it does not for a
        // NaN (`Vec4::min` leaves NaNs to the architecture).
        let flat = vertices.as_flattened();
        let mut lo = [Vec4::INFINITY; 3];
        let mut hi = [Vec4::NEG_INFINITY; 3];
        let mut groups = flat.chunks_exact(12);
        for group in &mut groups {
            for (k, (lo, hi)) in lo.iter_mut().zip(&mut hi).enumerate() {
                let v = Vec4::from_slice(&group[4 * k..4 * k + 4]);
                *lo = Vec4::select(v.cmplt(*lo), v, *lo);
                *hi = Vec4::select(v.cmpgt(*hi), v, *hi);
            }
        }
        let lanes = |v: [Vec4; 3]| v.map(|v| v.to_array()).concat();
        let (lo, hi) = (lanes(lo), lanes(hi));
        let rest = groups.remainder();
        for (i, (&l, &h)) in lo.iter().zip(&hi).chain(rest.iter().zip(rest)).enumerate() {
            let a = i % 3;
            self.min[a] = if l < self.min[a] { l } else { self.min[a] };
            self.max[a] = if h > self.max[a] { h } else { self.max[a] };
        }
    }

    /// Grows the box by `other`'s.
    pub fn merge(&mut self, other: &Reach) {
        for a in 0..3 {
            self.min[a] = self.min[a].min(other.min[a]);
            self.max[a] = self.max[a].max(other.max[a]);
        }
    }

    /// The box, or `None` before the first vertex or when a coordinate is
    /// infinite (no frame holds it).
    pub fn bounds(&self) -> Option<Bounds> {
        Bounds::of_points([self.min, self.max].map(|c| c.map(f64::from)))
    }

    /// Whether every vertex added lies in `frame` (the bounds the views
    /// were fitted to, so in every view's tile), give or take the
    /// rounding of `f32` coordinates: a ten-thousandth of the frame's
    /// side, or a few units in the last place of the largest coordinate.
    /// An empty box is in any frame.
    pub fn within(&self, frame: &Bounds) -> bool {
        (0..3).all(|a| {
            let (lo, hi) = (f64::from(self.min[a]), f64::from(self.max[a]));
            if lo > hi {
                return true;
            }
            let far = frame.min[a].abs().max(frame.max[a].abs());
            let slack = 1e-4 * (frame.max[a] - frame.min[a]) + 4.0 * f64::from(f32::EPSILON) * far;
            lo >= frame.min[a] - slack && hi <= frame.max[a] + slack
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_in_the_frame_are_within_it_and_those_out_of_it_are_not() {
        let frame = Bounds {
            min: [0.0, -5.0, 100.0],
            max: [10.0, 5.0, 110.0],
        };
        let mut reach = Reach::default();
        assert!(reach.within(&frame), "an empty box");
        assert_eq!(reach.bounds(), None);
        reach.add(&[[0.0, -5.0, 100.0], [10.0, 5.0, 110.0], [3.0, 0.0, 105.0]]);
        assert!(reach.within(&frame), "the frame's own corners");
        // A tenth of the frame past it on either side of each axis.
        for a in 0..3 {
            for side in [0, 1] {
                let mut out = reach;
                let mut p = [5.0, 0.0, 105.0];
                p[a] = if side == 0 {
                    frame.min[a] as f32 - 1.0
                } else {
                    frame.max[a] as f32 + 1.0
                };
                out.add(&[p]);
                assert!(!out.within(&frame), "axis {a}, side {side}");
            }
        }
        // A NaN is passed over; an infinity gives no bounds.
        let mut nan = reach;
        nan.add(&[[f32::NAN, 0.0, 105.0]]);
        assert_eq!(nan, reach);
        let mut inf = reach;
        inf.add(&[[f32::INFINITY, 0.0, 105.0]]);
        assert_eq!(inf.bounds(), None);
        assert!(!inf.within(&frame));
    }

    #[test]
    fn the_box_is_that_of_every_vertex_in_groups_and_the_remainder() {
        // 4 to 11 vertices: whole groups of four and a remainder, the
        // extremes in every lane, a NaN among them.
        for n in 4..12 {
            let points: Vec<[f32; 3]> = (0..n)
                .map(|i| {
                    let t = i as f32;
                    [(t * 7.3).sin() * 10.0, t * t - 3.0 * t, -(t * 1.7).cos()]
                })
                .collect();
            let mut with_nan = points.clone();
            with_nan[n / 2][1] = f32::NAN;
            let mut reach = Reach::default();
            reach.add(&with_nan);
            let clean: Vec<[f32; 3]> = (0..n).filter(|&i| i != n / 2).map(|i| points[i]).collect();
            for a in 0..3 {
                let values = |v: &[[f32; 3]]| v.iter().map(|p| p[a]).collect::<Vec<f32>>();
                let all = if a == 1 {
                    values(&clean)
                } else {
                    values(&points)
                };
                let lo = all.iter().copied().fold(f32::INFINITY, f32::min);
                let hi = all.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(
                    (reach.min[a], reach.max[a]),
                    (lo, hi),
                    "{n} vertices, axis {a}"
                );
            }
        }
    }

    #[test]
    fn merged_boxes_are_the_box_of_all_the_vertices() {
        let points = [[1.0, -2.0, 3.0], [-4.0, 5.0, 0.5], [2.0, 2.0, 9.0]];
        let mut whole = Reach::default();
        whole.add(&points);
        let (mut a, mut b) = (Reach::default(), Reach::default());
        a.add(&points[..1]);
        b.add(&points[1..]);
        b.merge(&a);
        assert_eq!(b, whole);
        assert_eq!(
            whole.bounds(),
            Some(Bounds {
                min: [-4.0, -2.0, 0.5],
                max: [2.0, 5.0, 9.0],
            })
        );
    }
}
