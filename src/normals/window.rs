//! The planes of samples around one cell layer, read as the walk moves up.

use crate::error::try_filled;
use crate::volume::SampleSource;
use crate::Result;

/// The four planes a cell layer's gradients need: for layer `z` (between
/// planes `z` and `z + 1`), planes `z - 1`, `z`, `z + 1`, `z + 2`, each
/// clamped into the volume.
///
/// Invariants: each slot holds the samples of the plane named beside it,
/// with NaN replaced by the isovalue (NaN is outside, a tie, as in the
/// extraction: so a difference across a NaN sample, such as the border
/// `Padded` adds for `--close`, stays finite); a plane is read once per
/// visit of the walk, and at most four are held.
pub struct Window<'a> {
    /// Where the samples come from.
    source: &'a dyn SampleSource,
    /// The value NaN samples take.
    iso: f64,
    /// Planes held: (plane number, samples), at most four.
    slots: Vec<(usize, Vec<f64>)>,
}

impl<'a> Window<'a> {
    /// An empty window on `source` (at least two planes), NaN read as `iso`.
    pub fn new(source: &'a dyn SampleSource, iso: f64) -> Self {
        Window {
            source,
            iso,
            slots: Vec::with_capacity(4),
        }
    }

    /// The planes for cell layer `z`, in the order below `z`, `z`,
    /// `z + 1`, above `z + 1`, with their plane numbers (the first equals
    /// `z` at the bottom of the volume, the last `z + 1` at the top);
    /// planes not held yet are read, into the slots of planes no longer
    /// needed.
    pub fn around(&mut self, z: usize) -> Result<([&[f64]; 4], [usize; 4])> {
        let last = self.source.grid().dims[2] - 1;
        let wanted = [z.saturating_sub(1), z, z + 1, (z + 2).min(last)];
        for &plane in &wanted {
            if self.slots.iter().any(|(p, _)| *p == plane) {
                continue;
            }
            let free = self.slots.iter().position(|(p, _)| !wanted.contains(p));
            let slot = match free {
                Some(i) => i,
                None => {
                    let len = self.source.grid().plane_len();
                    self.slots
                        .push((plane, try_filled("a plane of samples", len, 0.0)?));
                    self.slots.len() - 1
                }
            };
            let (number, samples) = &mut self.slots[slot];
            *number = plane;
            self.source.read_plane(plane, samples)?;
            for v in samples.iter_mut().filter(|v| v.is_nan()) {
                *v = self.iso;
            }
        }
        let find = |plane: usize| {
            let held = self.slots.iter().find(|(p, _)| *p == plane);
            held.map_or(&[][..], |(_, s)| s.as_slice())
        };
        Ok((wanted.map(find), wanted))
    }
}
