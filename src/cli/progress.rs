//! A progress bar on stderr: percent, rate and ETA, shown only when stderr
//! is a terminal and the run is not `--quiet`.

use indicatif::{ProgressBar, ProgressState, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar over `total` units of work (voxels, samples), or nothing
/// when stderr is not a terminal or output is suppressed. Cleared from the
/// terminal when dropped, so that the lines printed after it (errors, the
/// statistics table) stand alone.
pub(crate) struct Bar {
    bar: Option<ProgressBar>,
    total: u64,
}

impl Bar {
    /// A bar over `total` units named `unit` (for the rate: "voxels/s").
    pub(crate) fn new(total: u64, unit: &'static str, quiet: bool) -> Bar {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
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
        Bar { bar, total }
    }

    /// Moves the bar to `fraction` (0 to 1) of the work.
    pub(crate) fn set_fraction(&self, fraction: f64) {
        if let Some(bar) = &self.bar {
            bar.set_position((fraction.clamp(0.0, 1.0) * self.total as f64) as u64);
        }
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
