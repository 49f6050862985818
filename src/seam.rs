//! Seams: from per-plane blocks to one mesh with global vertex numbers.
//!
//! Each block's vertices get consecutive global numbers in plane order, so a
//! vertex on a slab seam, computed by both slabs, is numbered once: by the
//! block of its plane. Nothing is matched by position.

use crate::slab::{Block, NEXT_BLOCK};
use crate::{Error, Mesh, Result};

/// Concatenates `blocks` (in plane order, one per grid plane) into a mesh.
pub fn stitch(blocks: Vec<Block>) -> Result<Mesh> {
    let mut offsets = Vec::with_capacity(blocks.len() + 1);
    let mut total = 0u64;
    for b in &blocks {
        offsets.push(total);
        total += b.vertices.len() as u64;
    }
    offsets.push(total);
    if total > u32::MAX as u64 {
        return Err(Error::Invalid(format!(
            "the mesh has {total} vertices, more than an in-memory mesh with 32-bit indices holds"
        )));
    }
    let triangles: usize = blocks.iter().map(|b| b.triangles.len()).sum();
    let mut mesh = Mesh {
        vertices: Vec::with_capacity(total as usize),
        triangles: Vec::with_capacity(triangles),
    };
    for (z, b) in blocks.into_iter().enumerate() {
        let (here, next) = (offsets[z] as u32, offsets[z + 1] as u32);
        mesh.vertices.extend_from_slice(&b.vertices);
        mesh.triangles.extend(b.triangles.iter().map(|t| {
            t.map(|r| {
                if r & NEXT_BLOCK != 0 {
                    next + (r & !NEXT_BLOCK)
                } else {
                    here + r
                }
            })
        }));
    }
    Ok(mesh)
}
