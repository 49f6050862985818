//! An in-memory volume, for tests and for callers that already hold samples.

use super::{Grid, SampleSource};
use crate::{Error, Result};

/// Samples held in memory, x fastest, then y, then z.
#[derive(Debug, Clone)]
pub struct ArrayVolume {
    grid: Grid,
    data: Vec<f64>,
}

impl ArrayVolume {
    /// Wraps `data` (length `dims[0] * dims[1] * dims[2]`) on `grid`.
    pub fn new(grid: Grid, data: Vec<f64>) -> Result<Self> {
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

    /// The samples, x fastest.
    pub fn data(&self) -> &[f64] {
        &self.data
    }
}

impl SampleSource for ArrayVolume {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let n = self.grid.plane_len();
        out.copy_from_slice(&self.data[z * n..(z + 1) * n]);
        Ok(())
    }
}
