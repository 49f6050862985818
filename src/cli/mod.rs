//! Command-line parsing, dispatch and error reporting.
//!
//! Every failure is reported as exactly one line `tmc: error: <message>` on
//! stderr; the exit status is 0 on success, 1 on failure, 2 on a usage error
//! and 130, 143 or 129 when SIGINT, SIGTERM or SIGHUP interrupted a command
//! that writes a file.

#[macro_use]
mod stderr;

mod batch;
mod check;
mod convert;
mod extract;
mod info;
mod manifest;
mod memory;
mod merge;
mod progress;
mod raw_input;
mod report;
mod require_surface;
mod signals;
mod synth;
mod values;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};
use std::io::Write;
use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Shared text at the end of `tmc --help` and `tmc extract --help`.
pub(crate) const CONVENTIONS: &str = "\
Sign convention:
  A sample is inside iff its value > ISO; a sample equal to ISO is outside, and
  NaN samples are outside. With --inside low the roles flip (inside iff value < ISO,
  for signed distance fields). Triangles are counter-clockwise seen from outside,
  so normals point toward the outside.

Input formats:
  .npy   numpy array, 3-D of shape (nz, ny, nx), C or Fortran order,
         dtype u1 i1 u2 i2 u4 i4 f4 f8 in either byte order; unit spacing
  .nrrd  NRRD, dimension 3, attached data or (also .nhdr) 'data file': one
  .nhdr  file, 'LIST [subdim]' (names on the following lines) or a printf
         pattern 'slice%03d.raw MIN MAX STEP [subdim]', one slice (subdim 2)
         or a block of slices (subdim 3) per file; encoding raw (mapped),
         gzip, bzip2 or ascii; any 8/16/32-bit integer type, float or double
         (not 64-bit integers); 'line skip' and 'byte skip' (-1: data at the
         end) apply to each data file; grid from 'space directions' (rotation
         and mirroring applied) or 'spacings', origin from 'space origin'
  .nii   NIfTI-1/2, also .nii.gz and .hdr + .img; all integer types up to
         32 bits, float, double; scl_slope/scl_inter applied (ISO in physical
         units); grid from the sform, else the qform, else pixdim
  .mhd   MetaImage, also .mha; ElementDataFile LOCAL, a file or LIST; zlib
         (CompressedData); HeaderSize; TransformMatrix, Offset, ElementSpacing
  .vtk   legacy VTK STRUCTURED_POINTS, binary (big-endian) or ASCII
  .vti   VTK XML ImageData: ascii, binary or appended, raw or base64, zlib;
         Origin, Spacing, Direction
  .tif   a multi-page TIFF (or BigTIFF), or a directory or glob ('dir/*.tif')
         of single-page TIFFs in natural name order; 8/16/32-bit; unit spacing
  DICOM  a directory of slice files (DICM magic or .dcm; other files skipped),
         one slice file (its series in its directory) or a multi-frame .dcm;
         slices sorted by position along the normal, RescaleSlope/Intercept
         applied per slice (CT in HU), patient (LPS) coordinates; one series
         per directory; uncompressed, deflate, RLE and JPEG baseline and
         lossless (not JPEG 2000/JPEG-LS)
  raw    headerless samples, x fastest: give --dims and --dtype
  Vertices are in the file's world frame (spacing, origin and direction
  cosines applied; a mirroring map flips the winding). Uncompressed data is
  memory-mapped; gzip, bzip2 and zlib data is decompressed once into a
  temporary file in TMPDIR and mapped. 'tmc info' shows how a file is read.

Output formats (chosen by the extension of -o):
  .ply   binary little-endian, shared vertices
  .obj   text, shared vertices
  .off   text, shared vertices
  .stl   binary; STL cannot share vertices (each facet stores its own corners),
         so 'tmc check' on an STL file is not meaningful
  .tmesh tmc's chunked, compressed mesh (64-bit vertex numbers, checksums);
         'tmc convert' turns it into any format above, 'tmc check' reads it,
         scripts/read_tmesh.py reads it with numpy
  Meshes are streamed to the output as they are extracted, never held whole.
  The output is written atomically: on failure nothing is left at the path.

Exit status:
  0    success (also when the isovalue is outside the data range: a note on
       stderr and an empty mesh, unless --require-surface is given)
  1    failure (unreadable, malformed or changing input, unwritable output,
       disk full, --max-memory too small, ...; one line 'tmc: error: ...');
       'tmc check' also exits 1 when the mesh is not a consistently oriented
       manifold (non-manifold edges or vertices, inconsistent orientation)
       or, with --require-surface, when it is empty (no triangles);
       a batch ('tmc extract' with several inputs, isovalues or --manifest)
       exits 1 when any item failed, after naming each on stderr
  2    usage error (unknown option, missing or malformed value)
  130  interrupted by SIGINT, 143 by SIGTERM, 129 by SIGHUP: extract, convert,
       merge and synth stop at the next slab, chunk or plane (also while
       decompressing the input or assembling the output) and no output is
       left; a signal inherited as ignored (nohup, a background job of a
       script) stays ignored";

/// Topologically correct and manifold isosurfaces (Grosso 2016 marching cubes).
///
/// Extracts the isosurface of the trilinear interpolant of a regular grid of
/// samples with R. Grosso's hybrid marching cubes, which resolves every
/// ambiguous cell with the asymptotic decider and the cell's interior
/// topology, so the mesh is topologically correct and manifold.
#[derive(Debug, Parser)]
#[command(
    name = "tmc",
    version,
    arg_required_else_help = true,
    after_help = CONVENTIONS
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
enum Command {
    Extract(extract::ExtractArgs),
    Convert(convert::ConvertArgs),
    Merge(merge::MergeArgs),
    Check(check::CheckArgs),
    Info(info::InfoArgs),
    Synth(synth::SynthArgs),
}

/// Runs the command line and returns the process exit status.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    install_panic_hook();
    if let Err(e) = signals::install_sigbus() {
        say!("tmc: error: cannot install the SIGBUS handler: {e}");
        return ExitCode::FAILURE;
    }
    let interrupts = match cli.command {
        Command::Extract(_) | Command::Convert(_) | Command::Merge(_) | Command::Synth(_) => {
            match signals::Interrupts::install() {
                Ok(i) => Some(i),
                Err(e) => {
                    say!("tmc: error: cannot install the SIGINT/SIGTERM/SIGHUP handlers: {e}");
                    return ExitCode::FAILURE;
                }
            }
        }
        _ => None,
    };
    let result = panic::catch_unwind(AssertUnwindSafe(|| match cli.command {
        Command::Extract(args) => extract::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Convert(args) => convert::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Merge(args) => merge::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Check(args) => check::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Synth(args) => synth::run(&args, interrupts.as_ref().map(|i| i.flag())),
    }));
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(tmc::Error::Interrupted)) => {
            let (name, code) = interrupts
                .as_ref()
                .and_then(|i| i.received())
                .unwrap_or(("a signal", 130));
            match batch::FINISHED_BEFORE_INTERRUPT.load(std::sync::atomic::Ordering::SeqCst) {
                0 => say!("tmc: error: interrupted by {name}; no output was written"),
                n => say!(
                    "tmc: error: interrupted by {name}; the outputs of the {n} input(s) that finished before it are kept, nothing else was written"
                ),
            }
            ExitCode::from(code)
        }
        Ok(Err(e)) => {
            say!("tmc: error: {}", one_line(&e.to_string()));
            ExitCode::FAILURE
        }
        // The panic hook has printed the message.
        Err(_) => ExitCode::FAILURE,
    }
}

/// Reports a clap error: help and version go out as clap prints them, real
/// usage errors as one line with exit status 2.
fn usage_error(e: &clap::Error) -> ExitCode {
    match e.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            // Help on a full disk is an error like any other failed
            // write; a closed pipe (`tmc --help | head`) is not.
            match e.print().and_then(|()| std::io::stdout().flush()) {
                Err(write) if write.kind() != std::io::ErrorKind::BrokenPipe => {
                    say!("tmc: error: cannot write to standard output: {write}");
                    return ExitCode::FAILURE;
                }
                _ => {}
            }
            ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2))
        }
        _ => {
            let text = e.to_string();
            let mut head = Vec::new();
            let mut tips = Vec::new();
            let mut in_head = true;
            for line in text.lines() {
                let line = line.trim();
                if in_head {
                    if line.is_empty() {
                        in_head = false;
                    } else {
                        head.push(line.strip_prefix("error:").unwrap_or(line).trim());
                    }
                } else if let Some(tip) = line.strip_prefix("tip:") {
                    tips.push(format!(" (tip: {})", tip.trim()));
                }
            }
            say!(
                "tmc: error: {}{}; see 'tmc --help'",
                head.join(" "),
                tips.concat()
            );
            ExitCode::from(2)
        }
    }
}

/// Prints a panic as one `tmc: internal error` line (only the first one, if
/// several worker threads panic).
fn install_panic_hook() {
    static REPORTED: AtomicBool = AtomicBool::new(false);
    panic::set_hook(Box::new(|info| {
        // A reader catches this one and reports it as an error line.
        if tmc::volume::in_guarded_call() {
            return;
        }
        if REPORTED.swap(true, Ordering::SeqCst) {
            return;
        }
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".to_string());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        say!("tmc: internal error: {}{place}", one_line(&message));
    }));
}

/// Writes to standard output through `write`, then flushes it. A closed
/// pipe (EPIPE: the reader, `head` say, has all it wanted) is not an error:
/// the rest of the output is dropped and the run ends as it would have
/// (the common convention, as ripgrep does); any other failure is.
pub(crate) fn to_stdout(
    write: impl FnOnce(&mut std::io::StdoutLock<'static>) -> std::io::Result<()>,
) -> tmc::Result<()> {
    let mut out = std::io::stdout().lock();
    match write(&mut out).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.map_err(|e| tmc::Error::io("standard output", e)),
    }
}

/// The error of a run whose outputs were committed but whose report (the
/// JSON on stdout, the --stats table, a --report line) could not be
/// written: the outputs are removed again, so that a run that exits 1
/// leaves no new output (a file that was at an output path before the run
/// was replaced when the mesh was committed and is not restored).
pub(crate) fn withdraw<'a>(
    outputs: impl IntoIterator<Item = &'a std::path::Path>,
    e: tmc::Error,
) -> tmc::Error {
    let removed: Vec<String> = outputs
        .into_iter()
        .filter(|o| std::fs::remove_file(o).is_ok())
        .map(|o| o.display().to_string())
        .collect();
    if removed.is_empty() {
        return e;
    }
    tmc::Error::Invalid(format!("{e}; removed the output {}", removed.join(", ")))
}

/// Joins the lines of `text` into one.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}
