//! [`SharedPlane`]: a plane decoded into a buffer of its own type that the
//! slab holds while it is triangulated (see [`HeldPlanes`](super::HeldPlanes)).
//!
//! Sources that decode (chunked stores, compressed TIFF pages, DICOM
//! frames) share their planes this way instead of writing `f64`s: two to
//! eight times less memory per plane held, and the slab loop compares the
//! samples with the isovalue in their own type. A shared plane may also
//! carry what reading it as `f64`s would apply on the way, so that such a
//! plane is still lent rather than copied:
//!
//! * a linear rescale (DICOM's `RescaleSlope`/`RescaleIntercept`), each
//!   sample read as `stored * slope + intercept`, the same `f64`
//!   arithmetic as the source's `read_plane`;
//! * the NaN border of `--close` ([`Padded`](super::Padded)).
//!
//! Either makes the plane lent as a [`LentPlane::View`] of itself; with
//! neither it is lent in its own type.

use super::{LentPlane, PlaneView, ScalarType};
use std::ops::Range;
use std::sync::Arc;

/// A plane held in a shared buffer: a decoded layer of chunks (Zarr,
/// HDF5) that the source's cache may drop while the plane is still in use,
/// or a decoded page or frame, so the holder keeps the buffer alive (see
/// [`SampleSource::share_plane`](super::SampleSource::share_plane) and
/// [`HeldPlanes`](super::HeldPlanes)).
#[derive(Debug, Clone)]
pub struct SharedPlane {
    /// The buffer holding the plane, native byte order.
    pub data: Arc<Vec<u8>>,
    /// The plane's bytes in `data`, x fastest.
    pub bytes: Range<usize>,
    /// The type of its samples.
    pub scalar: ScalarType,
    /// `(slope, intercept)`: each sample reads as `stored * slope +
    /// intercept`; `None` for the stored values.
    pub rescale: Option<(f64, f64)>,
    /// `Some([nx, ny])` when the plane is read with a one-sample border of
    /// NaN around its `nx` by `ny` stored samples (`--close`).
    pub border: Option<[usize; 2]>,
}

impl SharedPlane {
    /// The samples of `bytes` in `data`, stored values, no border.
    pub fn new(data: Arc<Vec<u8>>, bytes: Range<usize>, scalar: ScalarType) -> Self {
        SharedPlane {
            data,
            bytes,
            scalar,
            rescale: None,
            border: None,
        }
    }

    /// The plane, lent in its own type, or as a view of itself when it is
    /// rescaled or bordered (`None` if its bytes do not hold the samples
    /// it should).
    pub fn lent(&self) -> Option<LentPlane<'_>> {
        let stored = self.stored()?;
        let expected = match self.border {
            Some([nx, ny]) => nx.checked_mul(ny)?,
            None => stored.len(),
        };
        if stored.len() != expected {
            return None;
        }
        match (self.rescale, self.border) {
            (None, None) => Some(stored),
            _ => Some(LentPlane::View(self)),
        }
    }

    /// The stored samples, in their type.
    fn stored(&self) -> Option<LentPlane<'_>> {
        LentPlane::from_bytes(self.scalar, self.data.get(self.bytes.clone())?)
    }

    /// `v` as read: rescaled if the plane is.
    #[inline(always)]
    fn value(&self, v: f64) -> f64 {
        match self.rescale {
            Some((slope, intercept)) => v * slope + intercept,
            None => v,
        }
    }
}

impl PlaneView for SharedPlane {
    fn len(&self) -> usize {
        match self.border {
            Some([nx, ny]) => (nx + 2) * (ny + 2),
            None => self.stored().map_or(0, |s| s.len()),
        }
    }

    fn get(&self, i: usize) -> f64 {
        let Some(stored) = self.stored() else {
            return f64::NAN;
        };
        let j = match self.border {
            None => i,
            Some([nx, ny]) => {
                let wide = nx + 2;
                let (x, y) = ((i % wide).wrapping_sub(1), (i / wide).wrapping_sub(1));
                if x >= nx || y >= ny {
                    return f64::NAN;
                }
                y * nx + x
            }
        };
        self.value(stored.get(j))
    }

    fn range(&self, start: usize, out: &mut [f64]) {
        let Some(stored) = self.stored() else {
            out.fill(f64::NAN);
            return;
        };
        match self.border {
            None => {
                stored.get_range(start, out);
                if self.rescale.is_some() {
                    for v in out.iter_mut() {
                        *v = self.value(*v);
                    }
                }
            }
            Some(_) => {
                for (i, v) in (start..).zip(out.iter_mut()) {
                    *v = self.get(i);
                }
            }
        }
    }

    fn rows(&self, first: usize, row: usize, out: &mut [f64]) {
        let (Some([nx, ny]), Some(stored)) = (self.border, self.stored()) else {
            return self.range(first * row, out);
        };
        for (y, out) in (first..).zip(out.chunks_exact_mut(row)) {
            out.fill(f64::NAN);
            if let Some(y) = y.checked_sub(1).filter(|&y| y < ny) {
                stored.get_range(y * nx, &mut out[1..=nx]);
            }
        }
        if self.rescale.is_some() {
            for v in out.iter_mut() {
                *v = self.value(*v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rescaled, bordered plane reads, sample by sample and row by row,
    /// as its stored samples rescaled inside a border of NaN; a plain one
    /// is lent in its own type.
    #[test]
    fn rescaled_and_bordered_planes_read_as_their_values() {
        let stored: Vec<i16> = vec![-1024, 0, 7, 3000, -5, 12];
        let bytes: Vec<u8> = stored.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let data = Arc::new(bytes);
        let plain = SharedPlane::new(data.clone(), 0..12, ScalarType::I16);
        assert!(matches!(plain.lent(), Some(LentPlane::I16(_))));
        let plane = SharedPlane {
            rescale: Some((0.5, -10.0)),
            border: Some([3, 2]),
            ..plain
        };
        let Some(LentPlane::View(view)) = plane.lent() else {
            panic!("not lent as a view");
        };
        let value = |x: usize, y: usize| f64::from(stored[y * 3 + x]) * 0.5 - 10.0;
        let want: Vec<f64> = (0..20)
            .map(|i| {
                let (x, y) = (i % 5, i / 5);
                match (1..=3).contains(&x) && (1..=2).contains(&y) {
                    true => value(x - 1, y - 1),
                    false => f64::NAN,
                }
            })
            .collect();
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
        assert_eq!(view.len(), 20);
        let got: Vec<f64> = (0..20).map(|i| view.get(i)).collect();
        assert!(same(&got, &want), "{got:?}");
        let mut rows = vec![0.0; 15];
        view.rows(1, 5, &mut rows);
        assert!(same(&rows, &want[5..20]), "{rows:?}");
        // A border that does not fit the bytes is not lent.
        let wrong = SharedPlane {
            border: Some([4, 2]),
            ..plane.clone()
        };
        assert!(wrong.lent().is_none());
    }
}
