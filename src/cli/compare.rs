//! `tmc compare`: TMC against standard marching cubes on one volume, as
//! the paper's question is asked: how much slower, and what is different.
//!
//! The steps, each a pass of the ordinary pipeline or of the library:
//! 1. **time**: a warm-up of each method, then `--runs` pairs, interleaved
//!    (the order alternating from pair to pair), each an extraction into a
//!    sink that only counts: memory as in `tmc extract`, nothing written;
//! 2. **survey**: every ambiguous cell through the kernel, to count the
//!    cells TMC triangulates differently from MC, by kind
//!    ([`tmc::compare::survey`]); two planes per thread;
//! 3. **topology**: each method once more into memory and through the
//!    checker (components, Euler characteristic, genus), unless the meshes
//!    would not fit `--topology-memory`, in which case the table says so;
//! 4. with `--preview`: each method once more into a preview drawn in
//!    memory (streaming, as `tmc extract --preview`), the two side by side
//!    with the cells the survey found differing marked in red
//!    ([`tmc::preview::side_by_side`]).
//!
//! The peak anonymous memory reported is that of steps 1 and 2, sampled
//! before step 3 holds a mesh.

use super::extract_args::InsideArg;
use super::output::to_stdout;
use super::raw_input::RawArgs;
use super::values;
use clap::Args;
use serde::Serialize;
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::compare::{
    median, ratio_interval, survey_marking, DifferingCells, OnDiffering, RatioInterval,
};
use tmc::preview::{side_by_side, write_png, Bounds, Marks, PreviewSink, PAIR_DIMENSIONS};
use tmc::stream::check_grid;
use tmc::{
    Chunk, ExtractParams, Inside, MeshInfo, MeshSink, Method, PipelineOptions, Stats, Totals,
};

/// Memory the topology step may use by default (2 GiB).
const TOPOLOGY_MEMORY: u64 = 2 << 30;

/// Bytes per vertex and per triangle the topology step needs: the mesh in
/// memory (`f32` positions, `u32` indices) and the checker's incidence
/// lists and union-finds (a few words each, see [`tmc::check`]).
const TOPOLOGY_BYTES: (u64, u64) = (12 + 40, 12 + 60);

/// Times `--method tmc` against `--method mc` on one volume and reports
/// what their meshes differ in.
///
/// Runs the two methods interleaved, a warm-up and then --runs pairs, with
/// the options of 'tmc extract', writing no mesh, and prints one table:
/// median, minimum and maximum seconds of each, the ratio TMC/MC with a 95%
/// bootstrap interval of the paired per-run ratios, the cell statistics of
/// the paper's Table 1, triangles, vertices, components, Euler characteristic
/// and genus of each mesh, and the cells TMC triangulates differently from
/// MC, by kind (face decisions, tunnels, 12-vertex contours, interior
/// vertices).
#[derive(Debug, Args)]
pub(crate) struct CompareArgs {
    /// Input volume, any format 'tmc extract' reads.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,

    /// Isovalue, a finite number (inside iff value > ISO, as in 'tmc extract').
    #[arg(long, value_name = "VALUE", allow_hyphen_values = true, value_parser = values::finite)]
    pub iso: f64,

    /// Timed pairs of runs after the warm-up (1 to 1000).
    #[arg(long, value_name = "N", default_value_t = 7,
          value_parser = clap::value_parser!(u16).range(1..=1000))]
    pub runs: u16,

    /// Worker threads, as in 'tmc extract'; 0 (the default) uses all cores.
    #[arg(long, value_name = "N", value_parser = values::threads)]
    pub threads: Option<usize>,

    /// Which side of the isovalue is the object.
    #[arg(long, value_enum, default_value_t = InsideArg::High)]
    pub inside: InsideArg,

    /// Treat everything beyond the volume as outside (closed surfaces).
    #[arg(long)]
    pub close: bool,

    /// Bound the pipeline's memory as 'tmc extract --max-memory' does.
    #[arg(long, value_name = "BYTES", value_parser = values::bytes)]
    pub max_memory: Option<u64>,

    /// Memory the topology step (components, Euler characteristic, genus)
    /// may use: it holds each mesh in memory, about 52 bytes per vertex and
    /// 72 per triangle; larger meshes are left out of it, and the table says
    /// so [default: 2G].
    #[arg(long, value_name = "BYTES", value_parser = values::bytes)]
    pub topology_memory: Option<u64>,

    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,

    /// Also draw the two meshes side by side (TMC left, MC right) into
    /// this PNG picture, each as 'tmc extract --preview' draws it, with a
    /// red dot in every view where a cell is triangulated differently.
    /// {stem} and {iso} as in 'tmc extract --preview'.
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,

    /// Print nothing on stderr but errors (no line per run, no note that
    /// neither method found a surface).
    #[arg(short, long)]
    pub quiet: bool,

    #[command(flatten)]
    pub raw: RawArgs,
}

/// A sink that takes every chunk and keeps nothing: the timed runs write
/// no mesh.
struct Discard;

impl MeshSink for Discard {
    fn begin(&mut self, _: &MeshInfo) -> tmc::Result<()> {
        Ok(())
    }
    fn chunk(&mut self, _: u64, _: &Chunk) -> tmc::Result<()> {
        Ok(())
    }
    fn finish(&mut self, _: &Totals) -> tmc::Result<()> {
        Ok(())
    }
}

/// The topology of one method's mesh, or why it was left out.
#[derive(Debug, Clone, Serialize)]
struct Topology {
    components: Option<usize>,
    euler: Option<i64>,
    genus: Option<i64>,
}

/// What one method gave: its timings, its last run's statistics, its
/// topology.
struct Side {
    seconds: Vec<f64>,
    stats: Stats,
    topology: Topology,
}

impl Side {
    fn json(&self) -> serde_json::Value {
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

/// Runs `tmc compare`; setting `cancel` stops it with [`tmc::Error::Interrupted`].
pub(crate) fn run(args: &CompareArgs, cancel: Option<&AtomicBool>) -> tmc::Result<()> {
    // {stem} and {iso} as in 'tmc extract --preview' (they were written
    // into the picture's name as they stood).
    let preview = match &args.preview {
        Some(template) => {
            let known = super::placeholders::isosurface(None);
            super::placeholders::check(template, "--preview", &known)?;
            let picture = super::manifest::outputs(template, &args.input, &[args.iso]).remove(0);
            tmc::preview::check_picture(&picture, Some(&args.input), &[])?;
            Some(picture)
        }
        None => None,
    };
    let source = super::raw_input::open_input(&args.input, &args.raw, cancel, args.quiet)?;
    let grid = *source.grid();
    check_grid(&args.input, &grid, args.close)?;
    // The differing cells' marks, in the views the previews will have.
    let bounds = Bounds::of_grid(&grid);
    let marks = match (&preview, bounds) {
        (Some(_), Some(b)) => Some(Marks::new(&b)),
        (Some(picture), None) => {
            return Err(tmc::Error::Invalid(format!(
                "{}: the volume has no finite bounds to frame a preview",
                picture.display()
            )))
        }
        (None, _) => None,
    };
    let params = |method| ExtractParams {
        iso: args.iso,
        method,
        inside: match args.inside {
            InsideArg::High => Inside::High,
            InsideArg::Low => Inside::Low,
        },
        close: args.close,
        threads: args.threads.unwrap_or(0),
        normals: false,
    };
    let (tmc_params, mc_params) = (params(Method::Tmc), params(Method::Mc));
    // The peak of the streaming steps (time, survey), before the topology
    // step holds meshes.
    let peak = super::memory::PeakAnon::default();
    let on_slab = |_: &tmc::Progress| peak.sample_soon();
    let options = PipelineOptions {
        progress: Some(&on_slab),
        cancel,
        max_memory: args.max_memory,
        ..Default::default()
    };
    let timed = |p: &ExtractParams| -> tmc::Result<(f64, Stats)> {
        let start = Instant::now();
        let stats = tmc::extract_to(source.as_ref(), p, &options, &mut Discard)?;
        Ok((start.elapsed().as_secs_f64(), stats))
    };

    // 1. Time: a warm-up of each, then the pairs, the order alternating.
    timed(&tmc_params)?;
    timed(&mc_params)?;
    let runs = usize::from(args.runs);
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
        if !args.quiet {
            say!(
                "tmc: compare: run {} of {runs}: tmc {:.4} s, mc {:.4} s",
                i + 1,
                t.0,
                m.0
            );
        }
        tmc_seconds.push(t.0);
        mc_seconds.push(m.0);
        (tmc_stats, mc_stats) = (t.1, m.1);
    }
    let ratio = ratio_interval(&tmc_seconds, &mc_seconds);
    if tmc_stats.triangles == 0 && mc_stats.triangles == 0 && !args.quiet {
        // As 'tmc extract' says it: the table's zeros and times are of
        // extractions that found nothing, most likely an isovalue outside
        // the data range.
        say!(
            "tmc: note: no surface at isovalue {}: every sample of {} is on the same side of it \
             (the isovalue is outside the data range); the times are of extractions that found none",
            args.iso,
            args.input.display()
        );
    }

    // 2. The cells that differ (the survey reads two planes per thread).
    let mark = |p: [f64; 3]| {
        if let Some(m) = &marks {
            m.mark(p);
        }
    };
    let on_differing: Option<OnDiffering<'_>> = marks.as_ref().map(|_| &mark as OnDiffering<'_>);
    let (differing, surveyed) = survey_marking(
        source.as_ref(),
        &tmc_params,
        tmc_params.threads,
        cancel,
        on_differing,
    )?;
    debug_assert_eq!(surveyed.tunnels, tmc_stats.tunnels);
    peak.sample();
    let peak_rss_anon_bytes = peak.peak();

    // 3. Topology, within its memory.
    let limit = args.topology_memory.unwrap_or(TOPOLOGY_MEMORY);
    let need = |s: &Stats| s.vertices * TOPOLOGY_BYTES.0 + s.triangles * TOPOLOGY_BYTES.1;
    let most = need(&tmc_stats).max(need(&mc_stats));
    let (tmc_topology, mc_topology, topology_note) = if most <= limit {
        (
            topology(source.as_ref(), &tmc_params, &options)?,
            topology(source.as_ref(), &mc_params, &options)?,
            None,
        )
    } else {
        let none = Topology {
            components: None,
            euler: None,
            genus: None,
        };
        let note = format!(
            "components, Euler characteristic and genus left out: they hold the mesh in memory, about {}, over --topology-memory {}",
            super::report::human_bytes(most),
            super::report::human_bytes(limit)
        );
        (none.clone(), none, Some(note))
    };

    // 4. The picture.
    if let (Some(picture), Some(marks)) = (&preview, &marks) {
        let name = tmc::preview::title_of(&args.input);
        let caption = |method: &str| {
            format!(
                "{method}   {name}   {} differing cells in red",
                differing.cells
            )
        };
        let draw = |p: &ExtractParams, method: &str| -> tmc::Result<Vec<u8>> {
            let mut sink = PreviewSink::in_memory(caption(method), bounds, p.threads);
            tmc::extract_to(source.as_ref(), p, &options, &mut sink)?;
            sink.take_picture()
                .ok_or_else(|| tmc::Error::Invalid("preview: no picture".into()))
        };
        let (left, right) = (draw(&tmc_params, "TMC")?, draw(&mc_params, "MC")?);
        let (w, h) = PAIR_DIMENSIONS;
        write_png(picture, w, h, &side_by_side(&left, &right, marks))?;
    }

    let tmc_side = Side {
        seconds: tmc_seconds,
        stats: tmc_stats,
        topology: tmc_topology,
    };
    let mc_side = Side {
        seconds: mc_seconds,
        stats: mc_stats,
        topology: mc_topology,
    };
    let report = Report {
        args,
        tmc: &tmc_side,
        mc: &mc_side,
        ratio,
        differing,
        topology_note: topology_note.as_deref(),
        peak_rss_anon_bytes,
    };
    if args.json {
        to_stdout(|out| {
            serde_json::to_writer(&mut *out, &report.json())?;
            writeln!(out)
        })
    } else {
        to_stdout(|out| report.write_table(out))
    }
}

/// Components, Euler characteristic and genus of `params`' mesh, from an
/// extraction into memory and the checker.
fn topology(
    source: &dyn tmc::SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
) -> tmc::Result<Topology> {
    let mut builder = tmc::MeshBuilder::default();
    tmc::extract_to(source, params, options, &mut builder)?;
    let report = tmc::check::check_mesh(&builder.into_mesh());
    Ok(Topology {
        components: Some(report.components),
        euler: Some(report.euler),
        genus: report.total_genus(),
    })
}

/// Everything `tmc compare` prints.
struct Report<'a> {
    args: &'a CompareArgs,
    tmc: &'a Side,
    mc: &'a Side,
    ratio: RatioInterval,
    differing: DifferingCells,
    topology_note: Option<&'a str>,
    /// The peak anonymous memory of the timed runs and the survey.
    peak_rss_anon_bytes: Option<u64>,
}

impl Report<'_> {
    fn json(&self) -> serde_json::Value {
        json!({
            "input": self.args.input,
            "iso": self.args.iso,
            "inside": match self.args.inside { InsideArg::High => "high", InsideArg::Low => "low" },
            "close": self.args.close,
            // The workers the runs used, as 'tmc extract --json' says it.
            "threads": tmc::stream::threads::worker_threads(self.args.threads.unwrap_or(0)),
            "runs": self.args.runs,
            "tmc": self.tmc.json(),
            "mc": self.mc.json(),
            "ratio": self.ratio,
            "differing_cells": self.differing,
            "topology_note": self.topology_note,
            "peak_rss_anon_bytes": self.peak_rss_anon_bytes,
        })
    }

    fn write_table(&self, out: &mut impl Write) -> std::io::Result<()> {
        let (t, m) = (self.tmc.json(), self.mc.json());
        writeln!(
            out,
            "tmc compare {}, iso {}: {} timed pairs after a warm-up, no mesh written",
            self.args.input.display(),
            self.args.iso,
            self.args.runs
        )?;
        writeln!(out, "{:<26} {:>18} {:>18}", "", "tmc", "mc")?;
        let seconds = |v: &serde_json::Value| v.as_f64().map_or("-".into(), |s| format!("{s:.4}"));
        for (label, key) in [
            ("median seconds", "median_seconds"),
            ("min seconds", "min_seconds"),
            ("max seconds", "max_seconds"),
        ] {
            writeln!(
                out,
                "{label:<26} {:>18} {:>18}",
                seconds(&t[key]),
                seconds(&m[key])
            )?;
        }
        let plain = |v: &serde_json::Value| match v {
            serde_json::Value::Null => "-".to_string(),
            serde_json::Value::Array(a) => a
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join("/"),
            v => v.to_string(),
        };
        for (label, key) in [
            ("triangles", "triangles"),
            ("vertices", "vertices"),
            ("components", "components"),
            ("Euler characteristic", "euler"),
            ("genus", "genus"),
            ("ambiguous cells", "ambiguous_cells"),
            ("contours 3/4/5/6", "contours"),
            ("ambiguous contours 6-9", "ambiguous_contours"),
            ("tunnels", "tunnels"),
            ("12-vertex contours", "contours_12"),
        ] {
            writeln!(
                out,
                "{label:<26} {:>18} {:>18}",
                plain(&t[key]),
                plain(&m[key])
            )?;
        }
        let r = self.ratio;
        writeln!(
            out,
            "time TMC/MC: {:.3} (95% interval {:.3} to {:.3}, bootstrap of {} paired runs)",
            r.median, r.low, r.high, self.args.runs
        )?;
        let d = self.differing;
        writeln!(
            out,
            "cells TMC triangulates differently from MC: {} of {} ambiguous (face decisions {}, tunnels {}, 12-vertex contours {}, interior vertices {}; a cell may be of several kinds)",
            d.cells, self.tmc.stats.ambiguous_cells, d.face_decisions, d.tunnels, d.contours_12, d.interior_vertices
        )?;
        if let Some(note) = self.topology_note {
            writeln!(out, "note: {note}")?;
        }
        Ok(())
    }
}
