//! Peak memory of this process, from `/proc/self/status` (Linux; elsewhere
//! every figure is unknown).
//!
//! `VmHWM` (peak resident set) counts the pages of memory-mapped input
//! files too, which the kernel may drop at any time; `RssAnon` counts only
//! the process's own allocations, but the kernel keeps no peak of it, so it
//! is sampled (after every slab and at the end) and the largest sample kept.

use std::sync::atomic::{AtomicU64, Ordering};

/// The largest `RssAnon` seen so far.
#[derive(Debug, Default)]
pub(crate) struct PeakAnon {
    /// Bytes; 0 until a sample succeeds.
    peak: AtomicU64,
}

impl PeakAnon {
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
