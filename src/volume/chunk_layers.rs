//! The decoded chunk layers of a chunked source (Zarr), shared by the
//! workers of a pass, so that each chunk is decompressed once per pass.
//!
//! A *chunk layer* is every chunk whose z-range holds a given plane: the
//! slab loop reads planes in order, so a worker that asks for plane `z`
//! will soon ask for the planes after it in the same chunks. The first
//! request decodes the whole layer (its chunks in parallel, by the caller)
//! and keeps it; the other planes of the layer, and the worker of the next
//! slab that starts in it, are copied from memory. Only a few layers are
//! kept, two per worker and two more: a layer whose planes have all been
//! read goes first (the lowest such, as the pass moves up in z), else the
//! one used longest ago. So memory is bounded by a few layers per worker,
//! never by the volume.
//!
//! No lock is held while a layer decodes: two workers that miss the same
//! layer at the same moment both decode it (the second copy is dropped),
//! which costs time but cannot deadlock the worker pool. Waiting for
//! another worker's decode could: the decoding thread may itself wait on
//! the pool.

use super::{decode_samples, Endian, Grid, ScalarType, SharedPlane};
use crate::{Error, Result};
use std::sync::{Arc, Mutex};

/// One decoded layer.
struct Slot {
    /// The layer's number (its first plane over the chunk depth).
    layer: usize,
    /// Its samples: planes of the layer, x fastest, native byte order.
    data: Arc<Vec<u8>>,
    /// Which of its planes have been read.
    read: Vec<bool>,
    /// When it was last used (a counter).
    used: u64,
}

/// The kept layers (see the module documentation).
pub(crate) struct ChunkLayers {
    slots: Mutex<(Vec<Slot>, u64)>,
}

impl ChunkLayers {
    /// No layer kept.
    pub(crate) fn new() -> ChunkLayers {
        ChunkLayers {
            slots: Mutex::new((Vec::new(), 0)),
        }
    }

    /// How many layers are kept at most: two per thread of the pool the
    /// caller runs on, and two more.
    fn capacity() -> usize {
        2 * rayon::current_num_threads() + 2
    }

    /// The samples of layer `layer` (of `planes` planes), marking plane
    /// `plane` of it read; `decode` makes them if the layer is not kept.
    pub(crate) fn get(
        &self,
        layer: usize,
        planes: usize,
        plane: usize,
        decode: impl FnOnce() -> Result<Vec<u8>>,
    ) -> Result<Arc<Vec<u8>>> {
        if let Some(data) = self.find(layer, plane) {
            return Ok(data);
        }
        let data = Arc::new(decode()?);
        let mut guard = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let (slots, clock) = &mut *guard;
        *clock += 1;
        if let Some(s) = slots.iter_mut().find(|s| s.layer == layer) {
            // Another worker decoded it meanwhile: keep one copy.
            s.read[plane] = true;
            s.used = *clock;
            return Ok(Arc::clone(&s.data));
        }
        if slots.len() >= Self::capacity() {
            let done = (0..slots.len())
                .filter(|&i| slots[i].read.iter().all(|&r| r))
                .min_by_key(|&i| slots[i].layer);
            let oldest = (0..slots.len()).min_by_key(|&i| slots[i].used);
            if let Some(i) = done.or(oldest) {
                slots.swap_remove(i);
            }
        }
        let mut read = vec![false; planes];
        read[plane] = true;
        slots.push(Slot {
            layer,
            data: Arc::clone(&data),
            read,
            used: *clock,
        });
        Ok(data)
    }

    /// Plane `z` of a volume on `grid` of `scalar` samples, stored in
    /// layers of `depth` planes (the last may be thinner): the kept layer
    /// holding it and the plane's bytes in it; `decode(k)` makes layer `k`
    /// (its planes, x fastest, native byte order) if it is not kept.
    pub(crate) fn shared(
        &self,
        grid: &Grid,
        scalar: ScalarType,
        depth: usize,
        z: usize,
        decode: impl FnOnce(usize) -> Result<Vec<u8>>,
    ) -> Result<SharedPlane> {
        let nz = grid.dims[2];
        if z >= nz || depth == 0 {
            return Err(Error::Invalid(format!("plane {z} of {nz}")));
        }
        let plane_bytes = grid.plane_len() * scalar.size();
        let k = z / depth;
        let planes = depth.min(nz - k * depth);
        let data = self.get(k, planes, z - k * depth, || decode(k))?;
        let at = (z - k * depth) * plane_bytes;
        if data.len() < at + plane_bytes {
            return Err(Error::Invalid(format!(
                "layer {k} holds {} bytes, plane {z} needs {}",
                data.len(),
                at + plane_bytes
            )));
        }
        Ok(SharedPlane {
            data,
            bytes: at..at + plane_bytes,
            scalar,
        })
    }

    /// [`ChunkLayers::shared`]'s plane `z` as `f64`s into `out` (a plane
    /// long).
    pub(crate) fn read(
        &self,
        grid: &Grid,
        scalar: ScalarType,
        depth: usize,
        z: usize,
        out: &mut [f64],
        decode: impl FnOnce(usize) -> Result<Vec<u8>>,
    ) -> Result<()> {
        let plane = grid.plane_len();
        if out.len() != plane {
            return Err(Error::Invalid(format!(
                "a plane of {plane} samples into a buffer of {}",
                out.len()
            )));
        }
        let shared = self.shared(grid, scalar, depth, z, decode)?;
        decode_samples(scalar, Endian::native(), &shared.data[shared.bytes], out);
        Ok(())
    }

    /// The kept layer `layer`, marking plane `plane` read.
    fn find(&self, layer: usize, plane: usize) -> Option<Arc<Vec<u8>>> {
        let mut guard = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let (slots, clock) = &mut *guard;
        *clock += 1;
        let s = slots.iter_mut().find(|s| s.layer == layer)?;
        s.read[plane] = true;
        s.used = *clock;
        Some(Arc::clone(&s.data))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kept_layer_is_not_decoded_again_and_read_layers_go_first() {
        let layers = ChunkLayers::new();
        let mut decoded = 0;
        for plane in 0..4 {
            let d = layers
                .get(0, 4, plane, || {
                    decoded += 1;
                    Ok(vec![7; 8])
                })
                .unwrap();
            assert_eq!(*d, vec![7; 8]);
        }
        assert_eq!(decoded, 1);
        // Fill past capacity with layers read in part: layer 0, read
        // whole, is the one dropped.
        let cap = ChunkLayers::capacity();
        for layer in 1..=cap {
            layers.get(layer, 4, 0, || Ok(vec![1])).unwrap();
        }
        let kept: Vec<usize> = layers
            .slots
            .lock()
            .unwrap()
            .0
            .iter()
            .map(|s| s.layer)
            .collect();
        assert_eq!(kept.len(), cap);
        assert!(!kept.contains(&0), "{kept:?}");
    }
}
