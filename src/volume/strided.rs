//! [`StridedVolume`]: samples at any byte strides, in memory or in a mapped
//! file, read without a copy of the volume.
//!
//! This is how an array that a program already holds reaches the pipeline:
//! a numpy array in C or Fortran order, a sliced or reversed view (negative
//! strides), a broadcast one (zero strides), or a `numpy.memmap` of a file
//! larger than memory. A plane stored contiguously in native byte order is
//! lent as it is (see [`LentPlane`]), as [`super::RawVolume`] does; any
//! other plane is lent as a view ([`StridedPlane`]) that gathers the rows
//! the slab loop asks for, a band at a time, so that no plane is copied
//! whole into `f64`s (8 bytes a sample, two planes a worker).

use super::mapped::MappedFile;
use super::scalar::AsF64;
use super::scalar::{decode_strided, for_each_scalar};
use super::{Access, Endian, Grid, LentPlane, PlaneView, SampleSource, ScalarType};
use crate::{Error, Result};
use std::ops::Range;
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// Where the samples of a [`StridedVolume`] lie in its bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StridedLayout {
    /// Stored sample type.
    pub scalar: ScalarType,
    /// Byte order of the stored samples.
    pub endian: Endian,
    /// Byte offset of sample `(0, 0, 0)`.
    pub first: usize,
    /// Bytes from a sample to its neighbour along x, y and z: any value,
    /// negative (a reversed view) or zero (a broadcast axis) included.
    pub strides: [isize; 3],
}

/// The bytes behind a [`StridedVolume`] (shared with its plane views).
#[derive(Clone)]
enum Bytes<'a> {
    /// Memory the caller owns and keeps unchanged while the volume lives.
    Borrowed(&'a [u8]),
    /// A file mapped by the volume itself.
    Mapped(Arc<MappedFile>),
}

impl Bytes<'_> {
    fn get(&self) -> &[u8] {
        match self {
            Bytes::Borrowed(bytes) => bytes,
            Bytes::Mapped(map) => map.bytes(),
        }
    }
}

impl std::fmt::Debug for Bytes<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Bytes::Borrowed(b) => write!(f, "Borrowed({} bytes)", b.len()),
            Bytes::Mapped(map) => write!(f, "Mapped({})", map.path().display()),
        }
    }
}

/// A plane whose samples are not stored contiguously, lent as a
/// [`LentPlane::View`]: its rows are gathered from the strided bytes when
/// the slab loop reads them.
#[derive(Debug)]
struct StridedPlane<'a> {
    bytes: Bytes<'a>,
    layout: StridedLayout,
    nx: usize,
    ny: usize,
    z: usize,
}

impl PlaneView for StridedPlane<'_> {
    fn len(&self) -> usize {
        self.nx * self.ny
    }

    fn get(&self, i: usize) -> f64 {
        let mut v = [f64::NAN];
        self.range(i, &mut v);
        v[0]
    }

    fn range(&self, start: usize, out: &mut [f64]) {
        let (mut i, mut out) = (start, out);
        while !out.is_empty() {
            let (x, y) = (i % self.nx, i / self.nx);
            let n = (self.nx - x).min(out.len());
            let (row, rest) = out.split_at_mut(n);
            gather(self.bytes.get(), &self.layout, [x, y, self.z], row);
            (i, out) = (i + n, rest);
        }
    }
}

/// Byte offset of sample `(x, y, z)` of `layout`.
fn offset_of(layout: &StridedLayout, [x, y, z]: [usize; 3]) -> usize {
    let [sx, sy, sz] = layout.strides;
    let at = layout.first as isize + x as isize * sx + y as isize * sy + z as isize * sz;
    at as usize
}

/// Reads `out.len()` samples along x from `(x, y, z)` of `layout` in
/// `bytes` into `out`, in index order.
fn gather(bytes: &[u8], layout: &StridedLayout, [x, y, z]: [usize; 3], out: &mut [f64]) {
    let StridedLayout {
        scalar,
        endian,
        strides,
        ..
    } = *layout;
    if out.is_empty() {
        return;
    }
    if strides[0] >= 0 {
        let at = offset_of(layout, [x, y, z]);
        decode_strided(scalar, endian, bytes, at, strides[0] as usize, out);
    } else {
        // A reversed axis: read forward from the last sample, then put the
        // row back in index order.
        let at = offset_of(layout, [x + out.len() - 1, y, z]);
        decode_strided(scalar, endian, bytes, at, strides[0].unsigned_abs(), out);
        out.reverse();
    }
}

/// Samples of one scalar type at arbitrary byte strides (see the module
/// docs). Invariant: every sample of the grid lies inside the bytes,
/// checked once at construction.
pub struct StridedVolume<'a> {
    grid: Grid,
    layout: StridedLayout,
    bytes: Bytes<'a>,
    /// One slot per plane, filled when a plane that is not lent as it is
    /// is first lent as a view.
    views: Vec<OnceLock<StridedPlane<'a>>>,
}

impl<'a> StridedVolume<'a> {
    /// Samples of `grid` in memory the caller owns, laid out as `layout`
    /// says. Fails if a sample would lie outside `bytes`.
    pub fn borrowed(grid: Grid, layout: StridedLayout, bytes: &'a [u8]) -> Result<Self> {
        check_extent(&grid, &layout, bytes.len()).map_err(Error::Invalid)?;
        Ok(StridedVolume::new(grid, layout, Bytes::Borrowed(bytes)))
    }
}

impl StridedVolume<'_> {
    /// Samples of `grid` in the file at `path`, which the volume maps
    /// itself (`layout.first` is a byte offset into the file). Pages of
    /// planes the slab loop is done with are dropped from the map, so that
    /// resident memory stays bounded for files larger than memory when z is
    /// the slowest axis in the file.
    pub fn map_file<'a>(
        path: &Path,
        grid: Grid,
        layout: StridedLayout,
    ) -> Result<StridedVolume<'a>> {
        let map = MappedFile::open(path)?;
        check_extent(&grid, &layout, map.bytes().len())
            .map_err(|e| Error::Format(format!("{}: {e}", path.display())))?;
        Ok(StridedVolume::new(
            grid,
            layout,
            Bytes::Mapped(Arc::new(map)),
        ))
    }
}

impl<'a> StridedVolume<'a> {
    /// The volume over `bytes`, whose extent the caller has checked.
    fn new(grid: Grid, layout: StridedLayout, bytes: Bytes<'a>) -> Self {
        let views = (0..grid.dims[2]).map(|_| OnceLock::new()).collect();
        StridedVolume {
            grid,
            layout,
            bytes,
            views,
        }
    }
}

impl StridedVolume<'_> {
    /// The largest of the samples at `corner` and, along each axis `a`
    /// where `span[a]` is true, at `corner + 1` (none beyond the grid): the
    /// corners of a cell, a face, an edge or one sample. NaN samples are
    /// ignored; `None` outside the grid or when every one is NaN.
    pub fn cell_max(&self, corner: [usize; 3], span: [bool; 3]) -> Option<f64> {
        let mut most = f64::NAN;
        self.for_each_max(std::iter::once((corner, span)), |m| most = m);
        (!most.is_nan()).then_some(most)
    }

    /// [`StridedVolume::cell_max`] of each `(corner, span)` of `elements`,
    /// as f32 (NaN for `None`), appended to `out`: one look at the sample
    /// type and byte order for all of them, so that the loop over the
    /// elements is compiled for each type (the Python package's per-vertex
    /// values, hundreds of thousands per call).
    pub fn push_element_maxima<I>(&self, elements: I, out: &mut Vec<f32>)
    where
        I: Iterator<Item = ([usize; 3], [bool; 3])>,
    {
        out.reserve(elements.size_hint().0);
        self.for_each_max(elements, |m| out.push(m as f32));
    }

    /// Calls `emit` with the largest sample (NaN for none) of each element,
    /// in order, through a loop compiled for the volume's sample type and
    /// byte order.
    fn for_each_max<I, E>(&self, elements: I, emit: E)
    where
        I: Iterator<Item = ([usize; 3], [bool; 3])>,
        E: FnMut(f64),
    {
        macro_rules! run {
            ($t:ty) => {
                match self.layout.endian {
                    Endian::Little => self.maxima(elements, emit, <$t>::from_le_bytes),
                    Endian::Big => self.maxima(elements, emit, <$t>::from_be_bytes),
                }
            };
        }
        for_each_scalar!(self.layout.scalar, run)
    }

    /// [`StridedVolume::for_each_max`] for samples of `N` bytes that
    /// `decode` turns into a value.
    fn maxima<I, E, D, T, const N: usize>(&self, elements: I, mut emit: E, decode: D)
    where
        I: Iterator<Item = ([usize; 3], [bool; 3])>,
        E: FnMut(f64),
        // A function item, not a pointer: one type per function, so the
        // call is inlined rather than made through a pointer per sample.
        D: Fn([u8; N]) -> T,
        T: AsF64,
    {
        let [nx, ny, nz] = self.grid.dims;
        let bytes = self.bytes();
        let [sx, sy, sz] = self.layout.strides;
        let sample = |at: isize| -> f64 {
            let at = at as usize;
            let raw: [u8; N] = bytes[at..at + N].try_into().expect("N bytes");
            decode(raw).as_f64()
        };
        // Straight-line code per axis: this runs once per vertex of a mesh.
        for ([x, y, z], [span_x, span_y, span_z]) in elements {
            if x >= nx || y >= ny || z >= nz {
                emit(f64::NAN);
                continue;
            }
            // The stride to the element's next sample along each axis, 0
            // where it does not span (reading a sample twice changes no
            // maximum).
            let dx = if span_x && x + 1 < nx { sx } else { 0 };
            let dy = if span_y && y + 1 < ny { sy } else { 0 };
            let dz = if span_z && z + 1 < nz { sz } else { 0 };
            let base = self.offset(x, y, z) as isize;
            let spans = usize::from(dx != 0) + usize::from(dy != 0) + usize::from(dz != 0);
            let most = if spans <= 1 {
                // A sample or an edge (nearly every vertex): two reads.
                sample(base).max(sample(base + dx + dy + dz))
            } else {
                let mut most = f64::NAN;
                for row in [base, base + dy, base + dz, base + dy + dz] {
                    most = most.max(sample(row)).max(sample(row + dx));
                }
                most
            };
            emit(most);
        }
    }

    fn bytes(&self) -> &[u8] {
        self.bytes.get()
    }

    /// Byte offset of sample `(x, y, z)`; in range by the construction check.
    fn offset(&self, x: usize, y: usize, z: usize) -> usize {
        offset_of(&self.layout, [x, y, z])
    }

    /// Is plane `z` one run of packed samples, x fastest?
    fn plane_is_packed(&self) -> bool {
        let size = self.layout.scalar.size() as isize;
        let [nx, ny, _] = self.grid.dims;
        let [sx, sy, _] = self.layout.strides;
        (sx == size || nx == 1) && (sy == size * nx as isize || ny == 1)
    }
}

/// Checks that every sample of `grid` lies inside `len` bytes, without
/// overflow; the error says which bytes the layout needs.
fn check_extent(
    grid: &Grid,
    layout: &StridedLayout,
    len: usize,
) -> std::result::Result<(), String> {
    if grid.dims.contains(&0) {
        return Err(format!("dims {:?} contain a zero", grid.dims));
    }
    let size = layout.scalar.size() as i128;
    let (mut low, mut high) = (layout.first as i128, layout.first as i128 + size);
    for (n, s) in grid.dims.iter().zip(layout.strides) {
        let span = (*n as i128 - 1) * s as i128;
        if span < 0 {
            low += span;
        } else {
            high += span;
        }
    }
    if low < 0 || high > len as i128 {
        return Err(format!(
            "samples at strides {:?} from byte {} need bytes {low}..{high}, but there are {len}",
            layout.strides, layout.first
        ));
    }
    Ok(())
}

impl SampleSource for StridedVolume<'_> {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let [nx, ny, nz] = self.grid.dims;
        if z >= nz || out.len() != nx * ny {
            return Err(Error::Invalid(format!(
                "plane {z} of {nz} into {} samples: a plane has {}",
                out.len(),
                nx * ny
            )));
        }
        for (y, row) in out.chunks_exact_mut(nx).enumerate() {
            gather(self.bytes(), &self.layout, [0, y, z], row);
        }
        Ok(())
    }

    /// Lends planes stored packed, x fastest, in native byte order as they
    /// are; the others as views gathering their rows when they are read.
    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        if self.layout.endian != Endian::native() || !self.plane_is_packed() {
            let [nx, ny, _] = self.grid.dims;
            let view = self.views.get(z)?.get_or_init(|| StridedPlane {
                bytes: self.bytes.clone(),
                layout: self.layout,
                nx,
                ny,
                z,
            });
            return Some(LentPlane::View(view));
        }
        let start = self.offset(0, 0, z);
        let len = self.grid.plane_len() * self.layout.scalar.size();
        let bytes = self.bytes().get(start..start.checked_add(len)?)?;
        LentPlane::from_bytes(self.layout.scalar, bytes)
    }

    /// Passes the advice to the map when z is the slowest axis in the file
    /// (planes then occupy consecutive byte ranges).
    fn advise(&self, planes: Range<usize>, access: Access) {
        let Bytes::Mapped(map) = &self.bytes else {
            return;
        };
        let [sx, sy, sz] = self.layout.strides;
        let [nx, ny, _] = self.grid.dims;
        let plane_span = (nx as isize - 1) * sx + (ny as isize - 1) * sy;
        if sx < 0 || sy < 0 || sz <= plane_span || planes.is_empty() {
            return;
        }
        let start = self.offset(0, 0, planes.start);
        let end = self.offset(0, 0, planes.end - 1) + plane_span as usize;
        map.advise(start..end + self.layout.scalar.size(), access);
    }

    fn check_unchanged(&self) -> Result<()> {
        match &self.bytes {
            Bytes::Mapped(map) => map.check_unchanged(),
            Bytes::Borrowed(_) => Ok(()),
        }
    }

    fn data_files(&self) -> Vec<&Path> {
        match &self.bytes {
            Bytes::Mapped(map) => vec![map.path()],
            Bytes::Borrowed(_) => Vec::new(),
        }
    }

    fn sample_bytes(&self) -> usize {
        self.layout.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.layout.scalar)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::ArrayVolume;

    /// A small volume with distinct values, as `u16` samples x fastest.
    fn values(dims: [usize; 3]) -> Vec<u16> {
        (0..dims.iter().product::<usize>())
            .map(|i| (i * 37 % 1000) as u16)
            .collect()
    }

    fn planes(source: &dyn SampleSource) -> Vec<Vec<f64>> {
        let g = *source.grid();
        (0..g.dims[2])
            .map(|z| {
                let mut out = vec![0.0; g.plane_len()];
                source.read_plane(z, &mut out).unwrap();
                out
            })
            .collect()
    }

    #[test]
    fn every_layout_reads_the_same_samples() {
        let dims = [5, 4, 3];
        let [nx, ny, nz] = dims;
        let grid = Grid::unit(dims);
        let data = values(dims);
        let expected = planes(&ArrayVolume::new(grid, data.clone()).unwrap());
        let le = |v: &[u16]| v.iter().flat_map(|s| s.to_le_bytes()).collect::<Vec<u8>>();
        let be = |v: &[u16]| v.iter().flat_map(|s| s.to_be_bytes()).collect::<Vec<u8>>();
        // Fortran order: z fastest.
        let mut fortran = vec![0u16; data.len()];
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    fortran[z + nz * (y + ny * x)] = data[x + nx * (y + ny * z)];
                }
            }
        }
        let c = StridedLayout {
            scalar: ScalarType::U16,
            endian: Endian::Little,
            first: 0,
            strides: [2, 2 * nx as isize, 2 * (nx * ny) as isize],
        };
        let f = StridedLayout {
            strides: [2 * (nz * ny) as isize, 2 * nz as isize, 2],
            ..c
        };
        // Every axis reversed: the first sample is the last in memory.
        let reversed = StridedLayout {
            first: 2 * (data.len() - 1),
            strides: c.strides.map(|s| -s),
            ..c
        };
        let reversed_data: Vec<u16> = data.iter().rev().copied().collect();
        let big = StridedLayout {
            endian: Endian::Big,
            ..c
        };
        // The largest sample of each cell (fewer corners at the far faces).
        let cell_max = |x: usize, y: usize, z: usize, span: [bool; 3]| {
            let mut most = 0.0f64;
            for (dx, dy, dz) in (0..8).map(|c| (c & 1, c >> 1 & 1, c >> 2)) {
                if (dx == 1 && !span[0]) || (dy == 1 && !span[1]) || (dz == 1 && !span[2]) {
                    continue;
                }
                let (i, j, k) = (
                    (x + dx).min(nx - 1),
                    (y + dy).min(ny - 1),
                    (z + dz).min(nz - 1),
                );
                most = most.max(f64::from(data[i + nx * (j + ny * k)]));
            }
            most
        };
        for (layout, bytes) in [
            (c, le(&data)),
            (f, le(&fortran)),
            (reversed, le(&reversed_data)),
            (big, be(&data)),
        ] {
            let v = StridedVolume::borrowed(grid, layout, &bytes).unwrap();
            assert_eq!(planes(&v), expected, "{layout:?}");
            // Every plane is lent (as stored or as a view) with the samples
            // read_plane gives, one by one and in ranges across rows.
            for (z, want) in expected.iter().enumerate() {
                let lent = v.lend_plane(z).expect("every plane is lent");
                let one_by_one: Vec<f64> = (0..want.len()).map(|i| lent.get(i)).collect();
                assert_eq!(&one_by_one, want, "{layout:?} plane {z}");
                let mut ranged = vec![0.0; want.len() - 3];
                lent.get_range(2, &mut ranged);
                assert_eq!(ranged, want[2..want.len() - 1], "{layout:?} plane {z}");
            }
            for (x, y, z) in (0..nx * ny * nz).map(|i| (i % nx, i / nx % ny, i / (nx * ny))) {
                for span in [[true; 3], [false, true, false], [false; 3]] {
                    let expected = cell_max(x, y, z, span);
                    assert_eq!(v.cell_max([x, y, z], span), Some(expected), "{layout:?}");
                }
                let sample = f64::from(data[x + nx * (y + ny * z)]);
                assert_eq!(v.cell_max([x, y, z], [false; 3]), Some(sample));
            }
        }
        // The packed native layout is lent as stored; the others as views.
        let bytes = le(&data);
        let v = StridedVolume::borrowed(grid, c, &bytes).unwrap();
        let viewed = |p: Option<LentPlane>| matches!(p, Some(LentPlane::View(_)));
        assert_eq!(viewed(v.lend_plane(1)), cfg!(target_endian = "big"));
        let fbytes = le(&fortran);
        assert!(viewed(
            StridedVolume::borrowed(grid, f, &fbytes)
                .unwrap()
                .lend_plane(1)
        ));
    }

    #[test]
    fn zero_strides_repeat_a_sample() {
        let grid = Grid::unit([3, 2, 2]);
        let layout = StridedLayout {
            scalar: ScalarType::F32,
            endian: Endian::native(),
            first: 4,
            strides: [0, 0, 0],
        };
        let bytes: Vec<u8> = [1.0f32, 2.5].iter().flat_map(|v| v.to_ne_bytes()).collect();
        let v = StridedVolume::borrowed(grid, layout, &bytes).unwrap();
        assert!(planes(&v).iter().flatten().all(|&s| s == 2.5));
        assert_eq!(v.cell_max([2, 1, 1], [false; 3]), Some(2.5));
        assert_eq!(v.cell_max([3, 0, 0], [false; 3]), None);
        assert_eq!(v.cell_max([2, 1, 1], [true; 3]), Some(2.5));
        assert_eq!(v.cell_max([0, 2, 0], [true; 3]), None);
    }

    #[test]
    fn samples_outside_the_bytes_are_refused() {
        let grid = Grid::unit([4, 4, 4]);
        let layout = StridedLayout {
            scalar: ScalarType::U8,
            endian: Endian::Little,
            first: 0,
            strides: [1, 4, 16],
        };
        assert!(StridedVolume::borrowed(grid, layout, &[0; 64]).is_ok());
        let err = StridedVolume::borrowed(grid, layout, &[0; 63])
            .err()
            .unwrap();
        assert!(err.to_string().contains("need bytes 0..64"), "{err}");
        let backwards = StridedLayout {
            strides: [-1, 4, 16],
            ..layout
        };
        assert!(StridedVolume::borrowed(grid, backwards, &[0; 64]).is_err());
        let huge = StridedLayout {
            strides: [isize::MAX, 4, 16],
            ..layout
        };
        assert!(StridedVolume::borrowed(grid, huge, &[0; 64]).is_err());
    }

    #[test]
    fn a_mapped_file_gives_the_mesh_of_the_array() {
        let dims = [9, 8, 7];
        let grid = Grid::unit(dims);
        let data: Vec<f32> = (0..dims.iter().product::<usize>())
            .map(|i| {
                let (x, y, z) = (i % 9, i / 9 % 8, i / 72);
                let d = |a: usize, c: f32| (a as f32 - c).powi(2);
                d(x, 4.0) + d(y, 3.5) + d(z, 3.0)
            })
            .collect();
        let mut file = tempfile::NamedTempFile::new().unwrap();
        let header = [7u8; 12];
        let mut bytes = header.to_vec();
        bytes.extend(data.iter().flat_map(|v| v.to_le_bytes()));
        std::io::Write::write_all(&mut file, &bytes).unwrap();
        let layout = StridedLayout {
            scalar: ScalarType::F32,
            endian: Endian::Little,
            first: 12,
            strides: [4, 36, 288],
        };
        let mapped = StridedVolume::map_file(file.path(), grid, layout).unwrap();
        assert_eq!(mapped.data_files(), vec![file.path()]);
        let params = crate::ExtractParams {
            iso: 6.0,
            ..Default::default()
        };
        let (mesh, _) = crate::extract(&mapped, &params).unwrap();
        let array = ArrayVolume::new(grid, data).unwrap();
        let (expected, _) = crate::extract(&array, &params).unwrap();
        assert!(!mesh.triangles.is_empty());
        assert_eq!(mesh, expected);
        let short = StridedLayout {
            first: 13,
            ..layout
        };
        let err = StridedVolume::map_file(file.path(), grid, short)
            .err()
            .unwrap();
        assert!(err.to_string().contains("need bytes"), "{err}");
    }
}
