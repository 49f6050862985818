//! The extraction entry point: parameters, slabs in parallel, seams stitched.

use crate::{Mesh, Result, SampleSource, Stats};

/// Which algorithm triangulates the cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Grosso's topologically correct and manifold hybrid marching cubes.
    #[default]
    Tmc,
    /// Standard marching cubes with one consistent face rule (inside corners
    /// of an ambiguous face are always separated).
    Mc,
}

/// Which side of the isovalue is the object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Inside {
    /// Values above the isovalue are inside (CT, MRI, densities).
    #[default]
    High,
    /// Values below the isovalue are inside (signed distance fields).
    Low,
}

/// Options of one extraction.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtractParams {
    /// The isovalue (finite).
    pub iso: f64,
    /// The cell algorithm.
    pub method: Method,
    /// Which side is the object.
    pub inside: Inside,
    /// Treat everything outside the volume as outside the object, so that
    /// every surface is closed.
    pub close: bool,
    /// Worker threads (0 = all cores).
    pub threads: usize,
}

impl Default for ExtractParams {
    fn default() -> Self {
        ExtractParams {
            iso: 0.0,
            method: Method::Tmc,
            inside: Inside::High,
            close: false,
            threads: 0,
        }
    }
}

/// Extracts the isosurface of `source` at `params.iso`.
pub fn extract(source: &dyn SampleSource, params: &ExtractParams) -> Result<(Mesh, Stats)> {
    let _ = (source, params);
    todo!("kernel in progress")
}
