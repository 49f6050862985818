//! Replays a `.tmesh` file into any sink, chunk by chunk, as the pipeline
//! sent it: `tmc convert` and `tmc check` read `.tmesh` files this way.

use crate::mesh::{MeshSink, Totals};
use crate::meshfile::TmeshReader;
use crate::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};

/// Feeds every chunk of `reader` to `sink` (`begin`, the chunks in order,
/// `finish`), one chunk in memory at a time; returns the totals.
///
/// A damaged chunk stops the replay with the reader's error, which names
/// the chunk; `finish` is then never called, so a file sink commits nothing.
pub fn replay(reader: &mut TmeshReader, sink: &mut dyn MeshSink) -> Result<Totals> {
    replay_cancellable(reader, sink, &AtomicBool::new(false))
}

/// [`replay`] that looks at `cancel` before each chunk (and the sink within
/// one, [`MeshSink::chunk_cancellable`]) and stops with
/// [`Error::Interrupted`] once it is set (one relaxed load per chunk);
/// `finish` is then never called, so a file sink commits nothing.
pub fn replay_cancellable(
    reader: &mut TmeshReader,
    sink: &mut dyn MeshSink,
    cancel: &AtomicBool,
) -> Result<Totals> {
    sink.begin(reader.info())?;
    let count = reader.entries().len();
    for i in 0..count {
        if cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        let base = reader.entries()[i].vertex_base;
        let chunk = reader.chunk(i)?;
        sink.chunk_cancellable(base, &chunk, cancel)?;
    }
    if cancel.load(Ordering::Relaxed) {
        return Err(Error::Interrupted);
    }
    let totals = Totals {
        vertices: reader.vertices(),
        triangles: reader.triangles(),
        chunks: count as u64,
    };
    sink.finish_cancellable(&totals, cancel)?;
    Ok(totals)
}
