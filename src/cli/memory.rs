//! Peak memory of this process, from `/proc/self/status` (Linux; elsewhere
//! every figure is unknown).
//!
//! `VmHWM` (peak resident set) counts the pages of memory-mapped input
//! files too, which the kernel may drop at any time; `RssAnon` counts only
//! the process's own allocations, but the kernel keeps no peak of it, so it
//! is sampled (after a slab, at most once every [`SAMPLE_INTERVAL`], and at
//! the end) and the largest sample kept.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The least time between two samples after slabs. Reading
/// `/proc/self/status` takes some 15 us: after every slab it was a sixth
/// of the time of a volume of a million 2x2 planes.
const SAMPLE_INTERVAL: Duration = Duration::from_millis(1);

/// The largest `RssAnon` seen so far.
#[derive(Debug, Default)]
pub(crate) struct PeakAnon {
    /// Bytes; 0 until a sample succeeds.
    peak: AtomicU64,
    /// When [`sample_soon`](Self::sample_soon) last sampled.
    last: Mutex<Option<Instant>>,
}

impl PeakAnon {
    /// Samples `RssAnon` unless this sampled less than [`SAMPLE_INTERVAL`]
    /// ago.
    pub(crate) fn sample_soon(&self) {
        let now = Instant::now();
        {
            let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
            if last.is_some_and(|t| now - t < SAMPLE_INTERVAL) {
                return;
            }
            *last = Some(now);
        }
        self.sample();
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
