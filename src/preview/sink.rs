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
//!
//! The views are fitted before the first triangle. For a `.tmesh`
//! ([`PreviewSink::with_recorded_grid`]) that is to the recorded grid's
//! box, which holds the mesh unless the grid was rotated or mirrored (the
//! format keeps no direction cosines); the workers also track the
//! vertices' box ([`Reach`]), and when it leaves the frame the sink writes
//! nothing and [`PreviewSink::reframed`] gives the sink of a second pass
//! over the mesh, framed by that box.

use super::frame::Reach;
use super::lines::GridLines;
use super::picture;
use super::raster::{label_mark, Raster};
use super::views::{Bounds, View};
use crate::check::{Scratch, StreamCheck, Verdict};
use crate::{Chunk, Error, MeshInfo, MeshSink, Result, Totals};
use crossbeam::channel::{bounded, Sender};
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;

/// Raster workers at most, whatever the threads asked for.
const MAX_WORKERS: usize = 8;

/// A chunk with the next chunk's vertices its triangles use.
struct Job {
    /// The mesh it belongs to: 0, or a label's number in a picture of
    /// several meshes ([`PreviewSink::chunk_of`]).
    stream: u32,
    /// The chunk's own vertices, then the next chunk's first `next`.
    vertices: Vec<[f32; 3]>,
    /// How many of `vertices` are the chunk's own.
    own: u32,
    /// Triangles, indices into `vertices`.
    triangles: Vec<[u32; 3]>,
    /// In a picture of labels, each triangle's colour ([`label_mark`]);
    /// empty otherwise.
    marks: Vec<u32>,
}

/// What a raster worker hands back: its depth buffers, its grid lines
/// and the box of the vertices it was handed (tracked when `checked`,
/// [`Workers::start`]).
struct Drawn {
    raster: Raster,
    lines: Option<GridLines>,
    reach: Reach,
}

/// The workers' results merged: the depth buffers and the verdict, or,
/// when the mesh left the frame, the box of its vertices to frame it by.
enum Joined {
    /// The picture's depth buffers and the verdict.
    Drawn(Raster, Verdict),
    /// A vertex fell outside the frame: the vertices' box, and the verdict.
    Reframe(Bounds, Verdict),
}

/// The worker threads and the channels that feed them.
struct Workers {
    raster_tx: Option<Sender<Arc<Job>>>,
    /// `None` when the verdict is known ([`Workers::start`]).
    topology_tx: Option<Sender<Arc<Job>>>,
    rasters: Vec<JoinHandle<Drawn>>,
    topology: Option<JoinHandle<Verdict>>,
    /// The verdict of an earlier pass over the same mesh.
    known: Option<Verdict>,
    /// See [`Workers::start`].
    checked: bool,
    /// What the views were fitted to.
    frame: Bounds,
}

impl Workers {
    /// Starts `threads` raster workers and the topology worker. With
    /// `lines`, the axis views whose lines are dense come from the
    /// vertices on grid lines and the others are rasterised; without, all
    /// four are. `checked`: the lines' grid may not be the mesh's
    /// ([`GridOfMesh::Recorded`]): all four views are rasterised too, and
    /// the lines are used only if the vertices were on them, and the
    /// vertices' box is tracked, to tell whether they stayed in `frame`
    /// (what `views` were fitted to). `known`: the verdict of an earlier
    /// pass over the same mesh, which no topology worker counts again.
    fn start(
        frame: Bounds,
        threads: usize,
        lines: Option<GridLines>,
        checked: bool,
        known: Option<Verdict>,
    ) -> Workers {
        let views = View::four(&frame);
        let (raster_tx, raster_rx) = bounded::<Arc<Job>>(2 * threads + 2);
        let rasters = (0..threads)
            .map(|_| {
                let rx = raster_rx.clone();
                let mut lines = lines.clone();
                std::thread::spawn(move || {
                    let mut raster = Raster::empty();
                    let mut reach = Reach::default();
                    for job in rx {
                        if checked {
                            reach.add(&job.vertices[..job.own as usize]);
                        }
                        match &mut lines {
                            Some(l) => {
                                l.add(&job.vertices[..job.own as usize]);
                                for view in (0..4).filter(|&v| v == 3 || !l.dense(v) || checked) {
                                    raster.draw_view(&views, view, &job.vertices, &job.triangles);
                                }
                            }
                            None if job.marks.is_empty() => {
                                raster.draw(&views, &job.vertices, &job.triangles)
                            }
                            None => raster.draw_labelled(
                                &views,
                                &job.vertices,
                                &job.triangles,
                                &job.marks,
                            ),
                        }
                    }
                    Drawn {
                        raster,
                        lines,
                        reach,
                    }
                })
            })
            .collect();
        let (topology_tx, topology) = match known {
            Some(_) => (None, None),
            None => {
                let (tx, rx) = bounded::<Arc<Job>>(2 * threads + 2);
                let topology = std::thread::spawn(move || {
                    // One count per mesh, each fed its chunks in plane order.
                    let mut counts = vec![StreamCheck::default()];
                    let mut scratch = Scratch::default();
                    for job in rx {
                        let stream = job.stream as usize;
                        if counts.len() <= stream {
                            counts.resize_with(stream + 1, StreamCheck::default);
                        }
                        let next = job.vertices.len() as u32 - job.own;
                        counts[stream].chunk(&mut scratch, job.own, next, &job.triangles);
                    }
                    let verdicts = counts.into_iter().map(StreamCheck::finish);
                    verdicts.reduce(Verdict::with).unwrap_or_default()
                });
                (Some(tx), Some(topology))
            }
        };
        Workers {
            raster_tx: Some(raster_tx),
            topology_tx,
            rasters,
            topology,
            known,
            checked,
            frame,
        }
    }

    /// Hands `job` to the workers.
    fn send(&self, job: Job) -> Result<()> {
        let job = Arc::new(job);
        let gone = || Error::Invalid("a preview worker stopped".into());
        let Some(raster) = &self.raster_tx else {
            return Err(gone());
        };
        match (&self.topology_tx, self.known) {
            (Some(topology), _) => {
                raster.send(Arc::clone(&job)).map_err(|_| gone())?;
                topology.send(job).map_err(|_| gone())
            }
            (None, Some(_)) => raster.send(job).map_err(|_| gone()),
            (None, None) => Err(gone()),
        }
    }

    /// Waits for the workers; the merged depth buffers and the verdict, or
    /// (`checked`) the vertices' box when they left the frame.
    fn join(&mut self) -> Joined {
        self.raster_tx = None;
        self.topology_tx = None;
        let mut merged: Option<Drawn> = None;
        for handle in self.rasters.drain(..) {
            let drawn = handle
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p));
            match &mut merged {
                Some(m) => {
                    m.raster.merge(&drawn.raster);
                    if let (Some(l), Some(lines)) = (&mut m.lines, &drawn.lines) {
                        l.merge(lines);
                    }
                    m.reach.merge(&drawn.reach);
                }
                None => merged = Some(drawn),
            }
        }
        let verdict = self
            .topology
            .take()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .or(self.known)
            .unwrap_or_default();
        let Some(Drawn {
            mut raster,
            lines,
            reach,
        }) = merged
        else {
            let mut raster = Raster::empty();
            raster.complete();
            return Joined::Drawn(raster, verdict);
        };
        if self.checked && !reach.within(&self.frame) {
            if let Some(bounds) = reach.bounds() {
                return Joined::Reframe(bounds, verdict);
            }
        }
        if let Some(lines) = lines.filter(|l| !self.checked || l.fit()) {
            for view in (0..3).filter(|&v| lines.dense(v)) {
                raster.set_tile(view, lines.tile(view));
            }
        }
        raster.complete();
        Joined::Drawn(raster, verdict)
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
    /// Per mesh ([`PreviewSink::chunk_of`]), the chunk waiting for the
    /// next one's vertices, and how many of those its triangles use.
    pending: Vec<Option<(Job, u32)>>,
    /// What the finished picture showed: covered pixels and the verdict.
    summary: Option<(usize, Verdict)>,
    /// The finished picture's RGB bytes, kept by a sink without a path.
    picture: Option<Vec<u8>>,
    /// For the second pass over a mesh ([`PreviewSink::reframed`]): the
    /// first pass's verdict and totals.
    known: Option<(Verdict, Totals)>,
    /// The labels with a triangle: the meshes of [`PreviewSink::chunk_of`]
    /// that have one, or the triangles' labels of a labelled mesh (a
    /// `.tmesh` of every label of a map). Named in the caption, which then
    /// gives no isovalue (a label's surface is at 0.5 of its indicator).
    labels: BTreeSet<u32>,
    /// Whether the picture shows several labels' surfaces, each in its
    /// label's colour ([`PreviewSink::of_labels`], or a mesh whose chunks
    /// carry labels): every view is then rasterised, with the triangles'
    /// labels in the keys.
    labelled: bool,
    /// The label of each mesh of [`PreviewSink::chunk_of`] (its number
    /// where none is given), as a labelled mesh file keeps it (`as u32`).
    stream_labels: Vec<u32>,
    /// After a first pass whose mesh left the frame: the vertices' box,
    /// the verdict and the totals ([`PreviewSink::reframed`]).
    again: Option<(Bounds, Verdict, Totals)>,
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
    /// triangles, framed by the unrotated grid's box if the mesh lies in
    /// it, else by the mesh's own box in a second pass
    /// ([`PreviewSink::reframed`]).
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
            pending: vec![None],
            summary: None,
            picture: None,
            known: None,
            again: None,
            labels: BTreeSet::new(),
            labelled: false,
            stream_labels: Vec::new(),
        }
    }

    /// The sink for the surfaces of the labels `labels` of a label map, fed
    /// by [`PreviewSink::chunk_of`] (mesh `i` is label `labels[i]`'s): each
    /// surface in its label's colour, the colour a labelled mesh file of
    /// the same labels gets, so that the picture is that file's.
    pub fn of_labels(mut self, labels: &[i64]) -> Self {
        self.labelled = true;
        // The label as the mesh files keep it (export::labelled).
        self.stream_labels = labels.iter().map(|&l| l as u32).collect();
        self
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
    /// a rotated grid is then drawn from its triangles. If a vertex falls
    /// outside the box the views were framed by (a rotated or mirrored
    /// grid's mesh), `finish` writes nothing: see
    /// [`PreviewSink::reframed`].
    pub fn with_recorded_grid(mut self) -> Self {
        self.grid = GridOfMesh::Recorded;
        self
    }

    /// After `finish` of a sink made [`PreviewSink::with_recorded_grid`]
    /// that wrote no picture because a vertex fell outside the frame: the
    /// sink of a second pass over the same mesh (its chunks given again
    /// from `begin`), framed by the box of its vertices and drawn from its
    /// triangles (the picture `tmc preview` draws of the mesh as a PLY,
    /// with the isovalue in the caption). The verdict of the first pass is
    /// kept, not counted again; the second pass fails if the totals
    /// differ. `None` when the first pass wrote its picture.
    pub fn reframed(&mut self) -> Option<PreviewSink> {
        let (bounds, verdict, totals) = self.again.take()?;
        let mut sink = PreviewSink::new(PathBuf::new(), self.title.clone(), Some(bounds), 1);
        sink.path.clone_from(&self.path);
        sink.threads = self.threads;
        sink.grid = GridOfMesh::Unknown;
        sink.known = Some((verdict, totals));
        sink.labelled = self.labelled;
        sink.stream_labels.clone_from(&self.stream_labels);
        Some(sink)
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

    /// Sends mesh `stream`'s pending chunk with the first `next` vertices
    /// of `after`.
    fn flush(&mut self, stream: usize, after: &[[f32; 3]]) -> Result<()> {
        let Some((mut job, next)) = self.pending.get_mut(stream).and_then(Option::take) else {
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
        self.labelled |= info.labels;
        let lines = match self.grid {
            GridOfMesh::Unknown => None,
            // The lines keep no label: every view from the triangles.
            _ if self.labelled => None,
            _ => GridLines::new(&info.grid, &View::four(&bounds)),
        };
        let checked = self.grid == GridOfMesh::Recorded;
        let known = self.known.map(|(verdict, _)| verdict);
        self.workers = Some(Workers::start(bounds, self.threads, lines, checked, known));
        Ok(())
    }

    fn chunk(&mut self, _base: u64, chunk: &Chunk) -> Result<()> {
        let mut last = None;
        for &label in &chunk.labels {
            if last != Some(label) {
                self.labels.insert(label);
                last = Some(label);
            }
        }
        // One mark per triangle in a labelled picture (label 0's colour for
        // a triangle without a label), so that no chunk is drawn unmarked.
        let marks = match self.labelled {
            true => (0..chunk.triangles.len())
                .map(|i| label_mark(chunk.labels.get(i).copied().unwrap_or(0)))
                .collect(),
            false => Vec::new(),
        };
        self.hand_over(0, chunk, marks)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        for stream in 0..self.pending.len() {
            self.flush(stream, &[])?;
        }
        self.draw(totals)
    }
}

impl PreviewSink {
    /// [`MeshSink::chunk`] of one of several meshes drawn into one picture
    /// (the labels of a label map): `stream` numbers the mesh, whose chunks
    /// come in plane order, each mesh's vertices numbered from 0. The
    /// verdict sums the meshes' counts (components, edges, genus).
    pub fn chunk_of(&mut self, stream: usize, chunk: &Chunk) -> Result<()> {
        if !chunk.triangles.is_empty() {
            let label = u32::try_from(stream).unwrap_or(u32::MAX);
            self.labels.insert(label);
        }
        let marks = match self.labelled {
            true => {
                let number = u32::try_from(stream).unwrap_or(u32::MAX);
                let label = self.stream_labels.get(stream).copied().unwrap_or(number);
                vec![label_mark(label); chunk.triangles.len()]
            }
            false => Vec::new(),
        };
        self.hand_over(stream, chunk, marks)
    }

    /// Hands `chunk` of mesh `stream` over: the chunk before it, now that
    /// its next vertices are known, to the workers; this one kept.
    fn hand_over(&mut self, stream: usize, chunk: &Chunk, marks: Vec<u32>) -> Result<()> {
        let Ok(stream32) = u32::try_from(stream) else {
            return Err(Error::Invalid("preview: too many meshes".into()));
        };
        if self.pending.len() <= stream {
            self.pending.resize_with(stream + 1, || None);
        }
        self.flush(stream, &chunk.vertices)?;
        let own = chunk.vertices.len();
        let Ok(own32) = u32::try_from(own) else {
            return Err(Error::Invalid("preview: chunk too large".into()));
        };
        // The largest index of all, over the flat list (a reduction the
        // compiler does several indices at a time).
        let top = chunk.triangles.as_flattened().iter().copied().max();
        let past = top.map_or(0, |i| i.saturating_add(1).saturating_sub(own32));
        // Room for the next chunk's vertices too (`flush`).
        let mut vertices = Vec::with_capacity(own + past as usize);
        vertices.extend_from_slice(&chunk.vertices);
        let job = Job {
            stream: stream32,
            vertices,
            own: own32,
            triangles: chunk.triangles.clone(),
            marks,
        };
        self.pending[stream] = Some((job, past));
        Ok(())
    }

    /// Ends mesh `stream` of several ([`PreviewSink::chunk_of`]): its last
    /// chunk is drawn.
    pub fn end_of(&mut self, stream: usize) -> Result<()> {
        self.flush(stream, &[])
    }

    /// Draws the picture, all chunks handed over.
    fn draw(&mut self, totals: &Totals) -> Result<()> {
        let mut workers = self
            .workers
            .take()
            .ok_or_else(|| Error::Invalid("preview: finish before begin".into()))?;
        if let Some((_, first)) = self.known {
            if first != *totals {
                return Err(Error::Invalid(format!(
                    "{}: the mesh read again to frame it is not the one read first \
                     ({} triangles, then {})",
                    self.shown_path(),
                    first.triangles,
                    totals.triangles
                )));
            }
        }
        let (raster, verdict) = match workers.join() {
            Joined::Drawn(raster, verdict) => (raster, verdict),
            Joined::Reframe(bounds, verdict) => {
                self.again = Some((bounds, verdict, *totals));
                return Ok(());
            }
        };
        let labels = self.labels.len() as u64;
        let caption = [
            match labels {
                0 => self.title.clone(),
                n => format!("{}   {n} label{}", self.title, crate::check::plural(n)),
            },
            format!(
                "{}{} triangle{}   {}",
                if self.iso.is_nan() || labels > 0 {
                    String::new()
                } else {
                    format!("iso {}   ", crate::params::number_text(self.iso))
                },
                thousands(totals.triangles),
                crate::check::plural(totals.triangles),
                verdict.describe()
            ),
        ];
        let rgb = picture::compose(&raster, &caption, self.labelled);
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
