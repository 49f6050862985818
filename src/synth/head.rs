//! A CT-like head phantom in Hounsfield units.
//!
//! In coordinates `u` that run from -1 to 1 across the box along every axis
//! (so the head fills the box whatever the spacing; x is left-right, y
//! back-front, z feet-head):
//!
//! | region | ellipsoid centre | radii | value (HU) |
//! | --- | --- | --- | --- |
//! | air (background) | | | -1000 |
//! | soft tissue (scalp, face) | (0, 0, 0) | (0.72, 0.88, 0.92) | 40 |
//! | skull, outer surface | (0, 0, 0.04) | (0.66, 0.81, 0.84) | 1000 to 1500 |
//! | skull, inner surface = brain | (0, 0.02, 0.08) | (0.60, 0.74, 0.76) | 30 |
//! | ventricles (two) | (±0.10, 0.04, 0.12) | (0.06, 0.22, 0.10) | 5 |
//!
//! Each region is painted over the previous ones with a one-sample linear
//! ramp across its boundary (a partial-volume effect), so surfaces are
//! smooth at any isovalue between two regions. The skull is 0.04 (top) to
//! 0.12 (base) thick in `u`, and its density varies smoothly between 1000
//! and 1500 HU. Finally uniform white noise of ±15 HU, hashed from the seed
//! and the sample index, is added everywhere.

use super::row_field::RowField;
use super::value_noise::hash3;
use crate::Grid;

/// Suggested isovalue (Hounsfield units) for the skull: between soft tissue
/// and brain (at most 40 HU) and bone (at least 1000 HU).
pub const HEAD_SKULL_ISO_HU: f64 = 500.0;

/// Suggested isovalue (Hounsfield units) for the skin: between air
/// (-1000 HU) and soft tissue (40 HU).
pub const HEAD_SKIN_ISO_HU: f64 = -500.0;

const AIR: f64 = -1000.0;
const SOFT_TISSUE: f64 = 40.0;
const BRAIN: f64 = 30.0;
const VENTRICLE: f64 = 5.0;
/// Mean bone density and the amplitude of its variation.
const BONE: (f64, f64) = (1250.0, 250.0);
/// Amplitude of the white noise.
const NOISE: f64 = 15.0;

/// An axis-aligned ellipsoid, tabulated per axis for one grid.
struct Ellipsoid {
    /// Squared offsets from the centre in radii, per axis and sample.
    a2: [Vec<f64>; 3],
    /// Squared derivatives of those offsets per sample step, times the
    /// squared offset: the terms of the squared gradient of the radius.
    b2: [Vec<f64>; 3],
    /// A lower bound of the gradient of the radius per sample step.
    grad_min: f64,
    /// Squared radii beyond which the coverage is 0 and within which it
    /// is 1: `(1 ± max gradient / 2)^2` (the gradient is at most the
    /// largest per-axis step, so the ramp lies between them).
    outer2: f64,
    inner2: f64,
}

impl Ellipsoid {
    fn new(u: &[Vec<f64>; 3], step: [f64; 3], centre: [f64; 3], radii: [f64; 3]) -> Ellipsoid {
        let a = |i: usize| u[i].iter().map(move |v| (v - centre[i]) / radii[i]);
        let g = [0, 1, 2].map(|i| step[i] / radii[i]);
        let grad_max = g.iter().copied().fold(0.0, f64::max);
        Ellipsoid {
            a2: [0, 1, 2].map(|i| a(i).map(|a| a * a).collect()),
            b2: [0, 1, 2].map(|i| a(i).map(|a| (a * g[i]) * (a * g[i])).collect()),
            grad_min: g.iter().copied().fold(f64::INFINITY, f64::min),
            outer2: (1.0 + grad_max / 2.0).powi(2),
            inner2: (1.0 - grad_max / 2.0).max(0.0).powi(2),
        }
    }

    /// Paints `value` (per sample) over `out` with the ellipsoid's coverage:
    /// 1 inside, 0 outside, a linear ramp one sample wide across the surface
    /// (distance estimated from the radius and its gradient).
    fn paint(&self, y: usize, z: usize, value: impl Fn(usize) -> f64, out: &mut [f64]) {
        let q_yz = self.a2[1][y] + self.a2[2][z];
        if q_yz >= self.outer2 {
            return;
        }
        let n_yz = self.b2[1][y] + self.b2[2][z];
        for (x, o) in out.iter_mut().enumerate() {
            let q = self.a2[0][x] + q_yz;
            if q >= self.outer2 {
                continue;
            }
            let cover = if q <= self.inner2 {
                1.0
            } else {
                let rho = q.sqrt();
                let grad = if rho > 1e-12 {
                    (self.b2[0][x] + n_yz).sqrt() / rho
                } else {
                    self.grad_min
                };
                let distance = (rho - 1.0) / grad;
                (0.5 - distance).clamp(0.0, 1.0)
            };
            *o += (value(x) - *o) * cover;
        }
    }
}

/// The head phantom on one grid.
pub(crate) struct Head {
    seed: u64,
    skin: Ellipsoid,
    skull: Ellipsoid,
    brain: Ellipsoid,
    ventricles: [Ellipsoid; 2],
    /// Factors of the bone density variation along each axis.
    bone: [Vec<f64>; 3],
}

impl Head {
    pub(crate) fn new(grid: &Grid, seed: u64) -> Head {
        let step = grid.dims.map(|n| 2.0 / (n as f64 - 1.0).max(1.0));
        let u = [0, 1, 2].map(|i| {
            (0..grid.dims[i])
                .map(|k| k as f64 * step[i] - 1.0)
                .collect::<Vec<f64>>()
        });
        let e = |centre, radii| Ellipsoid::new(&u, step, centre, radii);
        let bone = [
            u[0].iter().map(|v| (3.1 * v).cos()).collect(),
            u[1].iter().map(|v| (2.3 * v + 0.4).cos()).collect(),
            u[2].iter().map(|v| (2.9 * v).cos()).collect(),
        ];
        Head {
            seed,
            skin: e([0.0, 0.0, 0.0], [0.72, 0.88, 0.92]),
            skull: e([0.0, 0.0, 0.04], [0.66, 0.81, 0.84]),
            brain: e([0.0, 0.02, 0.08], [0.60, 0.74, 0.76]),
            ventricles: [
                e([-0.10, 0.04, 0.12], [0.06, 0.22, 0.10]),
                e([0.10, 0.04, 0.12], [0.06, 0.22, 0.10]),
            ],
            bone,
        }
    }
}

impl RowField for Head {
    fn row(&self, _plane: &[f64], y: usize, z: usize, out: &mut [f64]) {
        out.fill(AIR);
        self.skin.paint(y, z, |_| SOFT_TISSUE, out);
        let (by, bz) = (self.bone[1][y], self.bone[2][z]);
        let bone = |x: usize| BONE.0 + BONE.1 * (0.6 * self.bone[0][x] * by + 0.4 * bz);
        self.skull.paint(y, z, bone, out);
        self.brain.paint(y, z, |_| BRAIN, out);
        for v in &self.ventricles {
            v.paint(y, z, |_| VENTRICLE, out);
        }
        let (yy, zz) = (y as u64, z as u64);
        for (x, o) in out.iter_mut().enumerate() {
            *o += NOISE * hash3(self.seed, x as u64, yy, zz);
        }
    }
}
