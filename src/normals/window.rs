//! The planes of samples around one cell layer, read as the walk moves up.

use crate::error::try_filled;
use crate::volume::{LentPlane, SampleSource};
use crate::Result;

/// One plane of samples as the window hands it out: lent by the source as
/// stored (no copy), or read into the window's `f64` buffer; read through
/// [`Samples`](super::samples::Samples).
#[derive(Debug, Clone, Copy)]
pub enum Plane<'a> {
    /// The source's own samples (see [`SampleSource::lend_plane`]).
    Lent(LentPlane<'a>),
    /// Samples read with [`SampleSource::read_plane`].
    Read(&'a [f64]),
}

/// The four planes a cell layer's gradients need: for layer `z` (between
/// planes `z` and `z + 1`), planes `z - 1`, `z`, `z + 1`, `z + 2`, each
/// clamped into the volume.
///
/// Invariants: each slot holds the samples of the plane named beside it;
/// a plane the source lends is not copied; a plane it does not lend is read
/// once per visit of the walk, and at most four are held.
pub struct Window<'a> {
    /// Where the samples come from.
    source: &'a dyn SampleSource,
    /// Planes held: (plane number, samples), at most four.
    slots: Vec<(usize, Vec<f64>)>,
}

impl<'a> Window<'a> {
    /// An empty window on `source` (at least two planes).
    pub fn new(source: &'a dyn SampleSource) -> Self {
        Window {
            source,
            slots: Vec::with_capacity(4),
        }
    }

    /// The planes for cell layer `z`, in the order below `z`, `z`,
    /// `z + 1`, above `z + 1`, with their plane numbers (the first equals
    /// `z` at the bottom of the volume, the last `z + 1` at the top);
    /// planes the source lends are borrowed, the others read if not held
    /// yet, into the slots of planes no longer needed.
    pub fn around(&mut self, z: usize) -> Result<([Plane<'_>; 4], [usize; 4])> {
        let source: &'a dyn SampleSource = self.source;
        let last = source.grid().dims[2] - 1;
        let len = source.grid().plane_len();
        let wanted = [z.saturating_sub(1), z, z + 1, (z + 2).min(last)];
        let lent = wanted.map(|p| source.lend_plane(p).filter(|l| l.len() == len));
        for (&plane, lent) in wanted.iter().zip(&lent) {
            if lent.is_some() || self.slots.iter().any(|(p, _)| *p == plane) {
                continue;
            }
            let free = self.slots.iter().position(|(p, _)| !wanted.contains(p));
            let slot = match free {
                Some(i) => i,
                None => {
                    self.slots
                        .push((plane, try_filled("a plane of samples", len, 0.0)?));
                    self.slots.len() - 1
                }
            };
            let (number, samples) = &mut self.slots[slot];
            *number = plane;
            source.read_plane(plane, samples)?;
        }
        let slots = &self.slots;
        let planes = [0, 1, 2, 3].map(|k| match lent[k] {
            Some(lent) => Plane::Lent(lent),
            None => {
                let held = slots.iter().find(|(p, _)| *p == wanted[k]);
                Plane::Read(held.map_or(&[][..], |(_, s)| s.as_slice()))
            }
        });
        Ok((planes, wanted))
    }
}
