//! [`FillPending`]: the normals the gradient could not give, from the
//! triangles, one chunk behind the stream.

use super::vector::{cross, dot, sub, unit};
use crate::mesh::{Chunk, MeshInfo, MeshSink, Totals};
use crate::Result;
use std::ops::Range;
use std::sync::atomic::AtomicBool;

/// Marks a vertex that has no normal yet (every other entry of the normals
/// is finite).
pub const PENDING: [f32; 3] = [f32::NAN; 3];

/// Whether `normal` is [`PENDING`].
fn is_pending(normal: &[f32; 3]) -> bool {
    normal[0].is_nan()
}

/// A sink wrapper that gives every [`PENDING`] normal the angle-weighted
/// average of the unit normals of the vertex's triangles, normalized
/// (`[0, 0, 0]` where that is zero: no triangle, or only degenerate ones),
/// and forwards only the chunks of the planes it is told to keep,
/// renumbered from 0.
///
/// Why: on a plateau or a tie (integer data at its isovalue, the NaN
/// border of `--close`) the interpolated gradient can vanish, while the
/// triangles around the vertex still show which way is out. Triangles are
/// counter-clockwise seen from outside in world coordinates (a mirroring
/// grid flips their winding), so their normals point outward as they are;
/// weighting by the angle at the vertex makes the result independent of
/// how the fan around it is cut.
///
/// A vertex of chunk `k` is a corner of triangles of chunks `k - 1` (those
/// that point into the next chunk) and `k` only, whose corners are
/// vertices of chunks `k - 1`, `k` and `k + 1`; so chunk `k` is forwarded
/// when chunk `k + 1` arrives (or at the end), the wrapper holding two
/// chunks: handed over by value ([`FillPending::push`], what the stream
/// does), or copied ([`MeshSink::chunk`]). The triangles are visited in stream order, so the result
/// is that of one pass over the whole mesh: the same for any slab, thread
/// or part. A part run hands it one chunk beyond each end of its range for
/// that context, and `keep` drops them.
///
/// Without normals ([`MeshInfo::normals`] false) chunks only pass through
/// the `keep` filter.
pub struct FillPending<'a> {
    /// Where the finished chunks go.
    inner: &'a mut dyn MeshSink,
    /// The planes whose chunks are forwarded.
    keep: Range<u64>,
    /// Whether the chunks carry normals.
    normals: bool,
    /// The chunk before `current` (its triangles point into `current`).
    previous: Option<Chunk>,
    /// The chunk waiting for its successor.
    current: Option<Chunk>,
    /// What was forwarded.
    totals: Totals,
}

impl<'a> FillPending<'a> {
    /// A wrapper around `inner` forwarding the chunks of planes `keep`.
    pub fn new(inner: &'a mut dyn MeshSink, keep: Range<u64>) -> Self {
        FillPending {
            inner,
            keep,
            normals: false,
            previous: None,
            current: None,
            totals: Totals::default(),
        }
    }

    /// What was forwarded to the wrapped sink (the chunks of `keep`).
    pub fn totals(&self) -> Totals {
        self.totals
    }

    /// Resolves the pending normals of `current` (with `next`, if any, for
    /// the positions its triangles point at) and forwards it if kept;
    /// returns the chunk before it, which nothing needs any more.
    fn release(
        &mut self,
        next: Option<&Chunk>,
        cancel: Option<&AtomicBool>,
    ) -> Result<Option<Chunk>> {
        let Some(mut current) = self.current.take() else {
            return Ok(None);
        };
        if current.normals.iter().any(is_pending) {
            resolve(self.previous.as_ref(), &mut current, next);
        }
        self.forward(&current, cancel)?;
        Ok(self.previous.replace(current))
    }

    /// Takes the next chunk of the stream by value (no copy); returns a
    /// chunk it is done with, whose vectors the caller may reuse: `chunk`
    /// itself without normals (forwarded at once), else the chunk two
    /// behind it, once the one before it is forwarded.
    pub fn push(&mut self, chunk: Chunk, cancel: Option<&AtomicBool>) -> Result<Option<Chunk>> {
        if !self.normals {
            // Nothing to wait for.
            self.forward(&chunk, cancel)?;
            return Ok(Some(chunk));
        }
        let done = self.release(Some(&chunk), cancel)?;
        self.current = Some(chunk);
        Ok(done)
    }

    /// Hands `chunk` to the wrapped sink if its plane is kept.
    fn forward(&mut self, chunk: &Chunk, cancel: Option<&AtomicBool>) -> Result<()> {
        if !self.keep.contains(&chunk.plane) {
            return Ok(());
        }
        let base = self.totals.vertices;
        match cancel {
            Some(cancel) => self.inner.chunk_cancellable(base, chunk, cancel)?,
            None => self.inner.chunk(base, chunk)?,
        }
        self.totals.vertices += chunk.vertices.len() as u64;
        self.totals.triangles += chunk.triangles.len() as u64;
        self.totals.chunks += 1;
        Ok(())
    }

    /// [`MeshSink::chunk`] with an optional cancel flag: [`push`](Self::push)
    /// of a copy (only with normals, which wait for the next chunk).
    fn take(&mut self, chunk: &Chunk, cancel: Option<&AtomicBool>) -> Result<()> {
        if !self.normals {
            return self.forward(chunk, cancel);
        }
        self.push(chunk.clone(), cancel).map(drop)
    }
}

impl MeshSink for FillPending<'_> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.normals = info.normals;
        self.inner.begin(info)
    }

    fn chunk(&mut self, _base: u64, chunk: &Chunk) -> Result<()> {
        self.take(chunk, None)
    }

    fn chunk_cancellable(&mut self, _base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.take(chunk, Some(cancel))
    }

    fn finish(&mut self, _totals: &Totals) -> Result<()> {
        self.release(None, None)?;
        self.previous = None;
        let totals = self.totals;
        self.inner.finish(&totals)
    }

    fn finish_cancellable(&mut self, _totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.release(None, Some(cancel))?;
        self.previous = None;
        let totals = self.totals;
        self.inner.finish_cancellable(&totals, cancel)
    }
}

/// Gives the pending normals of `current` the angle-weighted normal of
/// their triangles: those of `previous` that point into `current`, then
/// those of `current`, in order.
fn resolve(previous: Option<&Chunk>, current: &mut Chunk, next: Option<&Chunk>) {
    let own = current.vertices.len();
    let mut sums: Vec<(usize, [f64; 3])> = Vec::new();
    for (i, n) in current.normals.iter().enumerate() {
        if is_pending(n) {
            sums.push((i, [0.0; 3]));
        }
    }
    // The pending vertices lie in `first..=last` of the chunk: a triangle
    // without a corner there is passed over with two comparisons a corner.
    let (first, last) = match (sums.first(), sums.last()) {
        (Some(f), Some(l)) => (f.0, l.0),
        _ => return,
    };
    let mut slot = vec![usize::MAX; last + 1 - first];
    for (s, (i, _)) in sums.iter().enumerate() {
        slot[i - first] = s;
    }
    // Chunks `previous`, `current`, `next` as one run of vertices:
    // a position by its index from `previous`'s first vertex.
    let before = previous.map_or(0, |c| c.vertices.len());
    let position = |i: usize| -> Option<[f64; 3]> {
        let v = if i < before {
            previous?.vertices.get(i)
        } else if i < before + own {
            current.vertices.get(i - before)
        } else {
            next?.vertices.get(i - before - own)
        };
        v.map(|p| p.map(f64::from))
    };
    let mut add = |tri: [usize; 3]| {
        let (low, high) = (before + first, before + last);
        if tri.iter().all(|&i| i < low || i > high) {
            return;
        }
        let mine = tri.map(|i| (low..=high).contains(&i).then(|| slot[i - low]));
        if mine.iter().all(|s| s.is_none_or(|s| s == usize::MAX)) {
            return;
        }
        let Some(p) = tri.iter().map(|&i| position(i)).collect::<Option<Vec<_>>>() else {
            return;
        };
        let normal = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let twice_area = dot(normal, normal).sqrt();
        if !(twice_area > 0.0 && twice_area.is_finite()) {
            return;
        }
        for k in 0..3 {
            let Some(s) = mine[k].filter(|&s| s != usize::MAX) else {
                continue;
            };
            let u = sub(p[(k + 1) % 3], p[k]);
            let v = sub(p[(k + 2) % 3], p[k]);
            // |u x v| is twice the area at every corner.
            let angle = twice_area.atan2(dot(u, v));
            for (sum, n) in sums[s].1.iter_mut().zip(normal) {
                *sum += angle * n / twice_area;
            }
        }
    };
    if let Some(previous) = previous {
        for tri in &previous.triangles {
            add(tri.map(|i| i as usize));
        }
    }
    for tri in &current.triangles {
        add(tri.map(|i| i as usize + before));
    }
    for (i, sum) in sums {
        current.normals[i] = unit(sum).unwrap_or([0.0; 3]);
    }
}
