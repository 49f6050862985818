//! The analytic unit fields: sphere, torus and gyroid, evaluated a row at a
//! time from per-axis tables (no transcendental function per sample).

use super::row_field::RowField;
use crate::Grid;

/// Signed distances are divided by this many samples (of the finest
/// spacing) and clamped: the field ramps across 16 samples at the surface.
const BAND_SAMPLES: f64 = 8.0;

/// Gyroid periods across the shortest side of the box.
const GYROID_PERIODS: f64 = 4.0;

/// Per-axis geometry of the grid's physical box.
struct Frame {
    /// Physical positions of the samples along each axis, relative to the
    /// centre of the box.
    centred: [Vec<f64>; 3],
    /// Half the shortest side of the box.
    half: f64,
    /// The distance that maps to a field value of 1.
    band: f64,
}

impl Frame {
    fn new(grid: &Grid) -> Frame {
        let centred = [0, 1, 2].map(|i| {
            let (n, s) = (grid.dims[i], grid.spacing[i]);
            let c = (n as f64 - 1.0) * s / 2.0;
            (0..n).map(|k| k as f64 * s - c).collect()
        });
        let half = (0..3)
            .map(|i| (grid.dims[i] as f64 - 1.0) * grid.spacing[i] / 2.0)
            .fold(f64::INFINITY, f64::min);
        let finest = grid.spacing.iter().copied().fold(f64::INFINITY, f64::min);
        Frame {
            centred,
            half,
            band: BAND_SAMPLES * finest,
        }
    }

    /// Squared centred positions along `axis`.
    fn squares(&self, axis: usize) -> Vec<f64> {
        self.centred[axis].iter().map(|p| p * p).collect()
    }
}

/// A ball of radius `0.8 L` at the centre of the box.
pub(crate) struct Sphere {
    sq: [Vec<f64>; 3],
    radius: f64,
    scale: f64,
}

impl Sphere {
    pub(crate) fn new(grid: &Grid) -> Sphere {
        let frame = Frame::new(grid);
        Sphere {
            sq: [0, 1, 2].map(|i| frame.squares(i)),
            radius: 0.8 * frame.half,
            scale: 1.0 / frame.band,
        }
    }
}

impl RowField for Sphere {
    fn row(&self, _plane: &[f64], y: usize, z: usize, out: &mut [f64]) {
        let yz = self.sq[1][y] + self.sq[2][z];
        for (o, &xx) in out.iter_mut().zip(&self.sq[0]) {
            *o = (self.radius - (xx + yz).sqrt()) * self.scale;
        }
    }
}

/// A solid torus around the z axis through the centre of the box, ring
/// radius `0.55 L`, tube radius `0.25 L`.
pub(crate) struct Torus {
    sq: [Vec<f64>; 3],
    ring: f64,
    tube: f64,
    scale: f64,
}

impl Torus {
    pub(crate) fn new(grid: &Grid) -> Torus {
        let frame = Frame::new(grid);
        Torus {
            sq: [0, 1, 2].map(|i| frame.squares(i)),
            ring: 0.55 * frame.half,
            tube: 0.25 * frame.half,
            scale: 1.0 / frame.band,
        }
    }
}

impl RowField for Torus {
    fn row(&self, _plane: &[f64], y: usize, z: usize, out: &mut [f64]) {
        let (yy, zz) = (self.sq[1][y], self.sq[2][z]);
        for (o, &xx) in out.iter_mut().zip(&self.sq[0]) {
            let r = (xx + yy).sqrt() - self.ring;
            *o = (self.tube - (r * r + zz).sqrt()) * self.scale;
        }
    }
}

/// `(sin x cos y + sin y cos z + sin z cos x) / 1.5` with four periods
/// across the shortest side of the box (phase 0 at sample 0).
pub(crate) struct Gyroid {
    sin: [Vec<f64>; 3],
    cos: [Vec<f64>; 3],
}

impl Gyroid {
    pub(crate) fn new(grid: &Grid) -> Gyroid {
        let frame = Frame::new(grid);
        let k = GYROID_PERIODS * std::f64::consts::TAU / (2.0 * frame.half);
        let angles = |i: usize| (0..grid.dims[i]).map(move |n| k * n as f64 * grid.spacing[i]);
        Gyroid {
            sin: [0, 1, 2].map(|i| angles(i).map(f64::sin).collect()),
            cos: [0, 1, 2].map(|i| angles(i).map(f64::cos).collect()),
        }
    }
}

impl RowField for Gyroid {
    fn row(&self, _plane: &[f64], y: usize, z: usize, out: &mut [f64]) {
        const TWO_THIRDS: f64 = 1.0 / 1.5;
        // sin x cos y + sin z cos x + sin y cos z, the last term constant.
        let a = self.cos[1][y] * TWO_THIRDS;
        let c = self.sin[2][z] * TWO_THIRDS;
        let b = self.sin[1][y] * self.cos[2][z] * TWO_THIRDS;
        for ((o, &sx), &cx) in out.iter_mut().zip(&self.sin[0]).zip(&self.cos[0]) {
            *o = sx * a + cx * c + b;
        }
    }
}
