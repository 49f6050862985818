//! [`compare`]: the steps of `tmc compare` that make its figures, shared by
//! the CLI (which adds the picture and prints the table) and the Python
//! package's `tmc.compare`.
//!
//! 1. **time**: a warm-up of each method, then `runs` pairs, interleaved
//!    (the order alternating from pair to pair), each an extraction into a
//!    sink that only counts: memory as in an extraction, nothing written;
//! 2. **survey**: every ambiguous cell through the kernel, to count the
//!    cells TMC triangulates differently from MC, by kind
//!    ([`survey`](super::survey)); two planes per thread;
//! 3. **topology**: each method once more into memory and through the
//!    checker (components, Euler characteristic, genus), unless the meshes
//!    would need more than `topology_memory`, in which case
//!    [`Comparison::topology_left_out`] says how much they would.

use super::{median, ratio_interval, survey_marking, DifferingCells, OnDiffering, RatioInterval};
use crate::mesh::{Chunk, MeshBuilder, MeshInfo, MeshSink, Totals};
use crate::params::{ExtractParams, Method, PipelineOptions};
use crate::stats::Stats;
use crate::volume::SampleSource;
use crate::Result;
use serde::Serialize;
use serde_json::json;
use std::time::Instant;

/// The memory the topology step may hold when the caller sets none: the
/// two meshes, one at a time.
pub const TOPOLOGY_MEMORY: u64 = 2 << 30;

/// Bytes the topology step holds per vertex and per triangle: the mesh
/// (12 and 12) and the checker's tables (about 40 and 60).
pub const TOPOLOGY_BYTES: (u64, u64) = (12 + 40, 12 + 60);

/// A sink that takes the chunks and keeps nothing: the timed runs.
struct Discard;

impl MeshSink for Discard {
    fn begin(&mut self, _: &MeshInfo) -> Result<()> {
        Ok(())
    }
    fn chunk(&mut self, _: u64, _: &Chunk) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, _: &Totals) -> Result<()> {
        Ok(())
    }
}

/// Components, Euler characteristic and genus of one method's mesh;
/// `None` where the topology step was left out.
#[derive(Debug, Clone, Serialize)]
pub struct Topology {
    /// Connected components.
    pub components: Option<usize>,
    /// `V - E + F`.
    pub euler: Option<i64>,
    /// Total genus, where every component is a closed manifold.
    pub genus: Option<i64>,
}

/// One method's figures.
#[derive(Debug, Clone)]
pub struct Side {
    /// Seconds of each timed run, in order.
    pub seconds: Vec<f64>,
    /// The statistics of its last run (the paper's Table 1, sizes).
    pub stats: Stats,
    /// Its mesh's topology.
    pub topology: Topology,
}

impl Side {
    /// The figures as `tmc compare --json` gives each method's.
    pub fn json(&self) -> serde_json::Value {
        let s = &self.stats;
        json!({
            "seconds": self.seconds,
            "median_seconds": median(&self.seconds),
            "min_seconds": self.seconds.iter().copied().fold(f64::INFINITY, f64::min),
            "max_seconds": self.seconds.iter().copied().fold(0.0, f64::max),
            "triangles": s.triangles,
            "vertices": s.vertices,
            "components": self.topology.components,
            "euler": self.topology.euler,
            "genus": self.topology.genus,
            "ambiguous_cells": s.ambiguous_cells,
            "contours": s.contours,
            "ambiguous_contours": s.ambiguous_contours,
            "tunnels": s.tunnels,
            "contours_12": s.contours_12,
        })
    }
}

/// What [`compare`] found.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// TMC's figures.
    pub tmc: Side,
    /// Standard MC's figures.
    pub mc: Side,
    /// TMC/MC time: the median of the paired ratios and its interval.
    pub ratio: RatioInterval,
    /// The cells TMC triangulates differently from MC, by kind.
    pub differing: DifferingCells,
    /// The bytes the topology step would have held, where that was over
    /// the limit and the step was left out.
    pub topology_left_out: Option<u64>,
    /// The parameters both methods ran with (the method TMC's).
    pub params: ExtractParams,
    /// The timed pairs.
    pub runs: usize,
}

impl Comparison {
    /// The figures as `tmc compare --json` gives them: the run's `iso`,
    /// `inside`, `close`, `threads` (the workers used, as `tmc extract
    /// --json` says it) and `runs`, then `tmc`, `mc` ([`Side::json`]),
    /// `ratio` and `differing_cells`; the front ends add the input and
    /// their notes.
    pub fn json(&self) -> serde_json::Map<String, serde_json::Value> {
        let p = &self.params;
        let value = json!({
            "iso": p.iso,
            "inside": p.inside.name(),
            "close": p.close,
            "threads": crate::stream::threads::worker_threads(p.threads),
            "runs": self.runs,
            "tmc": self.tmc.json(),
            "mc": self.mc.json(),
            "ratio": self.ratio,
            "differing_cells": self.differing,
        });
        match value {
            serde_json::Value::Object(map) => map,
            _ => unreachable!("json! of braces is an object"),
        }
    }
}

/// What a caller of [`compare`] hears as it goes (each may be `None`).
#[derive(Default)]
pub struct Hooks<'a> {
    /// `(i, tmc_seconds, mc_seconds)` of each timed pair.
    pub on_run: Option<&'a mut dyn FnMut(usize, f64, f64)>,
    /// Each differing cell's centre (the picture's marks).
    pub on_differing: Option<OnDiffering<'a>>,
    /// The survey is done, before the topology step holds a mesh (where
    /// the CLI samples the peak memory of the streaming steps).
    pub after_survey: Option<&'a mut dyn FnMut()>,
}

/// Runs the three steps of the module documentation on `source` with
/// `params` (its method is ignored: both are run) and `options` (their
/// progress callback hears every run, their cancel flag stops any),
/// telling `hooks` as it goes.
pub fn compare(
    source: &dyn SampleSource,
    params: &ExtractParams,
    runs: usize,
    topology_memory: u64,
    options: &PipelineOptions,
    hooks: Hooks<'_>,
) -> Result<Comparison> {
    let Hooks {
        mut on_run,
        on_differing,
        mut after_survey,
    } = hooks;
    let with = |method| ExtractParams { method, ..*params };
    let (tmc_params, mc_params) = (with(Method::Tmc), with(Method::Mc));
    let timed = |p: &ExtractParams| -> Result<(f64, Stats)> {
        let start = Instant::now();
        let stats = crate::extract_to(source, p, options, &mut Discard)?;
        Ok((start.elapsed().as_secs_f64(), stats))
    };

    // 1. Time: a warm-up of each, then the pairs, the order alternating.
    timed(&tmc_params)?;
    timed(&mc_params)?;
    let (mut tmc_seconds, mut mc_seconds) = (Vec::new(), Vec::new());
    let (mut tmc_stats, mut mc_stats) = (Stats::default(), Stats::default());
    for i in 0..runs {
        let (t, m) = if i % 2 == 0 {
            let t = timed(&tmc_params)?;
            (t, timed(&mc_params)?)
        } else {
            let m = timed(&mc_params)?;
            (timed(&tmc_params)?, m)
        };
        if let Some(on_run) = on_run.as_mut() {
            on_run(i, t.0, m.0);
        }
        tmc_seconds.push(t.0);
        mc_seconds.push(m.0);
        (tmc_stats, mc_stats) = (t.1, m.1);
    }
    let ratio = ratio_interval(&tmc_seconds, &mc_seconds);

    // 2. The cells that differ (the survey reads two planes per thread).
    let (differing, surveyed) = survey_marking(
        source,
        &tmc_params,
        tmc_params.threads,
        options.cancel,
        on_differing,
    )?;
    debug_assert_eq!(surveyed.tunnels, tmc_stats.tunnels);
    if let Some(after_survey) = after_survey.as_mut() {
        after_survey();
    }

    // 3. Topology, within its memory.
    let need = |s: &Stats| s.vertices * TOPOLOGY_BYTES.0 + s.triangles * TOPOLOGY_BYTES.1;
    let most = need(&tmc_stats).max(need(&mc_stats));
    let (tmc_topology, mc_topology, topology_left_out) = if most <= topology_memory {
        (
            topology(source, &tmc_params, options)?,
            topology(source, &mc_params, options)?,
            None,
        )
    } else {
        let none = Topology {
            components: None,
            euler: None,
            genus: None,
        };
        (none.clone(), none, Some(most))
    };
    Ok(Comparison {
        tmc: Side {
            seconds: tmc_seconds,
            stats: tmc_stats,
            topology: tmc_topology,
        },
        mc: Side {
            seconds: mc_seconds,
            stats: mc_stats,
            topology: mc_topology,
        },
        ratio,
        differing,
        topology_left_out,
        params: tmc_params,
        runs,
    })
}

/// Components, Euler characteristic and genus of `params`' mesh, from an
/// extraction into memory and the checker.
fn topology(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
) -> Result<Topology> {
    let mut builder = MeshBuilder::default();
    crate::extract_to(source, params, options, &mut builder)?;
    let report = crate::check::check_mesh(&builder.into_mesh());
    Ok(Topology {
        components: Some(report.components),
        euler: Some(report.euler),
        genus: report.total_genus(),
    })
}
