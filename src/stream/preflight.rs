//! The check made of a grid before any work is done, by every front end
//! (the CLI, the Python package): a grid that has cells and fits the mesh's
//! f32 coordinates.

use crate::{Error, Grid, Result};
use std::path::Path;

/// Rejects grids with fewer than 2 samples along an axis (no cells), unless
/// `close` pads the volume with an outside border, which gives every grid
/// cells (a single inside sample then has a closed surface around it).
///
/// Also rejects grids whose corners (one sample beyond with `close`) lie
/// outside the range of the mesh's f32 coordinates, and grids on which
/// neighbouring samples fall on the same f32 point at a corner (a spacing
/// far below the origin's float resolution, such as 1e-320, or an origin
/// of 1e12 with spacing 1): every vertex between them would collapse
/// onto it, leaving zero-area triangles.
pub fn check_grid(input: &Path, grid: &Grid, close: bool) -> Result<()> {
    let pad = if close { 1.0 } else { 0.0 };
    // Corner `corner`'s sample index (bit `a` set: the last along axis
    // `a`), one beyond the samples with `close`.
    let corner_index = |corner: usize| -> [f64; 3] {
        std::array::from_fn(|a| {
            if corner >> a & 1 == 1 {
                grid.dims[a] as f64 - 1.0 + pad
            } else {
                -pad
            }
        })
    };
    for corner in 0..8 {
        let index = corner_index(corner);
        if grid
            .world(index)
            .iter()
            .any(|c| c.is_nan() || c.abs() > f64::from(f32::MAX))
        {
            return Err(Error::Invalid(format!(
                "{}: the grid's corners (origin + index * spacing) lie beyond the range of 32-bit float coordinates; check the spacing and origin",
                input.display()
            )));
        }
    }
    for corner in 0..8 {
        let index = corner_index(corner);
        let at = grid.world(index).map(|c| c as f32);
        for (a, axis) in ["x", "y", "z"].into_iter().enumerate() {
            // The neighbour inward along the axis (none along an axis of
            // one sample without --close: refused below).
            let step = if corner >> a & 1 == 1 { -1.0 } else { 1.0 };
            if grid.dims[a] < 2 && !close {
                continue;
            }
            let mut next = index;
            next[a] += step;
            if grid.world(next).map(|c| c as f32) == at {
                return Err(Error::Invalid(format!(
                    "{}: neighbouring samples along {axis} (spacing {}) fall on the same 32-bit float point {at:?} at a corner of the grid, so the mesh's vertices would collapse; check the spacing and origin (a far origin can be moved nearer 0 with --origin)",
                    input.display(),
                    crate::params::number_text(grid.spacing[a]),
                )));
            }
        }
    }
    if close {
        return Ok(());
    }
    for (axis, &n) in ["x", "y", "z"].iter().zip(&grid.dims) {
        if n < 2 {
            return Err(Error::Invalid(format!(
                "{}: grid {}x{}x{} has {n} sample along {axis}; need at least 2 on every axis (or --close)",
                input.display(),
                grid.dims[0],
                grid.dims[1],
                grid.dims[2]
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_grid;
    use crate::Grid;
    use std::path::Path;

    fn grid(spacing: [f64; 3], origin: [f64; 3]) -> Grid {
        Grid {
            spacing,
            origin,
            ..Grid::unit([4, 3, 5])
        }
    }

    #[test]
    fn a_grid_whose_neighbours_collapse_in_f32_is_refused() {
        let input = Path::new("v.npy");
        for (spacing, origin) in [
            ([1e-320, 1.0, 1.0], [0.0; 3]),
            ([1.0, 1.0, 1.0], [0.0, 1e12, 0.0]),
            ([1.0, 1.0, 1e-9], [0.0, 0.0, 5.0]),
        ] {
            for close in [false, true] {
                let err = check_grid(input, &grid(spacing, origin), close).unwrap_err();
                assert!(err.to_string().contains("collapse"), "{err}");
            }
        }
        // Small and far but distinct: taken.
        for (spacing, origin) in [
            ([1e-30, 1.0, 1.0], [0.0; 3]),
            ([0.5, 0.5, 0.5], [1e6, -1e6, 1e6]),
            ([1e30, 1.0, 1.0], [0.0; 3]),
        ] {
            check_grid(input, &grid(spacing, origin), false).unwrap();
        }
    }
}
