//! The picture: the four views' depth buffers turned into colours, the
//! tiles' names, and a caption band under them, written with the hand-drawn
//! font ([`super::font`]).
//!
//! Shading is deferred to here: a pixel's normal is that of the depth
//! buffer's surface, from its slope in x and y (the depth is in pixels, as
//! x and y are). Of the two one-sided differences on each axis the smaller
//! is taken, so that a step in depth (one surface in front of another)
//! does not shade as a steep slope, and none where both are steep and
//! differ in sign (a lone pixel of a surface behind others, as steps
//! between grid lines leave, would otherwise be a dark dot); a pixel with
//! no covered neighbour on an axis is taken as flat along it. Lambert's
//! cosine against a light at the viewer's upper left, plus some ambient
//! light. Each depth-buffer pixel is shaded once and fills a [`BLOCK`] by
//! [`BLOCK`] square of its tile.

use super::font;
use super::raster::{Raster, BACK, EMPTY, LABEL_BITS, LABEL_COLOURS};
use super::views::{BLOCK, DEPTH, GRID, SIZE, TILE, VIEW_NAMES};

/// Height of the caption band under the tiles, in pixels.
pub const CAPTION: usize = 40;

/// Width and height of the picture.
pub const DIMENSIONS: (usize, usize) = (SIZE, SIZE + CAPTION);

/// Background colour.
const BACKGROUND: [u8; 3] = [30, 32, 36];
/// Colour of a fully lit face seen from outside (bone).
const OUTSIDE: [f32; 3] = [232.0, 214.0, 180.0];
/// Colour of a fully lit face seen from inside (an open surface's back).
const INSIDE: [f32; 3] = [110.0, 150.0, 215.0];
/// Colours of the labels' surfaces seen from outside, in a picture of
/// several labels ([`super::raster::label_mark`]): sixteen hues far apart,
/// neighbours in the list (labels numbered one after the other) most of
/// all, light enough to shade.
const LABEL_PALETTE: [[f32; 3]; LABEL_COLOURS as usize] = [
    [232.0, 214.0, 180.0],
    [230.0, 159.0, 0.0],
    [86.0, 180.0, 233.0],
    [0.0, 170.0, 120.0],
    [240.0, 228.0, 66.0],
    [60.0, 120.0, 220.0],
    [225.0, 100.0, 40.0],
    [204.0, 121.0, 167.0],
    [152.0, 223.0, 138.0],
    [148.0, 103.0, 189.0],
    [23.0, 190.0, 207.0],
    [255.0, 152.0, 150.0],
    [188.0, 189.0, 34.0],
    [197.0, 176.0, 213.0],
    [180.0, 120.0, 90.0],
    [230.0, 90.0, 140.0],
];

/// Text and tile border colours.
const TEXT: [u8; 3] = [240, 240, 240];
const BORDER: [u8; 3] = [80, 84, 92];

/// Scale of the font (pixels per font pixel).
const FONT_SCALE: usize = 2;

/// The RGB bytes (row by row, [`DIMENSIONS`]) of the picture of `raster`
/// with `caption`'s lines (at most two fit) in the band under the tiles.
///
/// Each row of the tiles is made once, in a row buffer (the background,
/// then each shaded pixel [`BLOCK`] times along it), and appended
/// [`BLOCK`] times: the picture is written once, row by row, not filled
/// with the background and then overwritten. `labelled`: the raster's
/// keys carry their labels' colours ([`Raster::draw_labelled`]), which
/// the surfaces seen from outside take.
pub fn compose(raster: &Raster, caption: &[String], labelled: bool) -> Vec<u8> {
    let (w, h) = DIMENSIONS;
    let mut rgb = Vec::with_capacity(w * h * 3);
    let blank = BACKGROUND.repeat(w);
    let mut row = blank.clone();
    for band in 0..GRID {
        for y in 0..DEPTH {
            row.copy_from_slice(&blank);
            for column in 0..GRID {
                let tile = raster.tile(band * GRID + column);
                let out = &mut row[column * TILE * 3..(column + 1) * TILE * 3];
                shade_row(tile, y, out, labelled);
            }
            for _ in 0..BLOCK {
                rgb.extend_from_slice(&row);
            }
        }
    }
    for _ in SIZE..h {
        rgb.extend_from_slice(&blank);
    }
    let mut put = |x: usize, y: usize, c: [u8; 3]| {
        if x < w && y < h {
            rgb[(y * w + x) * 3..(y * w + x) * 3 + 3].copy_from_slice(&c);
        }
    };
    // Tile borders: the first and last column and row of every tile.
    for i in 0..GRID {
        for edge in [i * TILE, i * TILE + TILE - 1] {
            for t in 0..SIZE {
                put(edge, t, BORDER);
                put(t, edge, BORDER);
            }
        }
    }
    for (view, name) in VIEW_NAMES.iter().enumerate() {
        let (tx, ty) = ((view % GRID) * TILE, (view / GRID) * TILE);
        font::draw(name, tx + 8, ty + 6, FONT_SCALE, |x, y| put(x, y, TEXT));
    }
    let line_height = (font::GLYPH.1 + 3) * FONT_SCALE;
    for (i, line) in caption.iter().take(2).enumerate() {
        let fit: String = line
            .chars()
            .take(w / (font::ADVANCE * FONT_SCALE) - 2)
            .collect();
        font::draw(&fit, 8, SIZE + 3 + i * line_height, FONT_SCALE, |x, y| {
            put(x, y, TEXT)
        });
    }
    rgb
}

/// Direction toward the light in view coordinates (right, up, toward the
/// viewer's back): from the upper left, a little in front; unit length.
const LIGHT: [f32; 3] = [-0.4 / 1.233_15, 0.6 / 1.233_15, -1.0 / 1.233_15];

/// Depth difference (in pixels) beyond which a pixel whose two neighbours
/// on an axis are both nearer, or both farther, is a lone pixel of another
/// surface rather than a smooth peak or pit.
const LONE_STEP: f32 = 1.0;

/// The depth of a key, `None` for [`EMPTY`]: its bits less those of `mask`
/// ([`BACK`], and [`LABEL_BITS`] in a picture of labels).
#[inline]
fn depth(key: u32, mask: u32) -> Option<f32> {
    (key != EMPTY).then(|| f32::from_bits(key & !mask))
}

/// The slope of the depth at `here` from its neighbours `before` and
/// `after` on one axis: the smaller one-sided difference, or none where
/// the two differ in sign and both exceed [`LONE_STEP`].
#[inline]
fn slope(before: Option<f32>, here: f32, after: Option<f32>) -> f32 {
    match (before, after) {
        (Some(b), Some(a)) => {
            let (l, r) = (here - b, a - here);
            if l * r < 0.0 && l.abs().min(r.abs()) > LONE_STEP {
                // A steep peak or pit along the axis: a lone pixel of a
                // surface behind (or in front of) its neighbours, as a
                // step between grid lines leaves, shades flat rather than
                // as a dark dot.
                0.0
            } else if l.abs() <= r.abs() {
                l
            } else {
                r
            }
        }
        (Some(b), None) => here - b,
        (None, Some(a)) => a - here,
        (None, None) => 0.0,
    }
}

/// Row `y` of a view's keys (`DEPTH` by `DEPTH`, row by row) as RGB bytes
/// into `out` (`3 * TILE` bytes, the background already there): each
/// pixel drawn, shaded, [`BLOCK`] times; the others left as they are.
fn shade_row(tile: &[u32], y: usize, out: &mut [u8], labelled: bool) {
    let mask = if labelled { BACK | LABEL_BITS } else { BACK };
    let depth = |key: u32| depth(key, mask);
    let row = &tile[y * DEPTH..(y + 1) * DEPTH];
    let above = y.checked_sub(1).map(|u| &tile[u * DEPTH..(u + 1) * DEPTH]);
    let below = (y + 1 < DEPTH).then(|| &tile[(y + 1) * DEPTH..(y + 2) * DEPTH]);
    for (x, (&key, block)) in row.iter().zip(out.chunks_exact_mut(3 * BLOCK)).enumerate() {
        let Some(here) = depth(key) else {
            continue;
        };
        let gx = slope(
            x.checked_sub(1).and_then(|l| depth(row[l])),
            here,
            row.get(x + 1).and_then(|&k| depth(k)),
        );
        let gy = slope(
            above.and_then(|r| depth(r[x])),
            here,
            below.and_then(|r| depth(r[x])),
        );
        // The normal (gx, -gy, -1): x right, y up (pixel y grows downward),
        // depth away from the viewer.
        let cos = (gx * LIGHT[0] - gy * LIGHT[1] - LIGHT[2]) / (gx * gx + gy * gy + 1.0).sqrt();
        let light = 0.2 + 0.8 * cos.clamp(0.0, 1.0);
        let base = match (key & BACK == 0, labelled) {
            (false, _) => INSIDE,
            (true, false) => OUTSIDE,
            (true, true) => LABEL_PALETTE[((key & LABEL_BITS) >> 1) as usize],
        };
        let colour = base.map(|c| (c * light) as u8);
        for o in block.chunks_exact_mut(3) {
            o.copy_from_slice(&colour);
        }
    }
}

/// Pixels of the tiles that are not background: how much the picture shows
/// (each covered depth-buffer pixel is [`BLOCK`] by [`BLOCK`] of them).
pub fn covered(raster: &Raster) -> usize {
    let depth_pixels: usize = (0..4)
        .map(|v| raster.tile(v).iter().filter(|&&k| k != EMPTY).count())
        .sum();
    depth_pixels * BLOCK * BLOCK
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Row 1 of a three-row tile: `middle` is the row's keys, the rows
    /// above and below hold `around` in every pixel.
    fn shaded(middle: &[f32], around: f32) -> Vec<u8> {
        let key = |d: f32| d.to_bits() & !BACK;
        let mut tile = vec![EMPTY; DEPTH * 3];
        for x in 0..middle.len() {
            tile[x] = key(around);
            tile[DEPTH + x] = key(middle[x]);
            tile[2 * DEPTH + x] = key(around);
        }
        let mut out = BACKGROUND.repeat(TILE);
        shade_row(&tile, 1, &mut out, false);
        // Each pixel is there BLOCK times: once is enough.
        out.chunks_exact(3 * BLOCK)
            .flat_map(|p| &p[..3])
            .copied()
            .collect()
    }

    /// One pixel drawn in each view: it fills the BLOCK by BLOCK square
    /// of its own tile, and nothing else in the tiles (but the borders and
    /// the views' names) leaves the background.
    #[test]
    fn a_drawn_pixel_fills_its_square_of_its_own_tile() {
        let (w, _) = DIMENSIONS;
        let at = |view: usize| (40 + 30 * view, 100 + 20 * view);
        let mut raster = Raster::empty();
        for view in 0..4 {
            let mut keys = vec![EMPTY; DEPTH * DEPTH];
            let (x, y) = at(view);
            keys[y * DEPTH + x] = 7.0f32.to_bits() & !BACK;
            raster.set_tile(view, keys);
        }
        let rgb = compose(&raster, &[], false);
        let plain = compose(&Raster::new(), &[], false);
        let pixel = |img: &[u8], x: usize, y: usize| [0, 1, 2].map(|c| img[(y * w + x) * 3 + c]);
        let mut changed = Vec::new();
        for y in 0..SIZE {
            for x in 0..SIZE {
                if pixel(&rgb, x, y) != pixel(&plain, x, y) {
                    changed.push((x, y));
                }
            }
        }
        let mut want = Vec::new();
        for y in 0..SIZE {
            for x in 0..SIZE {
                let view = (y / TILE) * GRID + x / TILE;
                let (px, py) = at(view);
                let (tx, ty) = ((view % GRID) * TILE, (view / GRID) * TILE);
                if (x - tx) / BLOCK == px && (y - ty) / BLOCK == py {
                    want.push((x, y));
                }
            }
        }
        assert_eq!(changed, want);
        let lit = pixel(&rgb, TILE + BLOCK * at(1).0, BLOCK * at(1).1);
        assert_ne!(lit, BACKGROUND);
    }

    #[test]
    fn a_lone_pixel_behind_its_neighbours_shades_as_they_do() {
        let flat = shaded(&[50.0; 5], 50.0);
        let pit = shaded(&[50.0, 50.0, 80.0, 50.0, 50.0], 50.0);
        assert_eq!(pit[6..9], flat[6..9], "the pit is lit as the flat surface");
        let peak = shaded(&[50.0, 50.0, 20.0, 50.0, 50.0], 50.0);
        assert_eq!(peak[6..9], flat[6..9], "and so is a lone pixel in front");
    }

    #[test]
    fn a_slope_and_a_step_still_shade_by_the_surface() {
        // A ramp rising toward the viewer to the right: lit differently
        // from flat, and its last pixel, at a step down behind, keeps the
        // ramp's slope (the smaller one-sided difference).
        let flat = shaded(&[50.0; 5], 50.0);
        let ramp = shaded(&[54.0, 53.0, 52.0, 51.0, 50.0], 50.0);
        assert_ne!(ramp[3..6], flat[3..6]);
        let step = shaded(&[54.0, 53.0, 52.0, 51.0, 90.0], 50.0);
        assert_eq!(step[9..12], ramp[9..12]);
        assert_ne!(step[9..12], flat[9..12]);
    }
}
