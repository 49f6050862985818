//! Times `tmc::extract` alone: the volume is read whole into memory first and
//! the mesh is left in memory, so the figure is the extraction itself, the
//! same thing `scripts/bench-peers` times for the peer libraries (VTK Flying
//! Edges, MC33, scikit-image, PyMCubes), which also start from an array in
//! memory and return a mesh in memory.
//!
//! Two ways to run it:
//!
//! * `time_extract VOLUME --iso V --method tmc --threads 1 --runs 5` runs
//!   five extractions and prints one JSON line per run;
//! * `time_extract VOLUME --iso V --serve` loads the volume once, prints a
//!   `{"ready":...}` line, then reads requests `METHOD THREADS` (e.g.
//!   `tmc 2`) from stdin, one per line, and answers each with one JSON line.
//!   The benchmark driver uses this to interleave tmc's runs with the peers'
//!   without reloading the volume.
//!
//! With `--opened` the volume is not copied: tmc extracts from the file as
//! `tmc extract` opens it (memory-mapped, samples in their own type), as the
//! `tmc_vs_mc` bench does. With `--normals` the extraction computes vertex
//! normals too.
//!
//! Build with `cargo build --release --example time_extract`.

use clap::{Parser, ValueEnum};
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::time::Instant;
use tmc::volume::ScalarType;
use tmc::{extract, ArrayVolume, ExtractParams, Method, SampleSource};

/// Times tmc's extraction of a volume held in memory (JSON lines on stdout).
#[derive(Debug, Parser)]
struct Args {
    /// The volume (any format `tmc extract` reads).
    volume: PathBuf,
    /// The isovalue.
    #[arg(long, allow_hyphen_values = true)]
    iso: f64,
    /// The cell algorithm.
    #[arg(long, value_enum, default_value_t = MethodArg::Tmc)]
    method: MethodArg,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Timed extractions.
    #[arg(long, default_value_t = 1)]
    runs: usize,
    /// Untimed extractions before the timed ones.
    #[arg(long, default_value_t = 0)]
    warmup: usize,
    /// Read requests `METHOD THREADS` from stdin instead of using the
    /// options above.
    #[arg(long)]
    serve: bool,
    /// Extract from the file as `tmc extract` opens it (memory-mapped where
    /// the format allows, samples in their own type) instead of from an
    /// `f32`/`f64` copy in memory: the path `tmc extract` and the
    /// `tmc_vs_mc` bench take.
    #[arg(long)]
    opened: bool,
    /// Compute vertex normals too (`ExtractParams::normals`, as
    /// `tmc extract --normals`).
    #[arg(long)]
    normals: bool,
}

/// `--method`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum MethodArg {
    /// Grosso's hybrid marching cubes.
    Tmc,
    /// Standard marching cubes.
    Mc,
    /// No extraction: one pass over the samples in memory (their maximum),
    /// the memory-bandwidth floor an extraction is compared with.
    Pass,
}

impl MethodArg {
    fn method(self) -> Method {
        match self {
            MethodArg::Tmc | MethodArg::Pass => Method::Tmc,
            MethodArg::Mc => Method::Mc,
        }
    }

    fn name(self) -> &'static str {
        match self {
            MethodArg::Tmc => "tmc",
            MethodArg::Mc => "mc",
            MethodArg::Pass => "pass",
        }
    }
}

/// A volume held in memory, as `f32` (as the peers hold it) or `f64`, or
/// the file as opened (see `--opened`).
enum Loaded {
    F32(ArrayVolume<f32>),
    F64(ArrayVolume<f64>),
    Opened(Box<dyn SampleSource>),
}

impl Loaded {
    fn source(&self) -> &dyn SampleSource {
        match self {
            Loaded::F32(v) => v,
            Loaded::F64(v) => v,
            Loaded::Opened(v) => v.as_ref(),
        }
    }

    /// One pass over every sample (their maximum) on `threads` threads,
    /// in slabs of planes like the extraction: the bandwidth floor.
    fn pass(&self, threads: usize) -> tmc::Result<f64> {
        use rayon::prelude::*;
        if let Loaded::Opened(_) = self {
            return Err(tmc::Error::Invalid(
                "--method pass times a volume in memory, not --opened".into(),
            ));
        }
        let plane = self.source().grid().plane_len();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| tmc::Error::Invalid(e.to_string()))?;
        let max = pool.install(|| match self {
            Loaded::F32(v) => v
                .data()
                .par_chunks(plane * 16)
                .map(|c| c.iter().fold(f32::MIN, |m, &x| m.max(x)) as f64)
                .reduce(|| f64::MIN, f64::max),
            Loaded::F64(v) => v
                .data()
                .par_chunks(plane * 16)
                .map(|c| c.iter().fold(f64::MIN, |m, &x| m.max(x)))
                .reduce(|| f64::MIN, f64::max),
            Loaded::Opened(_) => unreachable!("refused above"),
        });
        Ok(max)
    }
}

/// Reads every plane of `path` into an [`ArrayVolume`] of the file's own
/// sample type when that is `f32` (as the peers hold it), else of `f64`.
fn load(path: &std::path::Path, opened: bool) -> tmc::Result<Loaded> {
    let source = tmc::volume::open(path, None)?;
    if opened {
        return Ok(Loaded::Opened(source));
    }
    let grid = *source.grid();
    let plane = grid.plane_len();
    let mut data = vec![0.0; plane * grid.dims[2]];
    for (z, out) in data.chunks_exact_mut(plane).enumerate() {
        source.read_plane(z, out)?;
    }
    if source.stored_type() == Some(ScalarType::F32) {
        let narrow: Vec<f32> = data.iter().map(|&v| v as f32).collect();
        return Ok(Loaded::F32(ArrayVolume::new(grid, narrow)?));
    }
    Ok(Loaded::F64(ArrayVolume::new(grid, data)?))
}

/// One extraction: seconds, triangles, vertices. The mesh is dropped after
/// the clock stops.
fn run_once(
    volume: &Loaded,
    iso: f64,
    method: MethodArg,
    threads: usize,
    normals: bool,
) -> tmc::Result<(f64, u64, u64)> {
    if let MethodArg::Pass = method {
        let start = Instant::now();
        std::hint::black_box(volume.pass(threads)?);
        return Ok((start.elapsed().as_secs_f64(), 0, 0));
    }
    let volume = volume.source();
    let params = ExtractParams {
        iso,
        method: method.method(),
        threads,
        normals,
        ..Default::default()
    };
    let start = Instant::now();
    let (mesh, stats) = extract(volume, &params)?;
    let seconds = start.elapsed().as_secs_f64();
    drop(mesh);
    Ok((seconds, stats.triangles, stats.vertices))
}

fn report(
    out: &mut impl Write,
    method: MethodArg,
    threads: usize,
    (seconds, triangles, vertices): (f64, u64, u64),
) -> std::io::Result<()> {
    let line = serde_json::json!({
        "method": method.name(),
        "threads": threads,
        "seconds": seconds,
        "triangles": triangles,
        "vertices": vertices,
    });
    writeln!(out, "{line}")?;
    out.flush()
}

fn serve(volume: &Loaded, iso: f64, normals: bool) -> Result<(), Box<dyn std::error::Error>> {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        let words: Vec<&str> = line.split_whitespace().collect();
        let (method, threads) = match words.as_slice() {
            [] => continue,
            [m, t] => (
                MethodArg::from_str(m, true)?,
                t.parse::<usize>()
                    .map_err(|e| format!("bad thread count {t:?}: {e}"))?,
            ),
            _ => return Err(format!("expected 'METHOD THREADS', got {line:?}").into()),
        };
        report(
            &mut out,
            method,
            threads,
            run_once(volume, iso, method, threads, normals)?,
        )?;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let start = Instant::now();
    let volume = load(&args.volume, args.opened)?;
    let load_seconds = start.elapsed().as_secs_f64();
    if args.serve {
        let ready = serde_json::json!({
            "ready": true,
            "dims": volume.source().grid().dims,
            "load_seconds": load_seconds,
        });
        println!("{ready}");
        return serve(&volume, args.iso, args.normals);
    }
    for _ in 0..args.warmup {
        run_once(&volume, args.iso, args.method, args.threads, args.normals)?;
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for _ in 0..args.runs {
        let timing = run_once(&volume, args.iso, args.method, args.threads, args.normals)?;
        report(&mut out, args.method, args.threads, timing)?;
    }
    Ok(())
}
