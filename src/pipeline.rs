//! The extraction entry point: parameters, slabs in parallel, seams stitched.

use crate::seam::stitch;
use crate::slab::{process_slab, Block};
use crate::volume::Padded;
use crate::{Error, Mesh, Result, SampleSource, Stats};
use rayon::prelude::*;
use std::ops::Range;
use std::time::Instant;

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
///
/// The cell layers are cut into slabs that worker threads triangulate in
/// parallel; the result does not depend on the number of threads.
pub fn extract(source: &dyn SampleSource, params: &ExtractParams) -> Result<(Mesh, Stats)> {
    let start = Instant::now();
    if !params.iso.is_finite() {
        return Err(Error::Invalid(format!(
            "the isovalue must be a finite number, not {}",
            params.iso
        )));
    }
    let padded;
    let source: &dyn SampleSource = if params.close {
        padded = Padded::new(source);
        &padded
    } else {
        source
    };
    let dims = source.grid().dims;
    if dims.iter().any(|&d| d < 2) {
        return Err(Error::Invalid(format!(
            "the grid {}x{}x{} needs at least 2 samples along every axis",
            dims[0], dims[1], dims[2]
        )));
    }
    let layers = dims[2] - 1;
    let threads = if params.threads == 0 {
        rayon::current_num_threads()
    } else {
        params.threads
    };
    let depth = layers.div_ceil(threads * 4).clamp(1, 64);
    let slabs: Vec<Range<usize>> = (0..layers)
        .step_by(depth)
        .map(|z| z..(z + depth).min(layers))
        .collect();
    let run = |r: &Range<usize>| process_slab(source, params, r.clone());
    let results: Vec<Result<(Vec<Block>, Stats)>> = if threads == 1 {
        slabs.iter().map(run).collect()
    } else {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))?
            .install(|| slabs.par_iter().map(run).collect())
    };
    let mut blocks = Vec::with_capacity(dims[2]);
    let mut stats = Stats::default();
    for r in results {
        let (b, s) = r?;
        blocks.extend(b);
        stats.add_counts(&s);
    }
    let mesh = stitch(blocks)?;
    stats.vertices = mesh.vertices.len() as u64;
    stats.triangles = mesh.triangles.len() as u64;
    stats.seconds = start.elapsed().as_secs_f64();
    Ok((mesh, stats))
}
