//! [`Monitor`]: the progress bar and the peak memory of one extraction.

use super::extract_args::ExtractArgs;
use super::{memory, progress};
use std::path::Path;
use tmc::Grid;

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
