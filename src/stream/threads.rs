//! How many workers, and how deep their slabs are when nobody says.

use crate::{Error, Result};

/// The number of worker threads that `threads` (`ExtractParams::threads`)
/// asks for: 0 is one per core. (An extraction uses no more than it has
/// cell layers.)
pub fn worker_threads(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    }
}

/// The slab depth when none is asked for: about 64M samples per slab, 16
/// to 64 layers (a slab re-reads the plane it shares with the slab below, so
/// thin slabs cost time, while memory grows with the plane size far more
/// than with the depth); but with several threads, thin enough that there
/// are about sixteen slabs per thread (at least 8 layers each), because
/// slabs are the unit of parallel work: the surface is rarely spread evenly
/// over the layers, and a few big slabs leave threads idle, waiting for a
/// slow one (two threads on 256^3 CT and noise were 8-14% faster with slabs
/// of 8 layers than of 32).
pub(crate) fn default_depth(plane_len: usize, layers: usize, threads: usize) -> usize {
    let by_size = ((64 << 20) / plane_len.max(1)).clamp(16, 64);
    if threads <= 1 {
        return by_size;
    }
    by_size.min(layers.div_ceil(16 * threads).max(8))
}

/// A rayon pool of `threads` threads (a count, not 0: see [`worker_threads`]);
/// front ends use it for their own parallel steps, so that `threads` holds
/// for the whole call.
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))
}
