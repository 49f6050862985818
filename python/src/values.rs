//! scikit-image's `values`: per vertex, "a measure for the maximum value of
//! the data in the local region near each vertex". Here: the largest sample
//! of the smallest grid element (sample, edge, face or cell) the vertex
//! lies on, read from the array in place: for the usual vertex, on a cell
//! edge, the larger of the edge's two samples. Computed chunk by chunk as
//! the extraction hands the chunks on (`skimage.rs`), while their vertices
//! and the planes around them are still in the caches.

use tmc::volume::StridedVolume;
use tmc::SampleSource;

/// How close (in samples) to a grid plane a vertex is taken to be on it:
/// vertices are f32 positions scaled by the spacing, so an edge vertex's
/// two grid coordinates are integers only up to rounding.
pub(crate) const ON_GRID: f64 = 1e-4;

/// Appends to `out` the largest sample of the grid element that holds each
/// of `vertices` (in tmc's `[x, y, z]`, on the volume's grid with zero
/// origin and identity direction, as `marching_cubes` builds it), NaN if
/// all are NaN. A vertex is located by dividing by the spacing; an index
/// within [`ON_GRID`] of an integer is on that grid plane, any other lies
/// between its floor and the next (clamped into the grid).
pub(crate) fn push_maxima(volume: &StridedVolume<'_>, vertices: &[[f32; 3]], out: &mut Vec<f32>) {
    let grid = volume.grid();
    let last_cell = grid.dims.map(|n| n.saturating_sub(2));
    // A product instead of a division per coordinate: the difference (an
    // ulp) cannot move an index across ON_GRID or an integer.
    let per_sample = grid.spacing.map(|s| 1.0 / s);
    out.extend(vertices.iter().map(|v| {
        let mut span = [true; 3];
        let corner: [usize; 3] = std::array::from_fn(|a| {
            // Truncation is floor here (the index is not negative), and
            // much cheaper than f64::floor and f64::round, which are
            // calls on baseline x86-64.
            let index = (f64::from(v[a]) * per_sample[a]).max(0.0);
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
    }));
}
