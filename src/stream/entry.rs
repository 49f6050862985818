//! The entry points of one extraction: into memory ([`extract`]), into any
//! sink ([`extract_to`]), or one part of a split run ([`extract_part_to`]).
//! All three are one pass over the volume with a single isovalue (see
//! [`super::pass`]).

use super::pass::extract_many_part_to;
use crate::mesh::{Mesh, MeshBuilder, MeshSink};
use crate::params::{ExtractParams, PipelineOptions};
use crate::volume::SampleSource;
use crate::{Result, Stats};

/// Extracts the isosurface of `source` at `params.iso` into an in-memory mesh.
pub fn extract(source: &dyn SampleSource, params: &ExtractParams) -> Result<(Mesh, Stats)> {
    let mut builder = MeshBuilder::default();
    let stats = extract_to(source, params, &PipelineOptions::default(), &mut builder)?;
    Ok((builder.into_mesh(), stats))
}

/// Extracts the isosurface of `source` at `params.iso`, streaming chunks in
/// plane order to `sink`.
///
/// The cell layers are cut into slabs that worker threads triangulate in
/// parallel; at most a few slabs per thread are in flight, so memory is
/// bounded by the slab size, not by the volume or the mesh. The output does
/// not depend on the number of threads or on the slab depth.
pub fn extract_to(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
    sink: &mut dyn MeshSink,
) -> Result<Stats> {
    extract_part_to(source, params, options, None, sink)
}

/// [`extract_to`] restricted to part `i` of `n` (1-based): only the chunks of
/// that part's cell layers (see [`layer_range`](super::layer_range)) reach `sink`,
/// numbered from 0, exactly as a whole run writes them.
pub fn extract_part_to(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sink: &mut dyn MeshSink,
) -> Result<Stats> {
    let params = std::slice::from_ref(params);
    let mut stats = extract_many_part_to(source, params, options, part, &mut [sink])?;
    Ok(stats.remove(0))
}
