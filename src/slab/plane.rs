//! [`Plane`]: one plane of samples relative to the isovalue, classified
//! into inside bits, with the numbers of its edge vertices (pass 1 of the
//! slab loop).

use super::bits::{each_bit, uniform_alike, x_crossings, RowKind, SignBits};
use super::block::{check_local_indices, VERTICES};
use super::edges::EdgeRows;
use super::level::Level;
use super::placement::Placement;
use super::spares::{PlaneBuffers, Scratch};
use crate::error::make_room;
use crate::grid::Grid;
use crate::params::ExtractParams;
use crate::volume::{LentPlane, PlaneView, Sample, SampleSource};
use crate::{Error, Result, Stats};
use std::time::Instant;

/// One plane of values relative to the isovalue, with the numbers of its
/// edge vertices; two of them are reused, plane after plane, by a slab.
///
/// The vertices of a plane's crossed edges are numbered in raster order,
/// x-edges first; only the number of each row's first vertex is kept (see
/// [`edges`](super::edges)).
pub(super) struct Plane<'s> {
    pub(super) z: usize,
    /// The samples as the source lends them, if it does; else `read`.
    pub(super) lent: Option<LentPlane<'s>>,
    /// The samples as read, when the source lends none.
    pub(super) read: Vec<f64>,
    pub(super) level: Level,
    /// Every sample's `rel` is exact (the sample type and the isovalue
    /// say so), so no cell needs residuals.
    pub(super) exact: bool,
    /// Every sample's `rel` is also the plain `(value - iso) * sign`:
    /// integer samples, so never NaN, and `exact`, so never clamped.
    pub(super) plain: bool,
    /// `plain`, of 8-bit samples and an integer isovalue: the `rel` of a
    /// sample is an integer, and in a cell of both signs at most 255 in
    /// magnitude (see [`crate::kernel::Known::SmallIntegers`]).
    pub(super) small: bool,
    /// `rel(sample) > 0` per sample.
    pub(super) inside: SignBits,
    /// Local index of the first x-edge vertex of each row.
    pub(super) x_first: Vec<u32>,
    /// Local index of the first vertex on the y-edges between rows `y` and
    /// `y + 1`.
    pub(super) y_first: Vec<u32>,
}

impl PlaneBuffers {
    /// New buffers for planes of `grid`.
    pub(super) fn new(grid: &Grid) -> Self {
        let [nx, ny, _] = grid.dims;
        PlaneBuffers {
            read: Vec::new(),
            inside: SignBits::new(nx, ny),
            x_first: vec![0; ny],
            y_first: vec![0; ny],
        }
    }
}

impl Scratch {
    /// New buffers for a slab of `grid`.
    pub(super) fn new(grid: &Grid) -> Self {
        Scratch {
            planes: [PlaneBuffers::new(grid), PlaneBuffers::new(grid)],
            dims: [grid.dims[0], grid.dims[1]],
            z_first: vec![0; grid.dims[1]],
            rows: EdgeRows::new(grid.dims[0]),
        }
    }
}

impl<'s> Plane<'s> {
    /// A plane working in `buffers` (sized for the grid; stale entries are
    /// never read).
    pub(super) fn new(buffers: PlaneBuffers) -> Self {
        let PlaneBuffers {
            read,
            inside,
            x_first,
            y_first,
        } = buffers;
        Plane {
            z: 0,
            lent: None,
            read,
            level: Level {
                iso: 0.0,
                sign: 1.0,
            },
            exact: true,
            plain: false,
            small: false,
            inside,
            x_first,
            y_first,
        }
    }

    /// The plane's buffers, for the next slab.
    pub(super) fn into_buffers(self) -> PlaneBuffers {
        PlaneBuffers {
            read: self.read,
            inside: self.inside,
            x_first: self.x_first,
            y_first: self.y_first,
        }
    }

    /// The kernel's value of sample `i` (see [`Level::rel`]).
    #[inline]
    pub(super) fn rel(&self, i: usize) -> f64 {
        rel_at(self.lent, &self.read, self.level, i)
    }

    /// The samples `at`, as `f64`s.
    #[inline(always)]
    pub(super) fn values<const N: usize>(&self, at: [usize; N]) -> [f64; N] {
        match &self.lent {
            Some(samples) => samples.get_many(at),
            None => at.map(|i| self.read[i]),
        }
    }

    /// Reads and classifies plane `z`; appends the positions of its edge
    /// vertices to `owned`.
    pub(super) fn load(
        &mut self,
        source: &'s dyn SampleSource,
        place: &Placement,
        params: &ExtractParams,
        z: usize,
        owned: &mut Vec<[f32; 3]>,
        stats: &mut Stats,
    ) -> Result<()> {
        let [nx, ny, _] = place.grid.dims;
        self.z = z;
        let start = Instant::now();
        self.lent = source.lend_plane(z).filter(|p| p.len() == nx * ny);
        if self.lent.is_none() {
            let missing = (nx * ny).saturating_sub(self.read.len());
            make_room(&mut self.read, missing, "a plane of samples")?;
            self.read.resize(nx * ny, 0.0);
            source.read_plane(z, &mut self.read)?;
        }
        stats.planes_read += 1;
        stats.read_seconds += start.elapsed().as_secs_f64();
        let level = Level::new(params);
        self.level = level;
        self.exact = match self.lent {
            Some(samples) => samples.subtracts_exactly(level.iso),
            None => level.iso == 0.0,
        };
        self.plain = self.exact && self.lent.is_some_and(|s| s.is_integer());
        self.small = self.plain
            && matches!(self.lent, Some(LentPlane::U8(_) | LentPlane::I8(_)))
            && level.iso.fract() == 0.0;
        match self.lent {
            None => classify_checked(&mut self.inside, &self.read, nx, level, source)?,
            Some(LentPlane::U8(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::I8(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::U16(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::I16(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::U32(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::I32(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::F32(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::F64(s)) => classify_checked(&mut self.inside, s, nx, level, source)?,
            Some(LentPlane::U16Bytes(s)) => {
                by_bands::<u16, 2, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::I16Bytes(s)) => {
                by_bands::<i16, 2, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::U32Bytes(s)) => {
                by_bands::<u32, 4, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::I32Bytes(s)) => {
                by_bands::<i32, 4, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::F32Bytes(s)) => {
                by_bands::<f32, 4, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::F64Bytes(s)) => {
                by_bands::<f64, 8, false>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::U16Swapped(s)) => {
                by_bands::<u16, 2, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::I16Swapped(s)) => {
                by_bands::<i16, 2, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::U32Swapped(s)) => {
                by_bands::<u32, 4, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::I32Swapped(s)) => {
                by_bands::<i32, 4, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::F32Swapped(s)) => {
                by_bands::<f32, 4, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::F64Swapped(s)) => {
                by_bands::<f64, 8, true>(&mut self.inside, s, nx, level, source)?
            }
            Some(LentPlane::View(v)) => by_view(&mut self.inside, v, nx, level, source)?,
        }
        if place.axis_aligned {
            self.edge_vertices::<true>(place, owned)?;
        } else {
            self.edge_vertices::<false>(place, owned)?;
        }
        check_local_indices(owned.len())
    }

    /// Appends the positions of the loaded plane's edge vertices to `owned`
    /// (x-edges, then y-edges, in raster order) and notes each row's first;
    /// `ALIGNED` is `place.axis_aligned`.
    fn edge_vertices<const ALIGNED: bool>(
        &mut self,
        place: &Placement,
        owned: &mut Vec<[f32; 3]>,
    ) -> Result<()> {
        let [nx, ny, _] = place.grid.dims;
        let (z, level) = (self.z, self.level);
        let (lent, read) = (self.lent, &self.read);
        let rel = |i: usize| rel_at(lent, read, level, i);
        let words = self.inside.words() - 1;
        // The plane's vertices open their block: local numbers start at 0.
        debug_assert!(owned.is_empty());
        for y in 0..ny {
            self.x_first[y] = owned.len() as u32;
            if self.inside.kind(y) != RowKind::Mixed {
                continue;
            }
            let row = self.inside.row(y);
            make_room(owned, nx, VERTICES)?;
            for k in 0..words {
                each_bit(x_crossings(row, k, nx), k, |x| {
                    let (a, b) = (rel(y * nx + x), rel(y * nx + x + 1));
                    owned.push(place.edge_in::<ALIGNED>(place.index(x, y, z), 0, a, b));
                    Ok::<(), Error>(())
                })?;
            }
        }
        for y in 0..ny - 1 {
            self.y_first[y] = owned.len() as u32;
            if uniform_alike([self.inside.kind(y), self.inside.kind(y + 1)]) {
                continue;
            }
            let (lower, upper) = (self.inside.row(y), self.inside.row(y + 1));
            make_room(owned, nx, VERTICES)?;
            for k in 0..words {
                each_bit(lower[k] ^ upper[k], k, |x| {
                    let (a, b) = (rel(y * nx + x), rel((y + 1) * nx + x));
                    owned.push(place.edge_in::<ALIGNED>(place.index(x, y, z), 1, a, b));
                    Ok::<(), Error>(())
                })?;
            }
        }
        Ok(())
    }
}

/// The kernel's value of sample `i` of a plane, lent or read.
#[inline(always)]
pub(super) fn rel_at(lent: Option<LentPlane>, read: &[f64], level: Level, i: usize) -> f64 {
    let value = match lent {
        Some(samples) => samples.get(i),
        None => read[i],
    };
    level.rel(value)
}

/// Bytes of samples [`by_bands`] copies at once (whole rows, at least
/// one).
const BAND_BYTES: usize = 64 << 10;

/// Classifies a plane lent as byte arrays (samples not aligned for their
/// type `T`, of `N` bytes, or in the other byte order if `SWAP`): a band of
/// rows at a time is copied into aligned samples (each one's bytes
/// reversed if `SWAP`) and classified as a lent plane of type `T` is (so
/// the bits are the same), the copy taking a few pages, not a plane.
fn by_bands<T: Sample + bytemuck::Pod, const N: usize, const SWAP: bool>(
    inside: &mut SignBits,
    plane: &[[u8; N]],
    nx: usize,
    level: Level,
    source: &dyn SampleSource,
) -> Result<()> {
    let ny = plane.len() / nx;
    let rows = (BAND_BYTES / (nx * N)).clamp(1, ny.max(1));
    let mut band = vec![T::zeroed(); rows * nx];
    for first in (0..ny).step_by(rows) {
        interrupted(first, source)?;
        let n = rows.min(ny - first);
        let band = &mut band[..n * nx];
        let bytes = &plane[first * nx..(first + n) * nx];
        let band_bytes = bytemuck::cast_slice_mut::<T, u8>(band);
        band_bytes.copy_from_slice(bytes.as_flattened());
        if SWAP {
            band_bytes.chunks_exact_mut(N).for_each(<[u8]>::reverse);
        }
        inside.classify_from(first, band, nx, level.iso, level.sign > 0.0);
    }
    Ok(())
}

/// Classifies a plane lent as a [`PlaneView`]: a band of rows at a time is
/// computed into `f64`s and classified as a plane read into `f64`s is (so
/// the bits are the same), the band taking a few pages, not a plane.
fn by_view(
    inside: &mut SignBits,
    view: &dyn PlaneView,
    nx: usize,
    level: Level,
    source: &dyn SampleSource,
) -> Result<()> {
    let ny = view.len() / nx;
    let rows = (BAND_BYTES / (nx * 8)).clamp(1, ny.max(1));
    let mut band = vec![0.0; rows * nx];
    for first in (0..ny).step_by(rows) {
        interrupted(first, source)?;
        let band = &mut band[..rows.min(ny - first) * nx];
        view.rows(first, nx, band);
        inside.classify_from(first, band, nx, level.iso, level.sign > 0.0);
    }
    Ok(())
}

/// Samples of a plane classified between two looks at whether the run
/// was interrupted: a plane of 10^10 samples (a broadcast array, a huge
/// raw file) takes minutes, and Ctrl-C must not wait for it. A plane of
/// a CT (512^2) is one band, classified as before.
const CHECK_SAMPLES: usize = 1 << 22;

/// [`SignBits::classify_from`] of a whole lent or read plane, in bands of about
/// [`CHECK_SAMPLES`] samples (the same bits), asking `source` whether the
/// run was interrupted before each band but the first.
fn classify_checked<T: Sample>(
    inside: &mut SignBits,
    samples: &[T],
    nx: usize,
    level: Level,
    source: &dyn SampleSource,
) -> Result<()> {
    let rows = (CHECK_SAMPLES / nx).max(1);
    for (k, band) in samples.chunks(rows * nx).enumerate() {
        interrupted(k * rows, source)?;
        inside.classify_from(k * rows, band, nx, level.iso, level.sign > 0.0);
    }
    Ok(())
}

/// [`Error::Interrupted`] when the run was interrupted, asked before the
/// bands of a plane after the first (row `first` > 0).
#[inline]
fn interrupted(first: usize, source: &dyn SampleSource) -> Result<()> {
    match first > 0 && source.interrupted() {
        true => Err(Error::Interrupted),
        false => Ok(()),
    }
}
