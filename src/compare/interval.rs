//! How sure a timing ratio is: the median of paired per-run ratios and a
//! percentile bootstrap interval around it.
//!
//! The runs of the two methods are interleaved, so run `i` of each saw
//! the same machine state as nearly as can be; their ratio is the unit of
//! evidence, and the interval says how much the median of those ratios
//! would move had other runs of the same kind been drawn. With few runs
//! (7 by default) the interval is rough, and it is wide when the machine is
//! noisy: that is what it is for.

use serde::Serialize;

/// The median of per-run ratios and a 95% bootstrap interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RatioInterval {
    /// The median of the per-run ratios.
    pub median: f64,
    /// The 2.5th percentile of the bootstrapped medians.
    pub low: f64,
    /// The 97.5th percentile of the bootstrapped medians.
    pub high: f64,
}

/// Resamples drawn by [`ratio_interval`].
pub const RESAMPLES: usize = 2000;

/// The median of `values` (the mean of the middle two for an even count);
/// NaN for none.
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
    }
}

/// The median of `numerator[i] / denominator[i]` and its percentile
/// bootstrap interval ([`RESAMPLES`] resamples with replacement, a fixed
/// seed, so the same timings always give the same interval). Pairs beyond
/// the shorter slice are ignored; no pairs give NaNs.
pub fn ratio_interval(numerator: &[f64], denominator: &[f64]) -> RatioInterval {
    let ratios: Vec<f64> = numerator
        .iter()
        .zip(denominator)
        .map(|(a, b)| a / b)
        .collect();
    let n = ratios.len();
    if n == 0 {
        return RatioInterval {
            median: f64::NAN,
            low: f64::NAN,
            high: f64::NAN,
        };
    }
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut draw = move || {
        // xorshift64*: plenty for choosing resample indices.
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 32) as usize % n
    };
    let mut sample = vec![0.0; n];
    let mut medians: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            for s in sample.iter_mut() {
                *s = ratios[draw()];
            }
            median(&sample)
        })
        .collect();
    medians.sort_by(f64::total_cmp);
    let at = |q: f64| medians[((q * (RESAMPLES - 1) as f64).round() as usize).min(RESAMPLES - 1)];
    RatioInterval {
        median: median(&ratios),
        low: at(0.025),
        high: at(0.975),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_odd_even_and_empty() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn identical_ratios_give_a_point_interval() {
        let r = ratio_interval(&[2.0, 4.0, 6.0], &[1.0, 2.0, 3.0]);
        assert_eq!((r.median, r.low, r.high), (2.0, 2.0, 2.0));
    }

    #[test]
    fn the_interval_holds_the_median_and_lies_within_the_ratios() {
        let tmc = [1.10, 1.02, 0.98, 1.30, 1.05, 1.01, 1.07];
        let mc = [1.0; 7];
        let r = ratio_interval(&tmc, &mc);
        assert_eq!(r.median, 1.05);
        assert!(r.low <= r.median && r.median <= r.high, "{r:?}");
        assert!(r.low >= 0.98 && r.high <= 1.30, "{r:?}");
        assert!(r.low < r.high, "{r:?}");
        // Deterministic: the same timings, the same interval.
        assert_eq!(r, ratio_interval(&tmc, &mc));
    }
}
