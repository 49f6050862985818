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
use crate::mesh::Chunk;
use crate::{Error, Result};
use std::cell::RefCell;

thread_local! {
    /// One compression context per thread, for every chunk it compresses:
    /// making one per chunk cost more than compressing small chunks (a
    /// 2x2x1000000 volume spent 57% of its 25 s there). It lives as long
    /// as its thread (a pass's workers end with the pass).
    static COMPRESSOR: RefCell<Option<zstd::bulk::Compressor<'static>>> =
        const { RefCell::new(None) };
}

/// The compressed payload of `chunk`, as the `.tmesh` format stores it.
pub fn encode_payload(chunk: &Chunk) -> Result<Vec<u8>> {
    let raw = raw_payload(chunk)?;
    let failed = |e: std::io::Error| Error::Invalid(format!("zstd compression failed: {e}"));
    COMPRESSOR.with(|slot| {
        let mut slot = slot.borrow_mut();
        let compressor = match &mut *slot {
            Some(compressor) => compressor,
            None => slot.insert(zstd::bulk::Compressor::new(ZSTD_LEVEL).map_err(failed)?),
        };
        compressor.compress(&raw).map_err(failed)
    })
}

/// The payload of a chunk before compression, packed
/// ([`super::packing`]): positions, then relative indices, then the
/// normals if it has any (as they are: see `packing.rs`), then the
/// triangles' labels if it has any.
fn raw_payload(chunk: &Chunk) -> Result<Vec<u8>> {
    let len = (chunk.vertices.len() + chunk.triangles.len() + chunk.normals.len())
        .saturating_mul(12)
        .saturating_add(chunk.labels.len().saturating_mul(4));
    let mut raw = crate::error::try_vec::<u8>("a .tmesh chunk", len)?;
    pack_triples(&mut raw, &chunk.vertices);
    pack_numbers(&mut raw, chunk.triangles.as_flattened());
    put_as_is(&mut raw, chunk.normals.as_flattened());
    pack_numbers(&mut raw, &chunk.labels);
    Ok(raw)
}
