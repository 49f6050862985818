//! [`Cancellable`]: a source that stops giving planes once the cancel flag
//! is set, so that a slab in progress stops at its next cell layer rather
//! than at its end, and that answers [`SampleSource::interrupted`], which
//! the slab loop asks every few rows of cells, so that it stops within a
//! layer too (Ctrl-C must stop a run within half a second even when one
//! layer of a dense volume with huge planes takes longer than that).

use crate::volume::{LentPlane, SampleSource, SharedPlane};
use crate::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};

/// Wraps a source: once `cancel` is set, [`SampleSource::read_plane`]
/// fails with [`Error::Interrupted`] and no plane is lent (so the slab loop
/// reads, and fails), and [`SampleSource::interrupted`] is true. Otherwise
/// every call goes to the wrapped source, so the output is unchanged; the
/// cost is one relaxed load per plane and per block of rows.
pub struct Cancellable<'a> {
    /// The wrapped source.
    pub inner: &'a dyn SampleSource,
    /// The flag that stops the reads.
    pub cancel: &'a AtomicBool,
}

impl Cancellable<'_> {
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

impl SampleSource for Cancellable<'_> {
    crate::volume::forward_to_inner!(
        grid,
        advise,
        check_unchanged,
        data_files,
        sample_bytes,
        stored_type,
        notes,
        plane_memory,
    );

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        if self.cancelled() {
            return Err(Error::Interrupted);
        }
        self.inner.read_plane(z, out)
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        if self.cancelled() {
            return None;
        }
        self.inner.lend_plane(z)
    }

    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        if self.cancelled() {
            return None;
        }
        self.inner.share_plane(z)
    }

    fn interrupted(&self) -> bool {
        self.cancelled() || self.inner.interrupted()
    }
}
