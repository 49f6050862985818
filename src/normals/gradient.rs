//! The field's gradient in index space: central differences at the
//! samples, trilinearly interpolated inside a cell.

/// One cell layer's planes, seen as a field whose gradient can be taken.
///
/// Invariants: `planes` are the planes below `z`, `z`, `z + 1` and above
/// `z + 1` (see [`Window::around`](super::window::Window::around)), each
/// `nx * ny` samples, `numbers` their plane numbers, strictly increasing
/// from the first to the third and from the second to the fourth; `nx`
/// and `ny` are at least 2.
pub struct Layer<'a> {
    /// The four planes.
    pub planes: [&'a [f64]; 4],
    /// Their plane numbers.
    pub numbers: [usize; 4],
    /// Samples per row.
    pub nx: usize,
    /// Rows per plane.
    pub ny: usize,
}

impl Layer<'_> {
    /// The gradient (per unit of index) at sample `(x, y)` of plane
    /// `planes[k]`, `k` 1 or 2: the central difference, one-sided at the
    /// volume's border (a neighbour index clamped into the volume, the
    /// difference divided by the distance actually spanned).
    #[inline]
    fn at_sample(&self, x: usize, y: usize, k: usize) -> [f64; 3] {
        let nx = self.nx;
        let plane = self.planes[k];
        let (xm, xp) = (x.saturating_sub(1), (x + 1).min(nx - 1));
        let (ym, yp) = (y.saturating_sub(1), (y + 1).min(self.ny - 1));
        let i = y * nx + x;
        let gx = (plane[y * nx + xp] - plane[y * nx + xm]) / (xp - xm) as f64;
        let gy = (plane[yp * nx + x] - plane[ym * nx + x]) / (yp - ym) as f64;
        let dz = (self.numbers[k + 1] - self.numbers[k - 1]) as f64;
        let gz = (self.planes[k + 1][i] - self.planes[k - 1][i]) / dz;
        [gx, gy, gz]
    }

    /// The gradient at position `t` (each coordinate in `[0, 1]`) of the
    /// cell whose lowest corner is `(x, y)` in this layer (`x < nx - 1`,
    /// `y < ny - 1`): the trilinear interpolation of the gradients at its
    /// eight corners, so it is continuous across cells.
    pub fn gradient(&self, [x, y]: [usize; 2], t: [f64; 3]) -> [f64; 3] {
        let mut sum = [0.0; 3];
        for (dz, wz) in [(0, 1.0 - t[2]), (1, t[2])] {
            for (dy, wy) in [(0, 1.0 - t[1]), (1, t[1])] {
                for (dx, wx) in [(0, 1.0 - t[0]), (1, t[0])] {
                    let g = self.at_sample(x + dx, y + dy, 1 + dz);
                    let w = wx * wy * wz;
                    for a in 0..3 {
                        sum[a] += w * g[a];
                    }
                }
            }
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear field's gradient is exact everywhere, borders included.
    #[test]
    fn a_linear_field_has_its_exact_gradient() {
        let (nx, ny) = (4, 3);
        let f = |x: usize, y: usize, z: usize| 2.0 * x as f64 - 3.0 * y as f64 + 0.5 * z as f64;
        let plane = |z: usize| -> Vec<f64> { (0..nx * ny).map(|i| f(i % nx, i / nx, z)).collect() };
        // Layer 0 of a volume of 3 planes: below is plane 0 itself.
        let p = [plane(0), plane(0), plane(1), plane(2)];
        let layer = Layer {
            planes: [&p[0], &p[1], &p[2], &p[3]],
            numbers: [0, 0, 1, 2],
            nx,
            ny,
        };
        for cell in [[0, 0], [2, 1], [1, 0]] {
            let g = layer.gradient(cell, [0.3, 0.9, 0.5]);
            assert_eq!(g, [2.0, -3.0, 0.5]);
        }
    }
}
