//! Command-line parsing, dispatch and error reporting.
//!
//! Every failure is reported as exactly one line `tmc: error: <message>` on
//! stderr; the exit status is 0 on success, 1 on failure, 2 on a usage error
//! and 130, 143 or 129 when SIGINT, SIGTERM or SIGHUP interrupted a command
//! that writes a file or streams a volume (`tmc info`).

#[macro_use]
mod stderr;

mod batch;
mod check;
mod compare;
mod convert;
mod dicom_series;
mod extract;
mod extract_args;
mod help_text;
mod info;
mod labels;
mod manifest;
mod memory;
mod merge;
mod monitor;
mod output;
mod placeholders;
mod preview;
mod progress;
mod raw_input;
mod report;
mod require_surface;
mod signals;
mod synth;
mod values;

use help_text::CONVENTIONS;
use output::one_line;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};
use std::io::Write;
use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

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
    Extract(extract_args::ExtractArgs),
    Convert(convert::ConvertArgs),
    Merge(merge::MergeArgs),
    Check(check::CheckArgs),
    Compare(compare::CompareArgs),
    Info(info::InfoArgs),
    Preview(preview::PreviewArgs),
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
        Command::Extract(_)
        | Command::Convert(_)
        | Command::Merge(_)
        | Command::Synth(_)
        | Command::Compare(_)
        | Command::Preview(_)
        | Command::Info(_) => match signals::Interrupts::install() {
            Ok(i) => Some(i),
            Err(e) => {
                say!("tmc: error: cannot install the SIGINT/SIGTERM/SIGHUP handlers: {e}");
                return ExitCode::FAILURE;
            }
        },
        _ => None,
    };
    let result = panic::catch_unwind(AssertUnwindSafe(|| match cli.command {
        Command::Extract(args) => extract::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Convert(args) => convert::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Merge(args) => merge::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Check(args) => check::run(&args),
        Command::Compare(args) => compare::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Info(args) => info::run(&args, interrupts.as_ref().map(|i| i.flag())),
        Command::Preview(args) => preview::run(&args, interrupts.as_ref().map(|i| i.flag())),
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
