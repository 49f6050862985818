//! The pass: one walk over the volume's cell layers, slab by slab, for one
//! or several isosurfaces.
//!
//! The writing thread cuts the layers into slabs ([`Schedule`], within the
//! [`budget`]), workers triangulate them
//! ([`process_slab`]), and each isovalue's [`Seam`] puts the finished slabs
//! back in plane order for its sink.
//!
//! Reading a large volume is the expensive part of an extraction, so each
//! slab is triangulated for every isovalue in turn while its planes are
//! resident: the first isovalue pages them in, the others find them in
//! memory, and they are released (see [`Access::Done`]) only after the last.
//! Each isovalue has its own seam and sink, so every output is exactly what
//! a separate run at that isovalue writes.

use super::budget;
use super::cancellable::Cancellable;
use super::parts::layer_range;
use super::schedule::Schedule;
use super::seam::Seam;
use super::threads::{default_depth, thread_pool, worker_threads};
use crate::mesh::{Chunk, ChunkEncoder, MeshInfo, MeshSink};
use crate::normals::{has_pending, FillPending};
use crate::params::{ExtractParams, PipelineOptions, Progress, VertexValues};
use crate::slab::{chunk_bytes, process_slab, Spares};
use crate::volume::{Access, HeldPlanes, Padded, PlaneMemory, SampleSource};
use crate::{Error, Result, Stats};
use std::ops::Range;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Extracts one isosurface per entry of `params` from `source` in one pass,
/// streaming the mesh of `params[i]` to `sinks[i]`; returns the statistics
/// of each.
///
/// The entries may differ in isovalue, method and inside side, but must
/// agree on `close` and `threads` (they share the padded source and the
/// workers). Slabs are scheduled as in [`extract_to`](super::extract_to); a slab in
/// flight holds the meshes of all isovalues. Every sink has had all its
/// chunks before the first is finished (so a sink can still refuse to
/// finish, and then none is). Any error fails the whole extraction; sinks
/// not finished by then are dropped unfinished.
pub fn extract_many_to(
    source: &dyn SampleSource,
    params: &[ExtractParams],
    options: &PipelineOptions,
    sinks: &mut [&mut dyn MeshSink],
) -> Result<Vec<Stats>> {
    extract_many_part_to(source, params, options, None, sinks)
}

/// [`extract_many_to`] restricted to part `i` of `n` (1-based, see
/// [`layer_range`]) when `part` is given: only the chunks of
/// that part's cell layers reach the sinks, numbered from 0, exactly as a
/// whole run writes them.
pub(crate) fn extract_many_part_to(
    source: &dyn SampleSource,
    params: &[ExtractParams],
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sinks: &mut [&mut dyn MeshSink],
) -> Result<Vec<Stats>> {
    run_pass(source, params, options, part, sinks, None)
}

/// What a worker makes of a slab instead of [`slab_for_each`]: given the
/// pass's source (padded with `--close`, cancellable) and the slab's cell
/// layers, the chunks and counts of every output, in the order of the
/// pass's `params`, each exactly what a single run of that output writes
/// for those layers, normals included where the params ask for them (the
/// pass computes none for a work: its outputs are not the source's
/// isosurfaces). Its planes per sample of a plane are `budget_planes` (as
/// the budget counts a plane of the slab loop).
pub(crate) struct SlabWork<'w> {
    /// The slab's chunks and counts, per output.
    pub(crate) run: &'w SlabFn<'w>,
    /// How many of the slab loop's planes the work holds, for the budget.
    pub(crate) budget_planes: usize,
    /// Bytes the work holds through the whole pass (a label map's runs),
    /// for the budget.
    pub(crate) held_bytes: u64,
}

/// The function of a [`SlabWork`].
pub(crate) type SlabFn<'w> = dyn Fn(&dyn SampleSource, Range<usize>, &Spares) -> Result<Vec<(Vec<Chunk>, Stats)>>
    + Sync
    + 'w;

/// The pass of [`extract_many_part_to`], each slab made by `work` when
/// given (else by [`slab_for_each`]).
pub(crate) fn run_pass(
    source: &dyn SampleSource,
    params: &[ExtractParams],
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sinks: &mut [&mut dyn MeshSink],
    work: Option<SlabWork>,
) -> Result<Vec<Stats>> {
    let start = Instant::now();
    let Some(first) = params.first() else {
        return Err(Error::Invalid("no isovalue to extract".into()));
    };
    if sinks.len() != params.len() {
        return Err(Error::Invalid(format!(
            "{} isovalues but {} outputs",
            params.len(),
            sinks.len()
        )));
    }
    if params
        .iter()
        .any(|p| p.close != first.close || p.threads != first.threads)
    {
        return Err(Error::Invalid(
            "the isovalues of one pass must share 'close' and 'threads'".into(),
        ));
    }
    if let Some(p) = params.iter().find(|p| !p.iso.is_finite()) {
        return Err(Error::Invalid(format!(
            "the isovalue must be a finite number, not {}",
            p.iso
        )));
    }
    let info = |p: &ExtractParams| MeshInfo {
        grid: *source.grid(),
        iso: p.iso,
        method: p.method,
        inside: p.inside,
        close: p.close,
        normals: p.normals,
        labels: false,
    };
    let padded;
    let source: &dyn SampleSource = if first.close {
        padded = Padded::new(source);
        &padded
    } else {
        source
    };
    // A slab in progress stops at its next layer once cancelled.
    let cancellable;
    let source: &dyn SampleSource = match options.cancel {
        Some(cancel) => {
            cancellable = Cancellable {
                inner: source,
                cancel,
            };
            &cancellable
        }
        None => source,
    };
    let dims = source.grid().dims;
    if dims.iter().any(|&d| d < 2) {
        return Err(Error::Invalid(format!(
            "the grid {}x{}x{} needs at least 2 samples along every axis",
            dims[0], dims[1], dims[2]
        )));
    }
    let layers = dims[2] - 1;
    let normals = params.iter().any(|p| p.normals);
    let (workers, plan) = plan_pass(
        dims,
        source.plane_memory(),
        first.threads,
        normals,
        work.as_ref().map(|w| (w.budget_planes, w.held_bytes)),
        options,
    )?;
    let (threads, depth) = (workers.threads, plan.depth);
    check_cancel(options)?;
    let range = match part {
        Some((i, n)) => layer_range(layers, i, n)?,
        None => 0..layers,
    };
    // The chunks the sinks get: those of the range's layers, and the top
    // plane's when the range ends there. With normals, a part computes one
    // layer more on each side, whose chunks only lend their triangles to
    // the normals of the part's first and last chunks (`FillPending`).
    let keep = range.start as u64..range.end as u64 + u64::from(range.end == layers);
    let range = if normals && part.is_some() {
        range.start.saturating_sub(1)..(range.end + 1).min(layers)
    } else {
        range
    };
    let mut schedule = Schedule::new(range, layers, plan, options.max_memory, &workers);
    let layers_total = schedule.layers_total();
    let mut fills: Vec<FillPending> = sinks
        .iter_mut()
        .map(|sink| FillPending::new(&mut **sink, keep.clone()))
        .collect();
    for (p, fill) in params.iter().zip(fills.iter_mut()) {
        fill.begin(&info(p))?;
    }
    // What each sink would encode its chunks with: done by the workers, so
    // that the one thread feeding the sinks does not bound the pass.
    let encoders: Vec<Option<ChunkEncoder>> = fills.iter().map(|f| f.encoder()).collect();
    // Scratch for every slab in flight; block vectors for one slab per
    // isovalue (see `Spares`; the budget counts them).
    let spares = Spares::new(plan.window, (depth + 1) * params.len());
    let mut seams: Vec<Seam> = fills
        .iter_mut()
        .map(|sink| {
            Seam::new(sink)
                .with_cancel(options.cancel)
                .with_spares(&spares)
        })
        .collect();
    let report = |seams: &[Seam], schedule: &Schedule| {
        if let Some(progress) = options.progress {
            let written = &schedule.started()[..seams[0].written()];
            progress(&Progress {
                layers_done: written.iter().map(|r| r.len()).sum(),
                layers_total,
            });
        }
    };
    let planes = dims[2];
    let run = |layers: Range<usize>| {
        check_cancel(options)?;
        source.check_unchanged()?;
        // The slab's planes, and one more on each side for the normals'
        // gradients, lent from a chunked source's decoded layers.
        let held = HeldPlanes::new(
            source,
            layers.start.saturating_sub(1)..(layers.end + 3).min(planes),
        );
        let source: &dyn SampleSource = &held;
        let mut results = match &work {
            Some(work) => {
                let mut results = (work.run)(source, layers, &spares)?;
                if let Some(values) = options.vertex_values {
                    for chunk in results.iter_mut().flat_map(|(chunks, _)| chunks) {
                        values(&chunk.vertices, &mut chunk.values);
                    }
                }
                results
            }
            // The slab loop fills the values block by block.
            None => slab_for_each(source, params, layers, &spares, options.vertex_values)?,
        };
        encode_chunks(&mut results, &encoders)?;
        Ok(results)
    };
    // Hands slab `i` to every seam; returns how many slabs got written
    // (the same for all seams, as they all see the same slabs).
    let accept = |seams: &mut [Seam], i: usize, results: Vec<(Vec<Chunk>, Stats)>| {
        let mut written = 0;
        for (seam, (chunks, stats)) in seams.iter_mut().zip(results) {
            written = seam.accept(i, chunks, stats)?;
        }
        Ok::<usize, Error>(written)
    };
    // The next slab, if the window and the budget allow one now.
    let start_next = |schedule: &mut Schedule, written: usize| {
        if schedule.spares_in_the_way(spares.block_bytes()) {
            spares.free_blocks();
        }
        schedule.start_next(written, spares.block_bytes())
    };
    // A source that decodes layers keeps one per thread of the pool its
    // reader runs on, and two more (`chunk_layers.rs`): one worker runs in
    // a pool of one, as the budget counts it.
    let decodes = matches!(workers.planes, PlaneMemory::Decoded { .. });
    if threads == 1 && !decodes {
        while let Some((i, layers)) = start_next(&mut schedule, seams[0].written()) {
            let result = run(layers)?;
            schedule.finished(i, mesh_bytes(&result));
            accept(&mut seams, i, result)?;
            report(&seams, &schedule);
        }
    } else {
        let pool = thread_pool(threads)?;
        let (tx, rx) = crossbeam::channel::unbounded();
        pool.in_place_scope(|scope| -> Result<()> {
            let run = &run;
            let launch = |i: usize, layers: Range<usize>| {
                let tx = tx.clone();
                scope.spawn(move |_| {
                    // The receiver outlives the scope; a send cannot fail.
                    let _ = tx.send((i, run(layers)));
                });
            };
            loop {
                // As many slabs as the window and the budget allow.
                while let Some((i, layers)) = start_next(&mut schedule, seams[0].written()) {
                    launch(i, layers);
                }
                if schedule.all_started() && seams[0].written() == schedule.started().len() {
                    break;
                }
                let (i, result) = rx.recv().expect("a worker holds a sender");
                let result = result?;
                schedule.finished(i, mesh_bytes(&result));
                accept(&mut seams, i, result)?;
                report(&seams, &schedule);
            }
            Ok(())
        })?;
    }
    check_cancel(options)?;
    let mut all = Vec::with_capacity(seams.len());
    for seam in seams {
        let (mut stats, _) = seam.finish()?;
        stats.slabs = schedule.started().len() as u64;
        all.push(stats);
    }
    // What the sinks got (a part's extra layers of context left out).
    for (stats, fill) in all.iter_mut().zip(&fills) {
        stats.vertices = fill.totals().vertices;
        stats.triangles = fill.totals().triangles;
        stats.seconds = start.elapsed().as_secs_f64();
    }
    Ok(all)
}

/// The workers of a pass over a source of `dims` (padded with `--close`
/// already) whose planes are held as `planes` says, at `threads` (0: one
/// per core), and the budget's plan for them: slab depth and slabs in
/// flight. `work` is a [`SlabWork`]'s `budget_planes` and `held_bytes`.
/// Reads nothing: an error here comes before any sample is read.
fn plan_pass(
    dims: [usize; 3],
    planes: PlaneMemory,
    threads: usize,
    normals: bool,
    work: Option<(usize, u64)>,
    options: &PipelineOptions,
) -> Result<(budget::Workers, budget::Plan)> {
    let plane_len = dims[0] * dims[1];
    let layers = dims[2].saturating_sub(1);
    // No more threads than layers: more would find no slab to work on.
    let threads = worker_threads(threads).min(layers.max(1));
    let depth = if options.slab_depth > 0 {
        options.slab_depth.min(64)
    } else {
        default_depth(plane_len, layers, threads)
    };
    // Normals hold up to four more planes of `f64` per worker (32 bytes
    // per sample beside the loop's 17) and 12 bytes per vertex: the budget
    // counts each plane three times, which covers both.
    let workers = budget::Workers {
        plane_len,
        work_planes: match work {
            Some((planes, _)) => planes,
            None if normals => 3,
            None => 1,
        },
        threads,
        planes,
        held: work.map_or(0, |(_, held)| held),
    };
    let plan = budget::plan(&workers, depth, options.max_memory)?;
    Ok((workers, plan))
}

/// Whether the budget (`options.max_memory`) allows extracting `params`
/// from `source`: the error [`extract_many_to`] would give before reading
/// anything, for a front end that reads the volume before the pass
/// (`--part` checksums the planes at its seams).
pub fn check_budget(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
) -> Result<()> {
    plan_source(source, params, None, options).map(|_| ())
}

/// [`plan_pass`] for `source` as the pass sees it (`--close` pads the grid
/// by a sample on every side, see `Padded`).
pub(super) fn plan_source(
    source: &dyn SampleSource,
    params: &ExtractParams,
    work: Option<(usize, u64)>,
    options: &PipelineOptions,
) -> Result<(budget::Workers, budget::Plan)> {
    let pad = if params.close { 2 } else { 0 };
    let dims = source.grid().dims.map(|d| d + pad);
    let planes = source.plane_memory();
    plan_pass(dims, planes, params.threads, params.normals, work, options)
}

/// Encodes the chunks of each output whose sink has an encoder
/// ([`MeshSink::encoder`]) into [`Chunk::encoded`]: those with a surface,
/// and no pending normal (which [`FillPending`] will change).
fn encode_chunks(
    results: &mut [(Vec<Chunk>, Stats)],
    encoders: &[Option<ChunkEncoder>],
) -> Result<()> {
    for ((chunks, _), encoder) in results.iter_mut().zip(encoders) {
        let Some(encode) = encoder else {
            continue;
        };
        for chunk in chunks {
            let empty = chunk.vertices.is_empty() && chunk.triangles.is_empty();
            if !empty && !has_pending(chunk) {
                chunk.encoded = encode(chunk)?;
            }
        }
    }
    Ok(())
}

/// Fails with [`Error::Interrupted`] once the cancel flag of `options` is
/// set (one relaxed load).
fn check_cancel(options: &PipelineOptions) -> Result<()> {
    match options.cancel {
        Some(flag) if flag.load(Ordering::Relaxed) => Err(Error::Interrupted),
        _ => Ok(()),
    }
}

/// Bytes of the meshes of one slab, all isovalues (capacities: what they
/// hold in memory while they wait to be written).
fn mesh_bytes(results: &[(Vec<Chunk>, Stats)]) -> u64 {
    results
        .iter()
        .flat_map(|(chunks, _)| chunks)
        .map(chunk_bytes)
        .sum()
}

/// Triangulates cell layers `layers` for every entry of `params`, the
/// planes staying resident from the first isovalue to the last, each
/// chunk's values filled by `values` if given.
fn slab_for_each(
    source: &dyn SampleSource,
    params: &[ExtractParams],
    layers: Range<usize>,
    spares: &Spares,
    values: Option<&VertexValues>,
) -> Result<Vec<(Vec<Chunk>, Stats)>> {
    if let [single] = params {
        // One isovalue: exactly the single-surface path.
        return Ok(vec![process_slab(source, single, layers, spares, values)?]);
    }
    let (last, others) = params.split_last().expect("several isovalues");
    let keep = KeepResident { inner: source };
    let mut results = Vec::with_capacity(params.len());
    for p in others {
        results.push(process_slab(&keep, p, layers.clone(), spares, values)?);
    }
    results.push(process_slab(source, last, layers, spares, values)?);
    Ok(results)
}

/// A source that ignores "release these pages" advice, so that the planes
/// of a slab stay resident while the slab is triangulated again for the
/// next isovalue; everything else goes to the wrapped source.
struct KeepResident<'a> {
    inner: &'a dyn SampleSource,
}

impl SampleSource for KeepResident<'_> {
    crate::volume::forward_to_inner!(
        grid,
        read_plane,
        lend_plane,
        share_plane,
        check_unchanged,
        interrupted,
        sample_bytes,
        stored_type,
        plane_memory,
    );

    fn advise(&self, planes: Range<usize>, access: Access) {
        if access != Access::Done {
            self.inner.advise(planes, access);
        }
    }
}
