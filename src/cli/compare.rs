//! `tmc compare`: TMC against standard marching cubes on one volume, as
//! the paper's question is asked: how much slower, and what is different.
//!
//! Steps 1 to 3 (time, survey, topology) are the library's
//! [`tmc::compare::compare`], which the Python package's `tmc.compare`
//! shares; the CLI adds:
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
use serde_json::json;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::compare::{Comparison, OnDiffering, TOPOLOGY_MEMORY};
use tmc::preview::{side_by_side, write_png, Bounds, Marks, PreviewSink, PAIR_DIMENSIONS};
use tmc::stream::check_grid;
use tmc::{ExtractParams, Inside, Method, PipelineOptions};

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
    let params = ExtractParams {
        iso: args.iso,
        method: Method::Tmc,
        inside: match args.inside {
            InsideArg::High => Inside::High,
            InsideArg::Low => Inside::Low,
        },
        close: args.close,
        threads: args.threads.unwrap_or(0),
        normals: false,
    };
    // The peak of the streaming steps (time, survey), before the topology
    // step holds meshes: sampled by the slabs of the timed runs and once
    // the survey is done.
    let peak = super::memory::PeakAnon::default();
    let on_slab = |_: &tmc::Progress| peak.sample_soon();
    let options = PipelineOptions {
        progress: Some(&on_slab),
        cancel,
        max_memory: args.max_memory,
        ..Default::default()
    };
    let runs = usize::from(args.runs);
    let mut on_run = |i: usize, t: f64, m: f64| {
        if !args.quiet {
            say!(
                "tmc: compare: run {} of {runs}: tmc {t:.4} s, mc {m:.4} s",
                i + 1
            );
        }
    };
    let mark = |p: [f64; 3]| {
        if let Some(m) = &marks {
            m.mark(p);
        }
    };
    let mut after_survey = || peak.sample();
    let hooks = tmc::compare::Hooks {
        on_run: Some(&mut on_run),
        on_differing: marks.as_ref().map(|_| &mark as OnDiffering<'_>),
        after_survey: Some(&mut after_survey),
    };
    let limit = args.topology_memory.unwrap_or(TOPOLOGY_MEMORY);
    let found = tmc::compare::compare(source.as_ref(), &params, runs, limit, &options, hooks)?;
    let peak_rss_anon_bytes = peak.peak();
    if found.tmc.stats.triangles == 0 && found.mc.stats.triangles == 0 && !args.quiet {
        // As 'tmc extract' says it: the table's zeros and times are of
        // extractions that found nothing, most likely an isovalue outside
        // the data range.
        say!(
            "tmc: note: no surface at isovalue {}: every sample of {} is on the same side of it \
             (the isovalue is outside the data range); the times are of extractions that found none",
            tmc::params::number_text(args.iso),
            args.input.display()
        );
    }
    let topology_note = found.topology_left_out.map(|most| {
        format!(
            "components, Euler characteristic and genus left out: they hold the mesh in memory, about {}, over --topology-memory {}",
            super::report::human_bytes(most),
            super::report::human_bytes(limit)
        )
    });

    // 4. The picture.
    if let (Some(picture), Some(marks)) = (&preview, &marks) {
        let name = tmc::preview::title_of(&args.input);
        let caption = |method: &str| {
            format!(
                "{method}   {name}   {} differing cells in red",
                found.differing.cells
            )
        };
        let draw = |method: Method, label: &str| -> tmc::Result<Vec<u8>> {
            let p = ExtractParams { method, ..params };
            let mut sink = PreviewSink::in_memory(caption(label), bounds, p.threads);
            tmc::extract_to(source.as_ref(), &p, &options, &mut sink)?;
            sink.take_picture()
                .ok_or_else(|| tmc::Error::Invalid("preview: no picture".into()))
        };
        let (left, right) = (draw(Method::Tmc, "TMC")?, draw(Method::Mc, "MC")?);
        let (w, h) = PAIR_DIMENSIONS;
        write_png(picture, w, h, &side_by_side(&left, &right, marks))?;
    }

    let report = Report {
        args,
        found: &found,
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

/// Everything `tmc compare` prints.
struct Report<'a> {
    args: &'a CompareArgs,
    found: &'a Comparison,
    topology_note: Option<&'a str>,
    /// The peak anonymous memory of the timed runs and the survey.
    peak_rss_anon_bytes: Option<u64>,
}

impl Report<'_> {
    fn json(&self) -> serde_json::Value {
        let mut map = self.found.json();
        map.insert("input".into(), json!(self.args.input));
        map.insert("topology_note".into(), json!(self.topology_note));
        map.insert(
            "peak_rss_anon_bytes".into(),
            json!(self.peak_rss_anon_bytes),
        );
        serde_json::Value::Object(map)
    }

    fn write_table(&self, out: &mut impl Write) -> std::io::Result<()> {
        let (t, m) = (self.found.tmc.json(), self.found.mc.json());
        writeln!(
            out,
            "tmc compare {}, iso {}: {} timed pairs after a warm-up, no mesh written",
            self.args.input.display(),
            tmc::params::number_text(self.args.iso),
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
        let r = self.found.ratio;
        writeln!(
            out,
            "time TMC/MC: {:.3} (95% interval {:.3} to {:.3}, bootstrap of {} paired runs)",
            r.median, r.low, r.high, self.args.runs
        )?;
        let d = self.found.differing;
        writeln!(
            out,
            "cells TMC triangulates differently from MC: {} of {} ambiguous (face decisions {}, tunnels {}, 12-vertex contours {}, interior vertices {}; a cell may be of several kinds)",
            d.cells, self.found.tmc.stats.ambiguous_cells, d.face_decisions, d.tunnels, d.contours_12, d.interior_vertices
        )?;
        if let Some(note) = self.topology_note {
            writeln!(out, "note: {note}")?;
        }
        Ok(())
    }
}
