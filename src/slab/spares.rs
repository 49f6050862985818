//! Buffers a finished slab hands back for the next slab to reuse.
//!
//! A large fresh allocation comes from the kernel as untouched pages, and
//! the first write to each page costs a page fault. Slabs of one extraction
//! need buffers of about the same sizes, slab after slab: the plane buffers
//! (samples, inside bits, edge numbers) and the vectors of each block. Taking
//! them from the slab before instead of from the allocator saves a fault
//! per 4 KiB of mesh and of plane: on dense value noise (258^3, 29M
//! triangles) that was more than half of all page faults of an in-memory
//! extraction, and about a fifth of its time on this machine.

use super::bits::SignBits;
use super::edges::EdgeRows;
use crate::sink::Chunk;
use crossbeam::queue::ArrayQueue;

/// One plane's buffers, contents stale (see the plane's doc: stale entries
/// are never read).
#[derive(Debug)]
pub(super) struct PlaneBuffers {
    pub(super) read: Vec<f64>,
    pub(super) inside: SignBits,
    pub(super) x_first: Vec<u32>,
    pub(super) y_first: Vec<u32>,
}

/// What one slab works in besides its blocks: two planes, the first z-edge
/// vertex of each row and the row arrays of edge numbers.
#[derive(Debug)]
pub(super) struct Scratch {
    pub(super) planes: [PlaneBuffers; 2],
    pub(super) z_first: Vec<u32>,
    pub(super) rows: EdgeRows,
}

/// The spare buffers of one extraction, shared by its workers and the
/// thread that writes finished slabs. Bounded: a buffer handed back when
/// the store is full is freed.
#[derive(Debug)]
pub struct Spares {
    scratch: ArrayQueue<Scratch>,
    /// Written chunks, emptied; their vectors become blocks again.
    blocks: ArrayQueue<Chunk>,
}

impl Spares {
    /// Room for the scratch of `slabs` slabs in flight and for `blocks`
    /// block vectors (about one slab's worth is enough: a new slab takes a
    /// block per layer as the written slab hands them back).
    pub fn new(slabs: usize, blocks: usize) -> Self {
        Spares {
            scratch: ArrayQueue::new(slabs.max(1)),
            blocks: ArrayQueue::new(blocks.max(1)),
        }
    }

    /// A spare slab scratch, if any.
    pub(super) fn take_scratch(&self) -> Option<Scratch> {
        self.scratch.pop()
    }

    /// Hands a slab's scratch back.
    pub(super) fn give_scratch(&self, scratch: Scratch) {
        let _ = self.scratch.push(scratch);
    }

    /// Empty vectors for a block (with their old capacity), or new ones.
    pub(super) fn take_block(&self) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
        let chunk = self.blocks.pop().unwrap_or_default();
        (chunk.vertices, chunk.triangles)
    }

    /// Hands back the vectors of a chunk that has been written.
    pub fn give_chunk(&self, mut chunk: Chunk) {
        chunk.vertices.clear();
        chunk.triangles.clear();
        let _ = self.blocks.push(chunk);
    }
}
