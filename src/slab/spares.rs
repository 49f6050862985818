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
use crate::mesh::Chunk;
use crossbeam::queue::ArrayQueue;
use std::sync::atomic::{AtomicU64, Ordering};

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
    /// The plane size (x, y) the buffers are made for.
    pub(super) dims: [usize; 2],
    pub(super) z_first: Vec<u32>,
    pub(super) rows: EdgeRows,
}

/// A block's vertices, triangles and normals, as [`Spares::take_block`]
/// hands them out.
pub(super) type BlockVectors = (Vec<[f32; 3]>, Vec<[u32; 3]>, Vec<[f32; 3]>);

/// The spare buffers of one extraction, shared by its workers and the
/// thread that writes finished slabs. Bounded: a buffer handed back when
/// the store is full is freed.
#[derive(Debug)]
pub struct Spares {
    scratch: ArrayQueue<Scratch>,
    /// Written chunks, emptied; their vectors become blocks again.
    blocks: ArrayQueue<Chunk>,
    /// Bytes of block vectors held in `blocks` (their capacities).
    block_bytes: AtomicU64,
}

/// Bytes the vectors of `chunk` hold (capacity, not length).
pub fn chunk_bytes(chunk: &Chunk) -> u64 {
    let vertices = chunk.vertices.capacity() * std::mem::size_of::<[f32; 3]>();
    let triangles = chunk.triangles.capacity() * std::mem::size_of::<[u32; 3]>();
    let normals = chunk.normals.capacity() * std::mem::size_of::<[f32; 3]>();
    let values = chunk.values.capacity() * std::mem::size_of::<f32>();
    (vertices + triangles + normals + values + chunk.encoded.capacity()) as u64
}

impl Spares {
    /// Room for the scratch of `slabs` slabs in flight and for `blocks`
    /// block vectors (about one slab's worth is enough: a new slab takes a
    /// block per layer as the written slab hands them back).
    pub fn new(slabs: usize, blocks: usize) -> Self {
        Spares {
            scratch: ArrayQueue::new(slabs.max(1)),
            blocks: ArrayQueue::new(blocks.max(1)),
            block_bytes: AtomicU64::new(0),
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

    /// Empty vectors for a block's vertices, triangles and normals (with
    /// their old capacity), or new ones.
    pub(super) fn take_block(&self) -> BlockVectors {
        let chunk = self.blocks.pop().unwrap_or_default();
        self.block_bytes
            .fetch_sub(chunk_bytes(&chunk), Ordering::Relaxed);
        (chunk.vertices, chunk.triangles, chunk.normals)
    }

    /// Hands back the vectors of a chunk that has been written.
    pub fn give_chunk(&self, mut chunk: Chunk) {
        chunk.vertices.clear();
        chunk.triangles.clear();
        chunk.normals.clear();
        chunk.values.clear();
        // Blocks do not reuse encoded bytes.
        chunk.encoded = Vec::new();
        // Counted before it can be taken, so that the count never wraps.
        let bytes = chunk_bytes(&chunk);
        self.block_bytes.fetch_add(bytes, Ordering::Relaxed);
        if self.blocks.push(chunk).is_err() {
            self.block_bytes.fetch_sub(bytes, Ordering::Relaxed);
        }
    }

    /// Frees the spare block vectors (when a memory budget needs the room
    /// more than the next slab needs the speed).
    pub fn free_blocks(&self) {
        while let Some(chunk) = self.blocks.pop() {
            self.block_bytes
                .fetch_sub(chunk_bytes(&chunk), Ordering::Relaxed);
        }
    }

    /// Bytes held by the spare block vectors (counted against a memory
    /// budget: they are the written mesh's memory, kept for reuse).
    pub fn block_bytes(&self) -> u64 {
        self.block_bytes.load(Ordering::Relaxed)
    }
}
