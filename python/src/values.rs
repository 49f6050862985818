//! scikit-image's `values`: per vertex, "a measure for the maximum value of
//! the data in the local region near each vertex". Here: the largest sample
//! of the smallest grid element (sample, edge, face or cell) the vertex
//! lies on, read from the array in place: for the usual vertex, on a cell
//! edge, the larger of the edge's two samples. Computed chunk by chunk by
//! the worker that made the chunk (`extract.rs` hands [`push_maxima`] to
//! the pipeline as `PipelineOptions::vertex_values`), while its vertices
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
    let [sx, sy, sz] = grid.spacing.map(|s| 1.0 / s);
    let [lx, ly, lz] = last_cell;
    let elements = vertices.iter().map(|&[x, y, z]| {
        let (cx, ox) = locate(x, sx, lx);
        let (cy, oy) = locate(y, sy, ly);
        let (cz, oz) = locate(z, sz, lz);
        ([cx, cy, cz], [ox, oy, oz])
    });
    volume.push_element_maxima(elements, out);
}

/// The lower sample index of a vertex coordinate `v` (times `per_sample`
/// to index units) along one axis, and whether the vertex lies between
/// that sample and the next (false: on the sample's grid plane, within
/// [`ON_GRID`]); `last_cell` is the axis' last cell index.
#[inline(always)]
fn locate(v: f32, per_sample: f64, last_cell: usize) -> (usize, bool) {
    // Adding 1.5 * 2^52 rounds to the nearest integer, which is then the
    // low bits of the sum (for indices below 2^31, far beyond any grid):
    // two additions and no conversion, where f64::round and f64::floor are
    // calls on baseline x86-64 and `as` checks for saturation. `max` also
    // turns a NaN into 0; `min` keeps the index in the trick's range.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    const LIMIT: f64 = (1u64 << 31) as f64 - 1.0;
    // Not `clamp`, which keeps a NaN.
    let index = (f64::from(v) * per_sample).max(0.0);
    let index = index.min(LIMIT);
    let rounded = index + ROUND;
    let off = index - (rounded - ROUND);
    let nearest = rounded.to_bits() as u32 as usize;
    if off.abs() <= ON_GRID {
        (nearest.min(last_cell + 1), false)
    } else {
        (
            nearest
                .saturating_sub(usize::from(off < 0.0))
                .min(last_cell),
            true,
        )
    }
}
