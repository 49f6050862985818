//! `tmc merge`: part files of `tmc extract --part I/N` in, one mesh out.

use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use tmc::Result;

/// Stitch the part files of 'tmc extract --part I/N' (given in any order)
/// into one mesh, byte-identical to a single run with the same options.
///
/// Streams one chunk at a time from one open part at a time. Refuses
/// (exit 1) parts of different runs (input, isovalue, options, tmc version
/// or part count differ, or the samples of a plane two parts share),
/// missing, truncated parts and parts given twice.
#[derive(Debug, Args)]
pub(crate) struct MergeArgs {
    /// The part files, all N of them, in any order.
    #[arg(value_name = "PART", required = true)]
    pub parts: Vec<PathBuf>,

    /// Output mesh; the format comes from the extension, as for 'tmc
    /// extract'. Written atomically. Label parts merge into one file per
    /// label with {label} (the one placeholder it takes), or one .ply or
    /// .tmesh.
    #[arg(short, long, value_name = "OUTPUT")]
    pub output: PathBuf,

    /// Print nothing on stderr but errors (it prints nothing else today;
    /// accepted so that scripts can pass -q to every subcommand).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `tmc merge`; setting `cancel` (SIGINT, SIGTERM) stops it before
/// the next chunk with [`tmc::Error::Interrupted`], leaving no output.
pub(crate) fn run(args: &MergeArgs, cancel: Option<&AtomicBool>) -> Result<()> {
    // Label parts merge into a file per label with {label}; nothing else
    // is filled in.
    super::placeholders::check(&args.output, "-o", &[super::placeholders::LABEL])?;
    for part in &args.parts {
        tmc::files::check_distinct(part, &args.output)?;
    }
    // Label parts merge into a file per label, all open at once.
    tmc::files::raise_open_file_limit();
    let never = AtomicBool::new(false);
    tmc::part::merge(&args.parts, &args.output, cancel.unwrap_or(&never)).map(|_| ())
}
