//! Seams: slabs finished in any order become one stream of chunks with
//! global vertex numbers.
//!
//! Each chunk's vertices get consecutive global numbers in plane order. A
//! vertex on a slab seam is computed by both slabs but owned by the chunk of
//! its plane, and both slabs number it the same way, so the seam is exact by
//! construction: nothing is matched by position, and no hash map is needed
//! across slabs or across part files (`tmc merge` only adds the vertex
//! counts of the parts before).

use crate::mesh::{Chunk, MeshSink, Totals};
use crate::normals::FillPending;
use crate::slab::Spares;
use crate::{Result, Stats};
use std::collections::BTreeMap;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Reorders finished slabs and forwards their chunks to a sink in plane
/// order, through the sink's [`FillPending`], which takes them by value.
pub struct Seam<'a, 's> {
    sink: &'a mut FillPending<'s>,
    pending: BTreeMap<usize, (Vec<Chunk>, Stats)>,
    next: usize,
    totals: Totals,
    stats: Stats,
    cancel: Option<&'a AtomicBool>,
    spares: Option<&'a Spares>,
}

impl<'a, 's> Seam<'a, 's> {
    /// A seam feeding `sink`, expecting slab 0 first.
    pub fn new(sink: &'a mut FillPending<'s>) -> Self {
        Seam {
            sink,
            pending: BTreeMap::new(),
            next: 0,
            totals: Totals::default(),
            stats: Stats::default(),
            cancel: None,
            spares: None,
        }
    }

    /// Makes [`Seam::accept`] fail with [`crate::Error::Interrupted`] once `flag`
    /// is set, before the next chunk or within one
    /// ([`MeshSink::chunk_cancellable`]).
    pub fn with_cancel(mut self, flag: Option<&'a AtomicBool>) -> Self {
        self.cancel = flag;
        self
    }

    /// Hands the vectors of every written chunk to `spares`, for the slabs
    /// still to come.
    pub fn with_spares(mut self, spares: &'a Spares) -> Self {
        self.spares = Some(spares);
        self
    }

    /// Accepts slab `index`; writes it and every waiting successor when it
    /// is the next one due. Returns how many slabs were written.
    pub fn accept(&mut self, index: usize, chunks: Vec<Chunk>, stats: Stats) -> Result<usize> {
        self.pending.insert(index, (chunks, stats));
        let mut written = 0;
        while let Some((chunks, stats)) = self.pending.remove(&self.next) {
            let start = Instant::now();
            for chunk in chunks {
                let (vertices, triangles) = (chunk.vertices.len(), chunk.triangles.len());
                let done = self.sink.push(chunk, self.cancel)?;
                if let (Some(spares), Some(done)) = (self.spares, done) {
                    spares.give_chunk(done);
                }
                self.totals.vertices += vertices as u64;
                self.totals.triangles += triangles as u64;
                self.totals.chunks += 1;
            }
            self.stats.add_counts(&stats);
            self.stats.write_seconds += start.elapsed().as_secs_f64();
            self.next += 1;
            written += 1;
        }
        Ok(written)
    }

    /// Slabs written so far.
    pub fn written(&self) -> usize {
        self.next
    }

    /// Finishes the sink; returns the summed counts and the totals.
    pub fn finish(mut self) -> Result<(Stats, Totals)> {
        let start = Instant::now();
        match self.cancel {
            Some(cancel) => self.sink.finish_cancellable(&self.totals, cancel)?,
            None => self.sink.finish(&self.totals)?,
        }
        self.stats.write_seconds += start.elapsed().as_secs_f64();
        Ok((self.stats, self.totals))
    }
}
