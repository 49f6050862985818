//! Smooth value noise computed pointwise: hashed lattice values, interpolated
//! with a quintic fade, summed over octaves; and the hash itself, also used
//! for white noise.

use super::row_field::RowField;
use crate::Grid;

/// Lattice periods (in samples) and weights of the octaves.
const OCTAVES: [(usize, f64); 3] = [(32, 1.0), (16, 0.5), (8, 0.25)];

/// Hashes a seed and three integer coordinates to a uniform number in
/// `[-1, 1)` (a SplitMix64 finalizer over a mix of the inputs; the
/// constant keeps the all-zero input off the finalizer's fixed point 0).
pub(crate) fn hash3(seed: u64, x: u64, y: u64, z: u64) -> f64 {
    let mut h = (seed ^ 0x2545_F491_4F6C_DD1D)
        ^ x.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ y.wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ z.wrapping_mul(0x1656_67B1_9E37_79F9);
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^= h >> 31;
    (h >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
}

/// The quintic fade `6t^5 - 15t^4 + 10t^3` (C2 at the lattice points).
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The lattice cell of sample `n` at `period` and the faded position in it.
fn cell(n: usize, period: usize) -> (usize, f64) {
    (n / period, fade((n % period) as f64 / period as f64))
}

/// One octave: its period, weight, seed, where its lattice plane goes in
/// the plane cache, and the faded positions in a lattice cell.
struct Octave {
    period: usize,
    weight: f64,
    seed: u64,
    /// Lattice points along x and y that cover the grid.
    lattice: [usize; 2],
    /// Start of this octave's lattice plane in the plane cache.
    offset: usize,
    /// `fade(k / period)` for `k` in `0..period`.
    fades: Vec<f64>,
}

/// Value noise in `[-1, 1]` on the sample indices (spacing plays no part).
///
/// Per plane, each octave's lattice values are interpolated along z once
/// (the plane cache); a row then interpolates two lattice rows along y and
/// the result along x, so a sample costs a few multiply-adds per octave.
pub(crate) struct ValueNoise {
    octaves: Vec<Octave>,
    cache_len: usize,
}

impl ValueNoise {
    /// The noise of `seed` on `grid`.
    pub(crate) fn new(grid: &Grid, seed: u64) -> ValueNoise {
        let [nx, ny, _] = grid.dims;
        let total: f64 = OCTAVES.iter().map(|o| o.1).sum();
        let mut offset = 0;
        let octaves = OCTAVES
            .iter()
            .enumerate()
            .map(|(i, &(period, weight))| {
                let fades = (0..period).map(|k| cell(k, period).1).collect();
                let lattice = [nx, ny].map(|n| (n - 1) / period + 2);
                let octave = Octave {
                    period,
                    weight: weight / total,
                    seed: seed
                        .wrapping_add(i as u64 + 1)
                        .wrapping_mul(0xD1B5_4A32_D192_ED03),
                    lattice,
                    offset,
                    fades,
                };
                offset += lattice[0] * lattice[1];
                octave
            })
            .collect();
        ValueNoise {
            octaves,
            cache_len: offset,
        }
    }
}

impl RowField for ValueNoise {
    /// Each octave's weighted lattice values interpolated to plane `z`, x
    /// fastest.
    fn plane(&self, z: usize) -> Vec<f64> {
        let mut cache = Vec::with_capacity(self.cache_len);
        for o in &self.octaves {
            let (cz, tz) = cell(z, o.period);
            let cz = cz as u64;
            for cy in 0..o.lattice[1] as u64 {
                for cx in 0..o.lattice[0] as u64 {
                    let near = hash3(o.seed, cx, cy, cz);
                    let far = hash3(o.seed, cx, cy, cz + 1);
                    cache.push((near + (far - near) * tz) * o.weight);
                }
            }
        }
        cache
    }

    fn row(&self, plane: &[f64], y: usize, _z: usize, out: &mut [f64]) {
        out.fill(0.0);
        let mut line = Vec::new();
        for o in &self.octaves {
            let (cy, ty) = cell(y, o.period);
            let width = o.lattice[0];
            let near = &plane[o.offset + cy * width..][..width];
            let far = &plane[o.offset + (cy + 1) * width..][..width];
            // The noise along the row's lattice line, at every lattice x.
            line.clear();
            line.extend(near.iter().zip(far).map(|(a, b)| a + (b - a) * ty));
            // Lattice cell `c` covers the samples `c * period..`.
            for (run, ab) in out.chunks_mut(o.period).zip(line.windows(2)) {
                let (a, d) = (ab[0], ab[1] - ab[0]);
                for (out, &t) in run.iter_mut().zip(&o.fades) {
                    *out += a + d * t;
                }
            }
        }
    }
}
