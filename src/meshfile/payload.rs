//! A chunk's `.tmesh` payload ([`encode_payload`]): its numbers as
//! little-endian bytes, compressed into one zstd frame, on whichever thread
//! asks (the pipeline's workers, through
//! [`MeshSink::encoder`](crate::mesh::MeshSink::encoder), or the writer
//! itself for a chunk that comes without one).
//!
//! A frame depends only on the bytes and the level (zstd compresses each
//! frame afresh, whatever the context compressed before), so the payload
//! is the same on any thread and in any order: the files stay byte for
//! byte what one writing thread made.

use super::packing::{pack_numbers, pack_triples, put_as_is};
use super::ZSTD_LEVEL;
use crate::error::make_room;
use crate::mesh::Chunk;
use crate::{Error, Result};
use std::cell::RefCell;

thread_local! {
    /// One compression context per thread, for every chunk it compresses:
    /// making one per chunk cost more than compressing small chunks (a
    /// 2x2x1000000 volume spent 57% of its 25 s there). It lives as long
    /// as its thread (a pass's workers end with the pass). The second is
    /// for small chunks: literals stored as they are.
    static COMPRESSOR: RefCell<[Option<zstd::bulk::Compressor<'static>>; 2]> =
        const { RefCell::new([None, None]) };
    /// The thread's packed bytes and compressed frame, kept from chunk to
    /// chunk while at most [`KEPT_BUFFER_BYTES`] each: a label map's pass
    /// compresses thousands of small chunks, and allocating both for each
    /// cost more than copying the frame out.
    static BUFFERS: RefCell<(Vec<u8>, Vec<u8>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

/// Chunks of fewer bytes (packed) than this keep their literals as they
/// are: building a Huffman table for them cost more than it saved
/// (see docs/performance-labels.md).
const SMALL_CHUNK_BYTES: usize = 16 << 10;

/// The most bytes of room each of a thread's buffers keeps after a chunk:
/// a larger chunk's (a dense plane's packed bytes may be hundreds of MB)
/// are freed, so that no thread holds memory the budget does not count.
const KEPT_BUFFER_BYTES: usize = 1 << 20;

/// The compressed payload of `chunk`, as the `.tmesh` format stores it.
pub fn encode_payload(chunk: &Chunk) -> Result<Vec<u8>> {
    BUFFERS.with(|buffers| {
        let (raw, frame) = &mut *buffers.borrow_mut();
        let payload = raw_payload(chunk, raw).and_then(|()| {
            compress(raw, frame)?;
            let mut payload = crate::error::try_vec("a .tmesh chunk's frame", frame.len())?;
            payload.extend_from_slice(frame);
            Ok(payload)
        });
        for buffer in [raw, frame] {
            if buffer.capacity() > KEPT_BUFFER_BYTES {
                *buffer = Vec::new();
            }
        }
        payload
    })
}

/// Compresses `raw` into `frame` (one zstd frame, replacing its bytes).
fn compress(raw: &[u8], frame: &mut Vec<u8>) -> Result<()> {
    let failed = |e: std::io::Error| Error::Invalid(format!("zstd compression failed: {e}"));
    frame.clear();
    make_room(
        frame,
        zstd::zstd_safe::compress_bound(raw.len()),
        "a .tmesh chunk's frame",
    )?;
    let small = raw.len() < SMALL_CHUNK_BYTES;
    COMPRESSOR.with(|slots| {
        let mut slots = slots.borrow_mut();
        let slot = &mut slots[usize::from(small)];
        let compressor = match slot {
            Some(compressor) => compressor,
            None => {
                let mut c = zstd::bulk::Compressor::new(ZSTD_LEVEL).map_err(failed)?;
                if small {
                    let raw_literals = zstd::zstd_safe::CParameter::LiteralCompressionMode(
                        zstd::zstd_safe::ParamSwitch::Disable,
                    );
                    c.set_parameter(raw_literals).map_err(failed)?;
                }
                slot.insert(c)
            }
        };
        compressor.compress_to_buffer(raw, frame).map_err(failed)?;
        Ok(())
    })
}

/// The payload of a chunk before compression into `raw` (its bytes
/// replaced), packed
/// ([`super::packing`]): positions, then relative indices, then the
/// normals if it has any (as they are: see `packing.rs`), then the
/// triangles' labels if it has any.
fn raw_payload(chunk: &Chunk, raw: &mut Vec<u8>) -> Result<()> {
    let len = (chunk.vertices.len() + chunk.triangles.len() + chunk.normals.len())
        .saturating_mul(12)
        .saturating_add(chunk.labels.len().saturating_mul(4));
    raw.clear();
    make_room(raw, len, "a .tmesh chunk")?;
    pack_triples(raw, &chunk.vertices);
    pack_numbers(raw, chunk.triangles.as_flattened());
    put_as_is(raw, chunk.normals.as_flattened());
    pack_numbers(raw, &chunk.labels);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chunk of `n` vertices and triangles (numbers like a mesh's).
    fn chunk(n: usize) -> Chunk {
        Chunk {
            vertices: (0..n)
                .map(|i| [i as f32 * 0.5, (i % 7) as f32, 3.0])
                .collect(),
            triangles: (0..n as u32).map(|i| [i, i + 1, i + 2]).collect(),
            ..Chunk::default()
        }
    }

    /// Chunks below and above the small-chunk size (literals stored as
    /// they are, or Huffman coded) decompress to their packed bytes, and a
    /// chunk's frame is the same whatever was compressed before it on the
    /// thread.
    #[test]
    fn small_and_large_chunks_give_back_their_bytes() {
        let sizes = [0, 1, 100, 600, 700, 5000];
        let mut raw = Vec::new();
        let mut first = Vec::new();
        let mut small = Vec::new();
        for &n in &sizes {
            let chunk = chunk(n);
            raw_payload(&chunk, &mut raw).unwrap();
            small.push(raw.len() < SMALL_CHUNK_BYTES);
            let frame = encode_payload(&chunk).unwrap();
            assert_eq!(zstd::decode_all(&frame[..]).unwrap(), raw, "{n} vertices");
            first.push(frame);
        }
        // Both sides of SMALL_CHUNK_BYTES are covered.
        assert!(small.contains(&true) && small.contains(&false));
        for (&n, frame) in sizes.iter().zip(&first).rev() {
            assert_eq!(&encode_payload(&chunk(n)).unwrap(), frame, "{n} vertices");
        }
    }

    /// A chunk larger than the kept room leaves no buffer of its size on
    /// the thread; a small one's buffers are kept.
    #[test]
    fn a_large_chunks_buffers_are_not_kept() {
        let room = || BUFFERS.with(|b| [b.borrow().0.capacity(), b.borrow().1.capacity()]);
        let large = chunk(100_000);
        let frame = encode_payload(&large).unwrap();
        let mut raw = Vec::new();
        raw_payload(&large, &mut raw).unwrap();
        assert!(raw.len() > KEPT_BUFFER_BYTES);
        assert_eq!(zstd::decode_all(&frame[..]).unwrap(), raw);
        assert!(
            room().iter().all(|&r| r <= KEPT_BUFFER_BYTES),
            "{:?}",
            room()
        );
        encode_payload(&chunk(100)).unwrap();
        assert!(room()[0] > 0, "a small chunk's packed bytes are kept");
    }
}
