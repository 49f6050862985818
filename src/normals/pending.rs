//! [`FillPending`]: the normals the gradient could not give, from the
//! triangles, one chunk behind the stream.

use super::vector::{cross, dot, sub, unit};
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Totals};
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

/// Whether some normal of `chunk` is [`PENDING`]: [`FillPending`] will
/// change the chunk (so encoding it before is wasted).
pub fn has_pending(chunk: &Chunk) -> bool {
    any_pending(&chunk.normals)
}

/// Whether any of `normals` is [`PENDING`]: whether any component is NaN
/// (the others are finite), tested [`BLOCK`] normals at a time in vector
/// registers. (Were a component of another normal NaN, [`resolve`] would
/// find no pending vertex and change nothing.)
fn any_pending(normals: &[[f32; 3]]) -> bool {
    let (blocks, rest) = normals.as_chunks::<BLOCK>();
    let nan = |any: bool, &c: &f32| any | c.is_nan();
    blocks
        .iter()
        .any(|b| b.as_flattened().iter().fold(false, nan))
        || rest.iter().any(is_pending)
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
        if any_pending(&current.normals) {
            resolve(self.previous.as_ref(), &mut current, next);
            // Bytes encoded before no longer hold its normals.
            current.encoded.clear();
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

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.inner.encoder()
    }
}

/// Gives the pending normals of `current` the angle-weighted normal of
/// their triangles: those of `previous` that point into `current`, then
/// those of `current`, in order.
///
/// Every triangle of the two chunks is looked at (three lookups in a
/// table of the chunk's vertices); only one with a pending corner costs
/// more ([`add_triangle`]).
fn resolve(previous: Option<&Chunk>, current: &mut Chunk, next: Option<&Chunk>) {
    let own = current.vertices.len();
    let mut sums: Vec<[f64; 3]> = Vec::new();
    // The slot of each vertex's sum, `NONE` for a vertex not pending.
    let mut slot = vec![NONE; own];
    // The pending vertices, in order.
    let mut pending = Vec::new();
    for (i, n) in current.normals.iter().enumerate() {
        if is_pending(n) {
            slot[i] = sums.len() as u32;
            sums.push([0.0; 3]);
            pending.push(i);
        }
    }
    let (Some(&low), Some(&high)) = (pending.first(), pending.last()) else {
        return;
    };
    // Chunks `previous`, `current`, `next` as one run of vertices:
    // a triangle's corners by their index from `previous`'s first vertex.
    let before = previous.map_or(0, |c| c.vertices.len());
    let chunks = [previous, Some(&*current), next];
    let tables = Tables {
        chunks,
        before,
        own,
        slot: &slot,
        pending: &pending,
        span: [low, high],
    };
    if let Some(previous) = previous {
        tables.scan(&previous.triangles, 0, &mut sums);
    }
    tables.scan(&current.triangles, before, &mut sums);
    let mut sums = sums.into_iter();
    for (n, &s) in current.normals.iter_mut().zip(&slot) {
        if s != NONE {
            *n = unit(sums.next().unwrap_or_default()).unwrap_or([0.0; 3]);
        }
    }
}

/// No pending vertex (a slot of [`resolve`]).
const NONE: u32 = u32::MAX;

/// What [`resolve`] looks triangles up in: the three chunks as one run
/// of vertices (`before` in the first, `own` in the second), the slot
/// of each of the second's vertices, those of them that are pending and
/// the first and last of these.
struct Tables<'a> {
    chunks: [Option<&'a Chunk>; 3],
    before: usize,
    own: usize,
    slot: &'a [u32],
    pending: &'a [usize],
    span: [usize; 2],
}

/// Up to how many pending vertices [`Tables::scan`] looks for each of them
/// in a block of triangles, rather than for the span between the first and
/// the last.
const FEW: usize = 8;

impl Tables<'_> {
    /// Adds the triangles (corners offset by `shift` into the run) that
    /// have a pending corner to `sums`, in order.
    ///
    /// Pending vertices are few: the triangles are tested [`BLOCK`] at a
    /// time, in vector registers, and only a block with a corner that may
    /// be pending is looked at triangle by triangle. The test compares
    /// the corners with each pending vertex when there are at most
    /// [`FEW`], else with the span between the first and the last.
    fn scan(&self, triangles: &[[u32; 3]], shift: usize, sums: &mut [[f64; 3]]) {
        let (blocks, rest) = triangles.as_chunks::<BLOCK>();
        // The pending vertices as stored corners: no corner reaches one
        // beyond `u32`.
        let stored = |p: usize| u32::try_from(self.before + p - shift).ok();
        if self.pending.len() <= FEW {
            let targets: Vec<u32> = self.pending.iter().filter_map(|&p| stored(p)).collect();
            for block in blocks {
                let corners = block.as_flattened();
                let hit = |&t: &u32| corners.iter().fold(0, |any, &i| any | u32::from(i == t));
                if targets.iter().any(|t| hit(t) != 0) {
                    self.visit_all(block, shift, sums);
                }
            }
            self.visit_all(rest, shift, sums);
            return;
        }
        // Corner `i` (as stored) is between the two iff `i - low <= width`,
        // wrapping: a corner below `low` wraps to more than `width` once
        // that is cut to what is left above `low`.
        let Some(low) = stored(self.span[0]) else {
            return;
        };
        let width = (self.span[1] - self.span[0]).min((u32::MAX - low) as usize) as u32;
        let near = |i: u32| u32::from(i.wrapping_sub(low) <= width);
        for block in blocks {
            if block.as_flattened().iter().fold(0, |any, &i| any | near(i)) != 0 {
                self.visit_all(block, shift, sums);
            }
        }
        self.visit_all(rest, shift, sums);
    }

    /// [`visit`](Self::visit) of each of `triangles`, in order.
    fn visit_all(&self, triangles: &[[u32; 3]], shift: usize, sums: &mut [[f64; 3]]) {
        for tri in triangles {
            self.visit(tri, shift, sums);
        }
    }

    /// Adds triangle `tri` (corners offset by `shift` into the run) to
    /// `sums` if it has a pending corner.
    #[inline(always)]
    fn visit(&self, tri: &[u32; 3], shift: usize, sums: &mut [[f64; 3]]) {
        let (before, own, slot) = (self.before, self.own, self.slot);
        let tri = tri.map(|i| i as usize + shift);
        let hit = tri.map(|i| {
            let j = i.wrapping_sub(before);
            if j < own {
                slot[j]
            } else {
                NONE
            }
        });
        if hit != [NONE; 3] {
            add_triangle(self.chunks, before, own, tri, hit, sums);
        }
    }
}

/// How many triangles [`Tables::scan`], or normals [`any_pending`], tests
/// at a time.
const BLOCK: usize = 16;

/// Adds the angle-weighted unit normal of triangle `tri` (corner indices
/// into the run of vertices of `chunks`, `before` of them in the first and
/// `own` in the second) to the sums of its pending corners (`hit`, the
/// slot of each corner or [`NONE`]). Degenerate triangles and corners
/// outside the chunks add nothing.
#[inline(never)]
fn add_triangle(
    chunks: [Option<&Chunk>; 3],
    before: usize,
    own: usize,
    tri: [usize; 3],
    hit: [u32; 3],
    sums: &mut [[f64; 3]],
) {
    let position = |i: usize| -> Option<[f64; 3]> {
        let v = if i < before {
            chunks[0]?.vertices.get(i)
        } else if i < before + own {
            chunks[1]?.vertices.get(i - before)
        } else {
            chunks[2]?.vertices.get(i - before - own)
        };
        v.map(|p| p.map(f64::from))
    };
    let (Some(a), Some(b), Some(c)) = (position(tri[0]), position(tri[1]), position(tri[2])) else {
        return;
    };
    let p = [a, b, c];
    let normal = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let twice_area = dot(normal, normal).sqrt();
    if !(twice_area > 0.0 && twice_area.is_finite()) {
        return;
    }
    for k in 0..3 {
        if hit[k] == NONE {
            continue;
        }
        let u = sub(p[(k + 1) % 3], p[k]);
        let v = sub(p[(k + 2) % 3], p[k]);
        // |u x v| is twice the area at every corner.
        let angle = twice_area.atan2(dot(u, v));
        for (sum, n) in sums[hit[k] as usize].iter_mut().zip(normal) {
            *sum += angle * n / twice_area;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bumpy sheet of `w` by `h` vertices, two triangles a square, with
    /// the vertices `pending` marked pending and the others given `[1, 0, 0]`.
    fn sheet(w: usize, h: usize, pending: &[usize]) -> Chunk {
        let vertices: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                [x, y, (0.7 * x).sin() * (0.4 * y).cos()]
            })
            .collect();
        let mut triangles = Vec::new();
        for y in 0..h - 1 {
            for x in 0..w - 1 {
                let i = (y * w + x) as u32;
                let (w32, next) = (w as u32, (y * w + x + 1) as u32);
                triangles.push([i, next, i + w32]);
                triangles.push([next, next + w32, i + w32]);
            }
        }
        let mut normals = vec![[1.0, 0.0, 0.0]; w * h];
        for &p in pending {
            normals[p] = PENDING;
        }
        Chunk {
            plane: 0,
            vertices,
            triangles,
            normals,
            labels: Vec::new(),
            values: Vec::new(),
            encoded: Vec::new(),
        }
    }

    /// The angle-weighted normal at vertex `v` of `chunk`, from the
    /// angles' cosines (another way than `add_triangle`'s).
    fn expected(chunk: &Chunk, v: usize) -> [f64; 3] {
        let p = |i: u32| chunk.vertices[i as usize].map(f64::from);
        let mut sum = [0.0; 3];
        for t in &chunk.triangles {
            let Some(k) = t.iter().position(|&i| i as usize == v) else {
                continue;
            };
            let (a, b, c) = (p(t[k]), p(t[(k + 1) % 3]), p(t[(k + 2) % 3]));
            let n = cross(sub(p(t[1]), p(t[0])), sub(p(t[2]), p(t[0])));
            let (u, w) = (sub(b, a), sub(c, a));
            let cos = dot(u, w) / (dot(u, u) * dot(w, w)).sqrt();
            let length = dot(n, n).sqrt();
            for (s, c) in sum.iter_mut().zip(n) {
                *s += cos.acos() * c / length;
            }
        }
        let length = dot(sum, sum).sqrt();
        sum.map(|c| c / length)
    }

    /// A few pending vertices (each compared with the corners) and many
    /// (the span between the first and last), among more triangles than
    /// fill whole blocks: every pending vertex gets its triangles'
    /// angle-weighted normal, and no other normal changes.
    #[test]
    fn pending_vertices_get_their_triangles_normal() {
        let (w, h) = (21, 16);
        let few: Vec<usize> = vec![22, 160, 300];
        let many: Vec<usize> = (0..w * h).filter(|i| i % 7 == 3).collect();
        assert!(few.len() <= FEW && many.len() > FEW);
        for pending in [few, many] {
            let mut chunk = sheet(w, h, &pending);
            assert!(!chunk.triangles.len().is_multiple_of(BLOCK));
            resolve(None, &mut chunk, None);
            for (i, n) in chunk.normals.iter().enumerate() {
                if !pending.contains(&i) {
                    assert_eq!(*n, [1.0, 0.0, 0.0], "vertex {i}");
                    continue;
                }
                let want = expected(&chunk, i);
                for k in 0..3 {
                    assert!(
                        (f64::from(n[k]) - want[k]).abs() < 1e-5,
                        "vertex {i}: {n:?} {want:?}"
                    );
                }
            }
        }
    }
}
