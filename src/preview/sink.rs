//! [`PreviewSink`]: a [`MeshSink`] that draws the mesh while it streams and
//! writes the picture when the mesh is complete.
//!
//! The sink holds one chunk at a time (its triangles may use the next
//! chunk's first vertices) and hands each chunk, with the prefix of the next
//! one it needs, to worker threads: raster workers that draw it into their
//! own depth buffers ([`Raster`], merged by the per-pixel minimum at the
//! end, so the picture does not depend on which worker drew what), and one
//! topology worker that counts it, in plane order, for the verdict
//! ([`StreamCheck`]). Channels between them are bounded, so memory is a few
//! chunks and one depth buffer per worker, whatever the mesh.

use super::lines::GridLines;
use super::picture;
use super::raster::Raster;
use super::views::{Bounds, View};
use crate::check::{Scratch, StreamCheck, Verdict};
use crate::{Chunk, Error, MeshInfo, MeshSink, Result, Totals};
use crossbeam::channel::{bounded, Sender};
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;

/// Raster workers at most, whatever the threads asked for.
const MAX_WORKERS: usize = 8;

/// A chunk with the next chunk's vertices its triangles use.
struct Job {
    /// The chunk's own vertices, then the next chunk's first `next`.
    vertices: Vec<[f32; 3]>,
    /// How many of `vertices` are the chunk's own.
    own: u32,
    /// Triangles, indices into `vertices`.
    triangles: Vec<[u32; 3]>,
}

/// The worker threads and the channels that feed them.
struct Workers {
    raster_tx: Option<Sender<Arc<Job>>>,
    topology_tx: Option<Sender<Arc<Job>>>,
    rasters: Vec<JoinHandle<(Raster, Option<GridLines>)>>,
    topology: Option<JoinHandle<Verdict>>,
    /// See [`Workers::start`].
    checked: bool,
}

impl Workers {
    /// Starts `threads` raster workers and the topology worker. With
    /// `lines`, the axis views whose lines are dense come from the
    /// vertices on grid lines and the others are rasterised; without, all
    /// four are. `checked`: the lines' grid may not be the mesh's
    /// ([`GridOfMesh::Recorded`]): all four views are rasterised too, and
    /// the lines are used only if the vertices were on them.
    fn start(views: [View; 4], threads: usize, lines: Option<GridLines>, checked: bool) -> Workers {
        let (raster_tx, raster_rx) = bounded::<Arc<Job>>(2 * threads + 2);
        let rasters = (0..threads)
            .map(|_| {
                let rx = raster_rx.clone();
                let mut lines = lines.clone();
                std::thread::spawn(move || {
                    let mut raster = Raster::empty();
                    for job in rx {
                        match &mut lines {
                            Some(l) => {
                                l.add(&job.vertices[..job.own as usize]);
                                for view in (0..4).filter(|&v| v == 3 || !l.dense(v) || checked) {
                                    raster.draw_view(&views, view, &job.vertices, &job.triangles);
                                }
                            }
                            None => raster.draw(&views, &job.vertices, &job.triangles),
                        }
                    }
                    (raster, lines)
                })
            })
            .collect();
        let (topology_tx, topology_rx) = bounded::<Arc<Job>>(2 * threads + 2);
        let topology = std::thread::spawn(move || {
            let (mut count, mut scratch) = (StreamCheck::default(), Scratch::default());
            for job in topology_rx {
                let next = job.vertices.len() as u32 - job.own;
                count.chunk(&mut scratch, job.own, next, &job.triangles);
            }
            count.finish()
        });
        Workers {
            raster_tx: Some(raster_tx),
            topology_tx: Some(topology_tx),
            rasters,
            topology: Some(topology),
            checked,
        }
    }

    /// Hands `job` to the workers.
    fn send(&self, job: Job) -> Result<()> {
        let job = Arc::new(job);
        let gone = || Error::Invalid("a preview worker stopped".into());
        let (Some(raster), Some(topology)) = (&self.raster_tx, &self.topology_tx) else {
            return Err(gone());
        };
        raster.send(Arc::clone(&job)).map_err(|_| gone())?;
        topology.send(job).map_err(|_| gone())
    }

    /// Waits for the workers; the merged depth buffers and the verdict.
    fn join(&mut self) -> (Raster, Verdict) {
        self.raster_tx = None;
        self.topology_tx = None;
        let mut merged: Option<(Raster, Option<GridLines>)> = None;
        for handle in self.rasters.drain(..) {
            let (raster, lines) = handle
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p));
            match &mut merged {
                Some((m, l)) => {
                    m.merge(&raster);
                    if let (Some(l), Some(lines)) = (l, &lines) {
                        l.merge(lines);
                    }
                }
                None => merged = Some((raster, lines)),
            }
        }
        let (mut raster, lines) = merged.unwrap_or_default();
        if let Some(lines) = lines.filter(|l| !self.checked || l.fit()) {
            for view in (0..3).filter(|&v| lines.dense(v)) {
                raster.set_tile(view, lines.tile(view));
            }
        }
        raster.complete();
        let verdict = self
            .topology
            .take()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .unwrap_or_default();
        (raster, verdict)
    }
}

impl Drop for Workers {
    fn drop(&mut self) {
        // Closing the channels ends the workers; their results are dropped.
        self.raster_tx = None;
        self.topology_tx = None;
        for handle in self.rasters.drain(..) {
            let _ = handle.join();
        }
        if let Some(h) = self.topology.take() {
            let _ = h.join();
        }
    }
}

/// Draws the mesh it is given into a PNG picture at `path`: four views
/// (three orthogonal, one oblique), a caption naming `title`, the
/// isovalue, the triangle count and the topology verdict. The file is
/// written atomically in [`MeshSink::finish`]; a sink dropped before that
/// leaves nothing.
pub struct PreviewSink {
    /// Where the picture goes; `None` keeps it in memory
    /// ([`PreviewSink::in_memory`]).
    path: Option<PathBuf>,
    title: String,
    bounds: Option<Bounds>,
    /// What [`MeshInfo::grid`] is to the mesh.
    grid: GridOfMesh,
    threads: usize,
    iso: f64,
    workers: Option<Workers>,
    /// The chunk waiting for the next one's vertices, and how many of those
    /// its triangles use.
    pending: Option<(Job, u32)>,
    /// What the finished picture showed: covered pixels and the verdict.
    summary: Option<(usize, Verdict)>,
    /// The finished picture's RGB bytes, kept by a sink without a path.
    picture: Option<Vec<u8>>,
}

/// What the grid of [`MeshInfo`] is to the mesh a [`PreviewSink`] draws.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum GridOfMesh {
    /// The grid it is being extracted on: its axis views come from the
    /// grid lines when [`GridLines::new`] allows.
    Extracted,
    /// A `.tmesh`'s: the grid it was extracted on, but with the identity
    /// direction whatever the direction was (the format keeps none). The
    /// views are drawn both ways, and the lines kept only if the vertices
    /// were on them ([`GridLines::fit`]): on an unrotated grid, the same
    /// picture as the extraction's; on a rotated one, every view from the
    /// triangles (framed by the unrotated grid's box).
    Recorded,
    /// A grid that says nothing of the mesh: every view rasterised.
    Unknown,
}

impl PreviewSink {
    /// A sink that writes the picture to `path`. `bounds` frames the views;
    /// `None` takes the grid of [`MeshInfo`] widened by a cell (the
    /// volume's box, known before any triangle). `threads` raster workers
    /// draw (0: one per core; at most 8); the bytes do not depend on it.
    /// A NaN isovalue in [`MeshInfo`] (a mesh file without one) is left
    /// out of the caption.
    pub fn new(path: PathBuf, title: String, bounds: Option<Bounds>, threads: usize) -> Self {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n,
        };
        PreviewSink {
            path: Some(path),
            title,
            bounds,
            grid: GridOfMesh::Extracted,
            // Each worker holds at most 1 MiB of depth buffers (256 KiB per
            // view it draws) and at most 3 MiB of line depths.
            threads: threads.clamp(1, MAX_WORKERS),
            iso: f64::NAN,
            workers: None,
            pending: None,
            summary: None,
            picture: None,
        }
    }

    /// A sink as [`PreviewSink::new`] that writes no file: the finished
    /// picture's RGB bytes ([`picture::DIMENSIONS`]) are kept for
    /// [`PreviewSink::take_picture`] (`tmc compare --preview` puts two of
    /// them side by side).
    pub fn in_memory(title: String, bounds: Option<Bounds>, threads: usize) -> Self {
        let mut sink = PreviewSink::new(PathBuf::new(), title, bounds, threads);
        sink.path = None;
        sink
    }

    /// The sink for a mesh whose [`MeshInfo::grid`] is not the grid it was
    /// extracted from (a mesh file without one): every view is rasterised
    /// from the triangles.
    pub fn without_grid(mut self) -> Self {
        self.grid = GridOfMesh::Unknown;
        self
    }

    /// The sink for a mesh whose [`MeshInfo::grid`] was recorded with it
    /// (a `.tmesh`), without its direction: the axis views are drawn from
    /// the triangles and from the grid lines, and the lines kept only if
    /// the vertices were on them ([`GridLines::fit`]); a mesh extracted on
    /// a rotated grid is then drawn from its triangles.
    pub fn with_recorded_grid(mut self) -> Self {
        self.grid = GridOfMesh::Recorded;
        self
    }

    /// After `finish` of a sink made by [`PreviewSink::in_memory`]: the
    /// picture, row by row, 8-bit RGB.
    pub fn take_picture(&mut self) -> Option<Vec<u8>> {
        self.picture.take()
    }

    /// The path in messages.
    fn shown_path(&self) -> String {
        self.path
            .as_ref()
            .map_or_else(|| "preview".into(), |p| p.display().to_string())
    }

    /// After `finish`: the pixels of the tiles that are not background, and
    /// the topology verdict.
    pub fn summary(&self) -> Option<(usize, Verdict)> {
        self.summary
    }

    /// Sends the pending chunk with the first `next` vertices of `after`.
    fn flush(&mut self, after: &[[f32; 3]]) -> Result<()> {
        let Some((mut job, next)) = self.pending.take() else {
            return Ok(());
        };
        let next = next as usize;
        if next > after.len() {
            return Err(Error::Invalid(format!(
                "{}: a triangle refers to a vertex past the next chunk's",
                self.shown_path()
            )));
        }
        job.vertices.extend_from_slice(&after[..next]);
        match &self.workers {
            Some(w) => w.send(job),
            None => Err(Error::Invalid("preview: chunk before begin".into())),
        }
    }
}

impl MeshSink for PreviewSink {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        let bounds = match self.bounds.or_else(|| Bounds::of_grid(&info.grid)) {
            Some(b) => b,
            None => {
                return Err(Error::Invalid(format!(
                    "{}: the mesh has no finite bounds to frame a preview",
                    self.shown_path()
                )))
            }
        };
        self.iso = info.iso;
        let views = View::four(&bounds);
        let lines = match self.grid {
            GridOfMesh::Unknown => None,
            _ => GridLines::new(&info.grid, &views),
        };
        let checked = self.grid == GridOfMesh::Recorded;
        self.workers = Some(Workers::start(views, self.threads, lines, checked));
        Ok(())
    }

    fn chunk(&mut self, _base: u64, chunk: &Chunk) -> Result<()> {
        self.flush(&chunk.vertices)?;
        let own = chunk.vertices.len();
        let Ok(own32) = u32::try_from(own) else {
            return Err(Error::Invalid("preview: chunk too large".into()));
        };
        let top = chunk
            .triangles
            .iter()
            .map(|t| t[0].max(t[1]).max(t[2]))
            .max();
        let past = top.map_or(0, |i| i.saturating_add(1).saturating_sub(own32));
        // Room for the next chunk's vertices too (`flush`).
        let mut vertices = Vec::with_capacity(own + past as usize);
        vertices.extend_from_slice(&chunk.vertices);
        let job = Job {
            vertices,
            own: own32,
            triangles: chunk.triangles.clone(),
        };
        self.pending = Some((job, past));
        Ok(())
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.flush(&[])?;
        let mut workers = self
            .workers
            .take()
            .ok_or_else(|| Error::Invalid("preview: finish before begin".into()))?;
        let (raster, verdict) = workers.join();
        let caption = [
            self.title.clone(),
            format!(
                "{}{} triangles   {}",
                if self.iso.is_nan() {
                    String::new()
                } else {
                    format!("iso {}   ", self.iso)
                },
                thousands(totals.triangles),
                verdict.describe()
            ),
        ];
        let rgb = picture::compose(&raster, &caption);
        let (w, h) = picture::DIMENSIONS;
        match &self.path {
            Some(path) => super::png_out::write_png(path, w, h, &rgb)?,
            None => self.picture = Some(rgb),
        }
        self.summary = Some((picture::covered(&raster), verdict));
        Ok(())
    }
}

/// `n` with a comma between groups of three digits.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}
