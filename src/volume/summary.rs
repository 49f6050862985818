//! A streamed summary of a volume's samples: range, NaN count, mean, a
//! histogram and the isovalues it suggests (`tmc info`).
//!
//! Volumes may be larger than memory, so the samples are visited plane by
//! plane, in parallel over planes (rayon), each worker holding one plane
//! buffer; nothing grows with the volume. Two passes: the first finds the
//! range (and counts NaN and infinite samples and sums for the mean), the
//! second fills a histogram between the minimum and the maximum. The second
//! pass may visit only every k-th plane ([`SummaryOptions::plane_step`]) to
//! bound the time spent on huge volumes; the range, counts and mean are
//! always exact.

use super::histogram::{otsu, otsu2, Histogram};
use super::{Access, SampleSource};
use crate::error::try_filled;
use crate::Result;
use rayon::prelude::*;

/// How to summarize a volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SummaryOptions {
    /// Histogram bins (at least 3). Integer-valued data whose range is
    /// narrower gets one bin per integer instead.
    pub bins: usize,
    /// The histogram counts planes `0, k, 2k, ...` for `plane_step = k`
    /// (at least 1).
    pub plane_step: usize,
}

impl Default for SummaryOptions {
    fn default() -> Self {
        SummaryOptions {
            bins: 1024,
            plane_step: 1,
        }
    }
}

/// What the samples of a volume hold.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Samples in the volume.
    pub samples: u64,
    /// NaN samples.
    pub nan: u64,
    /// Infinite samples (left out of the range, mean and histogram).
    pub infinite: u64,
    /// Smallest finite sample, if any.
    pub min: Option<f64>,
    /// Largest finite sample, if any.
    pub max: Option<f64>,
    /// Mean of the finite samples, if any.
    pub mean: Option<f64>,
    /// Whether every finite sample is a whole number (integer sample types,
    /// unless a scaling makes them fractional).
    pub integer_valued: bool,
    /// Histogram of the finite samples of the planes visited (`None` when
    /// there are fewer than two distinct finite values).
    pub histogram: Option<Histogram>,
    /// The plane step the histogram used.
    pub plane_step: usize,
}

/// Isovalues suggested by Otsu's method (see [`Summary::suggestions`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Suggestions {
    /// Single-level Otsu: one isovalue separating two classes.
    pub single: Option<f64>,
    /// Two-level Otsu: two isovalues separating three classes (ascending).
    pub pair: Option<[f64; 2]>,
}

/// Per-worker accumulator of the first pass.
#[derive(Debug, Clone, Copy)]
struct Range {
    nan: u64,
    infinite: u64,
    finite: u64,
    min: f64,
    max: f64,
    /// The sum of the finite samples; infinite or NaN once it overflowed
    /// (values near `f64::MAX`), when `scaled` holds the mean.
    sum: f64,
    /// The same sum, each plane's times [`SUM_SCALE`]: it cannot overflow.
    scaled: f64,
    integer: bool,
}

/// The factor of [`Range::scaled`]: `2^-128`, exact, so that `2^64`
/// samples of `f64::MAX` still sum to a finite value.
const SUM_SCALE: f64 = 1.0 / (1u128 << 127) as f64 / 2.0;

impl Range {
    const EMPTY: Range = Range {
        nan: 0,
        infinite: 0,
        finite: 0,
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        sum: 0.0,
        scaled: 0.0,
        integer: true,
    };

    fn add_plane(&mut self, plane: &[f64]) {
        // Summing a plane on its own first keeps the rounding error of the
        // mean small for large volumes.
        let mut sum = 0.0;
        for &v in plane {
            if v.is_nan() {
                self.nan += 1;
            } else if v.is_infinite() {
                self.infinite += 1;
            } else {
                self.finite += 1;
                self.min = self.min.min(v);
                self.max = self.max.max(v);
                sum += v;
                self.integer &= v.fract() == 0.0;
            }
        }
        self.sum += sum;
        self.scaled += if sum.is_finite() {
            sum * SUM_SCALE
        } else {
            // The plane's own sum overflowed: again, scaled sample by sample.
            plane
                .iter()
                .filter(|v| v.is_finite())
                .map(|v| v * SUM_SCALE)
                .sum()
        };
    }

    /// The mean of the finite samples (at least one): the plain sum's when
    /// it is finite, else the scaled sum's; within `[min, max]` always.
    fn mean(&self) -> f64 {
        let n = self.finite as f64;
        let mean = if self.sum.is_finite() {
            self.sum / n
        } else {
            self.scaled / n / SUM_SCALE
        };
        mean.clamp(self.min, self.max)
    }

    fn merge(self, o: Range) -> Range {
        Range {
            nan: self.nan + o.nan,
            infinite: self.infinite + o.infinite,
            finite: self.finite + o.finite,
            min: self.min.min(o.min),
            max: self.max.max(o.max),
            sum: self.sum + o.sum,
            scaled: self.scaled + o.scaled,
            integer: self.integer && o.integer,
        }
    }
}

/// Runs `add` on every `step`-th plane `z` (from 0), in parallel, one
/// plane buffer per worker, and merges the accumulators. (The planes are
/// not listed first: a list of 2^32 plane numbers would not fit in memory.)
fn scan<A, I, F, M>(source: &dyn SampleSource, step: usize, init: I, add: F, merge: M) -> Result<A>
where
    A: Send,
    I: Fn() -> A + Sync + Send,
    F: Fn(&mut A, &[f64]) + Sync + Send,
    M: Fn(A, A) -> A + Sync + Send,
{
    let plane_len = source.grid().plane_len();
    (0..source.grid().dims[2])
        .into_par_iter()
        .step_by(step)
        .try_fold(
            || (init(), Vec::new()),
            |(mut acc, mut buf), z| {
                if buf.is_empty() {
                    buf = try_filled("a plane of samples", plane_len, 0.0)?;
                }
                source.read_plane(z, &mut buf)?;
                source.advise(z..z + 1, Access::Done);
                add(&mut acc, &buf);
                Ok((acc, buf))
            },
        )
        .map(|r: Result<(A, Vec<f64>)>| r.map(|(acc, _)| acc))
        .try_reduce(&init, |a, b| Ok(merge(a, b)))
}

/// Summarizes `source` in two streamed passes (see the module docs).
pub fn summarize(source: &dyn SampleSource, options: &SummaryOptions) -> Result<Summary> {
    let grid = source.grid();
    let samples = grid.dims.iter().map(|&n| n as u64).product();
    let range = scan(source, 1, || Range::EMPTY, Range::add_plane, Range::merge)?;
    let step = options.plane_step.max(1);
    let finite = range.finite > 0;
    let histogram = if finite && range.min < range.max {
        let template = histogram_bins(range.min, range.max, range.integer, options.bins);
        let h = scan(
            source,
            step,
            || template.clone(),
            |h, plane| {
                for &v in plane {
                    if v.is_finite() {
                        h.add(v);
                    }
                }
            },
            |mut a, b| {
                a.merge(&b);
                a
            },
        )?;
        Some(h)
    } else {
        None
    };
    Ok(Summary {
        samples,
        nan: range.nan,
        infinite: range.infinite,
        min: finite.then_some(range.min),
        max: finite.then_some(range.max),
        mean: finite.then(|| range.mean()),
        integer_valued: range.integer,
        histogram,
        plane_step: step,
    })
}

/// The empty histogram for samples in `[min, max]` (`min < max`): one bin
/// per integer for integer-valued data narrower than `bins`, so that every
/// bin edge is a half-integer; else `bins` bins (at least 3).
fn histogram_bins(min: f64, max: f64, integer: bool, bins: usize) -> Histogram {
    let bins = bins.max(3);
    if integer && max - min < bins as f64 {
        Histogram::new(min - 0.5, max + 0.5, (max - min) as usize + 1)
    } else {
        Histogram::new(min, max, bins)
    }
}

impl Summary {
    /// The isovalues Otsu's method suggests, as "nice" numbers strictly
    /// between the minimum and the maximum: for integer-valued data a
    /// half-integer (`floor(threshold) + 0.5`), which no sample equals, so
    /// no sample ties with the isovalue (ties are legal, a sample equal to
    /// the isovalue is outside, but a half-integer makes the choice
    /// obvious); otherwise the threshold rounded to a power of ten no
    /// larger than the bin width. The pair is two distinct values, so
    /// data with two values (a mask) get only the single isovalue.
    pub fn suggestions(&self) -> Suggestions {
        let (Some(h), Some(min), Some(max)) = (&self.histogram, self.min, self.max) else {
            return Suggestions {
                single: None,
                pair: None,
            };
        };
        let nice =
            |t: usize| nice_value(h.cut_value(t), h.bin_width(), min, max, self.integer_valued);
        Suggestions {
            single: otsu(&h.counts).map(nice),
            // With two distinct values (a mask) both cuts fall into the one
            // gap: the middle class is empty, and there is no pair.
            pair: otsu2(&h.counts)
                .map(|(a, b)| [nice(a), nice(b)])
                .filter(|[a, b]| a < b),
        }
    }
}

/// A round number near the threshold `edge` (strictly between `min` and
/// `max`, as every [`Histogram::cut_value`] is): see
/// [`Summary::suggestions`].
fn nice_value(edge: f64, width: f64, min: f64, max: f64, integer: bool) -> f64 {
    if integer {
        // `min < edge < max` with integer `min` and `max` gives
        // `min + 0.5 <= floor(edge) + 0.5 <= max - 0.5`.
        return edge.floor() + 0.5;
    }
    if width > 0.0 && width.is_finite() {
        // A negative power of ten divides by its exact inverse, so that
        // 1629 units of 1e-4 give 0.1629, not 0.16290000000000002.
        let power = width.log10().floor();
        let rounded = match power < 0.0 {
            true => {
                let inverse = 10f64.powf(-power);
                (edge * inverse).round() / inverse
            }
            false => {
                let unit = 10f64.powf(power);
                (edge / unit).round() * unit
            }
        };
        if rounded > min && rounded < max && rounded.is_finite() {
            return rounded;
        }
    }
    edge
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ArrayVolume, Grid};

    fn volume(dims: [usize; 3], values: Vec<f64>) -> ArrayVolume {
        ArrayVolume::new(Grid::unit(dims), values).unwrap()
    }

    #[test]
    fn range_counts_and_mean() {
        let mut values: Vec<f64> = (0..60).map(|i| i as f64).collect();
        values[5] = f64::NAN;
        values[7] = f64::INFINITY;
        let v = volume([3, 4, 5], values);
        let s = summarize(&v, &SummaryOptions::default()).unwrap();
        assert_eq!((s.samples, s.nan, s.infinite), (60, 1, 1));
        assert_eq!((s.min, s.max), (Some(0.0), Some(59.0)));
        let mean = (0..60).filter(|&i| i != 5 && i != 7).sum::<i32>() as f64 / 58.0;
        assert!((s.mean.unwrap() - mean).abs() < 1e-12);
        assert!(s.integer_valued);
        // One bin per integer.
        assert_eq!(s.histogram.as_ref().unwrap().counts.len(), 60);
    }

    /// Three plateaus of integers: the suggested pair is one half-integer
    /// in each gap.
    #[test]
    fn integer_suggestions_are_half_integers_between_modes() {
        let values: Vec<f64> = (0..8 * 8 * 6)
            .map(|i| match i % 10 {
                0..=4 => 10.0 + (i % 3) as f64,
                5..=7 => 100.0 + (i % 5) as f64,
                _ => 300.0 + (i % 2) as f64,
            })
            .collect();
        let s = summarize(&volume([8, 8, 6], values), &SummaryOptions::default()).unwrap();
        let [a, b] = s.suggestions().pair.unwrap();
        assert!(12.0 < a && a < 100.0, "{a}");
        assert!(102.0 < b && b < 300.0, "{b}");
        // Mid-gap: between 12 and 100, between 102 and 300.
        assert_eq!([a, b], [56.5, 201.5]);
        assert_eq!(a.fract(), 0.5);
        assert_eq!(b.fract(), 0.5);
        let single = s.suggestions().single.unwrap();
        assert_eq!(single.fract(), 0.5);
    }

    #[test]
    fn float_suggestions_are_round_and_inside_the_range() {
        let values: Vec<f64> = (0..4 * 4 * 4)
            .map(|i| if i % 2 == 0 { 0.1234 } else { 0.9876 } + i as f64 * 1e-4)
            .collect();
        let s = summarize(&volume([4, 4, 4], values), &SummaryOptions::default()).unwrap();
        assert!(!s.integer_valued);
        let t = s.suggestions().single.unwrap();
        let (min, max) = (s.min.unwrap(), s.max.unwrap());
        assert!(min < t && t < max, "{t}");
        // Rounded to a multiple of 1e-4 (bin width about 8.5e-4).
        assert!((t * 1e4 - (t * 1e4).round()).abs() < 1e-6, "{t}");
    }

    /// A suggestion prints as the round number it is: users copy it into
    /// `--iso` and into file names (`{iso}`).
    #[test]
    fn rounded_suggestions_print_short() {
        for (edge, width, text) in [
            (0.16287, 8.5e-4, "0.1629"),
            (0.50291, 8.5e-4, "0.5029"),
            (0.7, 0.3, "0.7"),
            (1234.4, 17.0, "1230"),
            (3.3e-7, 2e-9, "0.00000033"),
        ] {
            let t = nice_value(edge, width, 0.0, 2000.0, false);
            assert_eq!(t.to_string(), text, "edge {edge} width {width}");
        }
    }

    #[test]
    fn constant_and_all_nan_volumes_suggest_nothing() {
        let s = summarize(&volume([2, 2, 2], vec![3.0; 8]), &SummaryOptions::default()).unwrap();
        assert_eq!((s.min, s.max), (Some(3.0), Some(3.0)));
        assert_eq!(s.suggestions().pair, None);
        let s = summarize(
            &volume([2, 2, 2], vec![f64::NAN; 8]),
            &SummaryOptions::default(),
        )
        .unwrap();
        assert_eq!((s.min, s.mean, s.nan), (None, None, 8));
        assert_eq!(s.suggestions().single, None);
    }

    #[test]
    fn plane_step_thins_the_histogram_only() {
        let values: Vec<f64> = (0..4 * 4 * 10).map(|i| (i / 16) as f64).collect();
        let options = SummaryOptions {
            bins: 1024,
            plane_step: 3,
        };
        let s = summarize(&volume([4, 4, 10], values), &options).unwrap();
        assert_eq!((s.min, s.max), (Some(0.0), Some(9.0)));
        let h = s.histogram.unwrap();
        // Planes 0, 3, 6, 9.
        assert_eq!(h.counts.iter().sum::<u64>(), 64);
        assert_eq!(h.counts[3], 16);
        assert_eq!(h.counts[4], 0);
    }
}
