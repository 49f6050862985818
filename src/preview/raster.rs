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

use super::views::{View, DEPTH};
use glam::{Vec4, Vec4Swizzles};

/// The key of a pixel no triangle covered.
pub const EMPTY: u32 = u32::MAX;

/// The bit of a key set for a triangle seen from behind (its outward normal
/// points away from the viewer: the inside of an open surface).
pub const BACK: u32 = 1;

/// The bits of a key above [`BACK`] that say, in a picture of several
/// labels' surfaces, which colour the pixel's label has ([`label_mark`]):
/// the depth keeps the rest (a relative precision of `2^-18`: steps of
/// `2^-10` of a pixel for the depths of 256 to 512 pixels at the far end
/// of the views).
pub const LABEL_BITS: u32 = 0x1e;

/// How many colours [`LABEL_BITS`] tell apart.
pub const LABEL_COLOURS: u32 = 16;

/// The key bits of label `label` ([`LABEL_BITS`]): its colour's number,
/// `label` modulo [`LABEL_COLOURS`], so that labels numbered one after the
/// other (organs of one system, most atlases) differ.
#[inline]
pub fn label_mark(label: u32) -> u32 {
    (label % LABEL_COLOURS) << 1
}

/// Fixed-point pixel coordinates: 1 / [`SUB`] of a pixel.
const SUB: i32 = 256;

/// A vertex projected into the four views, one lane per view: pixel x and
/// y in fixed point (multiples of `1 / SUB` pixel, the buffer's pixel
/// `(i, j)` with its centre at `(i * SUB, j * SUB)`), clamped to the
/// buffer, and depth away from the viewer in pixels.
#[derive(Debug, Clone, Copy, Default)]
pub struct Projected {
    /// Pixel x, per view, in `1 / SUB` pixel.
    x: [i32; 4],
    /// Pixel y (downward), per view, in `1 / SUB` pixel.
    y: [i32; 4],
    /// Depth away from the viewer, in pixels, per view.
    d: [f32; 4],
    /// The first pixel column (`[0]`) and row (`[1]`) a triangle through
    /// this corner may cover, per view (`x` and `y` rounded up to whole
    /// pixels), as whole numbers in the `f32` lanes of a [`Vec4`], compared
    /// four at a time...
    first: [Vec4; 2],
    /// ... and the last (rounded down).
    last: [Vec4; 2],
}

/// The four views' depth buffers, one key per pixel ([`EMPTY`] where
/// nothing was drawn).
pub struct Raster {
    /// `tiles[v][y * DEPTH + x]`; an empty vector for a view not drawn
    /// yet by a raster made by [`Raster::empty`].
    tiles: [Vec<u32>; 4],
    /// Projected vertices of the batch being drawn (reused).
    projected: Vec<Projected>,
    /// The same for [`Raster::draw_view`], in its one view.
    corners: Vec<Corner>,
}

/// A vertex projected into one view ([`Raster::draw_view`]).
#[derive(Debug, Clone, Copy)]
struct Corner {
    /// The last pixel column and row a triangle through it may cover,
    /// and minus the first ones (whole numbers in `f32` lanes: a
    /// triangle's are the maximum of its corners', one `maxps` a corner).
    reach: Vec4,
    /// Fixed-point x and y, depth ([`fill`]'s corners).
    at: (i32, i32, f32),
}

impl Default for Raster {
    fn default() -> Self {
        Raster::new()
    }
}

/// `2^23`: adding it to a number in `0..2^22` leaves that number rounded to
/// a whole one (ties to even) in the low bits of the sum's mantissa.
const SHIFT: f32 = 8_388_608.0;

/// A vertex's four views' coordinates, by the products of [`View::rows`]:
/// x and y rounded to the nearest `1 / SUB` pixel (ties to even, without
/// a saturating conversion: the low bits of `v * SUB + 2^23`), so that
/// [`fill`]'s edge functions are exact integers.
#[inline]
fn project(rows: &[[Vec4; 4]; 3], p: [f32; 3]) -> Projected {
    let top = (DEPTH - 1) as f32;
    // All four lanes of a row at once.
    let lanes = |r: &[Vec4; 4]| (r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3]).max(Vec4::ZERO);
    let fixed = |v: f32| ((v.min(top) * SUB as f32 + SHIFT).to_bits() & 0x003f_ffff) as i32;
    let x: [i32; 4] = lanes(&rows[0]).to_array().map(fixed);
    let y: [i32; 4] = lanes(&rows[1]).to_array().map(fixed);
    // (The fixed-point values are never negative: a shift divides.)
    let shift = SUB.ilog2();
    let up =
        |c: [i32; 4]| Vec4::from_array(c.map(|c| ((c as u32 + SUB as u32 - 1) >> shift) as f32));
    let down = |c: [i32; 4]| Vec4::from_array(c.map(|c| (c as u32 >> shift) as f32));
    Projected {
        x,
        y,
        d: lanes(&rows[2]).to_array(),
        first: [up(x), up(y)],
        last: [down(x), down(y)],
    }
}

impl Raster {
    /// Empty buffers for the four views.
    pub fn new() -> Raster {
        Raster {
            tiles: [0; 4].map(|_| vec![EMPTY; DEPTH * DEPTH]),
            projected: Vec::new(),
            corners: Vec::new(),
        }
    }

    /// Buffers without any view: each is made when first drawn
    /// ([`Raster::draw`], [`Raster::draw_view`], [`Raster::merge`],
    /// [`Raster::set_tile`]); [`Raster::complete`] makes the rest. A
    /// worker drawing only the oblique view fills one buffer, not four.
    pub fn empty() -> Raster {
        Raster {
            tiles: Default::default(),
            projected: Vec::new(),
            corners: Vec::new(),
        }
    }

    /// Makes the views not drawn yet, empty ([`Raster::empty`]).
    pub fn complete(&mut self) {
        for tile in &mut self.tiles {
            drawn(tile);
        }
    }

    /// The key of pixel `(x, y)` of view `view`.
    #[inline]
    pub fn key(&self, view: usize, x: usize, y: usize) -> u32 {
        self.tiles[view][y * DEPTH + x]
    }

    /// The keys of view `view`, row by row (`DEPTH` by `DEPTH`).
    #[inline]
    pub fn tile(&self, view: usize) -> &[u32] {
        &self.tiles[view]
    }

    /// Replaces the keys of view `view` by `keys` (`DEPTH` by `DEPTH`).
    pub fn set_tile(&mut self, view: usize, mut keys: Vec<u32>) {
        keys.resize(DEPTH * DEPTH, EMPTY);
        self.tiles[view] = keys;
    }

    /// Keeps, per pixel, the smaller key of `self` and `other`.
    pub fn merge(&mut self, other: &Raster) {
        for (mine, theirs) in self.tiles.iter_mut().zip(&other.tiles) {
            if mine.is_empty() {
                mine.clone_from(theirs);
            }
            for (a, &b) in mine.iter_mut().zip(theirs) {
                *a = (*a).min(b);
            }
        }
    }

    /// Draws `triangles` (indices into `vertices`) in the four `views`.
    /// Triangles with an index past `vertices` are left out.
    pub fn draw(&mut self, views: &[View; 4], vertices: &[[f32; 3]], triangles: &[[u32; 3]]) {
        self.draw_marked(views, vertices, triangles, BACK, |_| 0);
    }

    /// [`Raster::draw`] of the surfaces of several labels: triangle `i`'s
    /// keys carry `marks[i]` ([`label_mark`]) in [`LABEL_BITS`]. Every
    /// triangle of a picture must be drawn this way or none.
    pub fn draw_labelled(
        &mut self,
        views: &[View; 4],
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
        marks: &[u32],
    ) {
        let mark = |i: usize| marks.get(i).copied().unwrap_or(0);
        self.draw_marked(views, vertices, triangles, BACK | LABEL_BITS, mark);
    }

    /// [`Raster::draw`] with the key bits `mask` below the depth replaced
    /// by `mark(i)` for triangle `i` (and [`BACK`]).
    #[inline(always)]
    fn draw_marked(
        &mut self,
        views: &[View; 4],
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
        mask: u32,
        mark: impl Fn(usize) -> u32,
    ) {
        let rows = View::rows(views).map(|axis| axis.map(Vec4::from_array));
        self.projected.clear();
        self.projected
            .extend(vertices.iter().map(|&p| project(&rows, p)));
        let projected = &self.projected;
        for (i, t) in triangles.iter().enumerate() {
            let (Some(a), Some(b), Some(c)) = (
                projected.get(t[0] as usize),
                projected.get(t[1] as usize),
                projected.get(t[2] as usize),
            ) else {
                continue;
            };
            // Pixel centres in the bounding box, all four views at once:
            // the first column and row at or after the box's low corner,
            // the last at or before its high one; a view is drawn when
            // the box holds a centre on both axes (on cthead at 256x256,
            // 41% of the (triangle, view) pairs, most with one centre).
            // (The ceiling of a minimum is the minimum of the ceilings.)
            let first = [0, 1].map(|i| a.first[i].min(b.first[i]).min(c.first[i]));
            let last = [0, 1].map(|i| a.last[i].max(b.last[i]).max(c.last[i]));
            let mut hit = (first[0].cmple(last[0]) & first[1].cmple(last[1])).bitmask();
            if hit == 0 {
                continue;
            }
            let (first, last) = (first.map(|f| f.to_array()), last.map(|l| l.to_array()));
            while hit != 0 {
                let v = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let corner = |p: &Projected| (p.x[v], p.y[v], p.d[v]);
                let tile = drawn(&mut self.tiles[v]);
                // (Whole numbers below 2^22: the low bits of `c + 2^23`.)
                let int = |c: f32| ((c + SHIFT).to_bits() & 0x003f_ffff) as usize;
                let bbox = [first[0][v], last[0][v], first[1][v], last[1][v]].map(int);
                fill(
                    tile,
                    [corner(a), corner(b), corner(c)],
                    bbox,
                    (mask, mark(i)),
                );
            }
        }
    }
}

impl Raster {
    /// Draws `triangles` (indices into `vertices`) in view `view` of
    /// `views` alone, with the same pixels as [`Raster::draw`] gives that
    /// view: each vertex projected once (fixed-point x and y, depth), each
    /// triangle rejected by its bounding box unless the box holds a pixel
    /// centre (most triangles of a CT surface hold none).
    pub fn draw_view(
        &mut self,
        views: &[View; 4],
        view: usize,
        vertices: &[[f32; 3]],
        triangles: &[[u32; 3]],
    ) {
        let rows = View::rows(views);
        // Columns: the coefficients of world x, y, z and the offset in
        // pixel x, pixel y and depth (a fourth lane unused): as `project`'s
        // lanes, the same operations in the same order (the same numbers).
        let column =
            |c: usize| Vec4::new(rows[0][c][view], rows[1][c][view], rows[2][c][view], 0.0);
        let (c0, c1, c2, c3) = (column(0), column(1), column(2), column(3));
        let top = Vec4::splat((DEPTH - 1) as f32);
        let (sub, shift) = (Vec4::splat(SUB as f32), SUB.ilog2());
        self.corners.clear();
        self.corners.extend(vertices.iter().map(|p| {
            let v = (c0 * p[0] + c1 * p[1] + c2 * p[2] + c3).max(Vec4::ZERO);
            // `project`'s rounding, in all lanes at once (the same
            // operations on the same numbers; the depth lane is kept
            // as it was).
            let [x, y, _, _] = (v.min(top) * sub + Vec4::splat(SHIFT))
                .to_array()
                .map(|f| (f.to_bits() & 0x003f_ffff) as i32);
            // The last column and row a triangle through this corner may
            // reach (rounded down), and minus the first (rounded up; the
            // coordinates are not negative: shifts divide).
            let first = |c: i32| -((c + SUB - 1) >> shift) as f32;
            let last = |c: i32| (c >> shift) as f32;
            Corner {
                reach: Vec4::new(last(x), last(y), first(x), first(y)),
                at: (x, y, v.z),
            }
        }));
        let corners = &self.corners;
        let tile = drawn(&mut self.tiles[view]);
        for t in triangles {
            let (Some(a), Some(b), Some(c)) = (
                corners.get(t[0] as usize),
                corners.get(t[1] as usize),
                corners.get(t[2] as usize),
            ) else {
                continue;
            };
            // The box's last column and row and minus its first ones, of
            // the three corners at once: the box holds a pixel centre when
            // last - first is not negative on both axes (most triangles of
            // a CT surface hold none and stop here).
            let m = a.reach.max(b.reach).max(c.reach);
            if (m + m.zwxy()).cmpge(Vec4::ZERO).bitmask() & 3 != 3 {
                continue;
            }
            // (Whole numbers below 2^22: the low bits of `c + 2^23`.)
            let [x1, y1, x0, y0] = (m * Vec4::new(1.0, 1.0, -1.0, -1.0) + Vec4::splat(SHIFT))
                .to_array()
                .map(|c| (c.to_bits() & 0x003f_ffff) as usize);
            let bbox = [x0, x1, y0, y1];
            fill(tile, [a.at, b.at, c.at], bbox, (BACK, 0));
        }
    }
}

/// The view's keys, made [`EMPTY`] if not made yet ([`Raster::empty`]).
fn drawn(tile: &mut Vec<u32>) -> &mut [u32] {
    if tile.is_empty() {
        tile.resize(DEPTH * DEPTH, EMPTY);
    }
    tile
}

/// Draws one projected triangle (fixed-point x and y, depth) into a tile:
/// every pixel centre of `bbox` (`[x0, x1, y0, y1]`, inclusive, inside the
/// tile) that lies in the triangle or on its edges gets the smaller of its
/// key and the triangle's (depth interpolated at the centre).
///
/// The three edge functions are integers, exact (the coordinates are below
/// `2^17`, so their products fit an `i64` with room to spare): evaluated
/// at the box's first centre and stepped by whole pixels. Hence triangles
/// sharing edges and corners leave no centre between them uncovered (each
/// centre is in at least one triangle of a closed fan, on an edge in
/// both), and the decision is the same in every run; the depth is the
/// weighted mean of the corners' by the three edge functions, in `f64`
/// (the weights are exact there: below `2^53`). Their sum is twice the
/// triangle's signed area, whose sign says which way it faces. The key is
/// the depth's bits with those of `mask` replaced by `mark` and [`BACK`].
#[inline(always)]
fn fill(
    tile: &mut [u32],
    [p0, p1, p2]: [(i32, i32, f32); 3],
    [x0, x1, y0, y1]: [usize; 4],
    (mask, mark): (u32, u32),
) {
    let sub = i64::from(SUB);
    let (fx, fy) = (x0 as i64 * sub, y0 as i64 * sub);
    // Corners relative to the first centre.
    let rel = |p: (i32, i32, f32)| (i64::from(p.0) - fx, i64::from(p.1) - fy);
    let (r0, r1, r2) = (rel(p0), rel(p1), rel(p2));
    // Edge i (opposite corner i) at the first centre.
    let w = [
        r1.0 * r2.1 - r1.1 * r2.0,
        r2.0 * r0.1 - r2.1 * r0.0,
        r0.0 * r1.1 - r0.1 * r1.0,
    ];
    let area = w[0] + w[1] + w[2];
    if area == 0 {
        return;
    }
    // With y downward, a positive area is a triangle whose outward normal
    // points away from the viewer (see `View::four`: right x up = -forward).
    let (back, sign) = if area > 0 { (BACK, 1) } else { (0, -1) };
    let depths = [p0.2, p1.2, p2.2].map(f64::from);
    let sum = (area * sign) as f64;
    let draw = |key: &mut u32, w: [i64; 3]| {
        if (w[0] | w[1] | w[2]) >= 0 {
            let [w0, w1, w2] = w.map(|w| w as f64);
            let depth = ((w0 * depths[0] + w1 * depths[1] + w2 * depths[2]) / sum).max(0.0) as f32;
            let k = (depth.to_bits() & !mask) | mark | back;
            *key = (*key).min(k);
        }
    };
    let mut row = w.map(|w| w * sign);
    let start = y0 * DEPTH + x0;
    if x0 == x1 && y0 == y1 {
        // One centre in the box: no steps.
        if let Some(key) = tile.get_mut(start) {
            draw(key, row);
        }
        return;
    }
    // Steps of the edge functions by one pixel in x and in y.
    let step = |a: (i64, i64), b: (i64, i64)| ((a.1 - b.1) * sub * sign, (b.0 - a.0) * sub * sign);
    let steps = [step(r1, r2), step(r2, r0), step(r0, r1)];
    let width = x1 + 1 - x0;
    let mut at = start;
    for _ in y0..y1 + 1 {
        let mut w = row;
        for key in &mut tile[at..at + width] {
            draw(key, w);
            w = [w[0] + steps[0].0, w[1] + steps[1].0, w[2] + steps[2].0];
        }
        row = [
            row[0] + steps[0].1,
            row[1] + steps[1].1,
            row[2] + steps[2].1,
        ];
        at += DEPTH;
    }
}

#[cfg(test)]
mod tests {
    use super::super::views::{Bounds, BLOCK};
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
        assert!(whole.tiles == first.tiles);
        let drawn = (0..DEPTH * DEPTH)
            .filter(|i| whole.key(0, i % DEPTH, i / DEPTH) != EMPTY)
            .count();
        // The unit square fills the front view's fitted box.
        assert!(drawn > (DEPTH - 30) * (DEPTH - 30), "{drawn}");
    }

    /// The unit square of x and z, `n` by `n` cells of two triangles, at
    /// `y = height(x, z)`.
    fn sheet(n: u32, height: impl Fn(f32, f32) -> f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let mut v = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
                v.push([x, height(x, z), z]);
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
        (v, t)
    }

    #[test]
    fn one_view_drawn_alone_has_the_pixels_of_four_drawn_together() {
        let views = View::four(&Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        });
        // A bumpy sheet of small triangles, seen in every view.
        let (v, t) = sheet(120, |x, z| 0.5 + 0.2 * (7.0 * x).sin() * (5.0 * z).cos());
        let mut all = Raster::new();
        all.draw(&views, &v, &t);
        for view in 0..4 {
            let mut one = Raster::new();
            one.draw_view(&views, view, &v, &t);
            assert!(one.tile(view) == all.tile(view), "view {view}");
            assert!(one.tile(view).iter().filter(|&&k| k != EMPTY).count() > 1000);
        }
    }

    /// The world point (x, 0.5, z) that the front view (view 0) of
    /// `views` projects within 1/512 pixel of depth-buffer pixel
    /// coordinates `fixed / SUB`: so that it rounds to `fixed` exactly.
    fn at_fixed(views: &[View; 4], fixed: [i32; 2]) -> [f32; 3] {
        let world = |screen: usize, axis: usize, f: i32| {
            let (scale, offset) = views[0].screen_axis(screen, axis);
            // Depth-buffer pixel p has its centre at tile pixel
            // (p + 0.5) * BLOCK.
            let tile = (f64::from(f) / f64::from(SUB) + 0.5) * BLOCK as f64;
            ((tile - offset) / scale) as f32
        };
        [world(0, 0, fixed[0]), 0.5, world(1, 2, fixed[1])]
    }

    /// The pixels whose centres lie in the triangle `t` (fixed-point
    /// corners) or on its edges, by brute force over the whole view: the
    /// signs of the three edge functions, in `i64`.
    fn covered_by(t: [[i32; 2]; 3]) -> Vec<usize> {
        let mut out = Vec::new();
        for y in 0..DEPTH {
            for x in 0..DEPTH {
                let (px, py) = (x as i64 * i64::from(SUB), y as i64 * i64::from(SUB));
                let e = |a: [i32; 2], b: [i32; 2]| {
                    let (ax, ay, bx, by) = (a[0] as i64, a[1] as i64, b[0] as i64, b[1] as i64);
                    (bx - ax) * (py - ay) - (by - ay) * (px - ax)
                };
                let w = [e(t[0], t[1]), e(t[1], t[2]), e(t[2], t[0])];
                if w.iter().all(|&w| w >= 0) || w.iter().all(|&w| w <= 0) {
                    out.push(y * DEPTH + x);
                }
            }
        }
        out
    }

    /// Triangles with corners exactly on pixel centres (the box's first
    /// and last centre on its edge), drawn by both rasterising paths: the
    /// pixels are exactly those whose centres a brute-force test puts in
    /// the triangle or on its edges. A box rounded up by a whole pixel
    /// where the corner is on a centre (`+ SUB` for `+ SUB - 1`) loses the
    /// corner's pixel; one rounded the other way at the far side gains
    /// pixels outside.
    #[test]
    fn triangles_with_corners_on_pixel_centres_cover_exactly_their_centres() {
        let views = unit_views();
        let c = |x: i32, y: i32| [x * SUB, y * SUB];
        let cases: [[[i32; 2]; 3]; 4] = [
            // The smallest x and y on a centre, the rest between centres.
            [
                c(100, 100),
                [105 * SUB + 51, 101 * SUB + 179],
                [101 * SUB + 7, 105 * SUB + 90],
            ],
            // The largest x and y on a centre.
            [
                c(60, 60),
                [54 * SUB + 33, 58 * SUB + 200],
                [58 * SUB + 120, 54 * SUB + 3],
            ],
            // Every corner on a centre; a thin one.
            [c(30, 200), c(40, 201), c(31, 203)],
            // A triangle within one pixel, its corner on the centre.
            [
                c(150, 150),
                [150 * SUB + 100, 150 * SUB + 20],
                [150 * SUB + 30, 150 * SUB + 90],
            ],
        ];
        for t in cases {
            let v: Vec<[f32; 3]> = t.iter().map(|&f| at_fixed(&views, f)).collect();
            let want = covered_by(t);
            assert!(!want.is_empty());
            let mut four = Raster::new();
            four.draw(&views, &v, &[[0, 1, 2]]);
            let mut one = Raster::new();
            one.draw_view(&views, 0, &v, &[[0, 1, 2]]);
            for (name, r) in [("draw", &four), ("draw_view", &one)] {
                let got: Vec<usize> = (0..DEPTH * DEPTH)
                    .filter(|&i| r.tile(0)[i] != EMPTY)
                    .collect();
                assert_eq!(got, want, "{name} {t:?}");
            }
        }
    }

    #[test]
    fn a_face_turned_away_is_marked_back() {
        let views = unit_views();
        let (v, t) = square();
        // Counter-clockwise seen from -y: the normal (0, -1, 0) faces the
        // front view, which looks along +y.
        let mut front = Raster::new();
        front.draw(&views, &v, &t);
        assert_eq!(front.key(0, DEPTH / 2, DEPTH / 2) & BACK, 0);
        let flipped: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let mut back = Raster::new();
        back.draw(&views, &v, &flipped);
        assert_eq!(back.key(0, DEPTH / 2, DEPTH / 2) & BACK, BACK);
    }

    #[test]
    fn tiny_triangles_cover_the_centres_they_contain_and_only_those() {
        let views = unit_views();
        // Many sub-pixel triangles tiling the square: no hole.
        let (v, t) = sheet(600, |_, _| 0.5);
        let mut fine = Raster::new();
        fine.draw(&views, &v, &t);
        let (sv, st) = square();
        let mut coarse = Raster::new();
        coarse.draw(&views, &sv, &st);
        // Only centres on the square's outline may differ (an edge of the
        // fine tiling is not exactly the square's).
        let mut inside_holes = 0;
        let mut outline = 0;
        for y in 1..DEPTH - 1 {
            for x in 1..DEPTH - 1 {
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
        assert!(outline < 4 * DEPTH, "{outline}");
    }

    #[test]
    fn a_labelled_key_is_the_depth_with_its_label_s_colour() {
        let views = unit_views();
        let (v, t) = sheet(40, |x, y| 0.3 + 0.2 * x + 0.1 * y);
        let mut plain = Raster::new();
        plain.draw(&views, &v, &t);
        let mut labelled = Raster::new();
        let marks: Vec<u32> = (0..t.len() as u32)
            .map(|i| label_mark(i % 3 + 17))
            .collect();
        labelled.draw_labelled(&views, &v, &t, &marks);
        let mut covered = 0;
        for view in 0..4 {
            for (&p, &l) in plain.tile(view).iter().zip(labelled.tile(view)) {
                assert_eq!(p == EMPTY, l == EMPTY);
                if p != EMPTY {
                    // The same depth but for the colour's bits, the same
                    // side, and one of the three labels' colours (17 to 19:
                    // colours 1 to 3).
                    assert_eq!(p & !(LABEL_BITS | BACK), l & !(LABEL_BITS | BACK));
                    assert_eq!(p & BACK, l & BACK);
                    assert!((1..=3).contains(&((l & LABEL_BITS) >> 1)), "{l:#x}");
                    covered += 1;
                }
            }
        }
        assert!(covered > 1000, "{covered}");
    }
}
