//! The decoded chunk layers of a chunked source (Zarr), shared by the
//! workers of a pass, so that each chunk is decompressed once per pass.
//!
//! A *chunk layer* is every chunk whose z-range holds a given plane: the
//! slab loop reads planes in order, so a worker that asks for plane `z`
//! will soon ask for the planes after it in the same chunks. The first
//! request decodes the whole layer (its chunks in parallel, by the caller)
//! and keeps it; the other planes of the layer, and the worker of the next
//! slab that starts in it, are copied from memory. Only a few layers are
//! kept, one per worker and two more: a layer whose planes have all been
//! read goes first (the lowest such, as the pass moves up in z), else the
//! one used longest ago. So memory is bounded by a few layers per worker,
//! never by the volume.
//!
//! A layer is kept as one buffer per plane, so that a plane a worker's slab
//! still holds (`held.rs`) keeps only itself alive once its layer is
//! dropped, not the whole layer: with one buffer per layer, slabs deeper
//! than a chunk kept dropped layers alive, and one worker on a Zarr of
//! 2048x2048 f32 planes in chunks 8 deep (128 MiB a layer) peaked at 715
//! MB. The memory budget counts the kept layers, a decode in flight per
//! worker and each worker's held planes (`stream/budget.rs`).
//!
//! No lock is held while a layer decodes. A worker that misses a layer
//! another worker is decoding waits for that decode (on a condition
//! variable, holding nothing) instead of decoding it a second time: with
//! slabs as deep as a chunk layer, two workers reach the next layer at
//! about the same moment, and before this wait most chunks of a 32 GiB
//! volume were decompressed twice. The wait cannot deadlock: a decode runs
//! on the caller's thread and threads of its own (Zarr's scoped threads),
//! never on the pass's worker pool, and waits for no worker; a decode that
//! fails or panics still wakes its waiters, which then decode the layer
//! themselves (and meet the error themselves).

use super::{decode_samples, Endian, Grid, ScalarType, SharedPlane};
use crate::{Error, Result};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};

/// One decoded layer.
struct Slot {
    /// The layer's number (its first plane over the chunk depth).
    layer: usize,
    /// Its samples: one buffer per plane of the layer, x fastest, native
    /// byte order.
    data: Vec<Arc<Vec<u8>>>,
    /// Which of its planes have been read.
    read: Vec<bool>,
    /// When it was last used (a counter).
    used: u64,
}

/// The kept layers and the clock of their use (see the module
/// documentation), and the layers being decoded.
#[derive(Default)]
struct Kept {
    slots: Vec<Slot>,
    clock: u64,
    /// Layers a worker is decoding now; no layer is here twice.
    decoding: Vec<usize>,
}

/// The kept layers (see the module documentation).
pub(crate) struct ChunkLayers {
    kept: Mutex<Kept>,
    /// Signalled whenever a decode ends (kept, failed or panicked).
    decoded: Condvar,
}

/// A layer in flight: ends its decode, whatever happens to it, and wakes
/// the workers waiting for it.
struct InFlight<'a> {
    layers: &'a ChunkLayers,
    layer: usize,
}

impl Drop for InFlight<'_> {
    fn drop(&mut self) {
        let mut kept = self.layers.lock();
        kept.decoding.retain(|&l| l != self.layer);
        drop(kept);
        self.layers.decoded.notify_all();
    }
}

impl ChunkLayers {
    /// No layer kept.
    pub(crate) fn new() -> ChunkLayers {
        ChunkLayers {
            kept: Mutex::new(Kept::default()),
            decoded: Condvar::new(),
        }
    }

    /// The kept layers, locked (a panic elsewhere leaves them usable: every
    /// change below is whole before the lock is released).
    fn lock(&self) -> MutexGuard<'_, Kept> {
        self.kept.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// How many layers are kept at most: one per thread of the pool the
    /// caller runs on, and two more (a worker reads its layer, and at the
    /// top of its slab the first plane of the next, which the worker above
    /// may have read whole already). Memory is this many layers, and those
    /// a worker's slab still holds (`HeldPlanes`), which are mostly the
    /// same. (Before missed layers were waited for, it was two per worker
    /// and two more.)
    fn capacity() -> usize {
        rayon::current_num_threads() + 2
    }

    /// The samples of plane `plane` of layer `layer` (of `planes` planes),
    /// marking it read; `decode` makes the layer's planes if the layer is
    /// not kept.
    pub(crate) fn get(
        &self,
        layer: usize,
        planes: usize,
        plane: usize,
        decode: impl FnOnce() -> Result<Vec<Vec<u8>>>,
    ) -> Result<Arc<Vec<u8>>> {
        let mut kept = self.lock();
        loop {
            if let Some(data) = Self::find(&mut kept, layer, plane) {
                return Ok(data);
            }
            if !kept.decoding.contains(&layer) {
                kept.decoding.push(layer);
                break;
            }
            kept = self.decoded.wait(kept).unwrap_or_else(|p| p.into_inner());
        }
        drop(kept);
        let flight = InFlight {
            layers: self,
            layer,
        };
        let data: Vec<Arc<Vec<u8>>> = decode()?.into_iter().map(Arc::new).collect();
        let Some(wanted) = data.get(plane).map(Arc::clone) else {
            return Err(Error::Invalid(format!(
                "layer {layer} decodes to {} planes, plane {plane} asked for",
                data.len()
            )));
        };
        let mut kept = self.lock();
        let Kept { slots, clock, .. } = &mut *kept;
        *clock += 1;
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
            data,
            read,
            used: *clock,
        });
        drop(kept);
        drop(flight);
        Ok(wanted)
    }

    /// Plane `z` of a volume on `grid` of `scalar` samples, stored in
    /// layers of `depth` planes (the last may be thinner): the kept layer
    /// holding it and the plane's bytes in it; `decode(k)` makes layer `k`
    /// (its planes, each x fastest, native byte order) if it is not kept.
    pub(crate) fn shared(
        &self,
        grid: &Grid,
        scalar: ScalarType,
        depth: usize,
        z: usize,
        decode: impl FnOnce(usize) -> Result<Vec<Vec<u8>>>,
    ) -> Result<SharedPlane> {
        let nz = grid.dims[2];
        if z >= nz || depth == 0 {
            return Err(Error::Invalid(format!("plane {z} of {nz}")));
        }
        let plane_bytes = grid.plane_len() * scalar.size();
        let k = z / depth;
        let planes = depth.min(nz - k * depth);
        let data = self.get(k, planes, z - k * depth, || decode(k))?;
        if data.len() != plane_bytes {
            return Err(Error::Invalid(format!(
                "plane {z} of layer {k} holds {} bytes, not {plane_bytes}",
                data.len()
            )));
        }
        Ok(SharedPlane::new(data, 0..plane_bytes, scalar))
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
        decode: impl FnOnce(usize) -> Result<Vec<Vec<u8>>>,
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

    /// Plane `plane` of the kept layer `layer`, marking it read.
    fn find(kept: &mut Kept, layer: usize, plane: usize) -> Option<Arc<Vec<u8>>> {
        kept.clock += 1;
        let clock = kept.clock;
        let s = kept.slots.iter_mut().find(|s| s.layer == layer)?;
        let data = Arc::clone(s.data.get(plane)?);
        s.read[plane] = true;
        s.used = clock;
        Some(data)
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
                    Ok(vec![vec![7; 8]; 4])
                })
                .unwrap();
            assert_eq!(*d, vec![7; 8]);
        }
        assert_eq!(decoded, 1);
        // Fill past capacity with layers read in part: layer 0, read
        // whole, is the one dropped.
        let cap = ChunkLayers::capacity();
        for layer in 1..=cap {
            layers.get(layer, 4, 0, || Ok(vec![vec![1]; 4])).unwrap();
        }
        let kept: Vec<usize> = layers.lock().slots.iter().map(|s| s.layer).collect();
        assert_eq!(kept.len(), cap);
        assert!(!kept.contains(&0), "{kept:?}");
    }

    #[test]
    fn a_held_plane_keeps_only_itself_once_its_layer_is_dropped() {
        let layers = ChunkLayers::new();
        let planes = |k: u8| {
            let plane = |p: u8| [vec![k], vec![p; 1 << 10]].concat();
            Ok((0..4).map(plane).collect())
        };
        let held = layers.get(0, 4, 0, || planes(0)).unwrap();
        let other = std::sync::Arc::downgrade(&layers.get(0, 4, 1, || planes(0)).unwrap());
        assert_eq!(held[..2], [0, 0]);
        for layer in 1..=ChunkLayers::capacity() {
            layers.get(layer, 4, 0, || planes(layer as u8)).unwrap();
        }
        assert!(layers.lock().slots.iter().all(|s| s.layer != 0));
        // The held plane lives on; the layer's other planes are freed.
        assert_eq!(held[..2], [0, 0]);
        assert!(other.upgrade().is_none());
    }

    #[test]
    fn a_layer_two_workers_miss_at_once_is_decoded_once() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let layers = ChunkLayers::new();
        let decodes = AtomicUsize::new(0);
        let start = std::sync::Barrier::new(4);
        std::thread::scope(|s| {
            for plane in 0..4 {
                let (layers, decodes, start) = (&layers, &decodes, &start);
                s.spawn(move || {
                    start.wait();
                    let d = layers
                        .get(3, 4, plane, || {
                            decodes.fetch_add(1, Ordering::SeqCst);
                            std::thread::sleep(std::time::Duration::from_millis(200));
                            Ok(vec![vec![5; 16]; 4])
                        })
                        .unwrap();
                    assert_eq!(*d, vec![5; 16]);
                });
            }
        });
        assert_eq!(decodes.load(Ordering::SeqCst), 1);
        assert!(layers.lock().decoding.is_empty());
    }

    #[test]
    fn a_failed_or_panicking_decode_wakes_its_waiters() {
        let layers = ChunkLayers::new();
        let err = layers.get(0, 2, 0, || Err(Error::Invalid("bad chunk".into())));
        assert!(err.is_err());
        assert!(layers.lock().decoding.is_empty());
        let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let _ = layers.get(1, 2, 0, || panic!("decoder panicked"));
        }));
        assert!(panicked.is_err());
        assert!(layers.lock().decoding.is_empty());
        // Both layers can still be decoded afterwards.
        assert_eq!(
            *layers.get(0, 2, 1, || Ok(vec![vec![1]; 2])).unwrap(),
            vec![1]
        );
        assert_eq!(
            *layers.get(1, 2, 1, || Ok(vec![vec![2]; 2])).unwrap(),
            vec![2]
        );
    }
}
