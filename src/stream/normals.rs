//! The normals of a finished slab, on the worker that triangulated it.

use crate::mesh::Chunk;
use crate::normals::SlabNormals;
use crate::params::ExtractParams;
use crate::volume::SampleSource;
use crate::{Result, Stats};

/// Gives every chunk of each isovalue's slab in `results` (as
/// `slab_for_each` returns them, in the order of `params`) its normals
/// ([`SlabNormals`]) where that isovalue asks for them, right after the
/// slab loop on the same worker, while the slab's planes are still cached.
/// Out of line, so that the slab loop's code is the same with normals off.
#[inline(never)]
pub(super) fn slab_normals(
    source: &dyn SampleSource,
    params: &[ExtractParams],
    results: &mut [(Vec<Chunk>, Stats)],
) -> Result<()> {
    for (p, (chunks, _)) in params.iter().zip(results) {
        if p.normals {
            let mut normals = SlabNormals::new(source, p);
            chunks
                .iter_mut()
                .try_for_each(|chunk| normals.fill(chunk))?;
        }
    }
    Ok(())
}
