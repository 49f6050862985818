//! What an extraction reports about itself, as one value: [`RunSummary`],
//! the part of the object `tmc extract --json` prints that depends on the
//! extraction alone (the CLI adds the paths before it and what the run cost
//! after it).
//!
//! The library owns it so that every caller (the CLI, a language binding)
//! reports a run under the same names, in the same order, with the same
//! values.

use super::threads::worker_threads;
use crate::grid::Grid;
use crate::params::ExtractParams;
use crate::stats::Stats;
use serde::Serialize;

/// One finished extraction: its parameters, the grid and the statistics.
/// Serialized (serde) it is a flat object, keys in this order, then the
/// keys of [`Stats`].
///
/// It owns its [`Stats`] (a copy of a few numbers) rather than borrowing
/// them, so that a caller can keep it, return it or hand it to another
/// language without a lifetime tying it to the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// The isovalue.
    pub iso: f64,
    /// The method's name ([`Method::name`](crate::params::Method::name)):
    /// "tmc" or "mc".
    pub method: &'static str,
    /// The side that is the object
    /// ([`Inside::name`](crate::params::Inside::name)): "high" or "low".
    pub inside: &'static str,
    /// Whether the surface was closed at the volume's boundary.
    pub close: bool,
    /// Worker threads the run meant ([`worker_threads`] of the parameters'
    /// `threads`).
    pub threads: usize,
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// Distance between samples along x, y, z.
    pub spacing: [f64; 3],
    /// World position of sample (0, 0, 0).
    pub origin: [f64; 3],
    /// The statistics of the run, flattened into the object.
    #[serde(flatten)]
    pub stats: Stats,
}

impl RunSummary {
    /// The summary of an extraction of a volume on `grid` with `params`
    /// that returned `stats`.
    pub fn new(params: &ExtractParams, grid: &Grid, stats: &Stats) -> RunSummary {
        RunSummary {
            iso: params.iso,
            method: params.method.name(),
            inside: params.inside.name(),
            close: params.close,
            threads: worker_threads(params.threads),
            dims: grid.dims,
            spacing: grid.spacing,
            origin: grid.origin,
            stats: stats.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{Inside, Method};

    #[test]
    fn keys_come_in_report_order_with_the_stats_flattened() {
        let params = ExtractParams {
            iso: 0.5,
            method: Method::Mc,
            inside: Inside::Low,
            close: true,
            threads: 3,
            normals: false,
        };
        let summary = RunSummary::new(&params, &Grid::unit([2, 3, 4]), &Stats::default());
        let json = serde_json::to_string(&summary).unwrap();
        assert!(json.starts_with(
            r#"{"iso":0.5,"method":"mc","inside":"low","close":true,"threads":3,"dims":[2,3,4],"spacing":[1.0,1.0,1.0],"origin":[0.0,0.0,0.0],"ambiguous_cells":0,"#
        ));
        assert!(json.ends_with(r#""seconds":0.0}"#));
    }
}
