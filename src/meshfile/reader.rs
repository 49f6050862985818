//! Reads `.tmesh` files: header, index and trailer first, then any chunk on
//! demand, every checksum verified.

use super::packing::{unpack_numbers, unpack_triples};
use super::{
    decode_header, le_u32, le_u64, ChunkEntry, CHUNK_HEADER_BYTES, END_MAGIC, HEADER_BYTES,
    INDEX_ENTRY_BYTES, TRAILER_BYTES,
};
use crate::mesh::{Chunk, MeshInfo};
use crate::{Error, Result};
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// An open `.tmesh` file.
pub struct TmeshReader {
    file: File,
    path: PathBuf,
    info: MeshInfo,
    /// The payload arrays are packed (version 3, `packing.rs`).
    packed: bool,
    entries: Vec<ChunkEntry>,
    /// Where the index starts: the end of the last chunk's room.
    index_offset: u64,
    vertices: u64,
    triangles: u64,
    /// One decompression context for every chunk.
    decompressor: zstd::bulk::Decompressor<'static>,
}

/// The most vertices and triangles one chunk (a grid plane) can hold: the
/// plane's x- and y-edges and the z-edges to the next plane, with 8
/// interior vertices and 32 triangles for each cell of the layer above.
/// That is above what the kernel makes: a cell's contours share its 12
/// edge vertices, a contour of n vertices takes at most n + 3 triangles
/// (a strip) and one interior vertex, and a tunnel or a 12-vertex contour
/// three more vertices and one more triangle. A file that claims more is
/// damaged or crafted, and is refused before its chunks are inflated.
/// A labelled file holds the surfaces of several labels: each is bounded
/// so, and at most 8 labels have a corner in a cell.
fn plane_bounds(info: &MeshInfo) -> (u64, u64) {
    let pad = if info.close { 2 } else { 0 };
    let [nx, ny, _] = info.grid.dims.map(|d| d as u64 + pad);
    let labels = if info.labels { 8 } else { 1 };
    let samples = nx.saturating_mul(ny).saturating_mul(labels);
    (samples.saturating_mul(3 + 8), samples.saturating_mul(32))
}

impl TmeshReader {
    /// Opens `path` and reads its header, trailer and index.
    pub fn open(path: &Path) -> Result<TmeshReader> {
        let io = |e| Error::io(path, e);
        let bad = |what: String| Error::Format(format!("{}: {what}", path.display()));
        // A FIFO would block the open below, and cannot seek.
        crate::files::check_input_kind(path)?;
        let mut file = File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut header = [0u8; HEADER_BYTES];
        if len < (HEADER_BYTES + TRAILER_BYTES) as u64 {
            return Err(bad(format!("{len} bytes is too short for a .tmesh file")));
        }
        file.read_exact(&mut header).map_err(io)?;
        let (info, packed) = decode_header(&header).map_err(|e| bad(e.to_string()))?;
        let mut trailer = [0u8; TRAILER_BYTES];
        file.seek(SeekFrom::End(-(TRAILER_BYTES as i64)))
            .map_err(io)?;
        file.read_exact(&mut trailer).map_err(io)?;
        if trailer[24..32] != END_MAGIC {
            return Err(bad(
                "truncated: the end marker is missing (the writer did not finish)".into(),
            ));
        }
        let index_offset = le_u64(&trailer);
        let (vertices, triangles) = (le_u64(&trailer[8..]), le_u64(&trailer[16..]));
        if index_offset < HEADER_BYTES as u64 || index_offset + 16 > len - TRAILER_BYTES as u64 {
            return Err(bad(format!(
                "index offset {index_offset} is outside the file"
            )));
        }
        file.seek(SeekFrom::Start(index_offset)).map_err(io)?;
        let mut head = [0u8; 16];
        file.read_exact(&mut head).map_err(io)?;
        let count = le_u64(&head[8..]);
        let room = len - TRAILER_BYTES as u64 - index_offset - 16;
        if &head[0..4] != b"INDX" || count.checked_mul(INDEX_ENTRY_BYTES as u64) != Some(room) {
            return Err(bad("the chunk index is damaged".into()));
        }
        let mut raw = crate::error::try_vec::<u8>("the .tmesh chunk index", room as usize)?;
        raw.resize(room as usize, 0);
        file.read_exact(&mut raw).map_err(io)?;
        if crc32fast::hash(&raw) != le_u32(&head[4..]) {
            return Err(bad("the chunk index checksum does not match".into()));
        }
        let entries: Vec<ChunkEntry> = raw
            .chunks_exact(INDEX_ENTRY_BYTES)
            .map(|e| ChunkEntry {
                offset: le_u64(e),
                vertex_base: le_u64(&e[8..]),
                vertex_count: le_u32(&e[16..]),
                triangle_count: le_u32(&e[20..]),
                plane: le_u64(&e[24..]),
            })
            .collect();
        // The index must add up to the totals and tile the vertex numbers.
        let mut next_base = 0u64;
        let mut sum_t = 0u64;
        // Planes increase and lie in the grid (padded by 2 with close).
        let planes = info.grid.dims[2] as u64 + if info.close { 2 } else { 0 };
        let (most_vertices, most_triangles) = plane_bounds(&info);
        for (i, e) in entries.iter().enumerate() {
            if u64::from(e.vertex_count) > most_vertices
                || u64::from(e.triangle_count) > most_triangles
            {
                return Err(bad(format!(
                    "chunk {i} claims {} vertices and {} triangles, more than one plane of the grid can have ({most_vertices} and {most_triangles})",
                    e.vertex_count, e.triangle_count
                )));
            }
            if e.vertex_base != next_base || e.offset >= index_offset {
                return Err(bad(format!("index entry {i} is inconsistent")));
            }
            if e.plane >= planes {
                return Err(bad(format!(
                    "chunk {i} is on plane {}, beyond the grid's {planes} planes",
                    e.plane
                )));
            }
            if i > 0 && e.plane <= entries[i - 1].plane {
                return Err(bad(format!(
                    "chunk {i} is on plane {}, not after the previous chunk's plane {}",
                    e.plane,
                    entries[i - 1].plane
                )));
            }
            next_base += e.vertex_count as u64;
            sum_t += e.triangle_count as u64;
        }
        if next_base != vertices || sum_t != triangles {
            return Err(bad("the index does not add up to the totals".into()));
        }
        let decompressor = zstd::bulk::Decompressor::new()
            .map_err(|e| Error::Invalid(format!("zstd decompression failed: {e}")))?;
        Ok(TmeshReader {
            decompressor,
            file,
            path: path.to_path_buf(),
            info,
            packed,
            entries,
            index_offset,
            vertices,
            triangles,
        })
    }

    /// The extraction the file records.
    pub fn info(&self) -> &MeshInfo {
        &self.info
    }

    /// Total vertices.
    pub fn vertices(&self) -> u64 {
        self.vertices
    }

    /// Total triangles.
    pub fn triangles(&self) -> u64 {
        self.triangles
    }

    /// The chunk index.
    pub fn entries(&self) -> &[ChunkEntry] {
        &self.entries
    }

    /// Reads chunk `i`, checking both checksums and every index.
    pub fn chunk(&mut self, i: usize) -> Result<Chunk> {
        let next = self.entries.get(i + 1).map_or(0, |n| n.vertex_count);
        self.chunk_then(i, next)
    }

    /// Reads chunk `i`, whose triangles may point into the first `next`
    /// vertices after it (those of another file for a part's last chunk).
    pub fn chunk_then(&mut self, i: usize, next: u32) -> Result<Chunk> {
        let e = self.entries[i];
        let name = format!(
            "{}: chunk {i} (plane {}, byte {})",
            self.path.display(),
            e.plane,
            e.offset
        );
        let bad = |what: &str| Error::Format(format!("{name}: {what}"));
        let io = |err: std::io::Error| Error::Format(format!("{name}: {err}"));
        self.file.seek(SeekFrom::Start(e.offset)).map_err(io)?;
        let mut h = [0u8; CHUNK_HEADER_BYTES];
        self.file.read_exact(&mut h).map_err(io)?;
        if &h[0..4] != b"CHNK" || le_u32(&h[40..]) != crc32fast::hash(&h[..40]) {
            return Err(bad("chunk header damaged"));
        }
        if le_u32(&h[44..]) != 0 {
            return Err(bad("chunk header bytes 44..48 are not zero"));
        }
        if le_u64(&h[8..]) != e.plane
            || le_u64(&h[16..]) != e.vertex_base
            || le_u32(&h[24..]) != e.vertex_count
            || le_u32(&h[28..]) != e.triangle_count
        {
            return Err(bad("chunk header disagrees with the index"));
        }
        let size = le_u64(&h[32..]);
        // A chunk ends before the next one starts, the last one before the
        // index (offsets are below the index offset, so the sum only
        // overflows for a damaged size).
        let limit = self
            .entries
            .get(i + 1)
            .map_or(self.index_offset, |n| n.offset);
        let end = (CHUNK_HEADER_BYTES as u64)
            .checked_add(e.offset)
            .and_then(|start| start.checked_add(size));
        if !matches!(end, Some(end) if end <= limit) {
            return Err(bad(&format!(
                "payload of {size} bytes runs past the chunk's room (byte {limit})"
            )));
        }
        let size = usize::try_from(size).map_err(|_| bad("payload size is too large"))?;
        let mut payload = crate::error::try_vec::<u8>("a .tmesh chunk", size)?;
        payload.resize(size, 0);
        self.file.read_exact(&mut payload).map_err(io)?;
        if crc32fast::hash(&payload) != le_u32(&h[4..]) {
            return Err(bad("payload checksum mismatch (the data is damaged)"));
        }
        let (nv, nt) = (e.vertex_count as usize, e.triangle_count as usize);
        let nn = if self.info.normals { nv } else { 0 };
        let nl = if self.info.labels { nt } else { 0 };
        let expect = nv * 12 + nt * 12 + nn * 12 + nl * 4;
        // The frame must say it holds exactly that many bytes before room
        // for them is reserved (the counts come from the file).
        match zstd::zstd_safe::get_frame_content_size(&payload) {
            Ok(Some(n)) if n == expect as u64 => {}
            _ => return Err(bad("payload frame size disagrees with the counts")),
        }
        let mut raw = crate::error::try_vec::<u8>("a .tmesh chunk's payload", expect)?;
        self.decompressor
            .decompress_to_buffer(&payload, &mut raw)
            .map_err(|err| bad(&err.to_string()))?;
        if raw.len() != expect {
            return Err(bad("payload has the wrong size"));
        }
        let at_normals = nv * 12 + nt * 12;
        let at_labels = at_normals + nn * 12;
        let (vertices, indices, normals, labels) = if self.packed {
            (
                unpack_triples(&raw[..nv * 12]),
                unpack_numbers(&raw[nv * 12..at_normals]),
                triples(&raw[at_normals..at_labels]),
                unpack_numbers(&raw[at_labels..]),
            )
        } else {
            let numbers = |b: &[u8]| b.chunks_exact(4).map(le_u32).collect::<Vec<u32>>();
            (
                triples(&raw[..nv * 12]),
                numbers(&raw[nv * 12..at_normals]),
                triples(&raw[at_normals..at_labels]),
                numbers(&raw[at_labels..]),
            )
        };
        if let Some(k) = first_not_finite(&vertices) {
            return Err(bad(&format!(
                "vertex {k} has a coordinate that is not a finite number"
            )));
        }
        if let Some(k) = first_not_finite(&normals) {
            return Err(bad(&format!(
                "the normal of vertex {k} has a component that is not a finite number"
            )));
        }
        let bound = e.vertex_count as u64 + next as u64;
        if indices.iter().any(|&k| k as u64 >= bound) {
            return Err(bad("a triangle points beyond the next chunk"));
        }
        let triangles = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        Ok(Chunk {
            plane: e.plane,
            vertices,
            triangles,
            normals,
            labels,
            values: Vec::new(),
            encoded: Vec::new(),
        })
    }
}

/// The little-endian `f32` triples of `raw` (an array stored as it is).
fn triples(raw: &[u8]) -> Vec<[f32; 3]> {
    let f = |b: &[u8]| f32::from_le_bytes(b[..4].try_into().expect("4 bytes"));
    raw.chunks_exact(12)
        .map(|v| [f(v), f(&v[4..]), f(&v[8..])])
        .collect()
}

/// The number of the first triple with a component that is not finite.
fn first_not_finite(triples: &[[f32; 3]]) -> Option<usize> {
    triples
        .iter()
        .position(|v| v.iter().any(|c| !c.is_finite()))
}
