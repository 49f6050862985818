//! scikit-image's `values`: per vertex, "a measure for the maximum value of
//! the data in the local region near each vertex". Here: the largest sample
//! of the smallest grid element (sample, edge, face or cell) the vertex
//! lies on, read from the array in place: for the usual vertex, on a cell
//! edge, the larger of the edge's two samples.

use rayon::prelude::*;
use tmc::volume::StridedVolume;
use tmc::SampleSource;

/// The largest sample of the grid element that holds each vertex
/// (`vertices` in tmc's `[x, y, z]`, on the volume's grid with zero origin
/// and identity direction, as `marching_cubes` builds it), NaN if all are
/// NaN. A vertex is located by dividing by the spacing; an index within
/// [`ON_GRID`] of an integer is on that grid plane, any other lies between
/// its floor and the next (clamped into the grid).
/// In parallel over vertices on `threads` threads (0: every core); the
/// result does not depend on them.
pub(crate) fn cell_maxima(
    volume: &StridedVolume<'_>,
    vertices: &[[f32; 3]],
    threads: usize,
) -> tmc::Result<Vec<f32>> {
    let pool = tmc::stream::threads::thread_pool(tmc::stream::threads::worker_threads(threads))?;
    Ok(pool.install(|| maxima(volume, vertices)))
}

/// How close (in samples) to a grid plane a vertex is taken to be on it:
/// vertices are f32 positions scaled by the spacing, so an edge vertex's
/// two grid coordinates are integers only up to rounding.
pub(crate) const ON_GRID: f64 = 1e-4;

fn maxima(volume: &StridedVolume<'_>, vertices: &[[f32; 3]]) -> Vec<f32> {
    let grid = volume.grid();
    let last_cell = grid.dims.map(|n| n.saturating_sub(2));
    let spacing = grid.spacing;
    vertices
        .par_iter()
        .with_min_len(4096)
        .map(|v| {
            let mut span = [true; 3];
            let corner: [usize; 3] = std::array::from_fn(|a| {
                // Truncation is floor here (the index is not negative), and
                // much cheaper than f64::floor and f64::round, which are
                // calls on baseline x86-64.
                let index = (f64::from(v[a]) / spacing[a]).max(0.0);
                let below = index as usize;
                let fraction = index - below as f64;
                if fraction <= ON_GRID || fraction >= 1.0 - ON_GRID {
                    span[a] = false;
                    (below + usize::from(fraction > 0.5)).min(last_cell[a] + 1)
                } else {
                    below.min(last_cell[a])
                }
            });
            volume.cell_max(corner, span).map_or(f32::NAN, |m| m as f32)
        })
        .collect()
}
