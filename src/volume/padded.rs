//! A one-sample border of "outside" around a volume, for `--close`.
//!
//! When the inner source lends its planes (a memory-mapped file), the
//! padded planes are lent too, as [`PlaneView`]s that read the inner plane
//! in place and supply the border on the fly: `--close` then holds no
//! plane of samples, as a run without it does not (before, each padded
//! plane was read into `f64`s, 8 bytes per sample, with the inner plane
//! copied on the way: some 1.5 GiB per worker for planes of 8192 x 8192).
//! When the inner source shares decoded planes instead (Zarr, HDF5,
//! compressed TIFF, DICOM), the padded plane is shared too: the inner
//! plane with a border ([`SharedPlane::border`]), lent as a view of it.

use super::{Access, Grid, LentPlane, PlaneView, SampleSource, SharedPlane};
use crate::{Error, Result};
use std::ops::Range;
use std::sync::OnceLock;

/// Wraps a source with one plane/row/column of NaN samples on every side.
/// NaN counts as outside (a tie at the isovalue), so every surface closes one
/// sample beyond the volume, with the topology of the surface cut off at the
/// volume's border.
pub struct Padded<'a> {
    inner: &'a dyn SampleSource,
    grid: Grid,
    /// One slot per padded plane, filled when it is first lent: the view
    /// of the inner plane (none for the two border planes), or `None` when
    /// the inner source does not lend that plane.
    views: Vec<OnceLock<Option<PaddedPlane<'a>>>>,
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
        let views = (0..grid.dims[2]).map(|_| OnceLock::new()).collect();
        Padded { inner, grid, views }
    }
}

/// A padded plane read from the inner source's lent plane (`inner`, of
/// `nx` by `ny` samples), NaN on the border; all NaN without `inner`.
#[derive(Debug)]
struct PaddedPlane<'a> {
    inner: Option<LentPlane<'a>>,
    nx: usize,
    ny: usize,
}

impl PlaneView for PaddedPlane<'_> {
    fn len(&self) -> usize {
        (self.nx + 2) * (self.ny + 2)
    }

    fn get(&self, i: usize) -> f64 {
        let wide = self.nx + 2;
        let (x, y) = ((i % wide).wrapping_sub(1), (i / wide).wrapping_sub(1));
        match self.inner {
            Some(inner) if x < self.nx && y < self.ny => inner.get(y * self.nx + x),
            _ => f64::NAN,
        }
    }

    fn rows(&self, first: usize, row: usize, out: &mut [f64]) {
        let nx = self.nx;
        for (y, out) in (first..).zip(out.chunks_exact_mut(row)) {
            out.fill(f64::NAN);
            let (Some(inner), Some(y)) = (self.inner, y.checked_sub(1)) else {
                continue;
            };
            if y < self.ny {
                inner.get_range(y * nx, &mut out[1..=nx]);
            }
        }
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

    /// The inner source's: its planes are lent or shared with the border
    /// supplied on the fly.
    fn plane_memory(&self) -> super::PlaneMemory {
        self.inner.plane_memory()
    }

    fn interrupted(&self) -> bool {
        self.inner.interrupted()
    }

    /// Reads the inner plane into the start of `out`, then spreads its
    /// rows to their padded places (last row first: a row never moves
    /// back) and fills the border with NaN.
    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        if out.len() != self.grid.plane_len() {
            return Err(Error::Invalid(format!(
                "plane buffer holds {} samples, a plane has {}",
                out.len(),
                self.grid.plane_len()
            )));
        }
        if z == 0 || z == self.grid.dims[2] - 1 {
            out.fill(f64::NAN);
            return Ok(());
        }
        let [nx, ny, _] = self.inner.grid().dims;
        self.inner.read_plane(z - 1, &mut out[..nx * ny])?;
        let wide = self.grid.dims[0];
        for y in (0..ny).rev() {
            let row = (y + 1) * wide + 1;
            out.copy_within(y * nx..(y + 1) * nx, row);
            out[row - 1] = f64::NAN;
            out[row + nx] = f64::NAN;
        }
        // The first and last rows are border.
        out[..wide].fill(f64::NAN);
        out[(ny + 1) * wide..].fill(f64::NAN);
        Ok(())
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        let inner: &dyn SampleSource = self.inner;
        let [nx, ny, nz] = inner.grid().dims;
        let view = self.views.get(z)?.get_or_init(|| {
            let lent = match z.checked_sub(1) {
                Some(k) if k < nz => Some(inner.lend_plane(k).filter(|p| p.len() == nx * ny)?),
                _ => None,
            };
            Some(PaddedPlane {
                inner: lent,
                nx,
                ny,
            })
        });
        view.as_ref().map(|v| LentPlane::View(v))
    }

    /// The inner source's shared plane with a border of NaN; `None` for
    /// the two border planes (lent as views of NaN) and when the inner
    /// source does not share the plane.
    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        let [nx, ny, nz] = self.inner.grid().dims;
        let k = z.checked_sub(1).filter(|&k| k < nz)?;
        let plane = self.inner.share_plane(k)?;
        // A plane bordered twice cannot be told apart: read it instead.
        if plane.border.is_some() {
            return None;
        }
        Some(SharedPlane {
            border: Some([nx, ny]),
            ..plane
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::ArrayVolume;

    /// Every padded plane, lent as a view (sample by sample and row by
    /// row) and read, next to the samples placed by hand.
    #[test]
    fn lent_views_and_read_planes_hold_the_padded_samples() {
        let (nx, ny, nz) = (3, 2, 2);
        let value = |x: usize, y: usize, z: usize| (100 * z + 10 * y + x) as f64;
        let inner = ArrayVolume::from_fn([nx, ny, nz], value);
        let padded = Padded::new(&inner);
        let [wide, high, deep] = padded.grid().dims;
        assert_eq!([wide, high, deep], [5, 4, 4]);
        for z in 0..deep {
            let want: Vec<f64> = (0..wide * high)
                .map(|i| {
                    let (x, y) = (i % wide, i / wide);
                    let inside = (1..=nx).contains(&x) && (1..=ny).contains(&y);
                    match inside && (1..=nz).contains(&z) {
                        true => value(x - 1, y - 1, z - 1),
                        false => f64::NAN,
                    }
                })
                .collect();
            let same = |got: &[f64]| {
                got.iter()
                    .zip(&want)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            };
            let mut read = vec![0.0; wide * high];
            padded.read_plane(z, &mut read).unwrap();
            assert!(same(&read), "plane {z} read: {read:?}");
            let Some(LentPlane::View(view)) = padded.lend_plane(z) else {
                panic!("plane {z} not lent as a view");
            };
            assert_eq!(view.len(), want.len());
            let got: Vec<f64> = (0..want.len()).map(|i| view.get(i)).collect();
            assert!(same(&got), "plane {z} lent: {got:?}");
            let mut rows = vec![0.0; 2 * wide];
            view.rows(1, wide, &mut rows);
            let one_and_two: Vec<f64> = want[wide..3 * wide].to_vec();
            assert!(
                rows.iter()
                    .zip(&one_and_two)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "plane {z} rows 1-2: {rows:?}"
            );
        }
    }
}
