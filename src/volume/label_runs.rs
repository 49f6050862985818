//! [`MapRuns`]: a label map's planes as runs of equal samples, kept by the
//! scan that counts the labels ([`super::scan_label_map`]) so that the pass
//! over the labels codes its slabs from them instead of reading the map a
//! second time (`stream::label_codes`).
//!
//! Segmentations are long runs (a 512^3 map of 114 labels has about 3
//! runs a row, 12 bytes each: 10 MiB for 256 MiB of samples), and reading
//! the map and finding its runs was as much work as the whole scan. The
//! runs are kept only up to a cap ([`MapRuns::cap`]): a map of short runs
//! (noise, or one label a sample) keeps the planes that fit, and the pass
//! reads the others from the map as before. Either way the pass sees the
//! same values: only the time differs.

/// A plane's runs in raster order: row `y`'s are `ends[rows[y]..rows[y +
/// 1]]`, each run ending (exclusively) where the next begins, with the
/// value of `values` at the same position (a whole number: the scan
/// refuses any other sample).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PlaneRuns {
    rows: Vec<u32>,
    ends: Vec<u32>,
    values: Vec<i64>,
}

impl PlaneRuns {
    /// The plane's runs.
    pub(super) fn len(&self) -> usize {
        self.ends.len()
    }

    /// Bytes the plane's runs take (their vectors' room).
    pub(super) fn bytes(&self) -> usize {
        4 * self.rows.capacity() + 4 * self.ends.capacity() + 8 * self.values.capacity()
    }

    /// Calls `f(y, x, end, value)` for every run `x..end` of each row `y`,
    /// in raster order, as [`super::plane_runs`] does for the plane in the
    /// map; with `padded`, as it does for the plane of
    /// [`super::Padded`] around the map (rows and columns one further,
    /// each row's border a NaN run of its own, the border rows one NaN run
    /// each: NaN is no label, so only where the runs split differs).
    pub fn each<E>(
        &self,
        padded: bool,
        mut f: impl FnMut(usize, usize, usize, f64) -> Result<(), E>,
    ) -> Result<(), E> {
        let shift = usize::from(padded);
        let rows = self.rows.len() - 1;
        let width = self.ends.last().map_or(0, |&e| e as usize);
        if padded {
            f(0, 0, width + 2, f64::NAN)?;
        }
        for y in 0..rows {
            let runs = self.rows[y] as usize..self.rows[y + 1] as usize;
            if padded {
                f(y + 1, 0, 1, f64::NAN)?;
            }
            let mut x = 0;
            for (&end, &value) in self.ends[runs.clone()].iter().zip(&self.values[runs]) {
                let end = end as usize;
                f(y + shift, x + shift, end + shift, value as f64)?;
                x = end;
            }
            if padded {
                f(y + 1, width + 1, width + 2, f64::NAN)?;
            }
        }
        if padded {
            f(rows + 1, 0, width + 2, f64::NAN)?;
        }
        Ok(())
    }
}

/// Builds a [`PlaneRuns`] from the runs of a plane of `ny` rows handed to
/// it in raster order.
pub(super) struct PlaneRunsBuilder {
    runs: PlaneRuns,
    ny: usize,
}

impl PlaneRunsBuilder {
    /// A builder with room for `expected` runs (the plane before's, so
    /// that a plane's vectors seldom grow: growing them on two threads at
    /// once made the threads wait for the allocator's lock).
    pub(super) fn new(ny: usize, expected: usize) -> Self {
        let mut runs = PlaneRuns::default();
        runs.rows.reserve(ny + 1);
        runs.rows.push(0);
        runs.ends.reserve(expected);
        runs.values.reserve(expected);
        PlaneRunsBuilder { runs, ny }
    }

    /// Adds the run ending at `end` in row `y` with value `value` (whole).
    pub(super) fn push(&mut self, y: usize, end: usize, value: i64) {
        let runs = &mut self.runs;
        while runs.rows.len() <= y {
            runs.rows.push(runs.ends.len() as u32);
        }
        runs.ends.push(end as u32);
        runs.values.push(value);
    }

    /// The plane's runs (no more of them to come).
    pub(super) fn finish(mut self) -> PlaneRuns {
        let runs = &mut self.runs;
        while runs.rows.len() <= self.ny {
            runs.rows.push(runs.ends.len() as u32);
        }
        self.runs
    }
}

/// The runs of a label map's planes that the scan kept: plane `z`'s, or
/// `None` for a plane past the cap.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MapRuns {
    planes: Vec<Option<PlaneRuns>>,
}

impl MapRuns {
    /// The most bytes of runs kept for a map of `samples` samples stored in
    /// `sample_bytes` bytes each: an eighth of the map's own size (runs
    /// that take more are short, and reading them again costs less than
    /// the memory) and at most 128 MiB, so that the memory of a pass stays
    /// bounded whatever the map's size.
    pub fn cap(samples: u64, sample_bytes: usize) -> usize {
        let eighth = samples.saturating_mul(sample_bytes as u64) / 8;
        eighth.min(128 << 20) as usize
    }

    /// Runs from the planes' runs, in z order.
    pub(super) fn new(planes: Vec<Option<PlaneRuns>>) -> Self {
        MapRuns { planes }
    }

    /// The runs of plane `z` of the map, when kept.
    pub fn plane(&self, z: usize) -> Option<&PlaneRuns> {
        self.planes.get(z)?.as_ref()
    }

    /// Bytes the kept runs take.
    pub fn bytes(&self) -> usize {
        self.planes.iter().flatten().map(PlaneRuns::bytes).sum()
    }

    /// Planes whose runs are kept.
    pub fn kept_planes(&self) -> usize {
        self.planes.iter().flatten().count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(runs: &PlaneRuns, padded: bool) -> Vec<(usize, usize, usize, String)> {
        let mut out = Vec::new();
        runs.each::<()>(padded, |y, x, end, v| {
            out.push((y, x, end, format!("{v}")));
            Ok(())
        })
        .unwrap();
        out
    }

    #[test]
    fn a_plane_gives_back_its_runs_and_those_of_its_padded_plane() {
        // Rows of 4: [7 7 0 0], [5 5 5 5].
        let mut b = PlaneRunsBuilder::new(2, 0);
        b.push(0, 2, 7);
        b.push(0, 4, 0);
        b.push(1, 4, 5);
        let runs = b.finish();
        assert_eq!(
            collect(&runs, false),
            [
                (0, 0, 2, "7".into()),
                (0, 2, 4, "0".into()),
                (1, 0, 4, "5".into())
            ]
        );
        assert_eq!(
            collect(&runs, true),
            [
                (0, 0, 6, "NaN".into()),
                (1, 0, 1, "NaN".into()),
                (1, 1, 3, "7".into()),
                (1, 3, 5, "0".into()),
                (1, 5, 6, "NaN".into()),
                (2, 0, 1, "NaN".into()),
                (2, 1, 5, "5".into()),
                (2, 5, 6, "NaN".into()),
                (3, 0, 6, "NaN".into()),
            ]
        );
        // At least the numbers held (room may be more).
        assert!(runs.bytes() >= 4 * 3 + 12 * 3);
    }

    #[test]
    fn the_cap_is_an_eighth_of_the_map_and_at_most_128_mib() {
        assert_eq!(MapRuns::cap(800, 2), 200);
        assert_eq!(MapRuns::cap(1 << 40, 2), 128 << 20);
    }
}
