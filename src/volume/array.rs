//! An in-memory volume, for tests and for callers that already hold samples.
//!
//! The samples keep their own type (`u8` ... `f64`): a caller holding a
//! 16-bit CT in memory does not need a four times larger `f64` copy; each
//! plane is converted when the slab loop reads it.

use super::sample::Sample;
use super::{Grid, LentPlane, SampleSource};
use crate::{Error, Result};

/// Samples held in memory, x fastest, then y, then z.
#[derive(Debug, Clone)]
pub struct ArrayVolume<T = f64> {
    grid: Grid,
    data: Vec<T>,
}

impl<T: Sample> ArrayVolume<T> {
    /// Wraps `data` (length `dims[0] * dims[1] * dims[2]`) on `grid`.
    pub fn new(grid: Grid, data: Vec<T>) -> Result<Self> {
        let expected = grid.dims.iter().product::<usize>();
        if data.len() != expected {
            return Err(Error::Invalid(format!(
                "volume has {} samples, dims {:?} need {}",
                data.len(),
                grid.dims,
                expected
            )));
        }
        Ok(ArrayVolume { grid, data })
    }

    /// The samples, x fastest.
    pub fn data(&self) -> &[T] {
        &self.data
    }
}

impl ArrayVolume<f64> {
    /// Builds a volume with unit spacing by evaluating `f(x, y, z)` at every sample.
    pub fn from_fn(dims: [usize; 3], mut f: impl FnMut(usize, usize, usize) -> f64) -> Self {
        let mut data = Vec::with_capacity(dims.iter().product());
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    data.push(f(x, y, z));
                }
            }
        }
        ArrayVolume {
            grid: Grid::unit(dims),
            data,
        }
    }
}

impl<T: Sample> SampleSource for ArrayVolume<T> {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let n = self.grid.plane_len();
        for (o, v) in out.iter_mut().zip(&self.data[z * n..(z + 1) * n]) {
            *o = v.to_f64();
        }
        Ok(())
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        let n = self.grid.plane_len();
        self.data.get(z * n..(z + 1) * n).map(T::lend)
    }

    fn sample_bytes(&self) -> usize {
        std::mem::size_of::<T>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_subtraction_is_claimed_only_where_it_holds() {
        use crate::kernel::wide::subtraction_residual;
        let exact = |v: f64, iso: f64| subtraction_residual(v, iso, v - iso) == 0.0;
        let isos = [
            0.0,
            500.0,
            -3.5,
            127.5,
            0.25,
            1.0 / 3.0,
            0.1,
            1e-300,
            (1u64 << 40) as f64 + 0.5,
            4e15,
            2f64.powi(-30),
            // MIN - iso rounds while the bound rounds down to 2^53 (i32,
            // i16, i8): a review found them claimed exact.
            2f64.powi(-22),
            2f64.powi(-38),
            2f64.powi(-46),
        ];
        let mut claimed = 0;
        for iso in isos {
            // Every value of the 8- and 16-bit types, the ends and a
            // stride of the 32-bit ones.
            let check = |claim: bool, values: &mut dyn Iterator<Item = f64>| {
                if claim {
                    for v in values {
                        assert!(exact(v, iso), "{v} - {iso} claimed exact");
                    }
                }
                usize::from(claim)
            };
            claimed += check(u8::subtracts_exactly(iso), &mut (0..=255).map(f64::from));
            claimed += check(i8::subtracts_exactly(iso), &mut (-128..=127).map(f64::from));
            claimed += check(u16::subtracts_exactly(iso), &mut (0..=65535).map(f64::from));
            claimed += check(
                i16::subtracts_exactly(iso),
                &mut (-32768..=32767).map(f64::from),
            );
            let wide = |min: f64, max: f64| {
                (0..=4096).map(move |k| min + (max - min) * f64::from(k) / 4096.0)
            };
            let (u, i) = (u32::MAX as f64, i32::MIN as f64);
            claimed += check(
                u32::subtracts_exactly(iso),
                &mut wide(0.0, u).map(f64::floor),
            );
            claimed += check(
                i32::subtracts_exactly(iso),
                &mut wide(i, -i - 1.0).map(f64::floor),
            );
        }
        // Integers and half-integers at any integer type, quarters too.
        for t in [500.0, -3.5, 127.5, 0.25] {
            assert!(u8::subtracts_exactly(t) && i32::subtracts_exactly(t), "{t}");
        }
        for t in [1.0 / 3.0, 0.1, 1e-300] {
            assert!(
                !u8::subtracts_exactly(t) && !f32::subtracts_exactly(t),
                "{t}"
            );
        }
        assert!(f32::subtracts_exactly(0.0) && f64::subtracts_exactly(0.0));
        assert!(claimed > 20, "{claimed}");
    }

    #[test]
    fn narrow_samples_read_as_their_f64_values() {
        let grid = Grid::unit([3, 2, 2]);
        let wide: Vec<f64> = (0..12).map(|i| f64::from(i * 5000)).collect();
        let narrow: Vec<u16> = (0..12).map(|i| i * 5000).collect();
        let (a, b) = (
            ArrayVolume::new(grid, wide).unwrap(),
            ArrayVolume::new(grid, narrow).unwrap(),
        );
        assert_eq!(b.sample_bytes(), 2);
        let (mut pa, mut pb) = (vec![0.0; 6], vec![1.0; 6]);
        for z in 0..2 {
            a.read_plane(z, &mut pa).unwrap();
            b.read_plane(z, &mut pb).unwrap();
            assert_eq!(pa, pb);
        }
        assert!(ArrayVolume::new(grid, vec![0f32; 11]).is_err());
    }
}
