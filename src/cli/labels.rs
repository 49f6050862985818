//! `tmc extract --labels`: the boundary surface of each label of a
//! segmentation in one pass ([`tmc::stream::extract_labels_to`]), one file
//! per label (`{label}` in `-o`) or one PLY or `.tmesh` with a per-face
//! label; with `--part I/N`, one part file per label.
//!
//! The values are counted first ([`tmc::volume::scan_label_map`]: one
//! reading of the volume, plane by plane on `--threads` threads, which also
//! refuses a sample that is not a whole number); `all` is every value
//! present but the background. The label files
//! ([`tmc::export::LabelFiles`], which the Python package shares) are
//! finished after the pass, several at once, and the figures of `--stats`
//! and `--json` are counted while each label's chunks stream
//! ([`tmc::check::Measured`], which the Python package shares too). What
//! this file adds is the command line: the options, part files, the table
//! and the JSON.

use super::extract_args::{ExtractArgs, InsideArg};
use super::monitor::Monitor;
use super::output::{to_stdout, withdraw};
use super::placeholders;
use super::values::LabelSpec;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::check::{measure_reports, Measured};
use tmc::export::{LabelFiles, LabelSink};
use tmc::part::PartSpec;
use tmc::preview::LabelPicture;
use tmc::stream::label_report::label_reports;
use tmc::stream::{check_grid, LabelReport, LabelRun};
use tmc::{Error, MeshSink, Result};

/// The output name `template` with `{part}` replaced by the part's number
/// and `{stem}` by the name of `input`; `{iso}`, which batch scripts often
/// carry, is refused: a label map's pass has no isovalue, and `{label}`
/// names its files. So is any other unknown placeholder.
fn expand_template(template: &Path, input: &Path, part: Option<PartSpec>) -> Result<PathBuf> {
    if tmc::files::has_placeholder(template, "{iso}") {
        return Err(Error::Invalid(format!(
            "{}: {{iso}} has no value with --labels (a label's surface is no isovalue's): use {{label}} instead, e.g. -o 'out/{{stem}}_{{label}}.ply'",
            template.display()
        )));
    }
    placeholders::check(template, "-o", &placeholders::labels(part))?;
    let template = placeholders::fill_part(template, part);
    let stem = super::manifest::stem(input);
    Ok(tmc::files::fill_placeholder(&template, "{stem}", &stem))
}

/// The picture's name `template` with `{stem}` replaced by the name of
/// `input`; any other placeholder is refused (one picture of all labels:
/// no `{label}`, no `{iso}`).
fn expand_picture(template: &Path, input: &Path) -> Result<PathBuf> {
    placeholders::check(template, "--preview", &["{stem}"])?;
    let stem = super::manifest::stem(input);
    Ok(tmc::files::fill_placeholder(template, "{stem}", &stem))
}

/// Runs `tmc extract --labels`.
pub(crate) fn run(args: &ExtractArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    let started = Instant::now();
    let (input, template) = match (&args.input[..], &args.output) {
        ([input], Some(output)) if !args.batch.given() => (input, output),
        _ => {
            return Err(Error::Invalid(
                "--labels takes one input and -o (no batch options)".into(),
            ))
        }
    };
    let wanted = match &args.labels {
        Some(LabelSpec::List(list)) => Some(list.as_slice()),
        Some(LabelSpec::All) | None => None,
    };
    // The background only says which value 'all' leaves out.
    if let (Some(b), Some(list)) = (args.background, wanted) {
        let list: Vec<String> = list.iter().map(i64::to_string).collect();
        return Err(Error::Invalid(format!(
            "--background {b} chooses what --labels all leaves out; with the list '{}' it would change nothing: drop it, or give --labels all",
            list.join(",")
        )));
    }
    let background = args.background.unwrap_or(0);
    // Each part's files need their own names: the same -o for every part
    // let part 2 replace part 1's files without a word.
    let per_part = tmc::files::has_placeholder(template, placeholders::PART);
    let template = &expand_template(template, input, args.part)?;
    let per_label = tmc::files::has_placeholder(template, "{label}");
    if args.part.is_some()
        && (!per_label || !per_part || template.extension().is_none_or(|e| e != "tmesh"))
    {
        return Err(Error::Invalid(format!(
            "{}: --labels with --part writes one part file per label and part for 'tmc merge': -o must contain {{label}} and {{part}} and end in .tmesh (e.g. -o 'parts/{{label}}.{{part}}.tmesh')",
            args.output.as_deref().unwrap_or(template).display()
        )));
    }
    // A name without {label} must be one .ply or .tmesh, of a known format
    // in a directory that takes files: refused before the input is read.
    tmc::export::check_label_template(template, wanted.unwrap_or_default())?;
    if args.part.is_some() && (args.stats || args.json) {
        return Err(Error::Invalid(
            "--labels with --part writes part files: --stats and --json need the merged meshes"
                .into(),
        ));
    }
    if args.inside == InsideArg::Low {
        return Err(Error::Invalid(
            "--inside low does not apply to --labels: a label's surface always faces out of the label's samples".into(),
        ));
    }
    args.check_normals_output(template)?;
    let picture = match &args.preview {
        Some(_) if args.part.is_some() => {
            return Err(Error::Invalid(
                "--preview draws every label's whole surface, part files hold pieces of them: merge the parts and run 'tmc preview' on a merged .tmesh".into(),
            ))
        }
        Some(picture) => Some(expand_picture(picture, input)?),
        None => None,
    };
    let source = super::raw_input::open_input(input, &args.raw, cancel, args.quiet)?;
    let grid = *source.grid();
    check_grid(input, &grid, args.close)?;
    // A budget too small for the pass is refused before the map is read;
    // the runs the scan keeps take only what the pass leaves.
    let params = args.params(0.5);
    let no_progress = |_: &tmc::Progress| {};
    let runs_room = tmc::stream::label_runs_room(
        source.as_ref(),
        &params,
        &args.pipeline_options(&no_progress, cancel),
    )?;
    let scan_start = Instant::now();
    let (counts, runs) = tmc::volume::scan_label_map(
        input,
        source.as_ref(),
        cancel,
        args.threads.unwrap_or(0),
        runs_room,
    )?;
    let scan_seconds = scan_start.elapsed().as_secs_f64();
    let labels = counts.select(wanted, background, input)?;
    if !args.quiet {
        match wanted {
            Some(_) => note_absent(&labels, &counts, input),
            None if counts.samples(background) == 0 => {
                note_background_absent(background, &labels, input)
            }
            None => {}
        }
    }
    // Every label's file stays open until all are committed.
    tmc::files::raise_open_file_limit();
    tmc::files::check_open_files(labels.len(), tmc::export::open_files_per_label(template))?;
    let outputs = tmc::export::label_outputs(template, &labels)?;
    let inputs: Vec<&Path> = std::iter::once(input.as_path())
        .chain(source.data_files())
        .collect();
    tmc::export::check_label_outputs(&outputs, &inputs)?;
    if let Some(picture) = &picture {
        let outputs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
        tmc::preview::check_picture(picture, Some(input), &outputs)?;
    }
    let picture_path = picture.clone();
    let picture = picture.map(|path| {
        let title = tmc::preview::title_of(input);
        LabelPicture::new(&path, title, args.threads.unwrap_or(0), &labels)
    });
    let measure = args.stats || args.json;
    // With --part, one part file per label, recording its label.
    let record = match args.part {
        Some(spec) => {
            let reading = args.raw.options().map(|r| format!("{r:?}"));
            let source = source.as_ref();
            Some(tmc::part::PartRecord {
                selection: args.raw.selection(input),
                ..tmc::part::PartRecord::new(spec, input, source, args.close, reading)?
            })
        }
        None => None,
    };
    let mut files =
        LabelFiles::create(template, &labels, &outputs, |target, label| match &record {
            Some(record) => {
                let record = tmc::part::PartRecord {
                    label: Some(label),
                    label_count: Some(labels.len()),
                    ..record.clone()
                };
                Ok(LabelSink::Send(Box::new(tmc::part::PartWriter::create(
                    target, record,
                )?)))
            }
            None => LabelSink::create(target, labels.len()),
        })?;
    // Each label's file finished as soon as the pass is past the label
    // (not part files: 'tmc merge' finishes those).
    if record.is_none() {
        files.finish_early(&tmc::stream::last_label_chunks(
            &counts, &labels, args.close,
        ));
    }
    let mut sinks = Measured::all(
        files.sinks().iter_mut().map(|f| f as &mut dyn MeshSink),
        measure,
    );
    // With --preview, each label's sink paired with the picture.
    let mut paired = Vec::new();
    let mut dyn_sinks = LabelPicture::sinks(picture.as_ref(), &mut sinks, &mut paired);
    let mut monitor = Monitor::new(&grid, args, input);
    let on_progress = |p: &tmc::Progress| monitor.slab_done(p);
    let options = args.pipeline_options(&on_progress, cancel);
    let pass_start = Instant::now();
    let part = args.part.map(|p| (p.index, p.count));
    let stats = tmc::stream::extract_labels_with_runs_to(
        source.as_ref(),
        &runs,
        &labels,
        &params,
        &options,
        part,
        &mut dyn_sinks,
    )?;
    drop(dyn_sinks);
    let mut reports = label_reports(&labels, &outputs, &stats, &counts, &grid);
    // Each label's last chunk counted before any file is put in place.
    measure_reports(sinks, &mut reports)?;
    // The picture before the files are settled: if it fails, the files
    // are taken back (and earlier runs' put back) as after a failed pass;
    // if settling them fails, the picture is removed.
    if let Some(picture) = &picture {
        picture.finish()?;
    }
    files
        .finish(cancel)
        .map_err(|e| withdraw(picture_path.as_deref(), e))?;
    monitor.finish();
    let pass_seconds = pass_start.elapsed().as_secs_f64();
    if !measure {
        return Ok(());
    }
    // The files (and the picture) are committed; if the report cannot be
    // written, the run fails and takes them back.
    let written: Vec<&Path> = (outputs.iter().map(PathBuf::as_path))
        .chain(picture_path.as_deref())
        .collect();
    if args.stats {
        write_table(&reports)
            .map_err(|e| withdraw(written.iter().copied(), Error::io("standard error", e)))?;
    }
    if args.json {
        let run = LabelRun {
            input: input.display().to_string(),
            close: args.close,
            method: params.method.name(),
            background,
            labels: &reports,
            scan_seconds,
            pass_seconds,
            seconds: started.elapsed().as_secs_f64(),
        };
        to_stdout(|out| {
            serde_json::to_writer(&mut *out, &run).map_err(std::io::Error::other)?;
            writeln!(out)
        })
        .map_err(|e| withdraw(written.iter().copied(), e))?;
    }
    Ok(())
}

/// Says which labels of a list the map does not hold (a mistyped label
/// gave an empty mesh without a word, where an isovalue outside the data
/// range gets a note): one line, naming up to 10.
fn note_absent(labels: &[i64], counts: &tmc::volume::LabelCounts, input: &Path) {
    let absent: Vec<i64> = labels
        .iter()
        .copied()
        .filter(|&l| counts.samples(l) == 0)
        .collect();
    let list = listed(&absent);
    match absent.len() {
        0 => {}
        1 => say!(
            "tmc: note: label {list} is not in {}: its mesh is empty",
            input.display()
        ),
        n => say!(
            "tmc: note: {n} labels are not in {} ({list}): their meshes are empty",
            input.display()
        ),
    }
}

/// Says that the background of `--labels all` is not in the map, so that
/// every value is a label (a mistyped `--background` gave the real
/// background's surface as a label without a word): one line, naming up
/// to 10 of the labels.
fn note_background_absent(background: i64, labels: &[i64], input: &Path) {
    say!(
        "tmc: note: background {background} is not in {}: every value present is a label ({})",
        input.display(),
        listed(labels)
    );
}

/// Up to 10 labels, comma-separated, then how many more.
fn listed(labels: &[i64]) -> String {
    let shown = labels.len().min(10);
    let names: Vec<String> = labels[..shown].iter().map(i64::to_string).collect();
    names.join(", ")
        + &match labels.len() - shown {
            0 => String::new(),
            more => format!(" and {more} more"),
        }
}

/// The `--stats` table on stderr.
fn write_table(reports: &[LabelReport]) -> std::io::Result<()> {
    let mut err = std::io::stderr().lock();
    let opt = |v: Option<String>| v.unwrap_or_else(|| "-".into());
    writeln!(
        err,
        "{:>8} {:>10} {:>6} {:>6} {:>7} {:>14} {:>14} {:>14}",
        "label", "triangles", "comps", "genus", "closed", "area", "volume", "voxels*voxel"
    )?;
    for r in reports {
        writeln!(
            err,
            "{:>8} {:>10} {:>6} {:>6} {:>7} {:>14} {:>14} {:>14.3}",
            r.label,
            r.triangles,
            opt(r.components.map(|c| c.to_string())),
            opt(r.genus.map(|g| g.to_string())),
            opt(r.closed.map(|c| if c { "yes" } else { "no" }.to_string())),
            opt(r.area.map(|a| format!("{a:.3}"))),
            opt(r.enclosed_volume.map(|v| format!("{v:.3}"))),
            r.voxel_volume,
        )?;
    }
    Ok(())
}
