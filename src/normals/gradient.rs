//! The field's gradient in index space: central differences at the
//! samples, trilinearly interpolated inside a cell.

use super::samples::Samples;

/// One cell layer's planes, seen as a field whose gradient can be taken;
/// `P` is how a plane's samples are read (see
/// [`with_planes`](super::samples::with_planes)).
///
/// Invariants: `planes` are the planes below `z`, `z`, `z + 1` and above
/// `z + 1` (see [`Window::around`](super::window::Window::around)), each
/// `nx * ny` samples, `numbers` their plane numbers, strictly increasing
/// from the first to the third and from the second to the fourth, by one or
/// two; `nx` and `ny` are at least 2.
pub struct Layer<P> {
    /// The four planes.
    pub planes: [P; 4],
    /// Their plane numbers.
    pub numbers: [usize; 4],
    /// Samples per row.
    pub nx: usize,
    /// Rows per plane.
    pub ny: usize,
    /// The value a NaN sample takes in the differences: the isovalue.
    pub tie: f64,
}

impl<P: Samples> Layer<P> {
    /// The gradient at position `t` (each coordinate in `[0, 1]`) of the
    /// cell whose lowest corner is `(x, y)` in this layer (`x < nx - 1`,
    /// `y < ny - 1`): the trilinear interpolation of the gradients at its
    /// eight corners, so it is continuous across cells.
    ///
    /// Corners of weight zero are skipped: a vertex on a grid edge (two
    /// coordinates of `t` exactly 0 or 1, see
    /// [`Locator::locate_in_layer`](super::locate::Locator::locate_in_layer)) costs the
    /// differences at the edge's two ends, 12 samples, and one on a sample
    /// costs one difference. The sum runs over the corners in the same
    /// order either way, so skipping changes nothing but the work.
    #[inline]
    pub fn gradient(&self, [x, y]: [usize; 2], t: [f64; 3]) -> [f64; 3] {
        if x >= 1 && y >= 1 && x + 2 < self.nx && y + 2 < self.ny {
            self.corners::<true>([x, y], t)
        } else {
            self.corners::<false>([x, y], t)
        }
    }

    /// [`gradient`](Self::gradient), `INTERIOR` saying that no corner of
    /// the cell is on the border of its plane.
    #[inline(always)]
    fn corners<const INTERIOR: bool>(&self, [x, y]: [usize; 2], t: [f64; 3]) -> [f64; 3] {
        let on = |t: f64| t == 0.0 || t == 1.0;
        let up = |t: f64| usize::from(t == 1.0);
        match (on(t[0]), on(t[1]), on(t[2])) {
            (false, true, true) => {
                self.edge::<INTERIOR>([x, y + up(t[1]), 1 + up(t[2])], [1, 0, 0], t[0])
            }
            (true, false, true) => {
                self.edge::<INTERIOR>([x + up(t[0]), y, 1 + up(t[2])], [0, 1, 0], t[1])
            }
            (true, true, false) => {
                self.edge::<INTERIOR>([x + up(t[0]), y + up(t[1]), 1], [0, 0, 1], t[2])
            }
            (true, true, true) => {
                let g = self.at_sample::<INTERIOR>(x + up(t[0]), y + up(t[1]), 1 + up(t[2]));
                [0.0 + g[0], 0.0 + g[1], 0.0 + g[2]]
            }
            _ => self.interpolated([x, y], t),
        }
    }

    /// The gradient at `t` along the edge from sample `(x, y)` of plane `k`
    /// one step along `step`: what [`interpolated`](Self::interpolated)
    /// gives there, to the bit (the other weights are exactly 1, the sum
    /// starts at 0 and takes the lower end first), from the two ends only.
    #[inline(always)]
    fn edge<const INTERIOR: bool>(
        &self,
        [x, y, k]: [usize; 3],
        step: [usize; 3],
        t: f64,
    ) -> [f64; 3] {
        let low = self.at_sample::<INTERIOR>(x, y, k);
        let high = self.at_sample::<INTERIOR>(x + step[0], y + step[1], k + step[2]);
        let (w_low, w_high) = (1.0 - t, t);
        [
            0.0 + w_low * low[0] + w_high * high[0],
            0.0 + w_low * low[1] + w_high * high[1],
            0.0 + w_low * low[2] + w_high * high[2],
        ]
    }

    /// The trilinear interpolation of the corner gradients, corner by
    /// corner (z slowest, x fastest), skipping the corners of weight zero.
    fn interpolated(&self, [x, y]: [usize; 2], t: [f64; 3]) -> [f64; 3] {
        let weights = t.map(|t| [1.0 - t, t]);
        let mut sum = [0.0; 3];
        for (dz, &wz) in weights[2].iter().enumerate() {
            if wz == 0.0 {
                continue;
            }
            for (dy, &wy) in weights[1].iter().enumerate() {
                if wy == 0.0 {
                    continue;
                }
                for (dx, &wx) in weights[0].iter().enumerate() {
                    if wx == 0.0 {
                        continue;
                    }
                    let g = self.at_sample::<false>(x + dx, y + dy, 1 + dz);
                    let w = wx * wy * wz;
                    for a in 0..3 {
                        sum[a] += w * g[a];
                    }
                }
            }
        }
        sum
    }

    /// The gradient at sample `(x, y)` of plane `k` (1 or 2, the planes
    /// bounding the layer): the central difference, one-sided at the
    /// volume's border (the neighbour index clamped into the volume, the
    /// difference divided by the distance actually spanned).
    ///
    /// `INTERIOR` says that `(x, y)` is not on the border of its plane, so
    /// that its four neighbours in the plane need no clamping. NaN samples
    /// are rare: the differences are taken as the samples are, and taken
    /// again with NaN as the tie only when one of them is NaN.
    #[inline(always)]
    fn at_sample<const INTERIOR: bool>(&self, x: usize, y: usize, k: usize) -> [f64; 3] {
        let (nx, planes) = (self.nx, &self.planes);
        let (xm, xp, ym, yp) = if INTERIOR {
            (x - 1, x + 1, y - 1, y + 1)
        } else {
            (
                x.saturating_sub(1),
                (x + 1).min(nx - 1),
                y.saturating_sub(1),
                (y + 1).min(self.ny - 1),
            )
        };
        let (here, below, above) = (planes[k], planes[k - 1], planes[k + 1]);
        let (row, at) = (y * nx, y * nx + x);
        let at = [row + xp, row + xm, yp * nx + x, ym * nx + x, at, at];
        let from = [here, here, here, here, above, below];
        let mut d = differences(from, at, |p, i| p.raw(i));
        if P::MAY_BE_NAN && (d[0] + d[1] + d[2]).is_nan() {
            let tie = self.tie;
            d = differences(from, at, |p, i| p.value(i, tie));
        }
        let (fx, fy) = if INTERIOR {
            (0.5, 0.5)
        } else {
            (per_span(xp - xm), per_span(yp - ym))
        };
        [
            d[0] * fx,
            d[1] * fy,
            d[2] * per_span(self.numbers[k + 1] - self.numbers[k - 1]),
        ]
    }
}

/// The three differences `value(from[0], at[0]) - value(from[1], at[1])`,
/// and so on for the next two pairs.
#[inline(always)]
fn differences<P: Copy>(from: [P; 6], at: [usize; 6], value: impl Fn(P, usize) -> f64) -> [f64; 3] {
    let v = |i: usize| value(from[i], at[i]);
    [v(0) - v(1), v(2) - v(3), v(4) - v(5)]
}

/// What a difference over `span` samples (1 or 2: a central difference,
/// or a one-sided one at the border) is multiplied by to divide it by the
/// span. Multiplying by 1 or by 0.5 is exact, so the product is the
/// quotient to the last bit.
#[inline(always)]
fn per_span(span: usize) -> f64 {
    debug_assert!(span == 1 || span == 2, "span {span}");
    if span == 1 {
        1.0
    } else {
        0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normals::window::Plane;
    use crate::volume::LentPlane;

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

    /// The shortcuts (edges, samples, interior cells, typed planes, NaN
    /// taken as the tie only when met) give what the full interpolation
    /// over `f64` planes gives, to the bit.
    #[test]
    fn shortcuts_change_nothing() {
        let (nx, ny, nz) = (6usize, 5usize, 4usize);
        let f =
            |x: usize, y: usize, z: usize| ((x * 5 + y * y * 3 + z * 7 + x * z) % 11) as i16 - 4;
        let plane = |z: usize| -> Vec<i16> { (0..nx * ny).map(|i| f(i % nx, i / nx, z)).collect() };
        let wide = |p: &Vec<i16>| -> Vec<f64> { p.iter().map(|&v| f64::from(v)).collect() };
        // NaN in a float copy: the tie must stand in for it.
        let with_nan = |p: &Vec<f64>, z: usize| -> Vec<f64> {
            let mut p = p.clone();
            let i = (z * 7 + 3) % p.len();
            p[i] = f64::NAN;
            p
        };
        let offsets = [0.0, 0.25, 1.0];
        for z in 0..nz - 1 {
            let numbers = [z.saturating_sub(1), z, z + 1, (z + 2).min(nz - 1)];
            let typed = numbers.map(plane);
            let floats = [0, 1, 2, 3].map(|k| wide(&typed[k]));
            let holed = [0, 1, 2, 3].map(|k| with_nan(&floats[k], numbers[k]));
            fn layer<P>(planes: [P; 4], numbers: [usize; 4], [nx, ny]: [usize; 2]) -> Layer<P> {
                Layer {
                    planes,
                    numbers,
                    nx,
                    ny,
                    tie: 0.75,
                }
            }
            let lent = layer([0, 1, 2, 3].map(|k| &typed[k][..]), numbers, [nx, ny]);
            let read = layer(
                [0, 1, 2, 3].map(|k| Plane::Read(&floats[k])),
                numbers,
                [nx, ny],
            );
            let mixed = [0, 1, 2, 3].map(|k| match k {
                1 => Plane::Lent(LentPlane::I16(&typed[k])),
                _ => Plane::Read(&floats[k]),
            });
            let mixed = layer(mixed, numbers, [nx, ny]);
            let nan = layer([0, 1, 2, 3].map(|k| &holed[k][..]), numbers, [nx, ny]);
            let holed_planes = [0, 1, 2, 3].map(|k| Plane::Read(&holed[k]));
            let nan_dynamic = layer(holed_planes, numbers, [nx, ny]);
            for y in 0..ny - 1 {
                for x in 0..nx - 1 {
                    for c in 0..27 {
                        let t = [c % 3, (c / 3) % 3, c / 9].map(|i| offsets[i]);
                        let full = read.interpolated([x, y], t);
                        let bits = |g: [f64; 3]| g.map(f64::to_bits);
                        let at = format!("{x} {y} {z} {t:?}");
                        assert_eq!(bits(read.gradient([x, y], t)), bits(full), "{at}");
                        assert_eq!(bits(lent.gradient([x, y], t)), bits(full), "{at}");
                        assert_eq!(bits(mixed.gradient([x, y], t)), bits(full), "{at}");
                        let full = nan_dynamic.interpolated([x, y], t);
                        assert!(full.iter().all(|c| c.is_finite()), "{at}");
                        assert_eq!(bits(nan.gradient([x, y], t)), bits(full), "{at}");
                    }
                }
            }
        }
    }
}
