//! `tmc synth`: write a synthetic test volume, plane by plane.

use super::{progress, values};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use tmc::synth::{Kind, Synthetic, HEAD_SKIN_ISO_HU, HEAD_SKULL_ISO_HU};
use tmc::volume::{write_volume_cancellable, ScalarType, VolumeFormat};
use tmc::{Grid, Result};

/// Text at the end of `tmc synth --help`.
const SYNTH_HELP: &str = "\
Kinds (L = half the shortest side of the box, index * spacing):
  sphere  ball of radius 0.8 L at the centre
  torus   solid torus around the z axis, ring radius 0.55 L, tube radius 0.25 L
  gyroid  (sin x cos y + sin y cos z + sin z cos x) / 1.5, 4 periods across 2 L
  noise   smooth value noise (quintic interpolation of hashed lattice values),
          3 octaves with lattice periods 32, 16, 8 samples; depends on --seed
  head    CT-like head phantom in Hounsfield units (HU); fills the box along
          every axis; depends on --seed (the noise)
The sphere and torus fields are signed distances (positive inside) divided by
8 samples and clamped to [-1, 1]; gyroid and noise lie in [-1, 1] already.

Stored values of sphere, torus, gyroid, noise (field f in [-1, 1], surface at 0):
  f16, f32, f64       f                       iso 0
  i8, i16, i32, i64   round(f * MAX)          iso 0
  u8, u16, u32, u64   round((f + 1)/2 * MAX)  iso MAX/2: 127.5, 32767.5, 2147483647.5
  (MAX is the largest value of the type; for i64 and u64 that of i32 and u32,
  so that every value is exact in the f64 tmc reads: u64's iso is u32's.)
  Inside is above the isovalue.

The head phantom (HU):
  air -1000; soft tissue (scalp, face) 40; skull 1000 to 1500, 0.04 to 0.12 of
  the half-box thick (thin on top, thick at the base); brain 30; two ventricles
  5; one-sample partial-volume ramps at every boundary; white noise +-15.
  Stored as:  f16 f32 f64 i16 i32 i64: HU;  u16 u32 u64: HU + 1000 (air 0);
              u8: (HU + 1000) / 10;  i8: HU / 12.5   (rounded, clamped)
  Suggested isovalues (HU -500 skin, HU 500 skull):
              f16 f32 f64 i16 i32 i64: -500, 500;  u16 u32 u64: 500, 1500;
              u8: 50, 150;  i8: -40, 40

Output formats (chosen by the extension of -o), all little-endian, x fastest:
  .nrrd  attached header, raw encoding, spacing as 'space directions'
  .npy   numpy version 1.0, shape (nz, ny, nx), C order
  .raw   samples only: read back with --dims and --dtype (printed after writing)
  The volume is computed plane by plane and never held in memory; the file is
  written atomically (nothing is left at the path on failure).";

/// Write a synthetic test volume (sphere, torus, gyroid, noise or a CT-like
/// head phantom) as .nrrd, .npy or raw samples.
///
/// Prints on stderr what it wrote and a suggested isovalue (unless --quiet).
#[derive(Debug, Args)]
#[command(after_help = SYNTH_HELP)]
pub(crate) struct SynthArgs {
    /// What the volume shows.
    #[arg(value_enum, value_name = "KIND")]
    pub kind: KindArg,

    /// Samples along x, y, z (e.g. 256,256,128), at least 2 each.
    #[arg(long, value_name = "X,Y,Z", value_parser = values::dims)]
    pub dims: [usize; 3],

    /// Sample type: u8, i8, u16, i16, u32, i32, f32, f64, i64, u64 or f16
    /// (f16 not in .nrrd, which has no such type).
    #[arg(long, value_name = "T", value_parser = values::dtype)]
    pub dtype: ScalarType,

    /// Output volume: .nrrd, .npy or .raw (by extension).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,

    /// Seed of the noise (kinds noise and head); the volume is a pure
    /// function of the kind, dims, spacing, type and seed.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub seed: u64,

    /// Distance between samples along x, y, z, finite and positive; written
    /// to the .nrrd header [default: 1,1,1].
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = values::spacing)]
    pub spacing: Option<[f64; 3]>,

    /// Print nothing on stderr but errors (no progress bar, no summary).
    #[arg(short, long)]
    pub quiet: bool,
}

/// `KIND`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum KindArg {
    /// A ball.
    Sphere,
    /// A solid torus (genus 1).
    Torus,
    /// The gyroid, a triply periodic surface.
    Gyroid,
    /// Smooth value noise.
    Noise,
    /// A CT-like head phantom.
    Head,
}

impl KindArg {
    fn kind(self) -> Kind {
        match self {
            KindArg::Sphere => Kind::Sphere,
            KindArg::Torus => Kind::Torus,
            KindArg::Gyroid => Kind::Gyroid,
            KindArg::Noise => Kind::Noise,
            KindArg::Head => Kind::Head,
        }
    }
}

/// Runs `tmc synth`; setting `cancel` (SIGINT, SIGTERM, SIGHUP) stops it
/// before the next plane with [`tmc::Error::Interrupted`], leaving no
/// output.
pub(crate) fn run(args: &SynthArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    let started = Instant::now();
    let grid = Grid {
        dims: args.dims,
        spacing: args.spacing.unwrap_or([1.0; 3]),
        origin: [0.0; 3],
        direction: tmc::grid::IDENTITY,
    };
    let kind = args.kind.kind();
    let format = VolumeFormat::from_path(&args.output)?;
    tmc::files::check_output_file(&args.output)?;
    let source = Synthetic::new(kind, grid, args.dtype, args.seed)?;
    let samples: u64 = grid.dims.iter().map(|&n| n as u64).product();
    let bytes = {
        let bar = progress::Bar::new(samples, "samples", args.quiet);
        let report = |done: usize, total: usize| bar.set_fraction(done as f64 / total as f64);
        let never = AtomicBool::new(false);
        let cancel = cancel.unwrap_or(&never);
        write_volume_cancellable(&args.output, &source, args.dtype, Some(&report), cancel)?
    };
    if args.quiet {
        return Ok(());
    }
    let seconds = started.elapsed().as_secs_f64();
    let [x, y, z] = grid.dims;
    let t = args.dtype;
    say!(
        "wrote {}: {kind} {x}x{y}x{z} {t}, {} bytes in {seconds:.2} s ({} samples/s)",
        args.output.display(),
        bytes,
        progress::si(samples as f64 / seconds.max(1e-9)),
    );
    let (iso, note) = match kind {
        Kind::Head => (
            tmc::synth::hounsfield_to_stored(HEAD_SKULL_ISO_HU, t),
            format!(
                " (the skull; --iso {} for the skin)",
                tmc::synth::hounsfield_to_stored(HEAD_SKIN_ISO_HU, t)
            ),
        ),
        _ => (source.suggested_iso(), String::new()),
    };
    let raw = if format == VolumeFormat::Raw {
        let mut raw = format!(" --dims {x},{y},{z} --dtype {t}");
        if let Some([sx, sy, sz]) = args.spacing {
            raw += &format!(" --spacing {sx},{sy},{sz}");
        }
        raw
    } else {
        String::new()
    };
    say!(
        "extract it with: tmc extract {}{raw} --iso {iso} -o OUTPUT.ply{note}",
        args.output.display()
    );
    Ok(())
}
