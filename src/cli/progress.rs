//! Progress on stderr: a bar with percent, rate and ETA when stderr is a
//! terminal, or (`--progress lines`, for the logs of batch jobs) a plain
//! line every tenth of the work and at least every half minute.

use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressState, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// `--progress`: how progress is shown on stderr.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub(crate) enum ProgressMode {
    /// A bar when stderr is a terminal, nothing otherwise.
    #[default]
    Auto,
    /// A line at every tenth of the work and at least every 30 s (for the
    /// log of a batch job), terminal or not.
    Lines,
    /// Nothing.
    Never,
}

/// Longest time between two lines of `--progress lines`.
const LINE_INTERVAL: Duration = Duration::from_secs(30);

/// Progress over `total` units of work (voxels, samples): a bar, lines or
/// nothing (see [`ProgressMode`]). A bar is cleared from the terminal when
/// dropped, so that the lines printed after it (errors, the statistics
/// table) stand alone.
pub(crate) struct Bar {
    bar: Option<ProgressBar>,
    lines: Option<Lines>,
    total: u64,
}

/// The state of `--progress lines`.
struct Lines {
    /// What the lines are about (the input).
    label: String,
    start: Instant,
    /// Tenths of the work done at the last line, and when it was printed.
    last: Mutex<(u64, Instant)>,
}

impl Bar {
    /// A bar over `total` units named `unit` (for the rate: "voxels/s"),
    /// shown when stderr is a terminal and not `quiet`.
    pub(crate) fn new(total: u64, unit: &'static str, quiet: bool) -> Bar {
        let mode = if quiet {
            ProgressMode::Never
        } else {
            ProgressMode::Auto
        };
        Bar::with_mode(total, unit, mode, "")
    }

    /// Progress over `total` units named `unit`, shown as `mode` says;
    /// lines name `label`.
    pub(crate) fn with_mode(
        total: u64,
        unit: &'static str,
        mode: ProgressMode,
        label: &str,
    ) -> Bar {
        let lines = (mode == ProgressMode::Lines).then(|| Lines {
            label: label.to_string(),
            start: Instant::now(),
            last: Mutex::new((0, Instant::now())),
        });
        let terminal = mode == ProgressMode::Auto && std::io::stderr().is_terminal();
        let bar = terminal.then(|| {
            let style =
                ProgressStyle::with_template("{percent:>3}% [{wide_bar}] {rate}, ETA {eta}")
                    .expect("the template is valid")
                    .with_key(
                        "rate",
                        move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                            let _ = write!(w, "{} {unit}/s", si(s.per_sec()));
                        },
                    )
                    .progress_chars("=> ");
            ProgressBar::new(total).with_style(style)
        });
        Bar { bar, lines, total }
    }

    /// Moves the bar to `fraction` (0 to 1) of the work.
    pub(crate) fn set_fraction(&self, fraction: f64) {
        if let Some(bar) = &self.bar {
            bar.set_position((fraction.clamp(0.0, 1.0) * self.total as f64) as u64);
        }
    }

    /// Moves the bar to `done` of `total` steps named `steps` (the lines
    /// count these: "40% of 511 cell layers").
    pub(crate) fn set_done(&self, done: u64, total: u64, steps: &str) {
        let fraction = (done as f64 / total.max(1) as f64).clamp(0.0, 1.0);
        self.set_fraction(fraction);
        if let Some(lines) = &self.lines {
            lines.update(fraction, &format!("{total} {steps}"));
        }
    }
}

impl Lines {
    /// Prints a line if `fraction` of the `total` work has reached a new
    /// tenth, or if [`LINE_INTERVAL`] has passed since the last line.
    fn update(&self, fraction: f64, total: &str) {
        let tenths = (fraction * 10.0).floor() as u64;
        let now = Instant::now();
        let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
        let (last_tenths, last_time) = *last;
        if tenths <= last_tenths && now - last_time < LINE_INTERVAL {
            return;
        }
        *last = (tenths.max(last_tenths), now);
        let elapsed = (now - self.start).as_secs_f64();
        let eta = if fraction >= 1.0 {
            String::new()
        } else if fraction > 0.0 {
            let eta = elapsed * (1.0 - fraction) / fraction;
            let digits = usize::from(eta < 10.0);
            format!(", ETA {eta:.digits$} s")
        } else {
            ", ETA unknown".to_string()
        };
        say!(
            "tmc: {}: {:.0}% of {total}, {elapsed:.1} s{eta}",
            self.label,
            fraction * 100.0
        );
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// `x` with an SI prefix and three significant digits: `152 M`, `4.27 k`,
/// `512`.
pub(crate) fn si(x: f64) -> String {
    let (value, prefix) = [(1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k")]
        .iter()
        .find(|(scale, _)| x >= *scale)
        .map_or((x, ""), |&(scale, p)| (x / scale, p));
    let digits = if value >= 100.0 {
        0
    } else if value >= 10.0 {
        1
    } else {
        2
    };
    if prefix.is_empty() {
        format!("{value:.digits$}")
    } else {
        format!("{value:.digits$} {prefix}")
    }
}
