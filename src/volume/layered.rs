//! [`LayeredVolume`]: a volume whose planes come a layer at a time from a
//! function the caller supplies, kept in the same shared cache as Zarr's
//! and HDF5's decoded chunk layers (`chunk_layers.rs`).
//!
//! The Python package reads a lazy array this way (a `dask.array`, an
//! `xarray.DataArray` backed by dask, a Zarr array in memory): each layer
//! is one slice of the array, computed by the array's own library, so the
//! array is never in memory whole. A Rust caller can use it for any
//! decoder of its own. The cache keeps a few layers (one per worker and
//! two more) and decodes each layer once per pass, whatever the workers'
//! order; the memory budget sees it as a decoded source
//! ([`PlaneMemory::Decoded`]).

use super::chunk_layers::ChunkLayers;
use super::{Grid, PlaneMemory, SampleSource, ScalarType, SharedPlane};
use crate::{Error, Result};
use std::ops::Range;

/// Reads a layer of planes of a [`LayeredVolume`].
pub trait LayerReader: Sync {
    /// The samples of planes `planes` (a range of whole planes within one
    /// layer), one buffer per plane, x fastest, in the volume's scalar type
    /// in native byte order: each buffer holds `grid.plane_len()` samples.
    /// It may be called from any worker thread, for any layer, and for the
    /// same layer again in a later pass; it must give the same samples each
    /// time.
    fn read_layer(&self, planes: Range<usize>) -> Result<Vec<Vec<u8>>>;
}

/// A volume read a layer of `depth` planes at a time through a
/// [`LayerReader`] (see the module documentation).
pub struct LayeredVolume<R> {
    grid: Grid,
    scalar: ScalarType,
    depth: usize,
    reader: R,
    layers: ChunkLayers,
}

impl<R: LayerReader> LayeredVolume<R> {
    /// A volume on `grid` of `scalar` samples read in layers of `depth`
    /// planes (the last may be thinner; a depth above the volume's planes
    /// reads it in one layer). An error for a depth of 0.
    pub fn new(grid: Grid, scalar: ScalarType, depth: usize, reader: R) -> Result<Self> {
        if depth == 0 {
            return Err(Error::Invalid(
                "a layered volume needs layers of at least one plane".into(),
            ));
        }
        let depth = depth.min(grid.dims[2].max(1));
        Ok(LayeredVolume {
            grid,
            scalar,
            depth,
            reader,
            layers: ChunkLayers::new(),
        })
    }

    /// The reader the planes come from.
    pub fn reader(&self) -> &R {
        &self.reader
    }

    /// Planes read at once.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Layer `k`, checked: as many planes as it spans, each a plane long.
    fn decode_layer(&self, k: usize) -> Result<Vec<Vec<u8>>> {
        let first = k * self.depth;
        let planes = first..(first + self.depth).min(self.grid.dims[2]);
        let expected = planes.len();
        let data = self.reader.read_layer(planes.clone())?;
        let bytes = self.grid.plane_len() * self.scalar.size();
        if data.len() != expected || data.iter().any(|plane| plane.len() != bytes) {
            return Err(Error::Invalid(format!(
                "planes {}..{} were read as {} buffers of {:?} bytes, not {expected} of {bytes}",
                planes.start,
                planes.end,
                data.len(),
                data.iter().map(Vec::len).collect::<Vec<_>>()
            )));
        }
        Ok(data)
    }
}

impl<R: LayerReader> SampleSource for LayeredVolume<R> {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let (grid, scalar) = (&self.grid, self.scalar);
        self.layers
            .read(grid, scalar, self.depth, z, out, |k| self.decode_layer(k))
    }

    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        let (grid, scalar) = (&self.grid, self.scalar);
        self.layers
            .shared(grid, scalar, self.depth, z, |k| self.decode_layer(k))
            .ok()
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.scalar)
    }

    /// Layers of `depth` planes; a read holds the new layer and the
    /// reader's own copy of it (a slice of the caller's array) until the
    /// layer is kept.
    fn plane_memory(&self) -> PlaneMemory {
        PlaneMemory::Decoded {
            sample_bytes: self.scalar.size(),
            layer: self.depth,
            decoding: 2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Layers of a ramp (sample = x + 10 y + 100 z as u16), counting reads.
    struct Ramp {
        dims: [usize; 3],
        reads: AtomicUsize,
    }

    impl LayerReader for Ramp {
        fn read_layer(&self, planes: Range<usize>) -> Result<Vec<Vec<u8>>> {
            self.reads.fetch_add(1, Ordering::SeqCst);
            let [nx, ny, _] = self.dims;
            Ok(planes
                .map(|z| {
                    (0..nx * ny)
                        .flat_map(|i| ((i % nx + 10 * (i / nx) + 100 * z) as u16).to_ne_bytes())
                        .collect()
                })
                .collect())
        }
    }

    fn ramp(dims: [usize; 3], depth: usize) -> LayeredVolume<Ramp> {
        let grid = Grid::unit(dims);
        let reads = AtomicUsize::new(0);
        LayeredVolume::new(grid, ScalarType::U16, depth, Ramp { dims, reads }).unwrap()
    }

    #[test]
    fn planes_come_from_their_layer_read_once() {
        let volume = ramp([3, 2, 7], 3);
        let mut plane = vec![0.0; 6];
        for z in 0..7 {
            volume.read_plane(z, &mut plane).unwrap();
            let want: Vec<f64> = (0..6)
                .map(|i| (i % 3 + 10 * (i / 3) + 100 * z) as f64)
                .collect();
            assert_eq!(plane, want, "plane {z}");
            let shared = volume.share_plane(z).unwrap();
            assert_eq!(shared.data[shared.bytes.clone()].len(), 12);
        }
        // Layers 0..3, 3..6 and the thin 6..7, each read once.
        assert_eq!(volume.reader().reads.load(Ordering::SeqCst), 3);
        assert_eq!(volume.depth(), 3);
    }

    #[test]
    fn a_reader_giving_the_wrong_planes_is_an_error_not_a_plane() {
        struct Short;
        impl LayerReader for Short {
            fn read_layer(&self, planes: Range<usize>) -> Result<Vec<Vec<u8>>> {
                Ok(planes.map(|_| vec![0; 3]).collect())
            }
        }
        let volume = LayeredVolume::new(Grid::unit([2, 2, 2]), ScalarType::U8, 2, Short).unwrap();
        let err = volume.read_plane(1, &mut [0.0; 4]).unwrap_err().to_string();
        assert!(err.contains("not 2 of 4"), "{err}");
        assert!(volume.share_plane(0).is_none());
        assert!(LayeredVolume::new(Grid::unit([2, 2, 2]), ScalarType::U8, 0, Short).is_err());
    }
}
