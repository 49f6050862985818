//! An in-memory volume, for tests and for callers that already hold samples.
//!
//! The samples keep their own type (`u8` ... `f64`): a caller holding a
//! 16-bit CT in memory does not need a four times larger `f64` copy; each
//! plane is converted when the slab loop reads it.

use super::{Grid, LentPlane, SampleSource};
use crate::{Error, Result};

/// A sample type an [`ArrayVolume`] can hold; every one converts to `f64`
/// exactly.
pub trait Sample: Copy + Send + Sync + 'static {
    /// The value as an `f64`.
    fn to_f64(self) -> f64;
    /// Samples of this type as a [`LentPlane`].
    fn lend(samples: &[Self]) -> LentPlane<'_>;
}

macro_rules! exact_sample {
    ($($t:ty => $v:ident),*) => {$(
        impl Sample for $t {
            #[inline]
            fn to_f64(self) -> f64 {
                f64::from(self)
            }
            fn lend(samples: &[Self]) -> LentPlane<'_> {
                LentPlane::$v(samples)
            }
        }
    )*};
}
exact_sample!(u8 => U8, i8 => I8, u16 => U16, i16 => I16, u32 => U32, i32 => I32, f32 => F32, f64 => F64);

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
