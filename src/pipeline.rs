//! The extraction entry point: parameters, slabs in parallel, seams stitched.

use crate::sink::{MeshBuilder, MeshSink};
use crate::{Error, Mesh, Result, SampleSource, Stats};
use std::sync::atomic::{AtomicBool, Ordering};

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
    /// A memory budget in bytes: the workers' buffers are planned to fit it
    /// (see [`crate::budget`]; the extraction fails with
    /// [`Error::OutOfMemory`] if even the thinnest slabs do not fit), and
    /// slabs start only as far as the measured mesh in flight allows (see
    /// [`crate::schedule`]).
    /// `None`: no budget.
    pub max_memory: Option<u64>,
}

impl PipelineOptions<'_> {
    /// Fails with [`Error::Interrupted`] once the cancel flag is set (one
    /// relaxed load).
    pub(crate) fn check_cancel(&self) -> Result<()> {
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
    Ok((builder.into_mesh(), stats))
}

/// The number of worker threads `params` asks for (0: one per core).
pub(crate) fn worker_threads(params: &ExtractParams) -> usize {
    if params.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        params.threads
    }
}

/// The slab depth when none is asked for: about 64M samples per slab, 16
/// to 64 layers (a slab re-reads the plane it shares with the slab below, so
/// thin slabs cost time, while memory grows with the plane size far more
/// than with the depth); but with several threads, thin enough that there
/// are about sixteen slabs per thread (at least 8 layers each), because
/// slabs are the unit of parallel work: the surface is rarely spread evenly
/// over the layers, and a few big slabs leave threads idle, waiting for a
/// slow one (two threads on 256^3 CT and noise were 8-14% faster with slabs
/// of 8 layers than of 32).
pub(crate) fn default_depth(plane_len: usize, layers: usize, threads: usize) -> usize {
    let by_size = ((64 << 20) / plane_len.max(1)).clamp(16, 64);
    if threads <= 1 {
        return by_size;
    }
    by_size.min(layers.div_ceil(16 * threads).max(8))
}

/// A rayon pool of `threads` threads.
pub(crate) fn thread_pool(threads: usize) -> Result<rayon::ThreadPool> {
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
    let params = std::slice::from_ref(params);
    let mut stats = crate::multi::extract_many_part_to(source, params, options, part, &mut [sink])?;
    Ok(stats.remove(0))
}
