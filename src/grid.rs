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

    /// The (fractional) grid index at world position `world`: the inverse
    /// of [`Grid::world`]. Computing [`Grid::world_to_index`] once is
    /// cheaper for many points.
    pub fn index_of(&self, world: [f64; 3]) -> [f64; 3] {
        self.world_to_index().index(world)
    }

    /// The inverse of the index-to-world map, computed once (the general
    /// inverse of `direction`, not its transpose, so that a direction
    /// matrix that is not orthogonal is inverted too).
    pub fn world_to_index(&self) -> WorldToIndex {
        let d = &self.direction;
        // Cofactors: the adjugate divided by the determinant is the inverse.
        let cof = |r0: usize, r1: usize, c0: usize, c1: usize| {
            d[r0][c0] * d[r1][c1] - d[r0][c1] * d[r1][c0]
        };
        let adjugate = [
            [cof(1, 2, 1, 2), -cof(0, 2, 1, 2), cof(0, 1, 1, 2)],
            [-cof(1, 2, 0, 2), cof(0, 2, 0, 2), -cof(0, 1, 0, 2)],
            [cof(1, 2, 0, 1), -cof(0, 2, 0, 1), cof(0, 1, 0, 1)],
        ];
        let det = (0..3).map(|k| d[0][k] * adjugate[k][0]).sum::<f64>();
        let matrix = [0, 1, 2].map(|i| [0, 1, 2].map(|j| adjugate[i][j] / det / self.spacing[i]));
        WorldToIndex {
            origin: self.origin,
            matrix,
        }
    }
}

/// The inverse of a [`Grid`]'s index-to-world map:
/// `index = diag(1 / spacing) * direction^-1 * (world - origin)`.
///
/// Its entries are not finite when the grid cannot be inverted (a zero or
/// non-finite spacing, a singular direction matrix); readers refuse such
/// grids (see `set_direction`), but `Grid`'s fields are public, so callers
/// check the results.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldToIndex {
    /// The grid's origin.
    origin: [f64; 3],
    /// `diag(1 / spacing) * direction^-1`: row `i` gives index `i` from a
    /// world offset.
    matrix: [[f64; 3]; 3],
}

impl WorldToIndex {
    /// The (fractional) grid index at world position `world`.
    pub fn index(&self, world: [f64; 3]) -> [f64; 3] {
        let offset = [0, 1, 2].map(|i| world[i] - self.origin[i]);
        self.matrix
            .map(|row| row[0] * offset[0] + row[1] * offset[1] + row[2] * offset[2])
    }

    /// A gradient taken with respect to grid indices, as a gradient with
    /// respect to world coordinates (the chain rule: the transpose of the
    /// index-from-world matrix applied to it, `direction^-T * diag(1 /
    /// spacing) * gradient`).
    pub fn gradient_to_world(&self, gradient: [f64; 3]) -> [f64; 3] {
        let m = &self.matrix;
        [0, 1, 2].map(|j| m[0][j] * gradient[0] + m[1][j] * gradient[1] + m[2][j] * gradient[2])
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
