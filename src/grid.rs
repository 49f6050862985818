//! The geometry of a regular grid: sample counts and the map from sample
//! indices to world coordinates.
//!
//! Readers fill it in, the slab loop places vertices with it, and `.tmesh`
//! files record its dims, spacing and origin (vertices are already in world
//! coordinates), so it imports nothing of the crate.

/// Geometry of a regular grid: sample counts and the index-to-world map
/// `world = origin + direction * (index * spacing)` (x varies fastest in
/// memory).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// Distance between samples along x, y, z.
    pub spacing: [f64; 3],
    /// Physical position of sample (0, 0, 0).
    pub origin: [f64; 3],
    /// Direction cosines: column `j` is the unit world direction of index
    /// axis `j` (`direction[i][j]`, row = world axis), as in NIfTI and ITK.
    /// A reflection (negative determinant) flips the triangles' winding so
    /// that normals still point outward.
    pub direction: [[f64; 3]; 3],
}

/// The identity direction matrix: index axes along world axes.
pub const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Grid {
    /// A grid with unit spacing, zero origin and identity direction.
    pub fn unit(dims: [usize; 3]) -> Self {
        Grid {
            dims,
            spacing: [1.0; 3],
            origin: [0.0; 3],
            direction: IDENTITY,
        }
    }

    /// World position of the (fractional) grid index `index`.
    pub fn world(&self, index: [f64; 3]) -> [f64; 3] {
        let scaled = [0, 1, 2].map(|j| index[j] * self.spacing[j]);
        [0, 1, 2].map(|i| {
            self.origin[i]
                + self.direction[i][0] * scaled[0]
                + self.direction[i][1] * scaled[1]
                + self.direction[i][2] * scaled[2]
        })
    }

    /// Does the index-to-world map mirror space (negative determinant)?
    pub fn is_mirrored(&self) -> bool {
        let d = &self.direction;
        let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
            - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
            + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        det < 0.0
    }

    /// Samples in one z-plane.
    pub fn plane_len(&self) -> usize {
        self.dims[0] * self.dims[1]
    }
}

/// Puts an index-to-world matrix into `grid`: column `j` of `matrix` is the
/// world step along index axis `j` before scaling by `grid.spacing[j]`. Its
/// length multiplies that spacing and its unit vector becomes the
/// direction, so [`Grid::direction`] always holds unit columns. A matrix
/// with a non-finite entry, a zero column or (nearly) parallel columns is
/// refused: it cannot map a grid to a volume of space.
pub(crate) fn set_direction(
    grid: &mut Grid,
    matrix: [[f64; 3]; 3],
) -> std::result::Result<(), String> {
    let mut unit = [[0.0; 3]; 3];
    for c in 0..3 {
        let norm = (0..3).map(|r| matrix[r][c].powi(2)).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(format!(
                "direction of axis {c} ({}, {}, {}) is not a usable vector",
                matrix[0][c], matrix[1][c], matrix[2][c]
            ));
        }
        for r in 0..3 {
            unit[r][c] = matrix[r][c] / norm;
        }
        grid.spacing[c] *= norm;
    }
    let d = &unit;
    let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
    if det.abs() < 1e-6 {
        return Err("the direction matrix is singular (axes are parallel)".into());
    }
    grid.direction = unit;
    Ok(())
}
