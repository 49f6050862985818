//! [`SampleSource`]: the one interface between the readers and the pipeline
//! ([`crate::stream`], [`crate::slab`]).

use super::{LentPlane, ScalarType, SharedPlane, SourceNotes};
use crate::grid::Grid;
use crate::Result;
use std::ops::Range;
use std::path::Path;

/// A source of samples, read plane by plane (`z` = slowest axis).
///
/// Implementations must be deterministic: reading the same plane twice gives
/// the same values. Values are converted to `f64` (exact for every supported
/// integer type).
pub trait SampleSource: Sync {
    /// The grid the samples live on.
    fn grid(&self) -> &Grid;
    /// Writes the samples of plane `z` (x fastest) into `out`, whose length
    /// is `grid().plane_len()`.
    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()>;

    /// Plane `z` as stored, when the source holds it in memory in native
    /// byte order and without scaling, so that no `f64` copy is needed;
    /// `None` (the default) makes the caller use [`SampleSource::read_plane`].
    /// Both must give the same values.
    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        let _ = z;
        None
    }

    /// Plane `z` as stored, in a buffer shared with the source's cache, for
    /// sources that decode layers of chunks and cannot lend a plane for as
    /// long as `&self` lives (the cache drops layers); the pipeline holds
    /// the planes of a slab this way ([`HeldPlanes`](super::HeldPlanes)) and
    /// lends them to the slab loop. `None` (the default) when the source
    /// has no such buffer, or could not decode the layer (then
    /// [`SampleSource::read_plane`] reports the error). Same values as
    /// `read_plane`.
    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        let _ = z;
        None
    }

    /// A hint about planes `planes`: they will be read soon, or this reader
    /// of them is done. A memory-mapped source passes it to the kernel, so
    /// that the page cache, not the process, holds the data. Never changes
    /// what is read.
    fn advise(&self, planes: Range<usize>, access: Access) {
        let _ = (planes, access);
    }

    /// Checks that the storage behind the samples is still whole: a
    /// memory-mapped file must not have shrunk below the mapped length (a
    /// read from the missing part would raise SIGBUS). The pipeline calls
    /// it before each slab; it must be cheap (one `fstat`). `Ok` by default.
    fn check_unchanged(&self) -> Result<()> {
        Ok(())
    }

    /// Whether the run reading this source has been cancelled (a wrapper
    /// such as the pipeline's cancellable source says so once its flag is
    /// set). The slab loop asks every few rows of cells, so that a layer of
    /// a huge plane does not delay a Ctrl-C; it must be cheap (an atomic
    /// load). `false` by default; wrappers pass the question on.
    fn interrupted(&self) -> bool {
        false
    }

    /// The files the samples are read from during the extraction (mapped
    /// data files, DICOM slices), which the output must not overwrite;
    /// empty (the default) for sources that read nothing after opening.
    fn data_files(&self) -> Vec<&Path> {
        Vec::new()
    }

    /// Bytes one sample takes where it is stored (the file's sample size for
    /// a file reader), for reporting the bytes read; 8 (an `f64`) unless a
    /// source says otherwise.
    fn sample_bytes(&self) -> usize {
        8
    }

    /// The sample type as stored in the file (before any scaling), if the
    /// source knows it; `None` (the default) for computed or in-memory
    /// sources. Only reported, never used to read.
    fn stored_type(&self) -> Option<ScalarType> {
        None
    }

    /// Where the grid's spacing and origin came from, and how the samples
    /// are stored if they are chunked; only reported (`tmc info`), never
    /// used to read. By default both come from the file's header and the
    /// samples are not chunked; wrappers pass the question on.
    fn notes(&self) -> SourceNotes {
        SourceNotes::default()
    }

    /// How the slab loop gets this source's planes, for the memory budget
    /// (`--max-memory`, [`crate::stream::budget`]); never used to read.
    /// [`PlaneMemory::Read`] (the default) assumes the most a worker can
    /// hold per sample; wrappers pass the question on.
    fn plane_memory(&self) -> PlaneMemory {
        PlaneMemory::Read
    }
}

/// What the workers of a pass hold of a source's planes (see
/// [`SampleSource::plane_memory`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlaneMemory {
    /// Read into `f64` buffers, two per worker.
    Read,
    /// Lent in place from a memory map ([`SampleSource::lend_plane`]):
    /// a worker holds only their inside bits; the pages belong to the
    /// page cache.
    Lent,
    /// Decoded a layer of `layer` planes at a time (Zarr, HDF5: a chunk's
    /// depth) into buffers of `sample_bytes` a sample that the source's
    /// cache keeps ([`SampleSource::share_plane`]); a worker holds the
    /// planes of its slab, and while it decodes a layer, up to
    /// `decoding` layers' worth of buffers (the new layer and the
    /// decoder's own).
    Decoded {
        /// Bytes of a decoded sample.
        sample_bytes: usize,
        /// Planes decoded at once.
        layer: usize,
        /// Layers' worth of memory a decode takes until its layer is kept.
        decoding: usize,
    },
}

/// What the pipeline is about to do with some planes (see [`SampleSource::advise`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// They will be read soon: read ahead.
    Soon,
    /// This slab has read them for the last time: release the pages.
    Done,
}

/// Implements the named [`SampleSource`] methods of a source that wraps
/// another, in its field `inner`, by passing each call on unchanged: the
/// wrappers (`HeldPlanes`, `Regridded`, `Cancellable`) list the methods
/// they do not change instead of writing each forwarding body again, and
/// write the others. Used inside the `impl SampleSource for ... { }` block.
macro_rules! forward_to_inner {
    ($($method:ident),+ $(,)?) => {
        $($crate::volume::forward_to_inner!(@ $method);)+
    };
    (@ grid) => {
        fn grid(&self) -> &$crate::Grid {
            self.inner.grid()
        }
    };
    (@ read_plane) => {
        fn read_plane(&self, z: usize, out: &mut [f64]) -> $crate::Result<()> {
            self.inner.read_plane(z, out)
        }
    };
    (@ lend_plane) => {
        fn lend_plane(&self, z: usize) -> Option<$crate::volume::LentPlane<'_>> {
            self.inner.lend_plane(z)
        }
    };
    (@ share_plane) => {
        fn share_plane(&self, z: usize) -> Option<$crate::volume::SharedPlane> {
            self.inner.share_plane(z)
        }
    };
    (@ advise) => {
        fn advise(&self, planes: ::std::ops::Range<usize>, access: $crate::volume::Access) {
            self.inner.advise(planes, access);
        }
    };
    (@ check_unchanged) => {
        fn check_unchanged(&self) -> $crate::Result<()> {
            self.inner.check_unchanged()
        }
    };
    (@ interrupted) => {
        fn interrupted(&self) -> bool {
            self.inner.interrupted()
        }
    };
    (@ data_files) => {
        fn data_files(&self) -> Vec<&::std::path::Path> {
            self.inner.data_files()
        }
    };
    (@ sample_bytes) => {
        fn sample_bytes(&self) -> usize {
            self.inner.sample_bytes()
        }
    };
    (@ stored_type) => {
        fn stored_type(&self) -> Option<$crate::volume::ScalarType> {
            self.inner.stored_type()
        }
    };
    (@ notes) => {
        fn notes(&self) -> $crate::volume::SourceNotes {
            self.inner.notes()
        }
    };
    (@ plane_memory) => {
        fn plane_memory(&self) -> $crate::volume::PlaneMemory {
            self.inner.plane_memory()
        }
    };
}
pub(crate) use forward_to_inner;
