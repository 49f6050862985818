//! A label's figures counted while its chunks stream (`tmc extract
//! --labels --stats` and `--json`, the Python package's
//! `extract_labels_to`): [`Measured`], a sink wrapper that passes each
//! chunk on to the label's file and counts it, and [`Measurement`], what
//! it counted once the last chunk is in, which fills the label's
//! [`LabelReport`] ([`measure_reports`]).
//!
//! The figures are a [`StreamCheck::full`] (components, genus, closed: the
//! figures `tmc check` gives the label's file) and the [`SurfaceSums`]
//! (area and enclosed volume, summed in the order of the file), both over
//! a window of two chunks: each chunk waits for the next one's vertices,
//! which its triangles end in. Memory does not grow with the mesh, and a
//! label absent from the planes being written holds nothing but counters.
//! The CLI and the Python package share this file, so that they report
//! the same figures to the last bit.

use super::stream::{Scratch, StreamCheck, Verdict};
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Totals};
use crate::stream::label_report::{LabelReport, SurfaceSums};
use crate::{Error, Result};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::atomic::AtomicBool;

/// A label's sink in a label map's pass: its file's (any [`MeshSink`],
/// to which every call is passed on) and, when measured, its figures
/// counted from each chunk before the file gets it.
pub struct Measured<'a> {
    sink: &'a mut dyn MeshSink,
    measure: Option<Measure>,
}

impl<'a> Measured<'a> {
    /// Each of `sinks` wrapped, measured when `measure` is set. The checks
    /// share one working space ([`Scratch`]): a label map's pass writes
    /// one label's chunk at a time.
    pub fn all(
        sinks: impl IntoIterator<Item = &'a mut dyn MeshSink>,
        measure: bool,
    ) -> Vec<Measured<'a>> {
        let scratch = Rc::new(RefCell::new(Scratch::default()));
        sinks
            .into_iter()
            .map(|sink| Measured {
                sink,
                measure: measure.then(|| Measure::new(Rc::clone(&scratch))),
            })
            .collect()
    }

    /// The figures, once the last chunk is in (`None` when not measured);
    /// an error when a triangle of the last chunk refers to a vertex past
    /// it.
    pub fn finish(self) -> Result<Option<Measurement>> {
        self.measure.map(Measure::finish).transpose()
    }
}

/// Finishes each of `sinks` ([`Measured::finish`]) and fills the figures
/// of the label's report, `reports` in the order of `sinks`.
pub fn measure_reports(sinks: Vec<Measured<'_>>, reports: &mut [LabelReport]) -> Result<()> {
    for (sink, report) in sinks.into_iter().zip(reports) {
        if let Some(measurement) = sink.finish()? {
            measurement.fill(report);
        }
    }
    Ok(())
}

/// What a [`Measured`] sink counted of its mesh.
#[derive(Debug, Clone, Copy)]
pub struct Measurement {
    /// The streaming check's verdict (from [`StreamCheck::full`]).
    pub verdict: Verdict,
    /// Area and enclosed volume.
    pub sums: SurfaceSums,
}

impl Measurement {
    /// Sets `report`'s components, genus, closed, area and enclosed
    /// volume (only for a closed manifold, as the genus only for an
    /// oriented one); left as they are when the verdict has no figures of
    /// [`check_mesh`](super::check_mesh) ([`Verdict::checked`]).
    pub fn fill(&self, report: &mut LabelReport) {
        let Some(checked) = self.verdict.checked() else {
            return;
        };
        report.components = Some(checked.components as usize);
        report.genus = checked.genus;
        report.closed = Some(checked.closed_manifold);
        report.area = Some(self.sums.area);
        // The divergence sum is a volume only over a closed surface: over
        // an open one (a label at the border without `--close`) it moves
        // with the origin.
        report.enclosed_volume = checked.closed_manifold.then_some(self.sums.volume);
    }
}

/// The counting of a [`Measured`] sink: the check, the sums and the chunk
/// waiting for the next one's vertices.
struct Measure {
    check: StreamCheck,
    /// The working space of every label's check.
    scratch: Rc<RefCell<Scratch>>,
    sums: SurfaceSums,
    pending: Option<Pending>,
}

/// The last chunk's vertices (with room for the next one's first) and
/// triangles, and how many of the next chunk's vertices they use.
struct Pending {
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    next: u32,
}

impl Measure {
    fn new(scratch: Rc<RefCell<Scratch>>) -> Self {
        Measure {
            check: StreamCheck::full(),
            scratch,
            sums: SurfaceSums::default(),
            pending: None,
        }
    }

    /// Counts the pending chunk with the first vertices of `after` (none
    /// after the last).
    fn flush(&mut self, after: &[[f32; 3]]) -> Result<()> {
        let Some(Pending {
            mut vertices,
            triangles,
            next,
        }) = self.pending.take()
        else {
            return Ok(());
        };
        let Some(first) = after.get(..next as usize) else {
            return Err(Error::Invalid(
                "a label's triangle refers to a vertex past the next chunk's".into(),
            ));
        };
        let own = vertices.len() as u32;
        vertices.extend_from_slice(first);
        self.sums.add(&vertices, &triangles);
        let mut scratch = self.scratch.borrow_mut();
        self.check.chunk(&mut scratch, own, next, &triangles);
        Ok(())
    }

    /// Takes `chunk` in, counting the one before.
    fn chunk(&mut self, chunk: &Chunk) -> Result<()> {
        self.flush(&chunk.vertices)?;
        let Ok(own) = u32::try_from(chunk.vertices.len()) else {
            return Err(Error::Invalid("a label's chunk is too large".into()));
        };
        let top = chunk
            .triangles
            .iter()
            .map(|t| t[0].max(t[1]).max(t[2]))
            .max();
        let next = top.map_or(0, |i| i.saturating_add(1).saturating_sub(own));
        let mut vertices = Vec::with_capacity(own as usize + next as usize);
        vertices.extend_from_slice(&chunk.vertices);
        self.pending = Some(Pending {
            vertices,
            triangles: chunk.triangles.clone(),
            next,
        });
        Ok(())
    }

    /// The verdict and the sums once the last chunk is in.
    fn finish(mut self) -> Result<Measurement> {
        self.flush(&[])?;
        Ok(Measurement {
            verdict: self.check.finish(),
            sums: self.sums,
        })
    }
}

impl MeshSink for Measured<'_> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.sink.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        if let Some(m) = &mut self.measure {
            m.chunk(chunk)?;
        }
        self.sink.chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        if let Some(m) = &mut self.measure {
            m.chunk(chunk)?;
        }
        self.sink.chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.sink.finish(totals)
    }

    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.sink.finish_cancellable(totals, cancel)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.sink.encoder()
    }
}
