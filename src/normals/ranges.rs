//! Ranges of cell layers for the workers.

use std::ops::Range;

/// Cuts the layers of `starts` (see [`Buckets`](super::buckets::Buckets))
/// into consecutive ranges of about `total / pieces` vertices each (at
/// least `min_vertices`), skipping nothing: the ranges cover every layer
/// from the first to the last, in order.
///
/// Each range re-reads the planes at its boundaries, so ranges are not cut
/// finer than `min_vertices` vertices; empty layers cost nothing (their
/// planes are not read), so the cut counts vertices, not layers.
pub fn layer_ranges(starts: &[usize], pieces: usize, min_vertices: usize) -> Vec<Range<usize>> {
    let layers = starts.len().saturating_sub(1);
    let total = starts.last().copied().unwrap_or(0);
    let target = (total / pieces.max(1)).max(min_vertices).max(1);
    let mut ranges = Vec::new();
    let mut begin = 0;
    for z in 0..layers {
        if starts[z + 1] - starts[begin] >= target {
            ranges.push(begin..z + 1);
            begin = z + 1;
        }
    }
    if begin < layers {
        ranges.push(begin..layers);
    }
    ranges
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_cover_every_layer_in_order() {
        let starts = [0, 5, 5, 12, 20, 20, 31];
        for pieces in 1..8 {
            for min in [0, 1, 7, 100] {
                let r = layer_ranges(&starts, pieces, min);
                assert_eq!(r.first().map(|r| r.start), Some(0));
                assert_eq!(r.last().map(|r| r.end), Some(6));
                assert!(r.windows(2).all(|w| w[0].end == w[1].start));
                assert!(r.iter().all(|r| !r.is_empty()));
            }
        }
        assert!(layer_ranges(&[0], 4, 1).is_empty());
    }
}
