//! `tmc extract`: volume in, isosurface mesh out.

use super::batch::BatchArgs;
use super::raw_input::RawArgs;
use super::require_surface::RequireSurface;
use super::{memory, progress, report, values, CONVENTIONS};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::{Error, ExtractParams, Grid, Inside, Method, PipelineOptions, Result};

/// Extract the isosurface of a volume at an isovalue and write it as a mesh.
///
/// The surface is the isosurface of the trilinear interpolant of the samples;
/// vertices are in physical coordinates (origin + index * spacing).
#[derive(Debug, Args)]
#[command(after_help = CONVENTIONS)]
pub(crate) struct ExtractArgs {
    /// Input volume: .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha,
    /// .vtk, .vti, .tif/.tiff, a directory or pattern of TIFFs, DICOM (.dcm
    /// or a directory of slices), or headerless samples with --dims and
    /// --dtype. Several inputs are a batch (see --keep-going): -o must
    /// contain {stem}.
    #[arg(value_name = "INPUT", required_unless_present = "manifest")]
    pub input: Vec<PathBuf>,

    /// Isovalue, a finite number. A sample is inside iff its value > ISO
    /// (equal is outside, NaN is outside). Several, comma-separated
    /// (--iso 550,1600), are extracted in one pass over the data, one output
    /// each: {iso} in -o is replaced by the isovalue, or '_iso<VALUE>' is
    /// inserted before the extension.
    #[arg(long, value_name = "VALUE", allow_hyphen_values = true, value_parser = values::finite,
          value_delimiter = ',', required_unless_present = "manifest")]
    pub iso: Vec<f64>,

    /// Output mesh; the format comes from the extension: .ply, .obj, .off,
    /// .stl or .tmesh (chunked and compressed, any size; see 'tmc convert').
    /// Streamed as it is extracted; written atomically: nothing is left there
    /// if the run fails. {stem} is replaced by the input's name without its
    /// extension(s), {iso} by the isovalue.
    #[arg(
        short,
        long,
        value_name = "OUTPUT",
        required_unless_present = "manifest"
    )]
    pub output: Option<PathBuf>,

    /// Cell algorithm.
    #[arg(long, value_enum, default_value_t = MethodArg::Tmc)]
    pub method: MethodArg,

    /// Which side of the isovalue is the object.
    #[arg(long, value_enum, default_value_t = InsideArg::High)]
    pub inside: InsideArg,

    /// Treat everything beyond the volume as outside, so every surface is
    /// closed (surfaces are otherwise open where they leave the volume).
    #[arg(long)]
    pub close: bool,

    /// Print the cell statistics (the paper's Table 1), sizes and time to
    /// stderr as a table.
    #[arg(long)]
    pub stats: bool,

    /// Print one JSON object on stdout: the run's parameters, the grid and all
    /// statistics. In a batch: one JSON line per input (see --report).
    #[arg(long)]
    pub json: bool,

    /// Worker threads, at most 1024 (and no more are started than there
    /// are cell layers); 0 (the default) uses all cores.
    #[arg(long, value_name = "N", value_parser = values::threads)]
    pub threads: Option<usize>,

    /// Cell layers per slab (1 to 64; a slab is the unit of parallel work);
    /// by default about 64 M samples per slab, 16 to 64 layers, and with
    /// several threads about sixteen slabs per thread (at least 8 layers
    /// each). Memory grows with it; the output does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=64))]
    pub slab_depth: Option<u16>,

    /// Bound the pipeline's memory to about BYTES (suffixes K, M, G, T:
    /// powers of 1024): the workers' buffers are planned to fit (an error if
    /// they do not beside one slab of 2 layers per worker), and a slab
    /// starts only when the mesh measured in flight leaves room for it (one
    /// layer always may). The memory-mapped input is not counted. The
    /// output does not depend on it.
    #[arg(long, value_name = "BYTES", value_parser = values::bytes)]
    pub max_memory: Option<u64>,

    /// Fail (exit 1, no output) when there is no surface, i.e. every
    /// sample is on the same side of the isovalue. Without it such a run
    /// writes an empty mesh, prints a note and exits 0. Not with --part: a
    /// part may hold no surface when the volume has one; check the merged
    /// mesh with 'tmc check --require-surface'.
    #[arg(long, conflicts_with = "part")]
    pub require_surface: bool,

    /// Print nothing on stderr but errors (no progress bar). A progress bar
    /// is shown otherwise, when stderr is a terminal.
    #[arg(short, long, conflicts_with = "stats")]
    pub quiet: bool,

    /// Progress on stderr: 'auto' a bar when stderr is a terminal; 'lines'
    /// a line at every 10% of the cell layers and at least every 30 s, with
    /// the time taken and the ETA (for the log of a batch job); 'never'.
    #[arg(
        long,
        value_name = "WHEN",
        value_enum,
        default_value_t,
        conflicts_with = "quiet"
    )]
    pub progress: progress::ProgressMode,

    /// Batch: --manifest, --report, --keep-going.
    #[command(flatten)]
    pub batch: BatchArgs,

    /// Extract only part I of N (e.g. 3/7): the I-th of N z-ranges of cell
    /// layers, written as a part file for 'tmc merge' (see README, HPC).
    /// One input and one isovalue only.
    #[arg(long, value_name = "I/N", value_parser = tmc::part::PartSpec::parse)]
    pub part: Option<tmc::part::PartSpec>,

    /// Headerless input: --dims, --dtype, --endian, ...
    #[command(flatten)]
    pub raw: RawArgs,
}

/// `--method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum MethodArg {
    /// Grosso's topologically correct and manifold hybrid marching cubes.
    Tmc,
    /// Standard marching cubes with one fixed rule for ambiguous faces
    /// (crack-free, but not topologically correct).
    Mc,
}

/// `--inside`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum InsideArg {
    /// Values above the isovalue are inside (CT, MRI, densities).
    High,
    /// Values below the isovalue are inside (signed distance fields).
    Low,
}

impl ExtractArgs {
    /// The extraction parameters at isovalue `iso`.
    pub(super) fn params(&self, iso: f64) -> ExtractParams {
        ExtractParams {
            iso,
            method: match self.method {
                MethodArg::Tmc => Method::Tmc,
                MethodArg::Mc => Method::Mc,
            },
            inside: match self.inside {
                InsideArg::High => Inside::High,
                InsideArg::Low => Inside::Low,
            },
            close: self.close,
            threads: self.threads.unwrap_or(0),
        }
    }
}

/// Runs `tmc extract`; setting `cancel` stops it with [`Error::Interrupted`].
pub(crate) fn run(args: &ExtractArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    let (input, iso, template) = match (&args.input[..], &args.iso[..], &args.output) {
        ([input], [iso], Some(output)) if !args.batch.given() => (input, *iso, output),
        _ => return super::batch::run(args, cancel),
    };
    let output = &super::manifest::outputs(template, input, &[iso])[0];
    if args.part.is_some() && output.extension().is_none_or(|e| e != "tmesh") {
        return Err(Error::Invalid(format!(
            "{}: --part writes a part file for 'tmc merge', so the output must end in .tmesh",
            output.display()
        )));
    }
    let started = Instant::now();
    let raw = args.raw.options();
    check_distinct(input, output)?;
    let source = super::raw_input::open_input(input, raw.as_ref(), cancel)?;
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
    let mut sink: Box<dyn tmc::MeshSink> = match args.part {
        Some(spec) => {
            let reading = raw.as_ref().map(|r| format!("{r:?}"));
            let record =
                tmc::part::PartRecord::new(spec, input, source.as_ref(), args.close, reading)?;
            Box::new(tmc::part::PartWriter::create(output, record)?)
        }
        None => tmc::export::create_sink(output)?,
    };
    let part = args.part.map(|p| (p.index, p.count));
    let no_surface = format!(
        "no surface at isovalue {}: every sample of {} is on the same side of it (the isovalue is outside the data range)",
        iso,
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
        params: &params,
        threads: effective_threads(params.threads),
        grid: &grid,
        stats: &stats,
        resources: &resources,
    };
    // The mesh is committed; if its report cannot be written, the run
    // fails and takes the mesh back.
    if args.stats {
        let mut err = std::io::stderr().lock();
        report::write_table(&mut err, &run)
            .map_err(|e| super::withdraw([output.as_path()], Error::io("standard error", e)))?;
    }
    if args.json {
        super::to_stdout(|out| report::write_json(out, &run))
            .map_err(|e| super::withdraw([output.as_path()], e))?;
    }
    Ok(())
}

impl ExtractArgs {
    /// How the pipeline runs for these arguments.
    pub(super) fn pipeline_options<'a>(
        &self,
        progress: &'a (dyn Fn(&tmc::Progress) + Sync),
        cancel: Option<&'a AtomicBool>,
    ) -> PipelineOptions<'a> {
        PipelineOptions {
            slab_depth: self.slab_depth.map_or(0, usize::from),
            progress: Some(progress),
            cancel,
            max_memory: self.max_memory,
        }
    }
}

/// The progress bar and the peak-memory sampling of one extraction, both
/// updated after every slab.
pub(super) struct Monitor {
    bar: Option<progress::Bar>,
    peak_anon: memory::PeakAnon,
}

impl Monitor {
    /// Progress over the grid's voxels of `input`, as `--quiet` and
    /// `--progress` say (see [`progress::Bar`]).
    pub(super) fn new(grid: &Grid, args: &ExtractArgs, input: &Path) -> Self {
        let voxels = grid.dims.iter().map(|&n| n as u64).product();
        let mode = if args.quiet {
            progress::ProgressMode::Never
        } else {
            args.progress
        };
        let label = match args.part {
            Some(p) => format!("{} part {}/{}", input.display(), p.index, p.count),
            None => input.display().to_string(),
        };
        Monitor {
            bar: Some(progress::Bar::with_mode(voxels, "voxels", mode, &label)),
            peak_anon: memory::PeakAnon::default(),
        }
    }

    /// After each slab.
    pub(super) fn slab_done(&self, p: &tmc::Progress) {
        if let Some(bar) = &self.bar {
            let (done, total) = (p.layers_done as u64, p.layers_total as u64);
            bar.set_done(done, total, "cell layers");
        }
        self.peak_anon.sample_soon();
    }

    /// Clears the bar; returns the peak anonymous memory sampled (one last
    /// sample included).
    pub(super) fn finish(&mut self) -> Option<u64> {
        self.bar = None;
        self.peak_anon.sample();
        self.peak_anon.peak()
    }
}

/// Rejects grids with fewer than 2 samples along an axis (no cells), unless
/// `close` pads the volume with an outside border, which gives every grid
/// cells (a single inside sample then has a closed surface around it).
///
/// Also rejects grids whose corners (one sample beyond with `close`) lie
/// outside the range of the mesh's f32 coordinates.
pub(super) fn check_grid(input: &Path, grid: &Grid, close: bool) -> Result<()> {
    let pad = if close { 1.0 } else { 0.0 };
    for corner in 0..8 {
        let index: [f64; 3] = std::array::from_fn(|a| {
            if corner >> a & 1 == 1 {
                grid.dims[a] as f64 - 1.0 + pad
            } else {
                -pad
            }
        });
        if grid
            .world(index)
            .iter()
            .any(|c| c.is_nan() || c.abs() > f64::from(f32::MAX))
        {
            return Err(Error::Invalid(format!(
                "{}: the grid's corners (origin + index * spacing) lie beyond the range of 32-bit float coordinates; check the spacing and origin",
                input.display()
            )));
        }
    }
    if close {
        return Ok(());
    }
    for (axis, &n) in ["x", "y", "z"].iter().zip(&grid.dims) {
        if n < 2 {
            return Err(Error::Invalid(format!(
                "{}: grid {}x{}x{} has {n} sample along {axis}; need at least 2 on every axis (or --close)",
                input.display(),
                grid.dims[0],
                grid.dims[1],
                grid.dims[2]
            )));
        }
    }
    Ok(())
}

/// Refuses to write the output over the input (also through a symbolic or
/// hard link): the input is read while the output is written.
pub(super) fn check_distinct(input: &Path, output: &Path) -> Result<()> {
    let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output)) else {
        return Ok(());
    };
    #[cfg(unix)]
    let same = {
        use std::os::unix::fs::MetadataExt;
        a.dev() == b.dev() && a.ino() == b.ino()
    };
    #[cfg(not(unix))]
    let same = {
        let _ = (a, b);
        matches!(
            (std::fs::canonicalize(input), std::fs::canonicalize(output)),
            (Ok(x), Ok(y)) if x == y
        )
    };
    if same {
        return Err(Error::Invalid(format!(
            "{}: the output is the input file {}; choose another output path",
            output.display(),
            input.display()
        )));
    }
    Ok(())
}

/// The number of worker threads `threads` (0 = all cores) stands for.
pub(super) fn effective_threads(threads: usize) -> usize {
    if threads > 0 {
        threads
    } else {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    }
}
