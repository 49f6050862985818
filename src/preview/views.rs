//! The four views of a preview: three orthogonal ones and one oblique, each
//! fitted to the mesh's bounding box, and where they sit in the picture.
//!
//! The view transform must be known before the first triangle arrives (the
//! picture is drawn while the mesh streams), so it is built from bounds
//! given up front: the volume's physical bounding box for an extraction,
//! the recorded grid (or a first pass over the vertices) for a mesh file.

/// Side of one view's square tile, in pixels.
pub const TILE: usize = 512;

/// Side of a picture's square pixel block that one depth-buffer pixel of
/// a view fills: the views are drawn at half the tile's resolution (on a
/// CT, about a voxel a pixel), which makes a preview cost a quarter of the
/// pixel tests and shading it would at full resolution.
pub const BLOCK: usize = 2;

/// Side of one view's depth buffer, in its pixels ([`BLOCK`] by [`BLOCK`]
/// of the tile's each).
pub const DEPTH: usize = TILE / BLOCK;

/// Tiles per row and per column of the picture (a 2x2 grid).
pub const GRID: usize = 2;

/// Width and height of the picture, in pixels.
pub const SIZE: usize = TILE * GRID;

/// Pixels left free around the projected bounding box in a tile.
const MARGIN: f64 = 24.0;

/// Names of the views, in tile order (left to right, top to bottom).
pub const VIEW_NAMES: [&str; 4] = ["FRONT (-Y)", "SIDE (+X)", "TOP (+Z)", "OBLIQUE"];

/// An axis-aligned box in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest x, y, z.
    pub min: [f64; 3],
    /// Largest x, y, z.
    pub max: [f64; 3],
}

impl Bounds {
    /// The box of `points`, or `None` when there are none or one is not
    /// finite.
    pub fn of_points(points: impl IntoIterator<Item = [f64; 3]>) -> Option<Bounds> {
        let mut b = Bounds {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        };
        let mut any = false;
        for p in points {
            if p.iter().any(|c| !c.is_finite()) {
                return None;
            }
            any = true;
            for (i, &c) in p.iter().enumerate() {
                b.min[i] = b.min[i].min(c);
                b.max[i] = b.max[i].max(c);
            }
        }
        any.then_some(b)
    }

    /// The physical box of a grid's index box widened by one cell on every
    /// side (a `--close` surface lies in the padding cells), through the
    /// grid's index-to-world map (any direction cosines).
    pub fn of_grid(grid: &crate::Grid) -> Option<Bounds> {
        let hi = grid.dims.map(|d| d as f64);
        let corners = (0..8).map(|c| {
            let pick = |axis: usize| if c >> axis & 1 == 1 { hi[axis] } else { -1.0 };
            grid.world([pick(0), pick(1), pick(2)])
        });
        Bounds::of_points(corners)
    }

    /// The eight corners.
    fn corners(&self) -> impl Iterator<Item = [f64; 3]> + '_ {
        (0..8).map(move |c| {
            [0, 1, 2].map(|a| {
                if c >> a & 1 == 1 {
                    self.max[a]
                } else {
                    self.min[a]
                }
            })
        })
    }
}

/// One view: an orthographic projection onto a tile. Pixel x grows to the
/// right, pixel y downward; `depth` grows away from the viewer, in pixels
/// (the same scale as x and y, so that the depth buffer's slope is the
/// surface's), and is never negative inside the bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Rows: screen right, screen down, viewing direction (unit vectors),
    /// each multiplied by the view's scale (pixels per world unit).
    axes: [[f32; 3]; 3],
    /// Added after the products: pixel x, pixel y (of the tile) and depth.
    offset: [f32; 3],
}

impl View {
    /// The four views of a box, fitted into [`TILE`]-pixel tiles.
    pub fn four(bounds: &Bounds) -> [View; 4] {
        let oblique = {
            let (az, el) = (35f64.to_radians(), 25f64.to_radians());
            let right = [az.cos(), az.sin(), 0.0];
            let forward = [-az.sin() * el.cos(), az.cos() * el.cos(), -el.sin()];
            let up = cross(right, forward);
            [right, up, forward]
        };
        [
            // Front: looking along +y, z up.
            [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            // Side: looking along -x, z up.
            [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]],
            // Top: looking along -z, y up.
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            oblique,
        ]
        .map(|axes| View::fit(bounds, axes))
    }

    /// The view along `axes` (right, up, forward) that fits `bounds`.
    fn fit(bounds: &Bounds, [right, up, forward]: [[f64; 3]; 3]) -> View {
        let extent = |dir: [f64; 3]| {
            let values: Vec<f64> = bounds.corners().map(|c| dot(c, dir)).collect();
            let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        };
        let (r, u, f) = (extent(right), extent(up), extent(forward));
        let span = (r.1 - r.0).max(u.1 - u.0);
        let room = TILE as f64 - 2.0 * MARGIN;
        let scale = if span > 0.0 { room / span } else { 1.0 };
        let half = TILE as f64 / 2.0;
        let scaled = |d: [f64; 3], s: f64| d.map(|c| (c * s) as f32);
        View {
            axes: [
                scaled(right, scale),
                scaled(up, -scale),
                scaled(forward, scale),
            ],
            offset: [
                (half - (r.0 + r.1) / 2.0 * scale) as f32,
                (half + (u.0 + u.1) / 2.0 * scale) as f32,
                (-f.0 * scale) as f32,
            ],
        }
    }

    /// The four views' projections side by side, for
    /// [`super::raster::Raster`], in depth-buffer pixels ([`BLOCK`] tile
    /// pixels each): `rows[axis][c][view]` is the coefficient of world
    /// coordinate `c` (the offset for `c == 3`) in pixel x (`axis` 0),
    /// pixel y (1) or depth (2), with x and y shifted by half a pixel so
    /// that pixel centres fall on whole numbers.
    pub fn rows(views: &[View; 4]) -> [[[f32; 4]; 4]; 3] {
        let mut rows = [[[0f32; 4]; 4]; 3];
        for (v, view) in views.iter().enumerate() {
            for (axis, row) in rows.iter_mut().enumerate() {
                let scale = 1.0 / BLOCK as f32;
                for (c, coefficient) in row.iter_mut().take(3).enumerate() {
                    coefficient[v] = view.axes[axis][c] * scale;
                }
                let centre = if axis < 2 { 0.5 } else { 0.0 };
                row[3][v] = view.offset[axis] * scale - centre;
            }
        }
        rows
    }

    /// Screen axis `screen` (0: x, 1: y) of the view as a function of world
    /// coordinate `axis` alone, in tile pixels: `(scale, offset)` with
    /// `pixel = scale * world + offset` (a view along a world axis, whose
    /// screen axes are world axes: [`View::four`]'s first three).
    pub fn screen_axis(&self, screen: usize, axis: usize) -> (f64, f64) {
        (
            f64::from(self.axes[screen][axis]),
            f64::from(self.offset[screen]),
        )
    }

    /// Pixel x, pixel y (tile coordinates, y down) and depth of `p`; the
    /// pixel `(i, j)` spans `i..i + 1` and `j..j + 1`.
    #[inline]
    pub fn project(&self, p: [f32; 3]) -> [f32; 3] {
        let a = &self.axes;
        [0, 1, 2].map(|i| a[i][0] * p[0] + a[i][1] * p[1] + a[i][2] * p[2] + self.offset[i])
    }
}

/// Dot product.
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_fits_every_tile() {
        let b = Bounds {
            min: [-3.0, 10.0, 0.5],
            max: [40.0, 25.0, 7.0],
        };
        for view in View::four(&b) {
            for c in b.corners() {
                let [x, y, d] = view.project(c.map(|v| v as f32));
                assert!((0.0..TILE as f32).contains(&x), "{x}");
                assert!((0.0..TILE as f32).contains(&y), "{y}");
                assert!(d >= -1e-3, "{d}");
            }
        }
    }

    #[test]
    fn up_is_up_on_screen() {
        let b = Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let front = View::four(&b)[0];
        let low = front.project([0.5, 0.5, 0.0]);
        let high = front.project([0.5, 0.5, 1.0]);
        assert!(high[1] < low[1], "screen y grows downward");
    }
}
