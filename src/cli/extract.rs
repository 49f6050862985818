//! `tmc extract`: volume in, isosurface mesh out (one input at one
//! isovalue; anything more is a batch, see [`super::batch`]).

use super::extract_args::ExtractArgs;
use super::monitor::Monitor;
use super::output::{to_stdout, withdraw};
use super::placeholders;
use super::require_surface::RequireSurface;
use super::{memory, report};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::files::check_distinct;
use tmc::stream::check_grid;
use tmc::stream::RunSummary;
use tmc::{Error, Result};

/// Runs `tmc extract`; setting `cancel` stops it with [`Error::Interrupted`].
pub(crate) fn run(args: &ExtractArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    if args.labels.is_some() {
        return super::labels::run(args, cancel);
    }
    // Without --labels, {label} would stay in the file's name.
    for template in args.output.iter().chain(&args.preview) {
        if tmc::files::has_placeholder(template, "{label}") {
            return Err(Error::Invalid(format!(
                "{}: {{label}} names the files of --labels; an isosurface's output may use {{stem}} and {{iso}}",
                template.display()
            )));
        }
    }
    let known = placeholders::isosurface(args.part);
    if let Some(template) = &args.output {
        placeholders::check(template, "-o", &known)?;
    }
    if let Some(template) = &args.preview {
        placeholders::check(template, "--preview", &known)?;
    }
    let (input, iso, template) = match (&args.input[..], &args.iso[..], &args.output) {
        ([input], [iso], Some(output)) if !args.batch.given() => (input, *iso, output),
        _ => return super::batch::run(args, cancel),
    };
    let template = &placeholders::fill_part(template, args.part);
    let output = &super::manifest::outputs(template, input, &[iso])[0];
    if args.part.is_some() && output.extension().is_none_or(|e| e != "tmesh") {
        return Err(Error::Invalid(format!(
            "{}: --part writes a part file for 'tmc merge', so the output must end in .tmesh",
            output.display()
        )));
    }
    args.check_normals_output(output)?;
    let preview = match &args.preview {
        Some(_) if args.part.is_some() => {
            return Err(Error::Invalid(
                "--preview draws the whole mesh, a part file holds a piece of it: merge the parts and run 'tmc preview' on the merged .tmesh".into(),
            ))
        }
        Some(template) => {
            let picture = super::manifest::outputs(template, input, &[iso]).remove(0);
            tmc::preview::check_picture(&picture, Some(input), &[output.as_path()])?;
            Some(picture)
        }
        None => None,
    };
    let started = Instant::now();
    let raw = args.raw.options();
    check_distinct(input, output)?;
    let source = super::raw_input::open_input(input, &args.raw, cancel, args.quiet)?;
    for data in source.data_files() {
        check_distinct(data, output)?;
    }
    let grid = *source.grid();
    check_grid(input, &grid, args.close)?;
    tmc::export::check_output_path(output)?;

    let params = args.params(iso);
    let mut monitor = Monitor::new(&grid, args, input);
    let on_progress = |p: &tmc::Progress| monitor.slab_done(p);
    let options = args.pipeline_options(&on_progress, cancel);
    // A budget too small is refused before anything is read (a part's
    // record reads the planes at its seams).
    tmc::stream::check_budget(source.as_ref(), &params, &options)?;
    let mut sink: Box<dyn tmc::MeshSink> = match args.part {
        Some(spec) => {
            let reading = raw.as_ref().map(|r| format!("{r:?}"));
            let record = tmc::part::PartRecord {
                selection: args.raw.selection(input),
                ..tmc::part::PartRecord::new(spec, input, source.as_ref(), args.close, reading)?
            };
            Box::new(tmc::part::PartWriter::create(output, record)?)
        }
        None => tmc::export::create_sink(output)?,
    };
    if let Some(picture) = &preview {
        let title = tmc::preview::title_of(input);
        let threads = args.threads.unwrap_or(0);
        sink = tmc::preview::WithPreview::wrap(sink, output, picture, title, threads);
    }
    let part = args.part.map(|p| (p.index, p.count));
    let no_surface = format!(
        "no surface at isovalue {}: every sample of {} is on the same side of it (the isovalue is outside the data range)",
        tmc::params::number_text(iso),
        input.display()
    );
    let stats = if args.require_surface {
        let mut sink = RequireSurface {
            inner: sink.as_mut(),
            message: format!("{no_surface}; nothing written (--require-surface)"),
        };
        tmc::extract_part_to(source.as_ref(), &params, &options, part, &mut sink)?
    } else {
        tmc::extract_part_to(source.as_ref(), &params, &options, part, sink.as_mut())?
    };
    let peak_anon = monitor.finish();
    if stats.triangles == 0 && !args.quiet && args.part.is_none() {
        say!(
            "tmc: note: {no_surface}; wrote an empty mesh to {}",
            output.display()
        );
    }
    let resources = report::Resources {
        slab_depth: args.slab_depth.map(usize::from),
        bytes_read: report::bytes_read(&stats, &grid, source.sample_bytes(), params.close),
        bytes_written: std::fs::metadata(output).ok().map(|m| m.len()),
        peak_rss_anon_bytes: peak_anon,
        vm_hwm_bytes: memory::peak_resident(),
        wall_seconds: started.elapsed().as_secs_f64(),
    };

    let run = report::Run {
        input,
        output,
        summary: RunSummary::new(&params, &grid, &stats),
        resources: &resources,
    };
    // The mesh (and its picture) is committed; if its report cannot be
    // written, the run fails and takes them back.
    let written = || std::iter::once(output.as_path()).chain(preview.as_deref());
    if args.stats {
        let mut err = std::io::stderr().lock();
        report::write_table(&mut err, &run)
            .map_err(|e| withdraw(written(), Error::io("standard error", e)))?;
    }
    if args.json {
        to_stdout(|out| report::write_json(out, &run)).map_err(|e| withdraw(written(), e))?;
    }
    Ok(())
}
