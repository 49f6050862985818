//! [`HeldPlanes`]: the planes of one slab, held while the slab is
//! triangulated, so that a source whose decoded layers live in a cache
//! that drops them (Zarr, HDF5: see `chunk_layers.rs`) can lend them to the
//! slab loop in their own type, as a memory-mapped source does, instead of
//! converting every sample to `f64`.
//!
//! A plane is held from the first time it is lent until the slab ends (the
//! lent plane borrows from the holder, so it cannot go sooner): a worker
//! keeps alive the layers its slab's planes lie in, most of which the
//! source's cache holds anyway.

use super::{LentPlane, SampleSource, SharedPlane};
use std::ops::Range;
use std::sync::OnceLock;

/// A source that lends planes `planes` of the wrapped source from the
/// buffers it shares ([`SampleSource::share_plane`]), holding them until
/// it is dropped; everything else goes to the wrapped source, which lends
/// first if it can.
pub struct HeldPlanes<'a> {
    inner: &'a dyn SampleSource,
    /// The first plane held.
    first: usize,
    /// One slot per plane from `first` on, filled when the plane is lent.
    slots: Vec<OnceLock<SharedPlane>>,
}

impl<'a> HeldPlanes<'a> {
    /// Holds planes `planes` of `inner` as they are lent.
    pub fn new(inner: &'a dyn SampleSource, planes: Range<usize>) -> Self {
        HeldPlanes {
            inner,
            first: planes.start,
            slots: planes.map(|_| OnceLock::new()).collect(),
        }
    }
}

impl SampleSource for HeldPlanes<'_> {
    super::forward_to_inner!(
        grid,
        read_plane,
        share_plane,
        advise,
        check_unchanged,
        interrupted,
        data_files,
        sample_bytes,
        stored_type,
        notes,
        plane_memory,
    );

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        if let Some(lent) = self.inner.lend_plane(z) {
            return Some(lent);
        }
        let slot = self.slots.get(z.checked_sub(self.first)?)?;
        if slot.get().is_none() {
            // Another thread cannot fill it: a slab is one worker's.
            let _ = slot.set(self.inner.share_plane(z)?);
        }
        slot.get()?.lent()
    }
}
