//! The three orthogonal views of an extracted mesh, drawn from its vertices
//! alone, without its triangles: exact, and a few operations per vertex.
//!
//! The views look along the grid's own axes (a scan's axial, coronal and
//! sagittal directions). A grid line along x (fixed sample indices `j`,
//! `k`) meets the mesh only at the vertices on that line's x-edges:
//! inside a cell every triangle lies in the closed cell and meets the cell's
//! boundary only along contour segments that join vertices on the edges of
//! a face, so it can touch a cell edge only at its vertices (a segment
//! touching an edge at an inner point lies along that edge, and then both
//! its ends are vertices on the line); an interior vertex of TMC lies on no
//! grid line. So the x-view's depth on the line `(j, k)` is exactly the
//! depth of the nearest vertex whose y and z are the grid line's: one
//! comparison per vertex, in any order (the minimum of a set: the same
//! pixels for any threads, slabs or parts), and no holes.
//!
//! Each view keeps the depth of only the lines its pixels need (the two
//! on either side of each pixel centre, on each axis: at most
//! `2 * DEPTH` by `2 * DEPTH` lines, whatever the grid), and
//! [`GridLines::tile`] resamples them to the view's pixels: the bilinear
//! mean of the four lines around a pixel centre where they are close in
//! depth, the nearest line's depth elsewhere (a silhouette or a step stays
//! sharp), nothing where the nearest line meets no surface.
//!
//! This needs vertices that sit on grid lines of a grid known up front: an
//! extraction's, or a `.tmesh`'s recorded one, with the identity direction
//! ([`GridLines::new`] says when it can be used). A `.tmesh` records no
//! direction cosines, so a rotated grid's `extract --preview` draws every
//! view from triangles, and `tmc preview` of its `.tmesh`, which cannot
//! tell, draws them both ways and keeps the lines only if the vertices
//! were on them ([`GridLines::fit`]).

use super::raster::EMPTY;
use super::views::{View, BLOCK, DEPTH};
use crate::Grid;

/// Not a line a view needs.
const NONE: u32 = u32::MAX;

/// The lines of one axis view: which grid axes are the view's screen
/// axes, and the nearest depth found on each line.
#[derive(Clone)]
struct AxisView {
    /// The grid axes of screen x and screen y.
    across: [usize; 2],
    /// Per screen axis: for each line index `i + 1` (`i` from -1, the
    /// `--close` padding, to the last sample plus one), its place in a
    /// row of `keys` (screen x) or the place of its row (screen y), or
    /// [`NONE`].
    ids: [Vec<u32>; 2],
    /// Per screen axis, per pixel: the first of the two lines around the
    /// pixel centre (as an index into `ids`) and the centre's fraction of
    /// the way to the second.
    pixels: [Vec<(usize, f32)>; 2],
    /// The smallest depth key per kept line (the lines kept on screen x by
    /// those on screen y, row by row along screen y).
    keys: Vec<u32>,
    /// The view's depth, in depth-buffer pixels, of world `p`: the
    /// coefficients of x, y, z and the offset.
    depth: [f32; 4],
    /// The largest spread in depth (depth-buffer pixels) of the four lines
    /// around a pixel centre that are blended: [`STEEP`] times the lines'
    /// spacing in pixels; beyond it the nearest line's depth is taken (one
    /// surface in front of another).
    jump: f32,
    /// Whether the lines are dense enough to draw the view: at most
    /// [`SPARSE`] depth-buffer pixels apart on both screen axes (a grid of
    /// a few dozen samples a side is rasterised instead: its silhouettes
    /// would show the lines' steps, and its triangles are few).
    dense: bool,
}

/// The three axis views' line depths; fed vertices by [`GridLines::add`],
/// merged by [`GridLines::merge`], turned into depth buffers by
/// [`GridLines::tile`].
#[derive(Clone)]
pub struct GridLines {
    views: [AxisView; 3],
    /// Per grid axis: origin and spacing (world to index), and how far
    /// from a whole index a coordinate may be and still be on a line.
    origin: [f64; 3],
    /// One over the spacing.
    per_unit: [f64; 3],
    tolerance: [f64; 3],
    /// Vertices added, and those on no grid line.
    added: u64,
    off_lines: u64,
}

/// Which views (0 front, 1 side, 2 top) look along which grid axis, and
/// the grid axes of their screen x and y (see [`View::four`]).
pub const AXES: [(usize, [usize; 2]); 3] = [(1, [0, 2]), (0, [1, 2]), (2, [0, 1])];

impl GridLines {
    /// The lines of `grid` for `views` ([`View::four`] of its bounds), or
    /// `None` when the vertices cannot be placed on its lines: a direction
    /// other than the identity, a spacing that is not positive and finite,
    /// or coordinates too large for `f32` vertices to keep their grid
    /// position.
    pub fn new(grid: &Grid, views: &[View; 4]) -> Option<GridLines> {
        if grid.direction != crate::grid::IDENTITY {
            return None;
        }
        let mut tolerance = [0.0; 3];
        for (a, tolerance) in tolerance.iter_mut().enumerate() {
            let (o, s, n) = (grid.origin[a], grid.spacing[a], grid.dims[a] as f64);
            if !(s.is_finite() && s > 0.0 && o.is_finite()) {
                return None;
            }
            // A vertex coordinate is an f32: its rounding, in index units.
            let far = (o - s).abs().max((o + n * s).abs());
            *tolerance = 1e-3f64.max(8.0 * far * f64::from(f32::EPSILON) / s);
            if *tolerance > 0.05 {
                return None;
            }
        }
        let rows = View::rows(views);
        let views = [0, 1, 2].map(|v| {
            let across = AXES[v].1;
            let screen = [0, 1].map(|s| views[v].screen_axis(s, across[s]));
            // The lines' spacing in depth-buffer pixels, the larger of the
            // two screen axes'.
            let apart = (0..2)
                .map(|s| (screen[s].0 * grid.spacing[across[s]]).abs() / BLOCK as f64)
                .fold(0.0, f64::max);
            let mut ids = [Vec::new(), Vec::new()];
            let mut pixels = [Vec::new(), Vec::new()];
            let mut width = [0usize; 2];
            for s in 0..2 {
                let a = across[s];
                let lines = grid.dims[a] + 2;
                ids[s] = vec![NONE; lines];
                let (scale, offset) = screen[s];
                for p in 0..DEPTH {
                    // The pixel centre in tile pixels, then world, then
                    // grid index (from -1).
                    let centre = (p as f64 + 0.5) * BLOCK as f64;
                    let world = (centre - offset) / scale;
                    let index = (world - grid.origin[a]) / grid.spacing[a] + 1.0;
                    let low = index.floor();
                    if !(0.0..(lines - 1) as f64).contains(&low) {
                        pixels[s].push((usize::MAX, 0.0));
                        continue;
                    }
                    let low = low as usize;
                    for line in [low, low + 1] {
                        if ids[s][line] == NONE {
                            ids[s][line] = width[s] as u32;
                            width[s] += 1;
                        }
                    }
                    pixels[s].push((low, (index - low as f64) as f32));
                }
            }
            for id in ids[1].iter_mut().filter(|id| **id != NONE) {
                *id *= width[0] as u32;
            }
            AxisView {
                across,
                ids,
                pixels,
                keys: vec![EMPTY; width[0] * width[1]],
                depth: [rows[2][0][v], rows[2][1][v], rows[2][2][v], rows[2][3][v]],
                jump: apart.max(1.0) as f32 * STEEP,
                dense: apart <= SPARSE,
            }
        });
        if !views.iter().any(|v| v.dense) {
            return None;
        }
        Some(GridLines {
            views,
            origin: grid.origin,
            per_unit: grid.spacing.map(|s| 1.0 / s),
            tolerance,
            added: 0,
            off_lines: 0,
        })
    }

    /// Puts each vertex of `vertices` that lies on a grid line (on a grid
    /// edge, or on a sample: three lines) into the views along those lines.
    pub fn add(&mut self, vertices: &[[f32; 3]]) {
        // Adding and subtracting 1.5 * 2^52 rounds to the nearest whole
        // number (for any index below 2^51): two additions, where
        // `f64::round` is a call on baseline x86-64.
        const ROUND: f64 = 6_755_399_441_055_744.0;
        const FAR: f64 = (1u64 << 50) as f64;
        self.added += vertices.len() as u64;
        for &p in vertices {
            let mut index = [0i64; 3];
            let mut on = 0usize;
            for a in 0..3 {
                let g = (f64::from(p[a]) - self.origin[a]) * self.per_unit[a];
                let sum = g + ROUND;
                let r = sum - ROUND;
                // The whole number in the low bits of the sum (valid below
                // 2^51; farther, the vertex is on no line).
                index[a] = (sum.to_bits() & ((1 << 52) - 1)) as i64 - (1 << 51);
                let near = (g - r).abs() <= self.tolerance[a] && g.abs() < FAR;
                on |= usize::from(near) << a;
            }
            match on {
                // On a grid edge: on the one line along the edge's axis,
                // which only the view looking along that axis sees.
                0b110 => self.views[1].put_if_dense(p, index),
                0b101 => self.views[0].put_if_dense(p, index),
                0b011 => self.views[2].put_if_dense(p, index),
                // On a sample: on three lines.
                0b111 => {
                    for view in &mut self.views {
                        view.put_if_dense(p, index);
                    }
                }
                _ => self.off_lines += 1,
            }
        }
    }

    /// Keeps, per line, the nearer depth of `self` and `other` (made by
    /// the same [`GridLines::new`]).
    pub fn merge(&mut self, other: &GridLines) {
        self.added += other.added;
        self.off_lines += other.off_lines;
        for (a, b) in self.views.iter_mut().zip(&other.views) {
            for (x, &y) in a.keys.iter_mut().zip(&b.keys) {
                *x = (*x).min(y);
            }
        }
    }

    /// Whether the vertices added were those of a mesh extracted on this
    /// grid: most of them on its lines (all but a TMC cell's interior
    /// vertices). A `.tmesh` records no direction cosines, so a mesh
    /// extracted on a rotated grid comes with an unrotated grid, and its
    /// vertices miss the lines.
    pub fn fit(&self) -> bool {
        self.off_lines * 4 <= self.added
    }

    /// Whether axis view `view` (0, 1 or 2) is drawn from the lines (else
    /// its triangles must be rasterised).
    pub fn dense(&self, view: usize) -> bool {
        self.views[view].dense
    }

    /// The depth buffer (`DEPTH` by `DEPTH` keys, row by row) of axis view
    /// `view` (0, 1 or 2).
    pub fn tile(&self, view: usize) -> Vec<u32> {
        self.views[view].tile()
    }
}

impl AxisView {
    /// A vertex `p` at grid indices `index`, on one of this view's lines
    /// (both its screen axes' indices whole), if the view is drawn from
    /// its lines.
    #[inline(always)]
    fn put_if_dense(&mut self, p: [f32; 3], index: [i64; 3]) {
        if !self.dense {
            return;
        }
        let [h, w] = self.across;
        // (An index of -2 or less wraps round to a large number: no line.)
        let line = |ids: &[u32], i: i64| ids.get((i + 1) as usize).copied().unwrap_or(NONE);
        let (a, b) = (line(&self.ids[0], index[h]), line(&self.ids[1], index[w]));
        if a == NONE || b == NONE {
            return;
        }
        let d = self.depth;
        let depth = (d[0] * p[0] + d[1] * p[1] + d[2] * p[2] + d[3]).max(0.0);
        let key = &mut self.keys[b as usize + a as usize];
        *key = (*key).min(depth.to_bits() & !super::raster::BACK);
    }

    /// The kept line depths resampled to the view's pixels.
    fn tile(&self) -> Vec<u32> {
        let mut out = vec![EMPTY; DEPTH * DEPTH];
        // Per pixel column: the places in a row of `keys` of the lines
        // before and after its centre, the nearer one's, the fraction.
        let columns: Vec<Option<([usize; 3], f32)>> = self.pixels[0]
            .iter()
            .map(|&(col, fx)| {
                (col != usize::MAX).then(|| {
                    let (c0, c1) = (self.ids[0][col] as usize, self.ids[0][col + 1] as usize);
                    ([c0, c1, if fx >= 0.5 { c1 } else { c0 }], fx)
                })
            })
            .collect();
        let keys = &self.keys[..];
        for (y, &(row, fy)) in self.pixels[1].iter().enumerate() {
            if row == usize::MAX {
                continue;
            }
            let (r0, r1) = (self.ids[1][row] as usize, self.ids[1][row + 1] as usize);
            let near_row = if fy >= 0.5 { r1 } else { r0 };
            for (o, column) in out[y * DEPTH..(y + 1) * DEPTH].iter_mut().zip(&columns) {
                let Some(([c0, c1, near_column], fx)) = *column else {
                    continue;
                };
                let nearest = keys[near_row + near_column];
                if nearest == EMPTY {
                    continue;
                }
                let corners = [keys[r0 + c0], keys[r0 + c1], keys[r1 + c0], keys[r1 + c1]];
                *o = nearest;
                if corners.contains(&EMPTY) {
                    continue;
                }
                let [a, b, c, d] = corners.map(f32::from_bits);
                if a.max(b).max(c).max(d) - a.min(b).min(c).min(d) <= self.jump {
                    let top = a + (b - a) * fx;
                    let bottom = c + (d - c) * fx;
                    *o = (top + (bottom - top) * fy).to_bits() & !super::raster::BACK;
                }
            }
        }
        out
    }
}

/// The widest spacing of the lines, in depth-buffer pixels, that a view
/// is drawn from (see [`AxisView::dense`]).
const SPARSE: f64 = 2.0;

/// The steepest slope (depth over distance on screen) blended between
/// lines: about 84 degrees from the viewing direction.
const STEEP: f32 = 10.0;

#[cfg(test)]
mod tests {
    use super::super::raster::Raster;
    use super::super::views::Bounds;
    use super::*;
    use crate::{ArrayVolume, ExtractParams, Grid};

    /// A ball of radius 60 (in samples) off the centre of a grid with
    /// unequal spacings and an origin away from zero, extracted (about a
    /// line a pixel or two).
    fn ball() -> (Grid, crate::Mesh) {
        let dims = [180, 160, 140];
        let mut grid = Grid::unit(dims);
        grid.spacing = [1.0, 0.8, 1.5];
        grid.origin = [-3.5, 10.25, 2.0];
        let v = ArrayVolume::from_fn(dims, |i, j, k| {
            let d = [i as f64 - 89.2, j as f64 - 79.6, k as f64 - 69.9];
            60.0 - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        });
        let data = v.data().to_vec();
        let volume = ArrayVolume::new(grid, data).unwrap();
        let params = ExtractParams {
            iso: 0.0,
            ..ExtractParams::default()
        };
        (grid, crate::extract(&volume, &params).unwrap().0)
    }

    /// The axis views from the vertices on grid lines against the
    /// rasteriser's drawing of every triangle (independent code): the same
    /// pixels covered but for a few on the outline, and the same depth
    /// within a pixel where both have it.
    #[test]
    fn line_views_match_the_rasterised_triangles() {
        let (grid, mesh) = ball();
        let views = View::four(&Bounds::of_grid(&grid).unwrap());
        let mut lines = GridLines::new(&grid, &views).expect("an identity grid");
        assert!((0..3).all(|v| lines.dense(v)));
        lines.add(&mesh.vertices);
        let mut raster = Raster::new();
        raster.draw(&views, &mesh.vertices, &mesh.triangles);
        for view in 0..3 {
            let tile = lines.tile(view);
            let (mut both, mut only, mut far) = (0, 0, 0);
            let depth = |x: usize, y: usize| {
                let k = raster.key(view, x, y);
                (k != EMPTY).then(|| f32::from_bits(k & !1))
            };
            for y in 1..DEPTH - 1 {
                for x in 1..DEPTH - 1 {
                    let a = tile[y * DEPTH + x];
                    match (a != EMPTY, depth(x, y)) {
                        (true, Some(db)) => {
                            both += 1;
                            // Where the surface is not steep (the raster's
                            // slope at most 1.5), within a pixel.
                            let slope = match [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                                .map(|(x, y)| depth(x, y))
                            {
                                [Some(l), Some(r), Some(u), Some(d)] => {
                                    ((r - l).abs().max((d - u).abs())) / 2.0
                                }
                                _ => f32::INFINITY,
                            };
                            if slope <= 1.5 && (f32::from_bits(a) - db).abs() > 1.0 {
                                far += 1;
                            }
                        }
                        (false, None) => {}
                        _ => only += 1,
                    }
                }
            }
            // The ball's disc is large in every view; its outline a few
            // hundred pixels long.
            assert!(both > 10_000, "view {view}: {both}");
            assert!(only * 40 < both, "view {view}: {only} of {both}");
            assert!(far * 200 < both, "view {view}: {far} of {both} differ");
        }
    }

    #[test]
    fn a_rotated_or_small_grid_has_no_line_views() {
        let mut grid = Grid::unit([400, 400, 400]);
        let views = View::four(&Bounds::of_grid(&grid).unwrap());
        assert!(GridLines::new(&grid, &views).is_some());
        grid.direction = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(GridLines::new(&grid, &views).is_none());
        // Lines some four pixels apart: the triangles are drawn.
        let small = Grid::unit([60, 60, 60]);
        let views = View::four(&Bounds::of_grid(&small).unwrap());
        assert!(GridLines::new(&small, &views).is_none());
    }
}
