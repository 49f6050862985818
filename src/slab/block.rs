//! Blocks: the vertices owned by one grid plane and the triangles of the
//! cell layer above it, while the layer is built, and as the [`Chunk`] it
//! leaves the slab as.

use super::Spares;
use crate::error::make_room;
use crate::mesh::Chunk;
use crate::{Error, Result};

/// What the slab loop's growing vectors hold, for out-of-memory errors.
pub(super) const VERTICES: &str = "the vertices of a slab";
pub(super) const TRIANGLES: &str = "the triangles of a slab";
/// Set in a triangle's vertex reference when it points into block `z + 1`.
pub(super) const NEXT_BLOCK: u32 = 1 << 31;

/// The vertices owned by one grid plane and the triangles of the cell layer
/// above it, while the layer is being built: triangle entries are local
/// indices, possibly tagged [`NEXT_BLOCK`].
#[derive(Debug, Default, Clone)]
pub(super) struct Block {
    pub(super) vertices: Vec<[f32; 3]>,
    pub(super) triangles: Vec<[u32; 3]>,
    /// One per vertex when the extraction asks for normals, else empty
    /// (filled once the block is complete, see `slab::normals`).
    pub(super) normals: Vec<[f32; 3]>,
}

impl Block {
    /// The finished block as a chunk: references into the next block follow
    /// this block's own vertices. A mirroring index-to-world map reverses the
    /// winding, so that triangles stay counter-clockwise seen from outside.
    pub(super) fn into_chunk(mut self, plane: usize, mirrored: bool) -> Chunk {
        // A tagged reference `NEXT_BLOCK + r` becomes `own + r`, without a
        // branch: the tag bit selects the offset (wrapping arithmetic).
        let shift = (self.vertices.len() as u32).wrapping_sub(NEXT_BLOCK);
        let resolve = |r: u32| r.wrapping_add(shift & 0u32.wrapping_sub(r >> 31));
        if mirrored {
            for t in &mut self.triangles {
                let [a, b, c] = t.map(resolve);
                *t = [a, c, b];
            }
        } else {
            for r in self.triangles.as_flattened_mut() {
                *r = resolve(*r);
            }
        }
        Chunk {
            plane: plane as u64,
            triangles: self.triangles,
            vertices: self.vertices,
            normals: self.normals,
            labels: Vec::new(),
            values: Vec::new(),
            encoded: Vec::new(),
        }
    }

    /// An empty block with a quarter more room than the finished block
    /// `(vertices, triangles)` of the layer below needed, plus the room the
    /// loops ask for per row (`row`), so that a layer like it does not grow
    /// its vectors; its vectors are spares when there are some.
    pub(super) fn sized_like(
        (vertices, triangles): (usize, usize),
        row: (usize, usize),
        spares: &Spares,
    ) -> Result<Block> {
        let (v, t, n) = spares.take_block();
        Ok(Block {
            normals: n,
            vertices: empty_with_room(v, vertices + vertices / 4 + row.0, VERTICES)?,
            triangles: empty_with_room(t, triangles + triangles / 4 + row.1, TRIANGLES)?,
        })
    }
}

/// The empty vector `spare` if it has room for `n`, else a new one with that
/// room (growing `spare` would copy its whole stale capacity).
pub(super) fn empty_with_room<T>(spare: Vec<T>, n: usize, what: &str) -> Result<Vec<T>> {
    debug_assert!(spare.is_empty());
    if spare.capacity() >= n {
        return Ok(spare);
    }
    drop(spare);
    let mut fresh = Vec::new();
    make_room(&mut fresh, n, what)?;
    Ok(fresh)
}

pub(super) fn local_index(block: &Block) -> Result<u32> {
    let n = block.vertices.len();
    check_local_indices(n)?;
    Ok(n as u32)
}

/// Fails when `n` vertices of one block would need local indices that
/// clash with the [`NEXT_BLOCK`] tag.
pub(super) fn check_local_indices(n: usize) -> Result<()> {
    if n as u64 >= NEXT_BLOCK as u64 {
        return Err(Error::Invalid(
            "more than 2^31 vertices in one grid plane".into(),
        ));
    }
    Ok(())
}
