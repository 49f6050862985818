//! [`Synthetic`]: a synthetic volume of any size, evaluated on demand.

use super::fields::{Gyroid, Sphere, Torus};
use super::head::{Head, HEAD_SKULL_ISO_HU};
use super::kind::Kind;
use super::levels::{hounsfield_to_stored, to_stored, unit_to_stored, Units};
use super::row_field::RowField;
use super::value_noise::ValueNoise;
use crate::volume::ScalarType;
use crate::{Error, Grid, Result, SampleSource};
use rayon::prelude::*;

/// Largest plane accepted, in samples (a plane of `f64` is held in memory).
const MAX_PLANE: usize = 1 << 31;

/// A synthetic volume of one [`Kind`]: a [`SampleSource`] that computes
/// each plane when it is read (rows in parallel on rayon's pool), so a
/// volume of any size can be written or extracted without being held in
/// memory.
///
/// Samples come out already rounded to the sample type `scalar` (see
/// [`unit_to_stored`] and [`hounsfield_to_stored`]), so a file written with
/// that type reads back exactly the same values. The volume is a pure
/// function of the kind, the grid, the type and the seed.
pub struct Synthetic {
    kind: Kind,
    grid: Grid,
    scalar: ScalarType,
    seed: u64,
    field: Box<dyn RowField>,
}

impl Synthetic {
    /// The volume of `kind` on `grid` (at least 2 samples along every axis;
    /// finite, positive spacing), stored as `scalar`, with `seed` for the
    /// kinds that use one.
    pub fn new(kind: Kind, grid: Grid, scalar: ScalarType, seed: u64) -> Result<Synthetic> {
        let [x, y, z] = grid.dims;
        if grid.dims.iter().any(|&n| n < 2) {
            return Err(Error::Invalid(format!(
                "dims {x}x{y}x{z}: need at least 2 samples along every axis"
            )));
        }
        if grid.spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
            return Err(Error::Invalid(format!(
                "spacing {:?} must be finite and positive",
                grid.spacing
            )));
        }
        if !matches!(x.checked_mul(y), Some(plane) if plane <= MAX_PLANE)
            || grid
                .dims
                .iter()
                .try_fold(1u64, |acc, &n| acc.checked_mul(n as u64))
                .is_none()
        {
            return Err(Error::Invalid(format!("dims {x}x{y}x{z} are too large")));
        }
        let field: Box<dyn RowField> = match kind {
            Kind::Sphere => Box::new(Sphere::new(&grid)),
            Kind::Torus => Box::new(Torus::new(&grid)),
            Kind::Gyroid => Box::new(Gyroid::new(&grid)),
            Kind::Noise => Box::new(ValueNoise::new(&grid, seed)),
            Kind::Head => Box::new(Head::new(&grid, seed)),
        };
        Ok(Synthetic {
            kind,
            grid,
            scalar,
            seed,
            field,
        })
    }

    /// What the volume shows.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// The type the samples are rounded to.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }

    /// The seed (ignored by the kinds without noise).
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The stored value of the kind's main surface, a good isovalue: the
    /// zero level of the unit fields, the skull ([`HEAD_SKULL_ISO_HU`]) of
    /// the head. Inside is above it.
    pub fn suggested_iso(&self) -> f64 {
        match self.kind {
            Kind::Head => hounsfield_to_stored(HEAD_SKULL_ISO_HU, self.scalar),
            _ => unit_to_stored(0.0, self.scalar),
        }
    }

    /// Computes one row of stored values.
    fn row(&self, plane: &[f64], y: usize, z: usize, out: &mut [f64]) {
        self.field.row(plane, y, z, out);
        let units = match self.kind {
            Kind::Head => Units::Hounsfield,
            _ => Units::Unit,
        };
        to_stored(out, units, self.scalar);
    }
}

impl std::fmt::Debug for Synthetic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Synthetic")
            .field("kind", &self.kind)
            .field("grid", &self.grid)
            .field("scalar", &self.scalar)
            .field("seed", &self.seed)
            .finish()
    }
}

impl SampleSource for Synthetic {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let [nx, _, nz] = self.grid.dims;
        if z >= nz {
            return Err(Error::Invalid(format!(
                "plane {z} out of range: the volume has {nz} planes"
            )));
        }
        if out.len() != self.grid.plane_len() {
            return Err(Error::Invalid(format!(
                "plane buffer holds {} samples, a plane has {}",
                out.len(),
                self.grid.plane_len()
            )));
        }
        let plane = self.field.plane(z);
        // Rows in tasks of at least ~4096 samples.
        out.par_chunks_mut(nx)
            .with_min_len((4096 / nx).max(1))
            .enumerate()
            .for_each(|(y, row)| self.row(&plane, y, z, row));
        Ok(())
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }
}
