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
/// outside the range of the mesh's f32 coordinates.
pub fn check_grid(input: &Path, grid: &Grid, close: bool) -> Result<()> {
    let pad = if close { 1.0 } else { 0.0 };
    for corner in 0..8 {
        let index: [f64; 3] = std::array::from_fn(|a| {
            if corner >> a & 1 == 1 {
                grid.dims[a] as f64 - 1.0 + pad
            } else {
                -pad
            }
        });
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
