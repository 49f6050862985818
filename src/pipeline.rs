//! The extraction entry point: parameters, slabs in parallel, seams stitched.

use crate::seam::Seam;
use crate::sink::{MeshBuilder, MeshInfo, MeshSink};
use crate::slab::process_slab;
use crate::volume::Padded;
use crate::{Error, Mesh, Result, SampleSource, Stats};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Which algorithm triangulates the cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Grosso's topologically correct and manifold hybrid marching cubes.
    #[default]
    Tmc,
    /// Standard marching cubes with one consistent face rule (inside corners
    /// of an ambiguous face are always separated).
    Mc,
}

/// Which side of the isovalue is the object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Inside {
    /// Values above the isovalue are inside (CT, MRI, densities).
    #[default]
    High,
    /// Values below the isovalue are inside (signed distance fields).
    Low,
}

/// Options of one extraction.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtractParams {
    /// The isovalue (finite).
    pub iso: f64,
    /// The cell algorithm.
    pub method: Method,
    /// Which side is the object.
    pub inside: Inside,
    /// Treat everything outside the volume as outside the object, so that
    /// every surface is closed.
    pub close: bool,
    /// Worker threads (0 = all cores).
    pub threads: usize,
}

impl Default for ExtractParams {
    fn default() -> Self {
        ExtractParams {
            iso: 0.0,
            method: Method::Tmc,
            inside: Inside::High,
            close: false,
            threads: 0,
        }
    }
}

/// How the pipeline runs (not what it computes: the output does not depend
/// on these).
#[derive(Clone, Copy, Default)]
pub struct PipelineOptions<'a> {
    /// Cell layers per slab; 0 chooses from the plane size.
    pub slab_depth: usize,
    /// Called on the writing thread after each slab is written.
    pub progress: Option<&'a (dyn Fn(&Progress) + Sync)>,
    /// Set to `true` (from any thread or a signal handler) to stop the
    /// extraction: it is looked at before each slab starts, before each
    /// chunk is written and before the output is finished (one relaxed
    /// atomic load each), and the extraction then returns
    /// [`Error::Interrupted`] without finishing the sink.
    pub cancel: Option<&'a AtomicBool>,
    /// A memory budget in bytes: the slab depth and the slabs in flight are
    /// chosen to fit it (see [`crate::budget`]), and the extraction fails
    /// with [`Error::OutOfMemory`] if even the thinnest slabs do not fit.
    /// `None`: no budget.
    pub max_memory: Option<u64>,
}

impl PipelineOptions<'_> {
    /// Fails with [`Error::Interrupted`] once the cancel flag is set (one
    /// relaxed load).
    fn check_cancel(&self) -> Result<()> {
        match self.cancel {
            Some(flag) if flag.load(Ordering::Relaxed) => Err(Error::Interrupted),
            _ => Ok(()),
        }
    }
}

/// How far an extraction has got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Cell layers written.
    pub layers_done: usize,
    /// Cell layers in all.
    pub layers_total: usize,
}

/// Extracts the isosurface of `source` at `params.iso` into an in-memory mesh.
pub fn extract(source: &dyn SampleSource, params: &ExtractParams) -> Result<(Mesh, Stats)> {
    let mut builder = MeshBuilder::default();
    let stats = extract_to(source, params, &PipelineOptions::default(), &mut builder)?;
    // The chunks are joined on as many threads as the extraction used.
    let pool = thread_pool(worker_threads(params))?;
    Ok((pool.install(|| builder.try_into_mesh())?, stats))
}

/// The number of worker threads `params` asks for (0: one per core).
fn worker_threads(params: &ExtractParams) -> usize {
    if params.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        params.threads
    }
}

/// A rayon pool of `threads` threads.
fn thread_pool(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))
}

/// Extracts the isosurface of `source` at `params.iso`, streaming chunks in
/// plane order to `sink`.
///
/// The cell layers are cut into slabs that worker threads triangulate in
/// parallel; at most a few slabs per thread are in flight, so memory is
/// bounded by the slab size, not by the volume or the mesh. The output does
/// not depend on the number of threads or on the slab depth.
pub fn extract_to(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
    sink: &mut dyn MeshSink,
) -> Result<Stats> {
    extract_part_to(source, params, options, None, sink)
}

/// [`extract_to`] restricted to part `i` of `n` (1-based): only the chunks of
/// that part's cell layers (see [`crate::part::layer_range`]) reach `sink`,
/// numbered from 0, exactly as a whole run writes them.
pub fn extract_part_to(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sink: &mut dyn MeshSink,
) -> Result<Stats> {
    let start = Instant::now();
    if !params.iso.is_finite() {
        return Err(Error::Invalid(format!(
            "the isovalue must be a finite number, not {}",
            params.iso
        )));
    }
    let info = MeshInfo {
        grid: *source.grid(),
        iso: params.iso,
        method: params.method,
        inside: params.inside,
        close: params.close,
    };
    let padded;
    let source: &dyn SampleSource = if params.close {
        padded = Padded::new(source);
        &padded
    } else {
        source
    };
    let dims = source.grid().dims;
    if dims.iter().any(|&d| d < 2) {
        return Err(Error::Invalid(format!(
            "the grid {}x{}x{} needs at least 2 samples along every axis",
            dims[0], dims[1], dims[2]
        )));
    }
    let layers = dims[2] - 1;
    let threads = worker_threads(params);
    let depth = if options.slab_depth > 0 {
        options.slab_depth.min(64)
    } else {
        // About 64M samples per slab, 16 to 64 layers: a slab re-reads the
        // plane it shares with the slab below, so thin slabs cost time, while
        // memory grows with the plane size far more than with the depth.
        ((64 << 20) / source.grid().plane_len().max(1)).clamp(16, 64)
    };
    let plan = crate::budget::plan(
        source.grid().plane_len(),
        threads,
        depth,
        options.max_memory,
    )?;
    let depth = plan.depth;
    options.check_cancel()?;
    let range = match part {
        Some((i, n)) => crate::part::layer_range(layers, i, n)?,
        None => 0..layers,
    };
    let slabs = crate::part::slabs(range, layers, depth);
    sink.begin(&info)?;
    let mut seam = Seam::new(sink).with_cancel(options.cancel);
    let report = |seam: &Seam| {
        if let Some(progress) = options.progress {
            let done = slabs[..seam.written()].iter().map(|r| r.len()).sum();
            progress(&Progress {
                layers_done: done,
                layers_total: slabs.iter().map(|r| r.len()).sum(),
            });
        }
    };
    let run = |i: usize| {
        options.check_cancel()?;
        source.check_unchanged()?;
        process_slab(source, params, slabs[i].clone())
    };
    if threads == 1 {
        for i in 0..slabs.len() {
            let (chunks, stats) = run(i)?;
            seam.accept(i, chunks, stats)?;
            report(&seam);
        }
    } else {
        let pool = thread_pool(threads)?;
        // At most `window` slabs computed but not yet written.
        let window = plan.window;
        let (tx, rx) = crossbeam::channel::unbounded();
        pool.in_place_scope(|scope| -> Result<()> {
            let run = &run;
            let launch = |i: usize| {
                let tx = tx.clone();
                scope.spawn(move |_| {
                    // The receiver outlives the scope; a send cannot fail.
                    let _ = tx.send((i, run(i)));
                });
            };
            let mut launched = 0;
            while launched < slabs.len().min(window) {
                launch(launched);
                launched += 1;
            }
            while seam.written() < slabs.len() {
                let (i, result) = rx.recv().expect("a worker holds a sender");
                let (chunks, stats) = result?;
                for _ in 0..seam.accept(i, chunks, stats)? {
                    if launched < slabs.len() {
                        launch(launched);
                        launched += 1;
                    }
                }
                report(&seam);
            }
            Ok(())
        })?;
    }
    options.check_cancel()?;
    let (mut stats, totals) = seam.finish()?;
    stats.vertices = totals.vertices;
    stats.triangles = totals.triangles;
    stats.slabs = slabs.len() as u64;
    stats.seconds = start.elapsed().as_secs_f64();
    Ok(stats)
}
