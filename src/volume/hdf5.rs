//! HDF5 datasets (`scan.h5:/exchange/data`, or `--dataset PATH`), read
//! with the pure-Rust `rust-hdf5` crate, so that no C library is needed:
//! contiguous and chunked datasets, the deflate (gzip) and shuffle filters
//! (and fletcher32), every chunk index h5py writes (version 1 B-trees, and
//! with `libver='latest'` fixed and extensible arrays and version 2
//! B-trees), either byte order, and the sample types tmc reads (8-, 16-
//! and 32-bit integers, 32- and 64-bit floats).
//!
//! The last three axes are z, y, x (C order, as h5py writes numpy arrays),
//! but for axes after them of one entry or picked by `--at` (a channel
//! axis last, as ilastik writes `zyxc`); of every other axis one entry is
//! read, the only one or the one `--at` picks. The spacing comes from one
//! attribute, where the dataset has it: `element_size_um`, three numbers
//! in micrometres in z, y, x order (the convention of ilastik and Fiji's
//! HDF5 plugin), converted to millimetres; without it the spacing is 1
//! and `--spacing` sets it. The origin is always 0 (`--origin` sets it).
//!
//! Planes are served from *layers* (a [`LayeredVolume`], whose cache is
//! `chunk_layers.rs`'s): a chunked
//! dataset's layer is one chunk deep, so each chunk is read and inflated
//! once per pass, and memory holds a few layers, never the volume; a
//! contiguous dataset's layer is one plane, read where it lies in the
//! file. The library reads under one lock, so the chunks of a layer are
//! inflated on one thread.

use super::{units, Grid, LayerReader, LayeredVolume, PlaneMemory, SampleSource, ScalarType};
use super::{ChunkNotes, SourceNotes, ValueFrom};
use crate::{Error, Result};
use rust_hdf5::{DatatypeMessage, H5Dataset, H5File};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The first bytes of an HDF5 file (at offset 0 when it has no user block).
const MAGIC: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// The attribute the spacing is read from (see the module documentation).
pub const SPACING_ATTRIBUTE: &str = "element_size_um";

/// An HDF5 dataset read plane by plane from its layers.
pub struct Hdf5Volume {
    /// The planes, a layer of chunks at a time.
    inner: LayeredVolume<Hdf5Layers>,
    /// Entries a chunk holds of the axes but z, y, x (1 when contiguous).
    other_chunk: usize,
    notes: SourceNotes,
}

/// Reads the layers of an HDF5 dataset (see [`LayerReader`]).
struct Hdf5Layers {
    path: PathBuf,
    dataset: H5Dataset,
    /// The volume's `[nx, ny, nz]`.
    dims: [usize; 3],
    scalar: ScalarType,
    /// Axes of the dataset (3 and more).
    rank: usize,
    /// One past the x axis: `rank`, less the trailing axes of one entry
    /// or picked by `--at` (channels last, as ilastik writes `zyxc`).
    end: usize,
    /// The entry read of each axis but z, y, x (`--at`), slowest first.
    others: Vec<u64>,
    /// Layers read from the file so far.
    read: AtomicU64,
}

/// Whether `path` names an HDF5 file: extension `.h5`, `.hdf5`, `.hdf`,
/// `.he5` or `.nxs` (NeXus), or the HDF5 signature at its start.
pub fn is_hdf5(path: &Path) -> bool {
    let ext = crate::files::lowercase_extension(path);
    if matches!(ext.as_str(), "h5" | "hdf5" | "hdf" | "he5" | "nxs") {
        return true;
    }
    let mut head = [0u8; 8];
    path.is_file()
        && std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
            .is_ok()
        && &head == MAGIC
}

/// Splits `FILE:/path/in/file` into the HDF5 file and the dataset's path,
/// when `path` itself does not exist and the part before a colon is an
/// HDF5 file; `None` otherwise.
pub fn split_path(path: &Path) -> Option<(PathBuf, String)> {
    if path.exists() {
        return None;
    }
    let text = path.to_str()?;
    text.match_indices(':').find_map(|(i, _)| {
        let file = Path::new(&text[..i]);
        (file.is_file() && is_hdf5(file)).then(|| (file.to_path_buf(), text[i + 1..].to_string()))
    })
}

/// The sample type of an HDF5 datatype, if tmc reads it.
fn scalar_of(t: &DatatypeMessage) -> Option<ScalarType> {
    Some(match *t {
        DatatypeMessage::FixedPoint { size, signed, .. } => match (size, signed) {
            (1, false) => ScalarType::U8,
            (1, true) => ScalarType::I8,
            (2, false) => ScalarType::U16,
            (2, true) => ScalarType::I16,
            (4, false) => ScalarType::U32,
            (4, true) => ScalarType::I32,
            (8, false) => ScalarType::U64,
            (8, true) => ScalarType::I64,
            _ => return None,
        },
        DatatypeMessage::FloatingPoint { size: 4, .. } => ScalarType::F32,
        DatatypeMessage::FloatingPoint { size: 8, .. } => ScalarType::F64,
        // IEEE half precision only (h5py's float16): a 2-byte float of
        // another layout (bfloat16: 8 exponent bits) is not a `half::f16`.
        DatatypeMessage::FloatingPoint {
            size: 2,
            exponent_size: 5,
            mantissa_size: 10,
            exponent_bias: 15,
            ..
        } => ScalarType::F16,
        // An enumeration is read as its integers (h5py stores a bool array
        // as an enumeration of i8: FALSE 0, TRUE 1, a mask).
        DatatypeMessage::Enum { ref base, .. } => match **base {
            DatatypeMessage::FixedPoint { .. } => scalar_of(base)?,
            _ => return None,
        },
        _ => return None,
    })
}

/// Opens dataset `dataset` of the HDF5 file at `path`.
pub fn open(path: &Path, dataset: Option<&str>) -> Result<Hdf5Volume> {
    open_at(path, dataset, &[])
}

/// [`open`], reading the entries `picks` chooses of the axes before z, y,
/// x (named by position, 0 the slowest: `("0", 2)`; see
/// [`super::leading_axes`]); an axis of one entry needs no pick.
pub fn open_at(path: &Path, dataset: Option<&str>, picks: &[(String, u64)]) -> Result<Hdf5Volume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = H5File::open(path).map_err(|e| fail(format!("cannot open as HDF5: {e}")))?;
    let listed = || {
        let mut names = file.dataset_names();
        names.sort();
        let more = names.len().saturating_sub(8);
        names.truncate(8);
        let mut list = names
            .iter()
            .map(|n| format!("/{}", n.trim_start_matches('/')))
            .collect::<Vec<_>>()
            .join(", ");
        if more > 0 {
            list.push_str(&format!(" and {more} more"));
        }
        if list.is_empty() {
            list = "none at the root".into();
        }
        list
    };
    let Some(name) = dataset.map(|d| d.trim_start_matches('/')) else {
        return Err(fail(format!(
            "name the dataset to read, as FILE:/path/to/dataset or with --dataset PATH (datasets: {})",
            listed()
        )));
    };
    let dataset = file.dataset(name).map_err(|e| match e {
        rust_hdf5::Hdf5Error::NotFound(_) => fail(format!(
            "no dataset '/{name}' in the file (datasets: {})",
            listed()
        )),
        e => fail(format!("dataset '/{name}': {e}")),
    })?;
    let dtype = dataset
        .datatype()
        .map_err(|e| fail(format!("dataset '/{name}': {e}")))?;
    let scalar = scalar_of(&dtype).ok_or_else(|| {
        fail(format!(
            "dataset '/{name}': its type is not one tmc reads (u8, i8, u16, i16, u32, i32, u64, i64, f16, f32, f64, or an enumeration of integers such as a bool mask)"
        ))
    })?;
    let shape = dataset.shape();
    let rank = shape.len();
    if rank < 3 {
        return Err(fail(format!(
            "dataset '/{name}' has {rank} axes; tmc reads 3-D volumes (z, y, x last)"
        )));
    }
    // Trailing axes of one entry (a channel axis last, ilastik's `zyxc`) are
    // dropped: a volume one sample wide in x has no cells, so an axis of one
    // entry last is never the x of a volume to extract; so are trailing
    // axes `--at` picks an entry of.
    let positions: Vec<String> = (0..rank).map(|i| i.to_string()).collect();
    let lengths: Vec<u64> = shape.iter().map(|&n| n as u64).collect();
    let axes = super::leading_axes::volume_axes(&lengths, &positions, picks)
        .map_err(|why| fail(format!("dataset '/{name}': {why}")))?;
    let end = axes.end;
    let others = [axes.lead, axes.trail].concat();
    let [nz, ny, nx] = [shape[end - 3], shape[end - 2], shape[end - 1]];
    if [nx, ny, nz].contains(&0) {
        return Err(fail(format!("dataset '/{name}' is empty")));
    }
    let chunk = dataset.chunk_dims();
    let depth = chunk.as_ref().map_or(1, |c| c[end - 3].max(1));
    let other_chunk = chunk.as_ref().map_or(1, |c| {
        let others = c[..end - 3].iter().chain(&c[end..]);
        others.fold(1usize, |n, &k| n.saturating_mul(k.max(1)))
    });
    let mut grid = Grid::unit([nx, ny, nz]);
    let mut spacing_from = ValueFrom::Default;
    if let Ok(attribute) = dataset.attr(SPACING_ATTRIBUTE) {
        // Floats widen exactly; integers (h5py writes `[1, 1, 1]` as
        // int64) are read as such.
        let values = attribute
            .read_numeric_as::<f64>()
            .or_else(|_| {
                let ints = attribute.read_numeric_as::<i64>()?;
                Ok(ints.into_iter().map(|v| v as f64).collect())
            })
            .map_err(|e: rust_hdf5::Hdf5Error| {
                fail(format!("attribute {SPACING_ATTRIBUTE} of '/{name}': {e}"))
            })?;
        let mm = units::millimetres_per("um").unwrap_or(1e-3);
        match values[..] {
            [z, y, x] if [x, y, z].iter().all(|v| v.is_finite() && *v > 0.0) => {
                grid.spacing = [x * mm, y * mm, z * mm];
                spacing_from = ValueFrom::File {
                    what: format!("attribute {SPACING_ATTRIBUTE} (z, y, x in µm), in mm"),
                };
            }
            _ => {
                return Err(fail(format!(
                    "attribute {SPACING_ATTRIBUTE} of '/{name}' is {values:?}; it must be three finite positive numbers (z, y, x in µm)"
                )))
            }
        }
    }
    let chunks = chunk.map(|c| {
        let filters = dataset.filters().unwrap_or_default();
        let names: Vec<String> = filters
            .iter()
            .map(|f| match f.id {
                1 => format!(
                    "deflate(level={})",
                    f.cd_values.first().copied().unwrap_or(0)
                ),
                2 => "shuffle".to_string(),
                3 => "fletcher32".to_string(),
                id => format!("filter {id}"),
            })
            .collect();
        let codec = if names.is_empty() {
            "HDF5 chunked, no filter".to_string()
        } else {
            format!("HDF5 chunked: {}", names.join(" > "))
        };
        let counts = [nx, ny, nz].map(|n| n as u64);
        let sizes = [c[end - 1], c[end - 2], c[end - 3]];
        ChunkNotes {
            chunk_shape: sizes,
            codec,
            stored_bytes: None,
            chunks: (0..3)
                .map(|i| counts[i].div_ceil(sizes[i].max(1) as u64))
                .product(),
            chunks_stored: None,
        }
    });
    let layers = Hdf5Layers {
        path: path.to_path_buf(),
        dataset,
        dims: grid.dims,
        scalar,
        rank,
        end,
        others,
        read: AtomicU64::new(0),
    };
    Ok(Hdf5Volume {
        inner: LayeredVolume::new(grid, scalar, depth, layers)?,
        other_chunk,
        notes: SourceNotes {
            spacing_from,
            origin_from: ValueFrom::Default,
            chunks,
            units: None,
            skipped: Vec::new(),
            segments: Vec::new(),
            overlapping_segments: Vec::new(),
            warnings: Vec::new(),
        },
    })
}

impl Hdf5Volume {
    /// Layers read from the file since it was opened (each layer's chunks
    /// read and inflated once): once per pass when the pass reads the
    /// planes in order.
    pub fn layers_read(&self) -> u64 {
        self.inner.reader().read.load(Ordering::Relaxed)
    }

    /// Planes per layer: the chunk depth, or 1 for a contiguous dataset.
    pub fn layer_depth(&self) -> usize {
        self.inner.depth()
    }
}

impl LayerReader for Hdf5Layers {
    /// Reads planes `planes`: each x fastest, native byte order.
    fn read_layer(&self, planes: Range<usize>) -> Result<Vec<Vec<u8>>> {
        let [nx, ny, _] = self.dims;
        let (z0, depth) = (planes.start, planes.len());
        let mut starts = vec![0; self.rank];
        let other_axes = (0..self.end - 3).chain(self.end..self.rank);
        for (axis, &entry) in other_axes.zip(&self.others) {
            starts[axis] = entry as usize;
        }
        let mut counts = vec![1; self.rank];
        starts[self.end - 3] = z0;
        counts[self.end - 3..self.end].copy_from_slice(&[depth, ny, nx]);
        let len = depth * ny * nx;
        let fail = |e: rust_hdf5::Hdf5Error| {
            Error::Format(format!(
                "{}: planes {z0}..{} of the dataset: {e}",
                self.path.display(),
                z0 + depth
            ))
        };
        fn typed<T: rust_hdf5::types::H5Type + bytemuck::Pod>(
            d: &H5Dataset,
            len: usize,
            starts: &[usize],
            counts: &[usize],
            plane: usize,
        ) -> Result<std::result::Result<Vec<Vec<u8>>, rust_hdf5::Hdf5Error>> {
            let mut samples =
                crate::error::try_filled("a layer of HDF5 samples", len, T::zeroed())?;
            Ok(d.read_slice_into(&mut samples, starts, counts).map(|()| {
                samples
                    .chunks(plane.max(1))
                    .map(|p| bytemuck::cast_slice(p).to_vec())
                    .collect()
            }))
        }
        let d = &self.dataset;
        self.read.fetch_add(1, Ordering::Relaxed);
        let read = match self.scalar {
            ScalarType::U8 => typed::<u8>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::I8 => typed::<i8>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::U16 => typed::<u16>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::I16 => typed::<i16>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::U32 => typed::<u32>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::I32 => typed::<i32>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::F32 => typed::<f32>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::F64 => typed::<f64>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::I64 => typed::<i64>(d, len, &starts, &counts, ny * nx)?,
            ScalarType::U64 => typed::<u64>(d, len, &starts, &counts, ny * nx)?,
            // The half floats' bits, in the host's byte order.
            ScalarType::F16 => typed::<u16>(d, len, &starts, &counts, ny * nx)?,
        };
        read.map_err(fail)
    }
}

impl SampleSource for Hdf5Volume {
    super::forward_to_inner!(grid, read_plane, share_plane, sample_bytes, stored_type);

    fn data_files(&self) -> Vec<&Path> {
        vec![self.inner.reader().path.as_path()]
    }

    /// Layers of a chunk's depth (a plane when contiguous); a read holds
    /// the layer's samples, their planes, and the library's buffers of a
    /// chunk (stored and inflated, each at most a layer times the entries
    /// the chunk holds of the axes other than z, y, x: channels in a chunk
    /// are all inflated).
    fn plane_memory(&self) -> PlaneMemory {
        PlaneMemory::Decoded {
            sample_bytes: self.inner.sample_bytes(),
            layer: self.inner.depth(),
            decoding: 2 + 2 * self.other_chunk,
        }
    }

    fn notes(&self) -> SourceNotes {
        self.notes.clone()
    }
}
