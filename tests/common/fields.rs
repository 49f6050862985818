//! Small integer-valued test fields with known isosurface topology.

use super::oracle;

/// Samples on a grid, x fastest. Every value is an integer, so any integer
/// or half-integer isovalue can be handed to the oracle.
#[derive(Debug, Clone)]
pub struct Field {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// The samples.
    pub values: Vec<f64>,
}

impl Field {
    /// Samples `f(x, y, z)` rounded to integers.
    pub fn from_fn(dims: [usize; 3], f: impl Fn(f64, f64, f64) -> f64) -> Field {
        let mut values = Vec::with_capacity(dims.iter().product());
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    values.push(f(x as f64, y as f64, z as f64).round());
                }
            }
        }
        Field { dims, values }
    }

    /// The oracle's integers for the isovalue `iso`.
    pub fn scaled(&self, iso: f64) -> Vec<i64> {
        oracle::scaled(&self.values, iso)
    }

    /// The oracle's topology at `iso`.
    pub fn topology(&self, iso: f64) -> oracle::Topology {
        oracle::topology(self.dims, &self.scaled(iso))
    }

    /// Pointwise maximum (union of the inside regions) of two fields of the
    /// same size.
    pub fn max(&self, other: &Field) -> Field {
        assert_eq!(self.dims, other.dims);
        Field {
            dims: self.dims,
            values: self
                .values
                .iter()
                .zip(&other.values)
                .map(|(a, b)| a.max(*b))
                .collect(),
        }
    }
}

fn dist(p: [f64; 3], c: [f64; 3]) -> f64 {
    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt()
}

/// `100 (r - |p - c|)`: a ball at iso 0 (sphere, χ = 2).
pub fn ball(dims: [usize; 3], c: [f64; 3], r: f64) -> Field {
    Field::from_fn(dims, |x, y, z| 100.0 * (r - dist([x, y, z], c)))
}

/// `100 (t - ||p - c| - r|)`: a hollow shell at iso 0 (two spheres).
pub fn shell(dims: [usize; 3], c: [f64; 3], r: f64, t: f64) -> Field {
    Field::from_fn(dims, |x, y, z| 100.0 * (t - (dist([x, y, z], c) - r).abs()))
}

/// A solid torus around the axis through `c` parallel to `axis`, with major
/// radius `big` and minor radius `small` (torus, χ = 0, at iso 0).
pub fn torus(dims: [usize; 3], c: [f64; 3], big: f64, small: f64, axis: usize) -> Field {
    Field::from_fn(dims, |x, y, z| {
        let p = [x - c[0], y - c[1], z - c[2]];
        let (u, v) = match axis {
            0 => (p[1], p[2]),
            1 => (p[0], p[2]),
            _ => (p[0], p[1]),
        };
        let ring = (u * u + v * v).sqrt() - big;
        100.0 * (small - (ring * ring + p[axis] * p[axis]).sqrt())
    })
}

/// A single sample of value 1 at `p` in a grid of zeros (iso 0: a small
/// sphere).
pub fn single_vertex(dims: [usize; 3], p: [usize; 3]) -> Field {
    let mut values = vec![0.0; dims.iter().product()];
    values[p[0] + dims[0] * (p[1] + dims[1] * p[2])] = 1.0;
    Field { dims, values }
}
