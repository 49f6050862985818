//! A one-sample border of "outside" around a volume, for `--close`.

use super::{Access, Grid, SampleSource};
use crate::error::try_filled;
use crate::Result;
use std::ops::Range;

/// Wraps a source with one plane/row/column of NaN samples on every side.
/// NaN counts as outside (a tie at the isovalue), so every surface closes one
/// sample beyond the volume, with the topology of the surface cut off at the
/// volume's border.
pub struct Padded<'a> {
    inner: &'a dyn SampleSource,
    grid: Grid,
}

impl<'a> Padded<'a> {
    /// Pads `inner`; the grid grows by two samples per axis and its origin
    /// moves one sample back along every index axis.
    pub fn new(inner: &'a dyn SampleSource) -> Self {
        let g = *inner.grid();
        let grid = Grid {
            dims: g.dims.map(|d| d + 2),
            origin: g.world([-1.0; 3]),
            ..g
        };
        Padded { inner, grid }
    }
}

impl SampleSource for Padded<'_> {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        let inner = self.inner.grid().dims[2];
        let start = planes.start.saturating_sub(1).min(inner);
        self.inner
            .advise(start..planes.end.saturating_sub(1).min(inner), access);
    }

    fn check_unchanged(&self) -> Result<()> {
        self.inner.check_unchanged()
    }

    fn interrupted(&self) -> bool {
        self.inner.interrupted()
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        out.fill(f64::NAN);
        if z == 0 || z == self.grid.dims[2] - 1 {
            return Ok(());
        }
        let [nx, ny, _] = self.inner.grid().dims;
        let mut plane = try_filled("a plane of samples", nx * ny, 0.0)?;
        self.inner.read_plane(z - 1, &mut plane)?;
        let wide = self.grid.dims[0];
        for y in 0..ny {
            let row = (y + 1) * wide + 1;
            out[row..row + nx].copy_from_slice(&plane[y * nx..(y + 1) * nx]);
        }
        Ok(())
    }

    fn sample_bytes(&self) -> usize {
        self.inner.sample_bytes()
    }

    fn stored_type(&self) -> Option<super::ScalarType> {
        self.inner.stored_type()
    }

    fn notes(&self) -> super::SourceNotes {
        self.inner.notes()
    }
}
