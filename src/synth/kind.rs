//! The kinds of synthetic volume.

use crate::{Error, Result};
use std::fmt;
use std::str::FromStr;

/// What a [`Synthetic`](super::Synthetic) volume shows.
///
/// Sizes are relative to the grid's physical box (`index * spacing`); `L`
/// below is half the shortest side of the box. The field of the first four
/// kinds lies in `[-1, 1]`, positive inside, with the surface at 0 (see
/// [`unit_to_stored`](super::unit_to_stored) for the stored values); `Head`
/// is in Hounsfield units (see [`hounsfield_to_stored`](super::hounsfield_to_stored)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A ball of radius `0.8 L` at the centre of the box: its signed
    /// distance divided by 8 samples and clamped (a ramp 16 samples wide
    /// across the surface).
    Sphere,
    /// A solid torus around the z axis through the centre, ring radius
    /// `0.55 L`, tube radius `0.25 L`; signed distance as for `Sphere`.
    Torus,
    /// The gyroid `(sin x cos y + sin y cos z + sin z cos x) / 1.5`, four
    /// periods across the shortest side of the box.
    Gyroid,
    /// Smooth value noise (quintic interpolation of hashed lattice values)
    /// with three octaves, lattice periods of 32, 16 and 8 samples, weights
    /// 1, 1/2, 1/4, divided by their sum; it depends on the seed.
    Noise,
    /// A CT-like head phantom in Hounsfield units: air, soft tissue, a skull
    /// of varying thickness and density, brain, two ventricles and a little
    /// noise; it fills the box along every axis and depends on the seed.
    Head,
}

impl Kind {
    /// Every kind.
    pub const ALL: [Kind; 5] = [
        Kind::Sphere,
        Kind::Torus,
        Kind::Gyroid,
        Kind::Noise,
        Kind::Head,
    ];

    /// The name (`sphere`, `torus`, `gyroid`, `noise`, `head`).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sphere => "sphere",
            Kind::Torus => "torus",
            Kind::Gyroid => "gyroid",
            Kind::Noise => "noise",
            Kind::Head => "head",
        }
    }

    /// Whether the volume depends on the seed.
    pub fn uses_seed(self) -> bool {
        matches!(self, Kind::Noise | Kind::Head)
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Kind {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        Kind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "unknown synthetic volume '{s}' (expected sphere, torus, gyroid, noise or head)"
                ))
            })
    }
}
