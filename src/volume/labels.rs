//! [`scan_labels`]: the values of a label map and how many samples each
//! has, read plane by plane, with the first sample that is not a whole
//! number refused.

use super::SampleSource;
use crate::error::try_filled;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// The values of a label map, ascending, each with its number of samples.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LabelCounts {
    /// `(value, samples)` for every value present, ascending.
    pub counts: Vec<(i64, u64)>,
}

impl LabelCounts {
    /// The samples of `label` (0 when absent).
    pub fn samples(&self, label: i64) -> u64 {
        self.counts
            .binary_search_by_key(&label, |&(l, _)| l)
            .map_or(0, |k| self.counts[k].1)
    }

    /// Every value present but `background`, ascending.
    pub fn labels_except(&self, background: i64) -> Vec<i64> {
        self.counts
            .iter()
            .map(|&(l, _)| l)
            .filter(|&l| l != background)
            .collect()
    }
}

/// Reads every plane of `source` once (in z order, one plane of `f64` in
/// memory) and counts the samples of each value. Label maps hold integers,
/// though many are stored as floats: a sample that is not a whole number
/// within ±2^53 (a fraction, NaN, an infinity) is an error naming its
/// position, the first in the file's order (x fastest, then y, then z).
/// Stops with [`Error::Interrupted`] once `cancel` is set (looked at every
/// plane).
pub fn scan_labels(source: &dyn SampleSource, cancel: Option<&AtomicBool>) -> Result<LabelCounts> {
    const LIMIT: f64 = (1u64 << 53) as f64;
    let [nx, ny, nz] = source.grid().dims;
    let mut plane = try_filled("a plane of samples", nx * ny, 0.0)?;
    let mut counts: BTreeMap<i64, u64> = BTreeMap::new();
    for z in 0..nz {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Err(Error::Interrupted);
        }
        source.read_plane(z, &mut plane)?;
        let mut i = 0;
        while i < plane.len() {
            let v = plane[i];
            let mut end = i + 1;
            while end < plane.len() && plane[end] == v {
                end += 1;
            }
            if !(v.fract() == 0.0 && v.abs() <= LIMIT) {
                return Err(Error::Invalid(format!(
                    "sample (x {}, y {}, z {}) is {v}, not a whole number: a label map holds integer labels",
                    i % nx,
                    i / nx,
                    z
                )));
            }
            *counts.entry(v as i64).or_default() += (end - i) as u64;
            i = end;
        }
    }
    Ok(LabelCounts {
        counts: counts.into_iter().collect(),
    })
}
