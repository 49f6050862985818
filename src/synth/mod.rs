//! Synthetic volumes with known surfaces, for tests, benchmarks and demos.
//!
//! Two families:
//! * in-memory helpers ([`sphere`], [`torus`], [`three_holes`], [`gyroid`],
//!   [`noise`]) that sample a field on a grid with unit spacing; the surface
//!   of interest is its level set at 0, inside where the field is positive;
//! * [`Synthetic`], a [`SampleSource`](crate::SampleSource) of any size that
//!   evaluates one of the [`Kind`]s on demand, plane by plane, already
//!   quantized to a stored sample type (what `tmc synth` writes to disk).

mod fields;
mod head;
mod kind;
mod levels;
mod row_field;
mod source;
mod value_noise;

pub use head::{HEAD_SKIN_ISO_HU, HEAD_SKULL_ISO_HU};
pub use kind::Kind;
pub use levels::{hounsfield_to_stored, unit_to_stored};
pub use source::Synthetic;

use crate::volume::ArrayVolume;

/// Signed distance to a sphere of `radius` around the grid centre, positive inside.
pub fn sphere(n: usize, radius: f64) -> ArrayVolume {
    let c = (n as f64 - 1.0) / 2.0;
    ArrayVolume::from_fn([n; 3], |x, y, z| {
        let (x, y, z) = (x as f64 - c, y as f64 - c, z as f64 - c);
        radius - (x * x + y * y + z * z).sqrt()
    })
}

/// A solid torus around the z axis (ring radius `big`, tube radius `small`),
/// signed distance, positive inside.
pub fn torus(n: usize, big: f64, small: f64) -> ArrayVolume {
    let c = (n as f64 - 1.0) / 2.0;
    ArrayVolume::from_fn([n; 3], |x, y, z| {
        let (x, y, z) = (x as f64 - c, y as f64 - c, z as f64 - c);
        let ring = (x * x + y * y).sqrt() - big;
        small - (ring * ring + z * z).sqrt()
    })
}

/// A plate with three round holes: a solid of genus 3 (Euler characteristic
/// of its surface: -4). Grid 48 x 24 x 16.
pub fn three_holes() -> ArrayVolume {
    ArrayVolume::from_fn([48, 24, 16], |x, y, z| {
        let (x, y, z) = (x as f64 - 23.5, y as f64 - 11.5, z as f64 - 7.5);
        // Inside the slab |x| < 20, |y| < 8, |z| < 4 ...
        let plate = (20.0 - x.abs()).min(8.0 - y.abs()).min(4.0 - z.abs());
        // ... and outside three cylinders of radius 3 along z.
        let holes = [-11.0, 0.0, 11.0]
            .iter()
            .map(|&cx| ((x - cx).powi(2) + y * y).sqrt() - 3.0)
            .fold(f64::INFINITY, f64::min);
        plate.min(holes)
    })
}

/// The gyroid `sin x cos y + sin y cos z + sin z cos x` with `periods` periods
/// across the grid.
pub fn gyroid(n: usize, periods: f64) -> ArrayVolume {
    let k = periods * std::f64::consts::TAU / (n as f64 - 1.0);
    ArrayVolume::from_fn([n; 3], |x, y, z| {
        let (x, y, z) = (x as f64 * k, y as f64 * k, z as f64 * k);
        x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
    })
}

/// Deterministic uniform noise in [-1, 1), smoothed by `passes` 3x3x3 box
/// filters (0 passes: raw noise, every cell a coin toss).
pub fn noise(n: usize, seed: u64, passes: usize) -> ArrayVolume {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let mut v: Vec<f64> = (0..n * n * n).map(|_| next()).collect();
    for _ in 0..passes {
        v = box_filter(&v, n);
    }
    ArrayVolume::new(crate::Grid::unit([n; 3]), v).expect("sizes match")
}

fn box_filter(v: &[f64], n: usize) -> Vec<f64> {
    let at = |x: isize, y: isize, z: isize| {
        let c = |i: isize| i.clamp(0, n as isize - 1) as usize;
        v[c(x) + n * (c(y) + n * c(z))]
    };
    let mut out = vec![0.0; v.len()];
    for z in 0..n as isize {
        for y in 0..n as isize {
            for x in 0..n as isize {
                let mut s = 0.0;
                for dz in -1..=1 {
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            s += at(x + dx, y + dy, z + dz);
                        }
                    }
                }
                out[x as usize + n * (y as usize + n * z as usize)] = s / 27.0;
            }
        }
    }
    out
}
