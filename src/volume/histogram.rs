//! Fixed-width histograms and Otsu thresholds, for suggesting isovalues.
//!
//! `tmc info` gathers a histogram of a volume's samples and proposes the
//! thresholds that best separate its classes of values (air, soft tissue and
//! bone in CT, say): Otsu's method, single-level (two classes) and
//! multi-level with two thresholds (three classes). The multi-level search
//! is exhaustive over bin pairs, O(bins²) with cumulative sums, which is
//! exact and fast enough for a few thousand bins; no iterative or
//! approximate variant is needed.
//!
//! Thresholds are bin indices: threshold `t` splits bins `0..=t` from
//! `t + 1..`. Since the bins are equally wide, maximizing the between-class
//! variance of bin indices is the same as maximizing it for values, so the
//! search never needs the values themselves. Every cut inside a run of
//! empty bins scores the same; the search returns the first, and
//! [`Histogram::cut_value`] moves it to the middle of the gap, where an
//! isosurface is least sensitive to the choice.

/// Counts of values in `bins` equal-width bins covering `[lo, hi]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub lo: f64,
    /// Upper edge of the last bin.
    pub hi: f64,
    /// Values counted in each bin.
    pub counts: Vec<u64>,
}

impl Histogram {
    /// An empty histogram of `bins` bins (at least 1) over `[lo, hi]`
    /// (`lo <= hi`, both finite).
    pub fn new(lo: f64, hi: f64, bins: usize) -> Self {
        Histogram {
            lo,
            hi,
            counts: vec![0; bins.max(1)],
        }
    }

    /// Width of one bin (0 when `lo == hi`); finite even when `hi - lo`
    /// is not (a range from near `-f64::MAX` to near `f64::MAX`).
    pub fn bin_width(&self) -> f64 {
        let n = self.counts.len() as f64;
        let span = self.hi - self.lo;
        if span.is_finite() {
            span / n
        } else {
            (self.hi / 2.0 - self.lo / 2.0) / n * 2.0
        }
    }

    /// The factor that puts the range in reach of plain arithmetic: `1/2`
    /// when `hi - lo` overflows, `2^900` when the bins' width underflows (a
    /// range of subnormal numbers, all below `2^-959` or so); `None` when
    /// no scaling is needed (or the range is empty). Powers of two: the
    /// scaling is exact.
    fn rescale(&self) -> Option<f64> {
        let finite = (self.hi - self.lo).is_finite();
        if self.hi <= self.lo || (finite && self.bin_width().is_normal()) {
            None
        } else if finite {
            Some(2f64.powi(900))
        } else {
            Some(0.5)
        }
    }

    /// The value `k` bin widths above `lo` (`0 <= k <= bins`), computed
    /// without overflow or underflow.
    fn value_at(&self, k: f64) -> f64 {
        match self.rescale() {
            None => self.lo + self.bin_width() * k,
            Some(s) => {
                let (lo, hi) = (self.lo * s, self.hi * s);
                (lo + (hi - lo) * (k / self.counts.len() as f64)) / s
            }
        }
    }

    /// The bin of `v`: values below `lo` go to the first bin, values at or
    /// above `hi` to the last; `None` for NaN.
    pub fn bin(&self, v: f64) -> Option<usize> {
        if v.is_nan() {
            return None;
        }
        let n = self.counts.len();
        let width = self.bin_width();
        if self.hi <= self.lo {
            return Some(0);
        }
        let position = match self.rescale() {
            None => (v - self.lo) / width,
            Some(s) => {
                let (v, lo, hi) = (v * s, self.lo * s, self.hi * s);
                (v - lo) / (hi - lo) * n as f64
            }
        };
        // Float-to-int `as` saturates: negative values become 0.
        Some((position as usize).min(n - 1))
    }

    /// Counts `v` (NaN is ignored).
    pub fn add(&mut self, v: f64) {
        if let Some(i) = self.bin(v) {
            self.counts[i] += 1;
        }
    }

    /// Adds the counts of `other`, which must have the same bins.
    pub fn merge(&mut self, other: &Histogram) {
        debug_assert_eq!(self.counts.len(), other.counts.len());
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
    }

    /// The value between bin `t` and bin `t + 1` (the upper edge of bin
    /// `t`): where a threshold index falls in value space.
    pub fn upper_edge(&self, t: usize) -> f64 {
        self.value_at((t + 1) as f64)
    }

    /// The value where threshold `t` cuts best: the middle of the run of
    /// empty bins around the cut between bins `t` and `t + 1` (every cut in
    /// that run splits the samples alike, and Otsu's method cannot tell them
    /// apart), from the upper edge of the last non-empty bin at or below `t`
    /// to the lower edge of the first non-empty bin above; just the edge
    /// between bins `t` and `t + 1` when one side is empty. Strictly inside
    /// `(lo, hi)` for `t + 1 < bins`.
    pub fn cut_value(&self, t: usize) -> f64 {
        let below = (0..=t).rev().find(|&i| self.counts[i] > 0);
        let above = (t + 1..self.counts.len()).find(|&i| self.counts[i] > 0);
        match (below, above) {
            (Some(a), Some(b)) => self.value_at((a + 1 + b) as f64 / 2.0),
            _ => self.upper_edge(t),
        }
    }
}

/// Cumulative weight `w[i]` and first moment `m[i]` of bins `0..i` (one
/// more entry than bins), with bin index as the value.
fn cumulative(counts: &[u64]) -> (Vec<f64>, Vec<f64>) {
    let mut w = Vec::with_capacity(counts.len() + 1);
    let mut m = Vec::with_capacity(counts.len() + 1);
    let (mut sw, mut sm) = (0.0, 0.0);
    w.push(0.0);
    m.push(0.0);
    for (i, &c) in counts.iter().enumerate() {
        sw += c as f64;
        sm += c as f64 * i as f64;
        w.push(sw);
        m.push(sm);
    }
    (w, m)
}

/// `moment² / weight` of the class of bins `a..b`, the class's share of the
/// between-class variance (up to constants); 0 for an empty class.
fn class_term(w: &[f64], m: &[f64], a: usize, b: usize) -> f64 {
    let weight = w[b] - w[a];
    if weight > 0.0 {
        let moment = m[b] - m[a];
        moment * moment / weight
    } else {
        0.0
    }
}

/// Single-level Otsu: the bin `t` such that splitting bins `0..=t` from
/// `t + 1..` maximizes the between-class variance (the first such `t` on a
/// tie). `None` with fewer than 2 bins or fewer than 2 non-empty bins.
pub fn otsu(counts: &[u64]) -> Option<usize> {
    if counts.iter().filter(|&&c| c > 0).count() < 2 {
        return None;
    }
    let n = counts.len();
    let (w, m) = cumulative(counts);
    let mut best: Option<(f64, usize)> = None;
    for t in 0..n - 1 {
        let score = class_term(&w, &m, 0, t + 1) + class_term(&w, &m, t + 1, n);
        if best.is_none_or(|(b, _)| score > b) {
            best = Some((score, t));
        }
    }
    best.map(|(_, t)| t)
}

/// Two-level Otsu: bins `t1 < t2` such that the three classes `0..=t1`,
/// `t1 + 1..=t2` and `t2 + 1..` maximize the between-class variance
/// (exhaustive search over all pairs, the first best pair on a tie). `None`
/// with fewer than 3 bins or fewer than 2 non-empty bins.
pub fn otsu2(counts: &[u64]) -> Option<(usize, usize)> {
    let n = counts.len();
    if n < 3 || counts.iter().filter(|&&c| c > 0).count() < 2 {
        return None;
    }
    let (w, m) = cumulative(counts);
    let mut best: Option<(f64, usize, usize)> = None;
    for t1 in 0..n - 2 {
        let low = class_term(&w, &m, 0, t1 + 1);
        for t2 in t1 + 1..n - 1 {
            let score = low + class_term(&w, &m, t1 + 1, t2 + 1) + class_term(&w, &m, t2 + 1, n);
            if best.is_none_or(|(b, _, _)| score > b) {
                best = Some((score, t1, t2));
            }
        }
    }
    best.map(|(_, t1, t2)| (t1, t2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Between-class variance of the classes cut at `cuts` (ascending bin
    /// indices, each the last bin of its class), computed directly from the
    /// definition: sum over classes of weight * (class mean - mean)².
    fn between_variance(counts: &[u64], cuts: &[usize]) -> f64 {
        let total: f64 = counts.iter().map(|&c| c as f64).sum();
        let mean: f64 = counts
            .iter()
            .enumerate()
            .map(|(i, &c)| i as f64 * c as f64)
            .sum::<f64>()
            / total;
        let mut bounds = vec![0];
        bounds.extend(cuts.iter().map(|t| t + 1));
        bounds.push(counts.len());
        bounds
            .windows(2)
            .map(|r| {
                let class = &counts[r[0]..r[1]];
                let w: f64 = class.iter().map(|&c| c as f64).sum();
                if w == 0.0 {
                    return 0.0;
                }
                let mu = class
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| (r[0] + i) as f64 * c as f64)
                    .sum::<f64>()
                    / w;
                w / total * (mu - mean).powi(2)
            })
            .sum()
    }

    /// A small pseudo-random histogram (a linear congruential generator, so
    /// the test needs no crate).
    fn random_counts(seed: u64, bins: usize) -> Vec<u64> {
        let mut s = seed;
        (0..bins)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 33) % 50
            })
            .collect()
    }

    #[test]
    fn single_level_matches_brute_force() {
        for seed in 0..20 {
            let counts = random_counts(seed, 17);
            let t = otsu(&counts).unwrap();
            let best = (0..counts.len() - 1)
                .map(|t| between_variance(&counts, &[t]))
                .fold(f64::MIN, f64::max);
            let got = between_variance(&counts, &[t]);
            assert!(
                (got - best).abs() <= 1e-9 * best,
                "seed {seed}: {got} vs {best}"
            );
        }
    }

    #[test]
    fn two_level_matches_brute_force() {
        for seed in 0..20 {
            let counts = random_counts(seed, 15);
            let (t1, t2) = otsu2(&counts).unwrap();
            assert!(t1 < t2 && t2 < counts.len() - 1);
            let mut best = f64::MIN;
            for a in 0..counts.len() {
                for b in a + 1..counts.len() - 1 {
                    best = best.max(between_variance(&counts, &[a, b]));
                }
            }
            let got = between_variance(&counts, &[t1, t2]);
            assert!(
                (got - best).abs() <= 1e-9 * best,
                "seed {seed}: {got} vs {best}"
            );
        }
    }

    /// Three well-separated modes (like air, soft tissue and bone): the two
    /// thresholds fall in the gaps, and the single one in one of the gaps.
    #[test]
    fn tri_modal_thresholds_fall_between_modes() {
        let mut h = Histogram::new(-1000.0, 2000.0, 300);
        let modes = [
            (-900.0, 40.0, 5000),
            (50.0, 30.0, 3000),
            (1200.0, 80.0, 800),
        ];
        let mut s = 7u64;
        for &(centre, spread, n) in &modes {
            for _ in 0..n {
                // Sum of two uniforms: a triangular bump around `centre`.
                let mut u = || {
                    s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                    (s >> 11) as f64 / (1u64 << 53) as f64
                };
                h.add(centre + spread * (u() + u() - 1.0));
            }
        }
        let (t1, t2) = otsu2(&h.counts).unwrap();
        let (v1, v2) = (h.cut_value(t1), h.cut_value(t2));
        assert!(-860.0 < v1 && v1 < 20.0, "first threshold {v1}");
        assert!(80.0 < v2 && v2 < 1120.0, "second threshold {v2}");
        // In the middle of the gaps, not at the edge of a mode.
        assert!((v1 - -420.0).abs() < 20.0, "first threshold {v1}");
        assert!((v2 - 600.0).abs() < 20.0, "second threshold {v2}");
        let v = h.cut_value(otsu(&h.counts).unwrap());
        assert!(
            (-860.0 < v && v < 20.0) || (80.0 < v && v < 1120.0),
            "single threshold {v}"
        );
    }

    #[test]
    fn degenerate_histograms_have_no_threshold() {
        assert_eq!(otsu(&[5]), None);
        assert_eq!(otsu(&[0, 7, 0]), None);
        assert_eq!(otsu2(&[3, 4]), None);
        assert_eq!(otsu2(&[0, 9, 0, 0]), None);
        // Two values: the single threshold separates them.
        assert_eq!(otsu(&[4, 0, 0, 6]).map(|t| t < 3), Some(true));
        assert!(otsu2(&[4, 0, 0, 6]).is_some());
    }

    /// Ranges whose width overflows (from near `-f64::MAX` to near
    /// `f64::MAX`) or whose bins underflow (subnormal numbers) bin like
    /// any other: the extremes in the end bins, the middle in the middle,
    /// every edge finite and inside the range.
    #[test]
    fn extreme_ranges_bin_and_cut_like_any_other() {
        let max = f64::MAX;
        let tiny = 1e-320;
        for (lo, hi) in [
            (-max, max),
            (0.0, max),
            (-max, 0.0),
            (0.0, tiny),
            (-tiny, tiny),
        ] {
            let mut h = Histogram::new(lo, hi, 4);
            for v in [lo, lo / 2.0 + hi / 2.0, hi] {
                h.add(v);
            }
            assert_eq!(h.counts, vec![1, 0, 1, 1], "[{lo}, {hi}]");
            let width = h.bin_width();
            assert!(width.is_finite() && width > 0.0, "[{lo}, {hi}]: {width}");
            for t in 0..3 {
                let (edge, cut) = (h.upper_edge(t), h.cut_value(t));
                assert!(lo < edge && edge < hi, "[{lo}, {hi}]: edge {t} at {edge}");
                assert!(lo < cut && cut < hi, "[{lo}, {hi}]: cut {t} at {cut}");
            }
        }
    }

    #[test]
    fn binning_clamps_and_skips_nan() {
        let mut h = Histogram::new(0.0, 10.0, 10);
        for v in [-1.0, 0.0, 0.99, 5.0, 10.0, 11.0, f64::NAN] {
            h.add(v);
        }
        assert_eq!(h.counts, vec![3, 0, 0, 0, 0, 1, 0, 0, 0, 2]);
        assert_eq!(h.upper_edge(4), 5.0);
        // Bins 1..=4 are empty: cuts 0..=4 all land mid-gap, at 3.
        assert_eq!(h.cut_value(0), 3.0);
        assert_eq!(h.cut_value(4), 3.0);
        assert_eq!(h.cut_value(5), 7.5);
        assert_eq!(h.cut_value(9), 10.0);
        let mut flat = Histogram::new(3.0, 3.0, 4);
        flat.add(3.0);
        assert_eq!(flat.counts, vec![1, 0, 0, 0]);
    }
}
