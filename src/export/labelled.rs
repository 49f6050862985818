//! [`write_labelled`]: the surfaces of several labels in one mesh file
//! (PLY with a per-face `uint label` property, or `.tmesh` with the labels
//! attribute), assembled from one `.tmesh` file per label.
//!
//! The labels' chunks are interleaved plane by plane: the chunk of plane
//! `z` holds the plane-`z` vertices of the first label, then the second's
//! ..., and their triangles in the same order, each with its label. A
//! triangle of the layer above plane `z` that points into its label's next
//! chunk is moved to where that label's vertices start in the next merged
//! chunk, so the stream keeps the chunk rule (indices reach at most into the
//! next chunk), and a label's vertices and triangles keep their order. Any
//! format the stream goes to is the same mesh: `tmc convert` of the
//! `.tmesh` writes the PLY's bytes.

use crate::mesh::{Chunk, MeshInfo, Totals};
use crate::meshfile::TmeshReader;
use crate::{Error, Result};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Writes `path` (atomically; the format by its extension, as
/// [`create_sink`](super::create_sink) chooses it) as the union of the
/// meshes of every `(label, tmesh)`, each triangle with its label (see the
/// module documentation for the order). The files must be of one
/// extraction (same grid, options and normals). Memory holds one plane's
/// chunks of every label. Stops with [`Error::Interrupted`] once `cancel`
/// is set, leaving nothing at `path`.
pub fn write_labelled(path: &Path, parts: &[(u32, &Path)], cancel: &AtomicBool) -> Result<Totals> {
    let mut readers = Vec::with_capacity(parts.len());
    for &(label, tmesh) in parts {
        readers.push((label, TmeshReader::open(tmesh)?, 0usize));
    }
    let Some((_, first, _)) = readers.first() else {
        return Err(Error::Invalid("no label mesh to write".into()));
    };
    let info = MeshInfo {
        labels: true,
        ..first.info().clone()
    };
    let same = |r: &TmeshReader| {
        let mine = r.info();
        !mine.labels
            && MeshInfo {
                labels: true,
                ..mine.clone()
            } == info
    };
    if let Some((_, &(_, other))) = readers.iter().zip(parts).find(|((_, r, _), _)| !same(r)) {
        return Err(Error::Invalid(format!(
            "{}: not a label mesh of the same extraction as {}",
            other.display(),
            parts[0].1.display()
        )));
    }
    crate::export::check_output_path(path)?;
    let mut sink = super::create_sink(path)?;
    sink.begin(&info)?;
    let mut totals = Totals::default();
    // The planes in order: the lowest plane any label's next chunk is on.
    while let Some(z) = readers
        .iter()
        .filter_map(|(_, r, j)| r.entries().get(*j).map(|e| e.plane))
        .min()
    {
        if cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        let chunk = merged_plane(&mut readers, z).map_err(|e| match e {
            Error::Invalid(m) => Error::Invalid(format!("{}: {m}", path.display())),
            other => other,
        })?;
        sink.chunk_cancellable(totals.vertices, &chunk, cancel)?;
        totals.vertices += chunk.vertices.len() as u64;
        totals.triangles += chunk.triangles.len() as u64;
        totals.chunks += 1;
    }
    sink.finish_cancellable(&totals, cancel)?;
    Ok(totals)
}

/// The merged chunk of plane `z`, advancing the readers (label, reader,
/// next entry) that have a chunk there.
fn merged_plane(readers: &mut [(u32, TmeshReader, usize)], z: u64) -> Result<Chunk> {
    // Each label's entry on plane z + 1 after this plane's (the next chunk's
    // vertices its triangles may point into), and where the label's
    // vertices start in the next merged chunk.
    let on = |r: &TmeshReader, j: usize, plane: u64| {
        r.entries().get(j).filter(|e| e.plane == plane).copied()
    };
    let mut next_start = Vec::with_capacity(readers.len());
    let (mut next_total, mut here) = (0u64, 0u64);
    for (_, r, j) in readers.iter() {
        let now = on(r, *j, z).map(|e| e.vertex_count);
        here += u64::from(now.unwrap_or(0));
        let after = j + usize::from(now.is_some());
        next_start.push(next_total);
        next_total += u64::from(on(r, after, z + 1).map_or(0, |e| e.vertex_count));
    }
    // Indices relative to the merged chunk are u32, as in every chunk.
    if here + next_total > u64::from(u32::MAX) {
        return Err(Error::Invalid(format!(
            "planes {z} and {} hold more than 2^32 vertices of all labels",
            z + 1
        )));
    }
    let here = here as u32;
    let mut merged = Chunk {
        plane: z,
        ..Chunk::default()
    };
    for ((label, r, j), &start) in readers.iter_mut().zip(&next_start) {
        let Some(e) = on(r, *j, z) else { continue };
        let next = on(r, *j + 1, z + 1).map_or(0, |n| n.vertex_count);
        let chunk = r.chunk_then(*j, next)?;
        *j += 1;
        let own = merged.vertices.len() as u32;
        let count = e.vertex_count;
        let moved = |k: u32| match k < count {
            true => own + k,
            false => here + start as u32 + (k - count),
        };
        merged
            .triangles
            .extend(chunk.triangles.iter().map(|t| t.map(moved)));
        merged
            .labels
            .extend(std::iter::repeat_n(*label, chunk.triangles.len()));
        merged.vertices.extend_from_slice(&chunk.vertices);
        merged.normals.extend_from_slice(&chunk.normals);
    }
    Ok(merged)
}
