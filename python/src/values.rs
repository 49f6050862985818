//! scikit-image's `values`: per vertex, "a measure for the maximum value of
//! the data in the local region near each vertex". Here: the largest sample
//! of the cell the vertex lies in, read from the array in place.

use tmc::volume::StridedVolume;
use tmc::SampleSource;

/// The largest of the 8 samples of the cell that holds each vertex
/// (`vertices` in tmc's `[x, y, z]`, on the volume's grid with zero origin
/// and identity direction, as `marching_cubes` builds it). Vertices are
/// located by dividing by the spacing and flooring; one on a cell face
/// belongs to the cell above it, clamped into the grid.
pub(crate) fn cell_maxima(volume: &StridedVolume<'_>, vertices: &[[f32; 3]]) -> Vec<f32> {
    let grid = volume.grid();
    let last_cell = grid.dims.map(|n| n.saturating_sub(2));
    vertices
        .iter()
        .map(|v| {
            let cell: [usize; 3] = std::array::from_fn(|a| {
                let index = (f64::from(v[a]) / grid.spacing[a]).floor();
                (index.max(0.0) as usize).min(last_cell[a])
            });
            let mut most = f64::NEG_INFINITY;
            for corner in 0..8 {
                let at = std::array::from_fn(|a| cell[a] + (corner >> a & 1));
                if let Some(sample) = volume.sample(at) {
                    most = most.max(sample);
                }
            }
            most as f32
        })
        .collect()
}
