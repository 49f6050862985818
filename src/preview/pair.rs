//! `tmc compare --preview`: two previews side by side, the TMC mesh's on
//! the left and the MC mesh's on the right, with a red mark in every view
//! of both where a cell is triangulated differently by the two methods.
//!
//! The marks are a set of pixels ([`Marks`]), filled from the cells'
//! centres in any order by any number of threads: a set does not depend on
//! the order, so the bytes of the picture do not either. They are drawn
//! over the shaded surface (a cell behind the surface is marked too: the
//! picture says where the differences are, not which are visible).

use super::picture::DIMENSIONS;
use super::views::{Bounds, View, GRID, TILE};
use std::sync::Mutex;

/// The colour of a mark: pure red, which neither the shading (bone and
/// blue), the background, the borders nor the text ever give.
pub const MARK: [u8; 3] = [255, 0, 0];

/// Width and height of a side-by-side picture: two previews in a row.
pub const PAIR_DIMENSIONS: (usize, usize) = (2 * DIMENSIONS.0, DIMENSIONS.1);

/// The pixels of the four views to mark, fitted as the previews' views
/// are.
pub struct Marks {
    views: [View; 4],
    /// `bits[v * TILE * TILE + y * TILE + x]`.
    bits: Mutex<Vec<bool>>,
}

impl Marks {
    /// No marks yet, in the views a preview of a mesh within `bounds` has
    /// (those of [`super::PreviewSink`] given the same bounds, or, for
    /// `Bounds::of_grid`, none).
    pub fn new(bounds: &Bounds) -> Marks {
        Marks {
            views: View::four(bounds),
            bits: Mutex::new(vec![false; 4 * TILE * TILE]),
        }
    }

    /// Marks the pixel of world point `p` in each view it falls in.
    pub fn mark(&self, p: [f64; 3]) {
        let p = p.map(|c| c as f32);
        let mut bits = self.bits.lock().unwrap_or_else(|e| e.into_inner());
        for (v, view) in self.views.iter().enumerate() {
            let [x, y, _] = view.project(p);
            let inside = |c: f32| (0.0..TILE as f32).contains(&c);
            if inside(x) && inside(y) {
                bits[v * TILE * TILE + y as usize * TILE + x as usize] = true;
            }
        }
    }

    /// How many pixels are marked, over the four views.
    pub fn count(&self) -> usize {
        let bits = self.bits.lock().unwrap_or_else(|e| e.into_inner());
        bits.iter().filter(|&&b| b).count()
    }
}

/// The RGB bytes ([`PAIR_DIMENSIONS`]) of `left` and `right` (two
/// previews' RGB bytes, [`DIMENSIONS`] each) side by side, each marked
/// with `marks` (a 3x3 dot per marked pixel, clipped to its tile).
pub fn side_by_side(left: &[u8], right: &[u8], marks: &Marks) -> Vec<u8> {
    let (w, h) = DIMENSIONS;
    let row = 3 * w;
    let mut out = Vec::with_capacity(2 * row * h);
    for y in 0..h {
        out.extend_from_slice(&left[y * row..(y + 1) * row]);
        out.extend_from_slice(&right[y * row..(y + 1) * row]);
    }
    let bits = marks.bits.lock().unwrap_or_else(|e| e.into_inner());
    for (i, _) in bits.iter().enumerate().filter(|(_, &b)| b) {
        let (v, at) = (i / (TILE * TILE), i % (TILE * TILE));
        let (x, y) = (at % TILE, at / TILE);
        let (tx, ty) = ((v % GRID) * TILE, (v / GRID) * TILE);
        for dy in y.saturating_sub(1)..(y + 2).min(TILE) {
            for dx in x.saturating_sub(1)..(x + 2).min(TILE) {
                for half in 0..2 {
                    let px = half * w + tx + dx;
                    let start = ((ty + dy) * 2 * w + px) * 3;
                    out[start..start + 3].copy_from_slice(&MARK);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_marked_point_is_a_red_dot_in_both_halves() {
        let bounds = Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let marks = Marks::new(&bounds);
        let (w, h) = DIMENSIONS;
        let grey = vec![7u8; w * h * 3];
        let plain = side_by_side(&grey, &grey, &marks);
        assert_eq!(plain.len(), PAIR_DIMENSIONS.0 * PAIR_DIMENSIONS.1 * 3);
        assert!(plain.iter().all(|&b| b == 7));
        marks.mark([0.5, 0.5, 0.5]);
        assert_eq!(marks.count(), 4, "the centre is in all four views");
        let marked = side_by_side(&grey, &grey, &marks);
        let red = marked.chunks(3).filter(|p| *p == MARK).count();
        assert_eq!(red, 2 * 4 * 9);
        // Marking the same point again changes nothing.
        marks.mark([0.5, 0.5, 0.5]);
        assert!(side_by_side(&grey, &grey, &marks) == marked);
    }
}
