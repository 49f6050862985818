//! The depth buffers of a preview and the triangle rasteriser that fills
//! them.
//!
//! Each pixel keeps the smallest key any triangle gave it: the depth of the
//! surface at the pixel's centre (an `f32`'s bits, which order as the
//! numbers do since the depth is never negative) with its lowest bit
//! replaced by [`BACK`], set where the triangle turns away from the viewer.
//! The nearest surface wins, and of two at the same depth the one facing
//! the viewer. The minimum does not depend on the order the triangles come
//! in, so a picture drawn by any number of workers, each into its own
//! [`Raster`] merged by the same rule ([`Raster::merge`]), has the same
//! pixels for any threads, slab depth or split: the bytes of the PNG are a
//! function of the mesh alone.
//!
//! The shading is deferred: a pixel keeps no normal, only its depth, and
//! [`super::picture`] shades it from the depth buffer's slope once the mesh
//! is complete. This is what makes a preview cheap: most triangles of a CT
//! surface cover one pixel or none, so the cost per triangle is that of a
//! bounding-box test in the four views at once ([`Projected`]), plus, for
//! the few pixel centres a triangle covers, an edge test and a depth.

use super::views::{View, TILE};

/// The key of a pixel no triangle covered.
pub const EMPTY: u32 = u32::MAX;

/// The bit of a key set for a triangle seen from behind (its outward normal
/// points away from the viewer: the inside of an open surface).
pub const BACK: u32 = 1;

/// A vertex projected into the four views: pixel x and y with pixel
/// centres at whole numbers (the tile's pixel `(i, j)` has its centre at
/// `(i, j)`), and depth in pixels, one lane per view; clamped to the tile.
#[derive(Debug, Clone, Copy, Default)]
pub struct Projected {
    /// Pixel x, per view.
    x: [f32; 4],
    /// Pixel y (downward), per view.
    y: [f32; 4],
    /// Depth away from the viewer, in pixels, per view.
    d: [f32; 4],
    /// The smallest whole numbers at least `x` and `y` (the first pixel
    /// centres a triangle through this corner may reach)...
    up: [[f32; 4]; 2],
    /// ... and the largest at most `x` and `y`.
    down: [[f32; 4]; 2],
}

/// The four views' depth buffers, one key per pixel ([`EMPTY`] where
/// nothing was drawn).
pub struct Raster {
    /// `keys[v * TILE * TILE + y * TILE + x]`.
    keys: Vec<u32>,
    /// Projected vertices of the batch being drawn (reused).
    projected: Vec<Projected>,
}

impl Default for Raster {
    fn default() -> Self {
        Raster::new()
    }
}

/// A vertex's four views' coordinates, by the products of [`View::rows`].
#[inline]
fn project(rows: &[[[f32; 4]; 4]; 3], p: [f32; 3]) -> Projected {
    let top = (TILE - 1) as f32;
    let lane = |r: &[[f32; 4]; 4], v: usize| {
        (r[0][v] * p[0] + r[1][v] * p[1] + r[2][v] * p[2] + r[3][v]).max(0.0)
    };
    let x = snap4(std::array::from_fn(|v| lane(&rows[0], v).min(top)));
    let y = snap4(std::array::from_fn(|v| lane(&rows[1], v).min(top)));
    Projected {
        x,
        y,
        d: std::array::from_fn(|v| lane(&rows[2], v)),
        up: [ceil4(x), ceil4(y)],
        down: [floor4(x), floor4(y)],
    }
}

/// `2^23`: adding it to a number in `0..2^22` leaves that number rounded to
/// a whole one in the low bits of the sum's mantissa.
const SHIFT: f32 = 8_388_608.0;

/// The smallest whole numbers at least `v` (for `0 <= v < 2^22`), without
/// a libm call or a saturating conversion: `v + 2^23 - 2^23` rounds to a
/// neighbouring whole number, one is added when that is below `v`.
#[inline]
fn ceil4(v: [f32; 4]) -> [f32; 4] {
    std::array::from_fn(|i| {
        let r = (v[i] + SHIFT) - SHIFT;
        if r < v[i] {
            r + 1.0
        } else {
            r
        }
    })
}

/// The largest whole numbers at most `v` (for `0 <= v < 2^22`), as
/// [`ceil4`].
#[inline]
fn floor4(v: [f32; 4]) -> [f32; 4] {
    std::array::from_fn(|i| {
        let r = (v[i] + SHIFT) - SHIFT;
        if r > v[i] {
            r - 1.0
        } else {
            r
        }
    })
}

/// The whole numbers `v` (in `0..2^22`) as integers: the low bits of
/// `v + 2^23`'s mantissa (no saturating conversion).
#[inline]
fn whole4(v: [f32; 4]) -> [usize; 4] {
    std::array::from_fn(|i| ((v[i] + SHIFT).to_bits() & 0x003f_ffff) as usize)
}

/// `v` (in `0..TILE`) rounded to a multiple of `1 / 256` of a pixel, so
/// that [`fill`]'s edge functions are exact in `f64`.
#[inline]
fn snap4(v: [f32; 4]) -> [f32; 4] {
    std::array::from_fn(|i| ((v[i] * 256.0 + SHIFT) - SHIFT) * (1.0 / 256.0))
}

/// Lane-wise minimum of three (plain comparisons: no NaN here).
#[inline]
fn min3(a: [f32; 4], b: [f32; 4], c: [f32; 4]) -> [f32; 4] {
    let min = |p: f32, q: f32| if p < q { p } else { q };
    std::array::from_fn(|i| min(min(a[i], b[i]), c[i]))
}

/// Lane-wise maximum of three.
#[inline]
fn max3(a: [f32; 4], b: [f32; 4], c: [f32; 4]) -> [f32; 4] {
    let max = |p: f32, q: f32| if p > q { p } else { q };
    std::array::from_fn(|i| max(max(a[i], b[i]), c[i]))
}

impl Raster {
    /// Empty buffers for the four views.
    pub fn new() -> Raster {
        Raster {
            keys: vec![EMPTY; 4 * TILE * TILE],
            projected: Vec::new(),
        }
    }

    /// The key of pixel `(x, y)` of view `view`.
    #[inline]
    pub fn key(&self, view: usize, x: usize, y: usize) -> u32 {
        self.keys[view * TILE * TILE + y * TILE + x]
    }

    /// Keeps, per pixel, the smaller key of `self` and `other`.
    pub fn merge(&mut self, other: &Raster) {
        for (a, &b) in self.keys.iter_mut().zip(&other.keys) {
            *a = (*a).min(b);
        }
    }

    /// Draws `triangles` (indices into `vertices`) in the four `views`.
    /// Triangles with an index past `vertices` are left out.
    pub fn draw(&mut self, views: &[View; 4], vertices: &[[f32; 3]], triangles: &[[u32; 3]]) {
        let rows = View::rows(views);
        self.projected.clear();
        self.projected
            .extend(vertices.iter().map(|&p| project(&rows, p)));
        let projected = &self.projected;
        for t in triangles {
            let (Some(a), Some(b), Some(c)) = (
                projected.get(t[0] as usize),
                projected.get(t[1] as usize),
                projected.get(t[2] as usize),
            ) else {
                continue;
            };
            // Pixel centres in the bounding box, all four views at once:
            // a view is drawn when the box holds a whole number on both
            // axes.
            // (The ceiling of a minimum is the minimum of the ceilings.)
            let x0 = min3(a.up[0], b.up[0], c.up[0]);
            let x1 = max3(a.down[0], b.down[0], c.down[0]);
            let y0 = min3(a.up[1], b.up[1], c.up[1]);
            let y1 = max3(a.down[1], b.down[1], c.down[1]);
            let mut hit = 0u32;
            for v in 0..4 {
                hit |= u32::from((x0[v] <= x1[v]) & (y0[v] <= y1[v])) << v;
            }
            if hit == 0 {
                continue;
            }
            let (x0, x1, y0, y1) = (whole4(x0), whole4(x1), whole4(y0), whole4(y1));
            while hit != 0 {
                let v = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let corner = |p: &Projected| [p.x[v], p.y[v], p.d[v]];
                let tile = &mut self.keys[v * TILE * TILE..(v + 1) * TILE * TILE];
                let bbox = [x0[v], x1[v], y0[v], y1[v]];
                fill(tile, [corner(a), corner(b), corner(c)], bbox);
            }
        }
    }
}

/// Draws one projected triangle into a tile: every pixel centre of `bbox`
/// (`[x0, x1, y0, y1]`, inclusive) that lies in the triangle or on its
/// edges gets the smaller of its key and the triangle's (depth interpolated
/// at the centre).
///
/// An edge's function is `A x + B y + C`, computed exactly: the corners
/// are multiples of `1 / 256` pixel below [`TILE`] ([`snap4`]), so every
/// product and sum fits the 53 bits of an `f64`. Hence triangles sharing
/// edges and corners leave no centre between them uncovered (each centre
/// is in at least one triangle of a closed fan, on an edge in both), and
/// the decision is the same in every run; the depth is the weighted mean
/// of the corners' by the three edge functions.
#[inline]
fn fill(tile: &mut [u32], [p0, p1, p2]: [[f32; 3]; 3], [x0, x1, y0, y1]: [usize; 4]) {
    let [q0, q1, q2] = [p0, p1, p2].map(|p| p.map(f64::from));
    let area = (q1[0] - q0[0]) * (q2[1] - q0[1]) - (q2[0] - q0[0]) * (q1[1] - q0[1]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    // With y downward, a positive area is a triangle whose outward normal
    // points away from the viewer (see `View::four`: right x up = -forward).
    let (back, sign) = if area > 0.0 { (BACK, 1.0) } else { (0, -1.0) };
    let coefficients = |a: [f64; 3], b: [f64; 3]| {
        [
            (a[1] - b[1]) * sign,
            (b[0] - a[0]) * sign,
            (a[0] * b[1] - a[1] * b[0]) * sign,
        ]
    };
    let e = [
        coefficients(q1, q2),
        coefficients(q2, q0),
        coefficients(q0, q1),
    ];
    let (x1, y1) = (x1.min(TILE - 1), y1.min(TILE - 1));
    let mut y = y0;
    while y <= y1 {
        let cy = y as f64;
        let row = &mut tile[y * TILE..(y + 1) * TILE];
        let mut x = x0;
        y += 1;
        while x <= x1 {
            let cx = x as f64;
            x += 1;
            let w = e.map(|[a, b, c]| (a * cx + b * cy) + c);
            if w[0] < 0.0 || w[1] < 0.0 || w[2] < 0.0 {
                continue;
            }
            let sum = w[0] + w[1] + w[2];
            if sum <= 0.0 {
                continue;
            }
            let depth = ((w[0] * q0[2] + w[1] * q1[2] + w[2] * q2[2]) / sum).max(0.0) as f32;
            let k = (depth.to_bits() & !BACK) | back;
            let key = &mut row[x - 1];
            *key = (*key).min(k);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::views::Bounds;
    use super::*;

    /// The four views of the unit cube.
    fn unit_views() -> [View; 4] {
        View::four(&Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        })
    }

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
        let views = unit_views();
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

    #[test]
    fn a_face_turned_away_is_marked_back() {
        let views = unit_views();
        let (v, t) = square();
        // Counter-clockwise seen from -y: the normal (0, -1, 0) faces the
        // front view, which looks along +y.
        let mut front = Raster::new();
        front.draw(&views, &v, &t);
        assert_eq!(front.key(0, TILE / 2, TILE / 2) & BACK, 0);
        let flipped: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let mut back = Raster::new();
        back.draw(&views, &v, &flipped);
        assert_eq!(back.key(0, TILE / 2, TILE / 2) & BACK, BACK);
    }

    #[test]
    fn tiny_triangles_cover_the_centres_they_contain_and_only_those() {
        let views = unit_views();
        // Many sub-pixel triangles tiling the square: no hole.
        let n = 600;
        let mut v = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                v.push([i as f32 / n as f32, 0.5, j as f32 / n as f32]);
            }
        }
        let at = |i: u32, j: u32| i * (n + 1) + j;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let mut fine = Raster::new();
        fine.draw(&views, &v, &t);
        let (sv, st) = square();
        let mut coarse = Raster::new();
        coarse.draw(&views, &sv, &st);
        // Only centres on the square's outline may differ (an edge of the
        // fine tiling is not exactly the square's).
        let mut inside_holes = 0;
        let mut outline = 0;
        for y in 1..TILE - 1 {
            for x in 1..TILE - 1 {
                let on = |r: &Raster, x: usize, y: usize| r.key(0, x, y) != EMPTY;
                if on(&coarse, x, y) && !on(&fine, x, y) {
                    let interior = on(&coarse, x - 1, y)
                        && on(&coarse, x + 1, y)
                        && on(&coarse, x, y - 1)
                        && on(&coarse, x, y + 1);
                    if interior {
                        inside_holes += 1;
                    } else {
                        outline += 1;
                    }
                }
                assert!(!on(&fine, x, y) || on(&coarse, x, y), "{x} {y}");
            }
        }
        assert_eq!(inside_holes, 0);
        assert!(outline < 4 * TILE, "{outline}");
    }
}
