//! Zarr v2 and v3 arrays, and OME-Zarr (NGFF 0.4 and 0.5) images, in a
//! directory store, read with the `zarrs` crate: any regular chunk shape,
//! the codecs zarr-python writes (blosc with each of its compressors, zstd,
//! gzip, bytes of either byte order, transpose, sharding, crc32c), and the
//! fill value for chunks that are not stored.
//!
//! The last three axes are z, y, x (C order, as numpy), but for axes after
//! them of one entry or picked by `--at` (a channel axis last); of each
//! other axis (OME's `t` and `c`) one entry is read: the only one, or the
//! one `--at` picks (`leading_axes.rs`). A group is read
//! through the array that `--array PATH` names, or through the level of
//! its OME-Zarr `multiscales` (`--level N`, 0 by default; a level opened
//! by its path, `image.zarr/1`, alike), whose `scale` and `translation`
//! become the spacing and origin, in millimetres when
//! the axes' unit is known (see `zarr_ome.rs`).
//!
//! Planes are served from decoded *chunk layers* (`chunk_layers.rs`): the
//! first plane asked for in a layer of chunks decodes all of that layer's
//! chunks, in parallel on scoped threads, and the layer is kept while its
//! planes are read, so each chunk is decompressed once per pass and memory
//! holds a few layers per worker (and, while a slab is triangulated, the
//! layers its planes lie in: they are lent, see `held.rs`).

use super::chunk_layers::ChunkLayers;
use super::zarr_ome::{self, OmeLevel};
use super::{ChunkNotes, SharedPlane, SourceNotes, ValueFrom};
use super::{Grid, PlaneMemory, SampleSource, ScalarType};
use crate::{Error, Result};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use zarrs::array::{data_type as dt, Array, ArrayBytes, ArrayMetadata, CodecOptions};
use zarrs::filesystem::FilesystemStore;

/// Which array of a Zarr store to read (`--array`, `--level`), or which
/// dataset of an HDF5 file (`--dataset`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ZarrSelect {
    /// The array's path inside the store (a group's member).
    pub array: Option<String>,
    /// The level of an OME-Zarr pyramid (0, the finest, by default).
    pub level: Option<usize>,
    /// The dataset's path in an HDF5 file (`--dataset`, or `FILE:PATH`).
    pub dataset: Option<String>,
    /// The series of a DICOM directory (`--series`): a
    /// `SeriesInstanceUID` or a `SeriesNumber`.
    pub series: Option<String>,
    /// The segment of a DICOM Segmentation object to read alone, as 0 to
    /// 1 (`--segment`), instead of the label map of all its segments.
    pub segment: Option<u32>,
    /// Zarr and HDF5: the entry to read of axes before z, y, x (`--at
    /// c=1`), as (axis name or position, entry); an axis of one entry
    /// needs none.
    pub at: Vec<(String, u64)>,
}

/// A Zarr array read plane by plane from its chunk layers.
pub struct ZarrVolume {
    root: PathBuf,
    array: Array<FilesystemStore>,
    grid: Grid,
    scalar: ScalarType,
    /// Chunk shape along z, y, x.
    chunk: [usize; 3],
    /// The entry read of each axis before z, y, x.
    lead: Vec<u64>,
    /// The chunk shape of those axes.
    lead_chunk: Vec<u64>,
    /// The entry read of each axis after z, y, x (of one entry, or picked
    /// by `--at`: a channel axis last).
    trail: Vec<u64>,
    /// The chunk shape of those axes.
    trail_chunk: Vec<u64>,
    /// Chunks along z, y, x.
    chunks: [usize; 3],
    layers: ChunkLayers,
    decoded: AtomicU64,
    notes: SourceNotes,
}

/// Whether `path` looks like a Zarr store or node: a directory holding
/// `zarr.json`, `.zarray`, `.zgroup` or `.zattrs`, or named `*.zarr`.
pub fn is_zarr(path: &Path) -> bool {
    let named = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("zarr"));
    named
        || (path.is_dir()
            && [".zarray", ".zgroup", ".zattrs", "zarr.json"]
                .iter()
                .any(|m| path.join(m).is_file()))
}

/// The attributes of the group (or array) at the store's root, v3 or v2.
fn root_attributes(root: &Path) -> Result<Option<Value>> {
    let read = |name: &str| -> Result<Option<Value>> {
        let file = root.join(name);
        if !file.is_file() {
            return Ok(None);
        }
        let text = std::fs::read(&file).map_err(|e| Error::io(&file, e))?;
        serde_json::from_slice(&text)
            .map(Some)
            .map_err(|e| Error::Format(format!("{}: not valid JSON: {e}", file.display())))
    };
    if let Some(meta) = read("zarr.json")? {
        return Ok(meta.get("attributes").cloned());
    }
    read(".zattrs")
}

/// The level of the OME-Zarr image whose dataset the array at `path` is
/// (`image.zarr/1`: the group `image.zarr` lists `1` in its
/// `multiscales`), looked for in the Zarr groups above it; `None` when no
/// group above it is an image listing it.
fn enclosing_level(path: &Path) -> Option<OmeLevel> {
    let full = path.canonicalize().ok()?;
    let mut names: Vec<String> = Vec::new();
    let mut node = full.as_path();
    while let (Some(parent), Some(name)) = (node.parent(), node.file_name()) {
        names.insert(0, name.to_string_lossy().into_owned());
        let is_node = [".zgroup", ".zattrs", "zarr.json"]
            .iter()
            .any(|m| parent.join(m).is_file());
        if !is_node {
            return None;
        }
        // A group above whose metadata does not parse places nothing:
        // the array itself still reads.
        let attributes = root_attributes(parent).ok().flatten();
        let attributes = attributes.unwrap_or(Value::Null);
        if zarr_ome::is_ome(&attributes) {
            let wanted = names.join("/");
            return (0..)
                .map_while(|i| zarr_ome::level(&attributes, i).ok())
                .find(|l| l.path.trim_matches('/') == wanted);
        }
        node = parent;
    }
    None
}

/// Whether `dir` holds a Zarr group (v2 `.zgroup`, or a v3 `zarr.json`
/// of node type `group`).
fn is_group(dir: &Path) -> bool {
    node_is(dir, ".zgroup", "group")
}

/// The images of a bioformats2raw store (its root's attributes say
/// `bioformats2raw.layout`): the series its `OME` group lists, else the
/// groups `0`, `1`, ... there are; none for any other group.
fn bioformats2raw_images(root: &Path, attributes: &Value) -> Vec<String> {
    let layout = |a: &Value| a.get("bioformats2raw.layout").is_some();
    if !layout(attributes) && !attributes.get("ome").is_some_and(layout) {
        return Vec::new();
    }
    let listed = root_attributes(&root.join("OME"))
        .ok()
        .flatten()
        .and_then(|a| {
            let series = a.get("series").or_else(|| a.get("ome")?.get("series"))?;
            let names = series.as_array()?.iter().filter_map(Value::as_str);
            Some(names.map(str::to_string).collect::<Vec<_>>())
        });
    listed.unwrap_or_else(|| {
        (0..)
            .map(|i: usize| i.to_string())
            .take_while(|n| is_group(&root.join(n)))
            .collect()
    })
}

/// Whether the store's root is itself an array.
fn root_is_array(root: &Path) -> bool {
    node_is(root, ".zarray", "array")
}

/// Whether `dir` holds a Zarr node of `kind`: v2's file `v2_file`, or a
/// v3 `zarr.json` of that `node_type`.
fn node_is(dir: &Path, v2_file: &str, kind: &str) -> bool {
    if dir.join(v2_file).is_file() {
        return true;
    }
    std::fs::read(dir.join("zarr.json"))
        .ok()
        .and_then(|t| serde_json::from_slice::<Value>(&t).ok())
        .is_some_and(|m| m.get("node_type").and_then(Value::as_str) == Some(kind))
}

/// The sample type of a Zarr data type, if tmc reads it.
fn scalar_of(array: &Array<FilesystemStore>) -> Option<ScalarType> {
    let t = array.data_type();
    Some(if t.is::<dt::UInt8DataType>() {
        ScalarType::U8
    } else if t.is::<dt::Int8DataType>() {
        ScalarType::I8
    } else if t.is::<dt::UInt16DataType>() {
        ScalarType::U16
    } else if t.is::<dt::Int16DataType>() {
        ScalarType::I16
    } else if t.is::<dt::UInt32DataType>() {
        ScalarType::U32
    } else if t.is::<dt::Int32DataType>() {
        ScalarType::I32
    } else if t.is::<dt::Float32DataType>() {
        ScalarType::F32
    } else if t.is::<dt::Float64DataType>() {
        ScalarType::F64
    } else if t.is::<dt::Int64DataType>() {
        ScalarType::I64
    } else if t.is::<dt::UInt64DataType>() {
        ScalarType::U64
    } else if t.is::<dt::Float16DataType>() {
        ScalarType::F16
    } else if t.is::<dt::BoolDataType>() {
        // One byte a sample, 0 or 1 (a mask): read as u8.
        ScalarType::U8
    } else {
        return None;
    })
}

/// Opens the Zarr array at `path` (a store, or a node inside one), chosen
/// by `select` when `path` is a group.
pub fn open(path: &Path, select: &ZarrSelect) -> Result<ZarrVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    if !path.is_dir() {
        return Err(fail("a Zarr store is a directory".into()));
    }
    let has_meta = [".zarray", ".zgroup", ".zattrs", "zarr.json"]
        .iter()
        .any(|m| path.join(m).is_file());
    if !has_meta {
        return Err(fail(
            "not a Zarr array or group: no zarr.json (v3) or .zarray/.zgroup (v2) in it".into(),
        ));
    }
    let attributes = root_attributes(path)?.unwrap_or(Value::Null);
    let ome = zarr_ome::is_ome(&attributes);
    let mut level: Option<OmeLevel> = None;
    let node = match (&select.array, root_is_array(path)) {
        // A group named by --array (an OME-Zarr label image,
        // `--array labels/cells`) is opened as if named by path.
        (Some(a), _) if is_group(&path.join(a.trim_matches('/'))) => {
            let inner = ZarrSelect {
                array: None,
                ..select.clone()
            };
            return open(&path.join(a.trim_matches('/')), &inner);
        }
        (Some(a), _) => {
            if select.level.is_some() {
                return Err(fail("give --array or --level, not both".into()));
            }
            // An array named by path that is a level of the image keeps
            // that level's grid.
            if ome {
                let name = a.trim_matches('/');
                level = (0..)
                    .map_while(|i| zarr_ome::level(&attributes, i).ok())
                    .find(|l| l.path.trim_matches('/') == name);
            }
            a.trim_matches('/').to_string()
        }
        (None, true) => {
            if select.level.is_some() {
                return Err(fail(
                    "--level picks a level of an OME-Zarr image; this is an array".into(),
                ));
            }
            // A level opened by its path (`image.zarr/1`) keeps its
            // grid, as `image.zarr --array 1` and `--level 1` do.
            level = enclosing_level(path);
            String::new()
        }
        (None, false) if ome => {
            let l = zarr_ome::level(&attributes, select.level.unwrap_or(0)).map_err(fail)?;
            let p = l.path.trim_matches('/').to_string();
            level = Some(l);
            p
        }
        (None, false) => {
            // An OME-Zarr `labels` group lists its label images, a
            // bioformats2raw store its images.
            let (what, names) = match zarr_ome::label_images(&attributes) {
                names if names.is_empty() => ("images", bioformats2raw_images(path, &attributes)),
                names => ("label images", names),
            };
            let hint = match names.is_empty() {
                true => String::new(),
                false => format!(
                    " (its {what}: {})",
                    names
                        .iter()
                        .map(|n| path.join(n).display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            };
            return Err(fail(format!(
                    "is a Zarr group, not an array: name the array with --array PATH or as STORE/PATH{hint}"
                )));
        }
    };
    let store = FilesystemStore::new(path)
        .map_err(|e| fail(format!("cannot open as a Zarr store: {e}")))?;
    let node_path = format!("/{node}");
    let array = Array::open(Arc::new(store), &node_path)
        .map_err(|e| fail(format!("cannot open the Zarr array at '{node_path}': {e}")))?;
    let scalar = scalar_of(&array).ok_or_else(|| {
        fail(format!(
            "Zarr data type {} is not supported (need bool, u8, i8, u16, i16, u32, i32, u64, i64, f16, f32 or f64)",
            array.data_type()
        ))
    })?;
    let shape = array.shape().to_vec();
    let rank = shape.len();
    if rank < 3 {
        return Err(fail(format!(
            "the array has {rank} axes; tmc reads 3-D volumes (z, y, x last)"
        )));
    }
    let names: Vec<String> = match &level {
        Some(l) if l.axes.len() == rank => l.axes.clone(),
        _ => (0..rank).map(|i| format!("{i}")).collect(),
    };
    let axes = super::leading_axes::volume_axes(&shape, &names, &select.at).map_err(fail)?;
    // z, y, x are axes end - 3, end - 2, end - 1.
    let end = axes.end;
    let to_usize = |v: u64| usize::try_from(v).map_err(|_| fail("array too large".into()));
    let [nz, ny, nx] = [
        to_usize(shape[end - 3])?,
        to_usize(shape[end - 2])?,
        to_usize(shape[end - 1])?,
    ];
    let first = array
        .chunk_shape(&vec![0; rank])
        .map_err(|e| fail(e.to_string()))?;
    let lead_chunk: Vec<u64> = first[..end - 3].iter().map(|c| c.get()).collect();
    let trail_chunk: Vec<u64> = first[end..].iter().map(|c| c.get()).collect();
    let chunk = [
        to_usize(first[end - 3].get())?,
        to_usize(first[end - 2].get())?,
        to_usize(first[end - 1].get())?,
    ];
    let grid_shape = array.chunk_grid_shape();
    let chunks = [
        to_usize(grid_shape[end - 3])?,
        to_usize(grid_shape[end - 2])?,
        to_usize(grid_shape[end - 1])?,
    ];
    if (0..3).any(|i| chunks[i] != [nz, ny, nx][i].div_ceil(chunk[i])) {
        return Err(fail("only regular chunk grids are read".into()));
    }
    let mut grid = Grid::unit([nx, ny, nz]);
    if [nx, ny, nz].contains(&0) {
        return Err(fail("the array is empty".into()));
    }
    let (spacing_from, origin_from) = match &level {
        Some(l) if l.scale.len() == rank => {
            grid.spacing = [0, 1, 2].map(|i| l.scale[end - 1 - i]);
            grid.origin = [0, 1, 2].map(|i| l.translation[end - 1 - i]);
            if grid.spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
                return Err(fail(format!(
                    "OME-Zarr scale {:?} must be finite and positive",
                    l.scale
                )));
            }
            let what = format!(
                "OME-Zarr multiscales, level '{}' of {}, {}",
                l.path, l.levels, l.units
            );
            (
                ValueFrom::File { what: what.clone() },
                ValueFrom::File { what },
            )
        }
        _ => (ValueFrom::Default, ValueFrom::Default),
    };
    let notes = SourceNotes {
        spacing_from,
        origin_from,
        chunks: Some(chunk_notes(path, &node, array.metadata(), chunk, chunks)),
        units: None,
        skipped: Vec::new(),
        segments: Vec::new(),
        overlapping_segments: Vec::new(),
        warnings: Vec::new(),
    };
    Ok(ZarrVolume {
        root: path.to_path_buf(),
        array,
        grid,
        scalar,
        chunk,
        lead: axes.lead,
        lead_chunk,
        trail: axes.trail,
        trail_chunk,
        chunks,
        layers: ChunkLayers::new(),
        decoded: AtomicU64::new(0),
        notes,
    })
}

/// What `tmc info` says of the chunks: shape (x, y, z), codecs, and the
/// bytes and count of the stored chunk files.
fn chunk_notes(
    root: &Path,
    node: &str,
    meta: &ArrayMetadata,
    chunk: [usize; 3],
    chunks: [usize; 3],
) -> ChunkNotes {
    let json = serde_json::to_value(meta).unwrap_or(Value::Null);
    let name = |c: &Value| -> String {
        let n = c
            .get("name")
            .or_else(|| c.get("id"))
            .and_then(Value::as_str)
            .or_else(|| c.as_str());
        let conf = c.get("configuration").unwrap_or(c);
        let detail: Vec<String> = ["cname", "clevel", "shuffle", "endian", "level", "order"]
            .iter()
            .filter_map(|k| conf.get(*k).map(|v| format!("{k}={v}")))
            .collect();
        format!("{}({})", n.unwrap_or("?"), detail.join(", "))
    };
    let mut shape = [chunk[2], chunk[1], chunk[0]];
    let codec = if let Some(list) = json.get("codecs").and_then(Value::as_array) {
        let mut parts: Vec<String> = Vec::new();
        for c in list {
            if c.get("name").and_then(Value::as_str) == Some("sharding_indexed") {
                let conf = &c["configuration"];
                if let Some(inner) = conf.get("chunk_shape").and_then(Value::as_array) {
                    let v: Vec<usize> = inner
                        .iter()
                        .filter_map(|x| x.as_u64())
                        .map(|x| x as usize)
                        .collect();
                    if v.len() >= 3 {
                        let n = v.len();
                        shape = [v[n - 1], v[n - 2], v[n - 3]];
                    }
                }
                let inner: Vec<String> = conf
                    .get("codecs")
                    .and_then(Value::as_array)
                    .map(|l| l.iter().map(name).collect())
                    .unwrap_or_default();
                parts.push(format!(
                    "sharding (shards of {} x {} x {}; inner: {})",
                    chunk[2],
                    chunk[1],
                    chunk[0],
                    inner.join(" > ")
                ));
            } else {
                parts.push(name(c));
            }
        }
        format!("Zarr v3: {}", parts.join(" > "))
    } else {
        let filters: Vec<String> = json
            .get("filters")
            .and_then(Value::as_array)
            .map(|l| l.iter().map(name).collect())
            .unwrap_or_default();
        let compressor = json
            .get("compressor")
            .filter(|c| !c.is_null())
            .map_or("no compressor".to_string(), name);
        let dtype = json.get("dtype").map_or(String::new(), |d| d.to_string());
        let mut parts = filters;
        parts.push(compressor);
        format!("Zarr v2 {dtype}: {}", parts.join(" > "))
    };
    let dir = root.join(node);
    let (bytes, files) = stored(&dir);
    ChunkNotes {
        chunk_shape: shape,
        codec,
        stored_bytes: Some(bytes),
        chunks: chunks.iter().map(|&c| c as u64).product(),
        chunks_stored: Some(files),
    }
}

/// Bytes and number of the chunk files under `dir` (metadata files apart).
fn stored(dir: &Path) -> (u64, u64) {
    let mut total = (0, 0);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return total;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let name = name.to_string_lossy();
        let Ok(meta) = e.metadata() else { continue };
        if meta.is_dir() {
            let (b, f) = stored(&e.path());
            total = (total.0 + b, total.1 + f);
        } else if !matches!(
            name.as_ref(),
            "zarr.json" | ".zarray" | ".zattrs" | ".zgroup"
        ) {
            total = (total.0 + meta.len(), total.1 + 1);
        }
    }
    total
}

impl ZarrVolume {
    /// Chunks decoded (read from disk and decompressed, or filled for a
    /// missing chunk) since the array was opened: each once per pass when
    /// the pass reads the planes in order.
    pub fn chunks_decoded(&self) -> u64 {
        self.decoded.load(Ordering::Relaxed)
    }

    /// Decodes chunk layer `k`: its planes, each x fastest, native byte
    /// order.
    fn decode_layer(&self, k: usize) -> Result<Vec<Vec<u8>>> {
        let [nx, ny, nz] = self.grid.dims;
        let [cz, cy, cx] = self.chunk;
        let z0 = k * cz;
        let depth = cz.min(nz - z0);
        let size = self.scalar.size();
        let layer = (0..depth)
            .map(|_| crate::error::try_filled("a layer of Zarr chunks", ny * nx * size, 0u8))
            .collect::<Result<Vec<Vec<u8>>>>()?;
        let layer = Mutex::new(layer);
        let jobs: Vec<(usize, usize)> = (0..self.chunks[1])
            .flat_map(|y| (0..self.chunks[2]).map(move |x| (y, x)))
            .collect();
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(jobs.len())
            .max(1);
        let options = CodecOptions::default().with_concurrent_target(1);
        // The chunks along the axes before z, y, x that hold the picked
        // entries, and where the picked (z, y, x) block starts in each
        // (chunks are C order over all axes, so the block is contiguous
        // but for the axes after x: a sample every `stride`, from
        // `trail_offset`).
        let (lead_index, block_start, _) = within_chunks(&self.lead, &self.lead_chunk);
        let (trail_index, trail_offset, stride) = within_chunks(&self.trail, &self.trail_chunk);
        let block = cz * cy * cx * stride * size;
        let block_start = block_start * block;
        let work = |t: usize| -> Result<()> {
            for &(gy, gx) in jobs.iter().skip(t).step_by(threads) {
                let mut index = lead_index.clone();
                index.extend([k as u64, gy as u64, gx as u64]);
                index.extend_from_slice(&trail_index);
                let bytes: ArrayBytes<'static> = self
                    .array
                    .retrieve_chunk_opt(&index, &options)
                    .map_err(|e| {
                        Error::Format(format!(
                            "{}: chunk {index:?} of the Zarr array: {e}",
                            self.root.display()
                        ))
                    })?;
                self.decoded.fetch_add(1, Ordering::Relaxed);
                let bytes = bytes.into_fixed().map_err(|e| {
                    Error::Format(format!("{}: chunk {index:?}: {e}", self.root.display()))
                })?;
                let (y0, x0) = (gy * cy, gx * cx);
                let run = cx.min(nx - x0) * size;
                let rows = cy.min(ny - y0);
                let need = block_start + block;
                if bytes.len() < need {
                    return Err(Error::Format(format!(
                        "{}: chunk {index:?} decodes to {} bytes, need {need}",
                        self.root.display(),
                        bytes.len()
                    )));
                }
                let mut out = layer.lock().unwrap_or_else(|p| p.into_inner());
                for (dz, plane) in out.iter_mut().enumerate() {
                    for r in 0..rows {
                        let from =
                            block_start + (((dz * cy + r) * cx) * stride + trail_offset) * size;
                        let to = ((y0 + r) * nx + x0) * size;
                        let row = &mut plane[to..to + run];
                        if stride == 1 {
                            row.copy_from_slice(&bytes[from..from + run]);
                        } else {
                            let samples = bytes[from..].chunks(stride * size);
                            for (out, sample) in row.chunks_exact_mut(size).zip(samples) {
                                out.copy_from_slice(&sample[..size]);
                            }
                        }
                    }
                }
            }
            Ok(())
        };
        if threads == 1 {
            work(0)?;
        } else {
            std::thread::scope(|s| {
                let handles: Vec<_> = (0..threads).map(|t| s.spawn(move || work(t))).collect();
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                    .collect::<Result<Vec<()>>>()
            })?;
        }
        Ok(layer.into_inner().unwrap_or_else(|p| p.into_inner()))
    }
}

/// Where the `entries` of some axes whose chunks are `chunk` entries long
/// lie: the chunk index along each axis, the entries' flat offset inside
/// their chunk (C order over those axes) and the number of flat places
/// (the product of `chunk`).
fn within_chunks(entries: &[u64], chunk: &[u64]) -> (Vec<u64>, usize, usize) {
    let (mut index, mut offset, mut places) = (Vec::with_capacity(entries.len()), 0, 1);
    for (&entry, &along) in entries.iter().zip(chunk) {
        index.push(entry / along);
        offset = offset * along as usize + (entry % along) as usize;
        places *= along as usize;
    }
    (index, offset, places)
}

impl SampleSource for ZarrVolume {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let (grid, scalar) = (&self.grid, self.scalar);
        self.layers.read(grid, scalar, self.chunk[0], z, out, |k| {
            self.decode_layer(k)
        })
    }

    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        let (grid, scalar) = (&self.grid, self.scalar);
        self.layers
            .shared(grid, scalar, self.chunk[0], z, |k| self.decode_layer(k))
            .ok()
    }

    fn data_files(&self) -> Vec<&Path> {
        vec![self.root.as_path()]
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.scalar)
    }

    /// Layers of a chunk's depth; a decode holds the new layer and, on each
    /// of its threads, a chunk decoded and its stored bytes (a layer's
    /// worth at most in all when the layer has as many chunks as threads,
    /// two layers' when a chunk spans the plane), times the entries a
    /// chunk holds of the other axes (channels in a chunk are all decoded).
    fn plane_memory(&self) -> PlaneMemory {
        let chunks = (self.chunks[1] * self.chunks[2]).max(1);
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let others: u64 = self.lead_chunk.iter().chain(&self.trail_chunk).product();
        let others = usize::try_from(others).unwrap_or(usize::MAX);
        PlaneMemory::Decoded {
            sample_bytes: self.scalar.size(),
            layer: self.chunk[0],
            decoding: 1
                + (2 * threads.min(chunks))
                    .saturating_mul(others)
                    .div_ceil(chunks),
        }
    }

    fn notes(&self) -> SourceNotes {
        self.notes.clone()
    }
}
