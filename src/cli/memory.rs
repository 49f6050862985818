//! Peak memory of this process, from `/proc/self/status` (Linux; elsewhere
//! every figure is unknown).
//!
//! `VmHWM` (peak resident set) counts the pages of memory-mapped input
//! files too, which the kernel may drop at any time; `RssAnon` counts only
//! the process's own allocations, but the kernel keeps no peak of it, so it
//! is sampled (after a slab, at most once every [`SAMPLE_INTERVAL`], and at
//! the end) and the largest sample kept.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// The least time between two samples after slabs. Reading
/// `/proc/self/status` takes some 15 us: after every slab it was a sixth
/// of the time of a volume of a million 2x2 planes.
const SAMPLE_INTERVAL: Duration = Duration::from_millis(1);

/// The largest `RssAnon` seen so far.
#[derive(Debug)]
pub(crate) struct PeakAnon {
    /// Bytes; 0 until a sample succeeds.
    peak: AtomicU64,
    /// When this started; the last sample's time counts from it.
    start: Instant,
    /// Nanoseconds from `start` to the last sample (0: none yet).
    last: AtomicU64,
}

impl Default for PeakAnon {
    fn default() -> Self {
        PeakAnon {
            peak: AtomicU64::new(0),
            start: Instant::now(),
            last: AtomicU64::new(0),
        }
    }
}

impl PeakAnon {
    /// Samples `RssAnon` unless a sample was taken less than
    /// [`SAMPLE_INTERVAL`] ago (the first one always is).
    pub(crate) fn sample_soon(&self) {
        let now = self.start.elapsed().as_nanos().max(1) as u64;
        let last = self.last.load(Ordering::Relaxed);
        let due = last == 0 || now.saturating_sub(last) >= SAMPLE_INTERVAL.as_nanos() as u64;
        if due
            && self
                .last
                .compare_exchange(last, now, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
        {
            self.sample();
        }
    }

    /// Samples `RssAnon` now and keeps the maximum.
    pub(crate) fn sample(&self) {
        if let Some(now) = status_bytes("RssAnon") {
            self.peak.fetch_max(now, Ordering::Relaxed);
        }
    }

    /// The largest sample in bytes, if any succeeded.
    pub(crate) fn peak(&self) -> Option<u64> {
        Some(self.peak.load(Ordering::Relaxed)).filter(|&b| b > 0)
    }
}

/// `VmHWM`, the peak resident set size in bytes.
pub(crate) fn peak_resident() -> Option<u64> {
    status_bytes("VmHWM")
}

/// A `kB` field of `/proc/self/status`, in bytes.
fn status_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(field)?.strip_prefix(':')?;
        let kb = rest.trim().strip_suffix("kB")?.trim();
        kb.parse::<u64>().ok()?.checked_mul(1024)
    })
}
