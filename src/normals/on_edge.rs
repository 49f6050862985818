//! [`on_edge`]: the gradient at a vertex on an inner grid edge, the common
//! case, without locating the vertex in its cell.

use super::gradient::Layer;
use super::locate::SNAP;
use super::samples::Samples;

/// The gradient at a vertex (grid index `p`, z counted from its layer's
/// lower plane) on a grid edge whose two ends are not on the border of
/// their plane, without locating it in its cell: what
/// [`Layer::gradient`] computes there (the same differences, factors and
/// weights, summed in the same order, so the same bits). `fz` is what a
/// difference across planes is multiplied by at the layer's lower and
/// upper plane, `extent` the samples per row and rows per plane as `f64`.
/// `None` for any other vertex (inside a cell, on a plane's
/// border, off the grid) and for a difference that is NaN (a NaN sample),
/// which [`Layer::gradient`] then handles.
///
/// Each edge direction has its own code, which reads the samples the two
/// ends share once and neighbouring samples as one run (one bounds check).
#[inline(always)]
pub fn on_edge<P: Samples>(
    field: &Layer<P>,
    fz: [f64; 2],
    extent: [f64; 2],
    p: [f64; 3],
) -> Option<[f64; 3]> {
    // NaN and positions off the plane fail these tests; the vertex is at
    // most `SNAP` off the layer's planes. Beyond `nx` or `ny` no edge is
    // inner, so nothing is lost, and the rounding below is exact.
    if !(p[0] >= 0.5
        && p[1] >= 0.5
        && p[2] >= -SNAP
        && p[2] <= 1.0 + SNAP
        && p[0] < extent[0]
        && p[1] < extent[1])
    {
        return None;
    }
    // Nearest grid line along each axis and whether the vertex is on it.
    let [(line_x, near_x), (line_y, near_y), (line_z, near_z)] = p.map(nearest);
    let (line, near) = ([line_x, line_y, line_z], [near_x, near_y, near_z]);
    let on = |a: usize| (p[a] - line[a]).abs() < SNAP;
    let on = [on(0), on(1), on(2)];
    let (nx, ny) = (field.nx as i64, field.ny as i64);
    // Along the edge's axis, its lower end: the floor (the coordinate is
    // positive, and not within `SNAP` of a grid line).
    let floor = |a: usize| near[a] - i64::from(line[a] > p[a]);
    let (w, [a, b]) = match on {
        [false, true, true] => {
            let (x, y) = (floor(0), near[1]);
            if x < 1 || y < 1 || x + 2 >= nx || y + 1 >= ny {
                return None;
            }
            (p[0] - x as f64, along_x(field, fz, x, y, near[2]))
        }
        [true, false, true] => {
            let (x, y) = (near[0], floor(1));
            if x < 1 || y < 1 || x + 1 >= nx || y + 2 >= ny {
                return None;
            }
            (p[1] - y as f64, along_y(field, fz, x, y, near[2]))
        }
        [true, true, false] => {
            let (x, y) = (near[0], near[1]);
            if x < 1 || y < 1 || x + 1 >= nx || y + 1 >= ny {
                return None;
            }
            (p[2], along_z(field, fz, x, y))
        }
        _ => return None,
    };
    let (w_low, w_high) = (1.0 - w, w);
    let g = [
        0.0 + w_low * a[0] + w_high * b[0],
        0.0 + w_low * a[1] + w_high * b[1],
        0.0 + w_low * a[2] + w_high * b[2],
    ];
    if P::MAY_BE_NAN && (g[0] + g[1] + g[2]).is_nan() {
        return None;
    }
    Some(g)
}

/// `c` (in `[-SNAP, 2^31)`) rounded to the nearest integer: ties may go
/// either way, which only matters for a coordinate half a cell from the
/// grid lines, never within `SNAP` of one. By adding and taking away
/// `1.5 * 2^52`, whose last mantissa bit counts units (exact, cheaper than
/// a saturating cast and back).
/// Returned as `f64` and as `i64`.
#[inline(always)]
fn nearest(c: f64) -> (f64, i64) {
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    let shifted = c + SHIFT;
    (
        shifted - SHIFT,
        shifted.to_bits() as i64 - SHIFT.to_bits() as i64,
    )
}

/// The planes below, at and above plane `k` (0 or 1) of the layer, and
/// what their difference is multiplied by.
#[inline(always)]
fn around<P: Samples>(field: &Layer<P>, fz: [f64; 2], k: i64) -> (P, P, P, f64) {
    let [p0, p1, p2, p3] = field.planes;
    if k == 0 {
        (p0, p1, p2, fz[0])
    } else {
        (p1, p2, p3, fz[1])
    }
}

/// The central differences at the ends of the edge from sample `(x, y)`
/// of the layer's plane `k` (0 or 1) to `(x + 1, y)`, both inner.
#[inline(always)]
fn along_x<P: Samples>(field: &Layer<P>, fz: [f64; 2], x: i64, y: i64, k: i64) -> [[f64; 3]; 2] {
    let (below, here, above, f) = around(field, fz, k);
    let nx = field.nx;
    let i = y as usize * nx + x as usize;
    let row = here.run::<4>(i - 1);
    let (up, down) = (here.run::<2>(i + nx), here.run::<2>(i - nx));
    let (over, under) = (above.run::<2>(i), below.run::<2>(i));
    let end = |e: usize| {
        [
            (row[e + 2] - row[e]) * 0.5,
            (up[e] - down[e]) * 0.5,
            (over[e] - under[e]) * f,
        ]
    };
    [end(0), end(1)]
}

/// The central differences at the ends of the edge from sample `(x, y)`
/// of the layer's plane `k` (0 or 1) to `(x, y + 1)`, both inner.
#[inline(always)]
fn along_y<P: Samples>(field: &Layer<P>, fz: [f64; 2], x: i64, y: i64, k: i64) -> [[f64; 3]; 2] {
    let (below, here, above, f) = around(field, fz, k);
    let nx = field.nx;
    let i = y as usize * nx + x as usize;
    let rows = [here.run::<3>(i - 1), here.run::<3>(i + nx - 1)];
    let (down, up) = (here.raw(i - nx), here.raw(i + 2 * nx));
    let column = [down, rows[0][1], rows[1][1], up];
    let end = |e: usize| {
        let at = i + e * nx;
        [
            (rows[e][2] - rows[e][0]) * 0.5,
            (column[e + 2] - column[e]) * 0.5,
            (above.raw(at) - below.raw(at)) * f,
        ]
    };
    [end(0), end(1)]
}

/// The central differences at the ends of the edge from sample `(x, y)`
/// of the layer's plane 0 to the same sample of plane 1, both inner.
#[inline(always)]
fn along_z<P: Samples>(field: &Layer<P>, fz: [f64; 2], x: i64, y: i64) -> [[f64; 3]; 2] {
    let nx = field.nx;
    let i = y as usize * nx + x as usize;
    let [p0, p1, p2, p3] = field.planes;
    let end = |below: P, here: P, above: P, f: f64| {
        let row = here.run::<3>(i - 1);
        [
            (row[2] - row[0]) * 0.5,
            (here.raw(i + nx) - here.raw(i - nx)) * 0.5,
            (above.raw(i) - below.raw(i)) * f,
        ]
    };
    [end(p0, p1, p2, fz[0]), end(p1, p2, p3, fz[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On every inner edge of a small grid, at offsets along it and with
    /// the rounding noise of `f32` positions across it, `on_edge` gives
    /// what `Layer::gradient` gives for the snapped position, to the bit,
    /// for typed and NaN-holding planes; `None` off inner edges.
    /// A layer of `planes` with the tie at 0.5.
    fn layer_of<P>(planes: [P; 4], numbers: [usize; 4], [nx, ny]: [usize; 2]) -> Layer<P> {
        Layer {
            planes,
            numbers,
            nx,
            ny,
            tie: 0.5,
        }
    }

    #[test]
    fn inner_edges_match_the_layer_gradient() {
        let (nx, ny, nz) = (7usize, 6usize, 5usize);
        let f =
            |x: usize, y: usize, z: usize| ((x * x * 3 + y * 5 + z * z * 7 + x * y) % 19) as u16;
        let plane = |z: usize| -> Vec<u16> { (0..nx * ny).map(|i| f(i % nx, i / nx, z)).collect() };
        let bits = |g: [f64; 3]| g.map(f64::to_bits);
        for z in 0..nz - 1 {
            let numbers = [z.saturating_sub(1), z, z + 1, (z + 2).min(nz - 1)];
            let typed = numbers.map(plane);
            let layer = layer_of([0, 1, 2, 3].map(|k| &typed[k][..]), numbers, [nx, ny]);
            let mut floats =
                [0, 1, 2, 3].map(|k| typed[k].iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
            floats[1][2 * nx + 3] = f64::NAN;
            let holed = layer_of([0, 1, 2, 3].map(|k| &floats[k][..]), numbers, [nx, ny]);
            let across = |k: usize| {
                if numbers[k + 1] - numbers[k - 1] == 1 {
                    1.0
                } else {
                    0.5
                }
            };
            let fz = [across(1), across(2)];
            let extent = [nx as f64, ny as f64];
            for y in 0..ny - 1 {
                for x in 0..nx - 1 {
                    for axis in 0..3 {
                        for t in [0.1, 0.5, 0.73] {
                            for noise in [0.0, 3e-5, -3e-5] {
                                for up in [0.0, 1.0] {
                                    let mut snapped = [up, up, up];
                                    snapped[axis] = t;
                                    let mut p = [x as f64, y as f64, 0.0];
                                    for a in 0..3 {
                                        p[a] += snapped[a];
                                        if a != axis {
                                            p[a] += noise;
                                        }
                                    }
                                    // The offset as the position gives it.
                                    snapped[axis] = p[axis] - [x as f64, y as f64, 0.0][axis];
                                    let at = format!("{x} {y} {z} {axis} {t} {noise} {up}");
                                    let want = layer.gradient([x, y], snapped);
                                    match on_edge(&layer, fz, extent, p) {
                                        Some(g) => assert_eq!(bits(g), bits(want), "{at}"),
                                        None => {
                                            // Only an edge with an end on the border is left out.
                                            let ends = [0, 1].map(|e| {
                                                let step = |a: usize| {
                                                    if a == axis {
                                                        e as f64
                                                    } else {
                                                        up
                                                    }
                                                };
                                                [x as f64 + step(0), y as f64 + step(1)]
                                            });
                                            let border = ends.iter().any(|c| {
                                                c[0] < 1.0
                                                    || c[1] < 1.0
                                                    || c[0] + 1.0 >= nx as f64
                                                    || c[1] + 1.0 >= ny as f64
                                            });
                                            assert!(border, "{at}");
                                        }
                                    }
                                    if let Some(g) = on_edge(&holed, fz, extent, p) {
                                        assert_eq!(
                                            bits(g),
                                            bits(holed.gradient([x, y], snapped)),
                                            "{at}"
                                        );
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}
