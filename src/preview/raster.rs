//! The depth buffers of a preview and the triangle rasteriser that fills
//! them.
//!
//! Each pixel keeps the smallest key `(depth, shade)` any triangle gave it:
//! the nearest surface wins, and of two at the same depth the smaller
//! shade. The minimum does not depend on the order the triangles come in,
//! so a picture drawn by any number of workers, each into its own
//! [`Raster`] merged by the same rule ([`Raster::merge`]), has the same
//! pixels for any threads, slab depth or split: the bytes of the PNG are a
//! function of the mesh alone.

use super::views::{View, TILE};

/// The key of a pixel no triangle covered.
pub const EMPTY: u64 = u64::MAX;

/// Bit of the shade byte set for a triangle seen from behind (its outward
/// normal points away from the viewer: the inside of an open surface).
pub const BACK: u8 = 0x80;

/// The four views' depth buffers, one key per pixel ([`EMPTY`] where
/// nothing was drawn).
pub struct Raster {
    /// `views[v][y * TILE + x]`.
    keys: Vec<u64>,
    /// Projected vertices of the batch being drawn, per view (reused).
    projected: [Vec<[f32; 3]>; 4],
}

impl Default for Raster {
    fn default() -> Self {
        Raster::new()
    }
}

impl Raster {
    /// Empty buffers for the four views.
    pub fn new() -> Raster {
        Raster {
            keys: vec![EMPTY; 4 * TILE * TILE],
            projected: Default::default(),
        }
    }

    /// The key of pixel `(x, y)` of view `view`.
    pub fn key(&self, view: usize, x: usize, y: usize) -> u64 {
        self.keys[view * TILE * TILE + y * TILE + x]
    }

    /// Keeps, per pixel, the smaller key of `self` and `other`.
    pub fn merge(&mut self, other: &Raster) {
        for (a, &b) in self.keys.iter_mut().zip(&other.keys) {
            *a = (*a).min(b);
        }
    }

    /// Draws `triangles` (indices into `vertices`) in the four `views`.
    pub fn draw(&mut self, views: &[View; 4], vertices: &[[f32; 3]], triangles: &[[u32; 3]]) {
        for (view, projected) in views.iter().zip(&mut self.projected) {
            projected.clear();
            projected.extend(vertices.iter().map(|&p| view.project(p)));
        }
        for t in triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let n = cross(sub(b, a), sub(c, a));
            let len2 = dot(n, n);
            if len2.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !len2.is_finite() {
                continue;
            }
            let inv = 1.0 / len2.sqrt();
            for (v, view) in views.iter().enumerate() {
                let shade = shade(n, inv, view);
                let p = &self.projected[v];
                let corners = t.map(|i| p[i as usize]);
                let tile = &mut self.keys[v * TILE * TILE..(v + 1) * TILE * TILE];
                fill(tile, corners, shade);
            }
        }
    }
}

/// The shade byte of a face with normal `n` (`inv` its inverse length) in
/// `view`: Lambert's cosine with the view's light, plus some ambient light,
/// in 0..=127, with [`BACK`] set when the face turns away from the viewer.
#[inline]
fn shade(n: [f32; 3], inv: f32, view: &View) -> u8 {
    let cos = dot(n, view.light) * inv;
    let facing = dot(n, view.forward()) < 0.0;
    let light = 0.2 + 0.8 * cos.abs().min(1.0);
    let level = (light * 127.0) as u8;
    if facing {
        level
    } else {
        level | BACK
    }
}

/// Draws one projected triangle into a tile: every pixel whose centre lies
/// in it or on its edges gets the smaller of its key and the triangle's
/// (depth interpolated at the centre).
#[inline]
fn fill(tile: &mut [u64], [p0, p1, p2]: [[f32; 3]; 3], shade: u8) {
    let area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    // Pixel centres x + 0.5 within the box, clamped to the tile; a box
    // off the tile (or not finite) ends empty.
    let top = TILE as f32 - 1.0;
    let lo = |i: usize| ceil((p0[i].min(p1[i]).min(p2[i]) - 0.5).clamp(0.0, TILE as f32));
    let hi = |i: usize| (p0[i].max(p1[i]).max(p2[i]) - 0.5).min(top);
    let (xh, yh) = (hi(0), hi(1));
    if xh.is_nan() || yh.is_nan() || xh < 0.0 || yh < 0.0 {
        return;
    }
    let (x0, x1, y0, y1) = (lo(0), xh as usize, lo(1), yh as usize);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let inv_area = 1.0 / area;
    let edge = |a: [f32; 3], b: [f32; 3], x: f32, y: f32| {
        ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) * inv_area
    };
    for y in y0..=y1 {
        let cy = y as f32 + 0.5;
        let row = &mut tile[y * TILE..(y + 1) * TILE];
        for (x, key) in row.iter_mut().enumerate().take(x1 + 1).skip(x0) {
            let cx = x as f32 + 0.5;
            let w0 = edge(p1, p2, cx, cy);
            let w1 = edge(p2, p0, cx, cy);
            let w2 = edge(p0, p1, cx, cy);
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let depth = (w0 * p0[2] + w1 * p1[2] + w2 * p2[2]).max(0.0);
            let k = (u64::from(depth.to_bits()) << 8) | u64::from(shade);
            *key = (*key).min(k);
        }
    }
}

/// The smallest integer at least `v`, for `v` in `0..=TILE` (`f32::ceil`
/// is a libm call where SSE4.1 is not assumed).
#[inline]
fn ceil(v: f32) -> usize {
    let t = v as usize;
    if (t as f32) < v {
        t + 1
    } else {
        t
    }
}

/// `a - b`.
#[inline]
fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Dot product.
#[inline]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
#[inline]
fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::super::views::Bounds;
    use super::*;

    fn square() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let v = vec![
            [0.0, 0.5, 0.0],
            [1.0, 0.5, 0.0],
            [1.0, 0.5, 1.0],
            [0.0, 0.5, 1.0],
        ];
        (v, vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn order_and_split_do_not_change_the_pixels() {
        let b = Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let views = View::four(&b);
        let (v, t) = square();
        let mut whole = Raster::new();
        whole.draw(&views, &v, &t);
        let mut first = Raster::new();
        first.draw(&views, &v, &t[1..]);
        let mut second = Raster::new();
        second.draw(&views, &v, &t[..1]);
        first.merge(&second);
        assert!(whole.keys == first.keys);
        let drawn = (0..TILE * TILE)
            .filter(|i| whole.key(0, i % TILE, i / TILE) != EMPTY)
            .count();
        // The unit square fills the front view's fitted box.
        assert!(drawn > (TILE - 60) * (TILE - 60), "{drawn}");
    }
}
