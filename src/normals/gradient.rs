//! The field's gradient in index space: central differences at the
//! samples, trilinearly interpolated inside a cell.

use super::window::Plane;

/// One cell layer's planes, seen as a field whose gradient can be taken.
///
/// Invariants: `planes` are the planes below `z`, `z`, `z + 1` and above
/// `z + 1` (see [`Window::around`](super::window::Window::around)), each
/// `nx * ny` samples, `numbers` their plane numbers, strictly increasing
/// from the first to the third and from the second to the fourth; `nx`
/// and `ny` are at least 2.
pub struct Layer<'a> {
    /// The four planes.
    pub planes: [Plane<'a>; 4],
    /// Their plane numbers.
    pub numbers: [usize; 4],
    /// Samples per row.
    pub nx: usize,
    /// Rows per plane.
    pub ny: usize,
    /// The value a NaN sample takes in the differences: the isovalue.
    pub tie: f64,
}

impl Layer<'_> {
    /// The gradient at position `t` (each coordinate in `[0, 1]`) of the
    /// cell whose lowest corner is `(x, y)` in this layer (`x < nx - 1`,
    /// `y < ny - 1`): the trilinear interpolation of the gradients at its
    /// eight corners, so it is continuous across cells. The gradient at a
    /// sample is the central difference, one-sided at the volume's border
    /// (the neighbour index clamped into the volume, the difference divided
    /// by the distance actually spanned).
    ///
    /// The 32 samples the eight differences need are fetched first, a row
    /// at a time (one look at the sample type per row).
    pub fn gradient(&self, [x, y]: [usize; 2], t: [f64; 3]) -> [f64; 3] {
        let (nx, tie) = (self.nx, self.tie);
        let xs = [x.saturating_sub(1), x, x + 1, (x + 2).min(nx - 1)];
        let ys = [y.saturating_sub(1), y, y + 1, (y + 2).min(self.ny - 1)];
        let n = self.numbers;
        // Distances spanned by the differences at the low and high corner.
        let span_x = [xs[2] - xs[0], xs[3] - xs[1]].map(|d| d as f64);
        let span_y = [ys[2] - ys[0], ys[3] - ys[1]].map(|d| d as f64);
        let span_z = [n[2] - n[0], n[3] - n[1]].map(|d| d as f64);
        // The four samples of row `r` (clamped x - 1 ..= x + 2) of plane `k`.
        let row = |k: usize, r: usize| {
            let at = r * nx;
            self.planes[k].get_many([at + xs[0], at + x, at + x + 1, at + xs[3]], tie)
        };
        // The two samples at columns x, x + 1 of row `r` of plane `k`.
        let pair = |k: usize, r: usize| self.planes[k].get_many([r * nx + x, r * nx + x + 1], tie);
        let mut sum = [0.0; 3];
        for (dz, span_z) in span_z.into_iter().enumerate() {
            let k = 1 + dz;
            let rows = [row(k, y), row(k, y + 1)];
            let (outer_lo, outer_hi) = (pair(k, ys[0]), pair(k, ys[3]));
            let (below, above) = (pair(k - 1, y), pair(k + 1, y));
            let (below1, above1) = (pair(k - 1, y + 1), pair(k + 1, y + 1));
            let wz = if dz == 0 { 1.0 - t[2] } else { t[2] };
            for dy in 0..2 {
                let wy = if dy == 0 { 1.0 - t[1] } else { t[1] };
                let r = &rows[dy];
                let (z_lo, z_hi) = if dy == 0 {
                    (below, above)
                } else {
                    (below1, above1)
                };
                for dx in 0..2 {
                    let wx = if dx == 0 { 1.0 - t[0] } else { t[0] };
                    // Column x + dx from row y - 1 to row y + 2.
                    let column = [outer_lo[dx], rows[0][dx + 1], rows[1][dx + 1], outer_hi[dx]];
                    let g = [
                        (r[dx + 2] - r[dx]) / span_x[dx],
                        (column[dy + 2] - column[dy]) / span_y[dy],
                        (z_hi[dx] - z_lo[dx]) / span_z,
                    ];
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
            planes: [0, 1, 2, 3].map(|k| Plane::Read(&p[k])),
            numbers: [0, 0, 1, 2],
            nx,
            ny,
            tie: 0.0,
        };
        for cell in [[0, 0], [2, 1], [1, 0]] {
            let g = layer.gradient(cell, [0.3, 0.9, 0.5]);
            assert_eq!(g, [2.0, -3.0, 0.5]);
        }
    }

    /// At a corner (t 0 or 1) the gradient is that sample's difference:
    /// central inside, one-sided at the border, against a direct stencil.
    #[test]
    fn corners_have_their_samples_differences() {
        let (nx, ny, nz) = (5, 4, 6);
        let f = |x: usize, y: usize, z: usize| ((x * x * 7 + y * 13 + z * z * z) % 23) as f64;
        let d = |i: usize, n: usize| (i.saturating_sub(1), (i + 1).min(n - 1));
        let stencil = |x: usize, y: usize, z: usize| {
            let ((xm, xp), (ym, yp), (zm, zp)) = (d(x, nx), d(y, ny), d(z, nz));
            [
                (f(xp, y, z) - f(xm, y, z)) / (xp - xm) as f64,
                (f(x, yp, z) - f(x, ym, z)) / (yp - ym) as f64,
                (f(x, y, zp) - f(x, y, zm)) / (zp - zm) as f64,
            ]
        };
        let plane = |z: usize| -> Vec<f64> { (0..nx * ny).map(|i| f(i % nx, i / nx, z)).collect() };
        for z in 0..nz - 1 {
            let numbers = [z.saturating_sub(1), z, z + 1, (z + 2).min(nz - 1)];
            let p = numbers.map(plane);
            let layer = Layer {
                planes: [0, 1, 2, 3].map(|k| Plane::Read(&p[k])),
                numbers,
                nx,
                ny,
                tie: 0.0,
            };
            for y in 0..ny - 1 {
                for x in 0..nx - 1 {
                    for c in 0..8 {
                        let (dx, dy, dz) = (c & 1, (c >> 1) & 1, c >> 2);
                        let t = [dx, dy, dz].map(|v| v as f64);
                        let got = layer.gradient([x, y], t);
                        assert_eq!(got, stencil(x + dx, y + dy, z + dz), "{x} {y} {z} {c}");
                    }
                }
            }
        }
    }
}
