//! `.tmesh`: the chunked, compressed mesh file that streams out of the
//! pipeline and into `tmc convert` / `tmc check`.
//!
//! All numbers are little-endian. CRC-32 is the IEEE polynomial (zlib's
//! `crc32`). A file is:
//!
//! ```text
//! header   128 bytes
//!   0   8  magic  89 54 4D 45 53 48 0D 0A  ("\x89TMESH\r\n")
//!   8   4  version u32: 3 (this build writes; 1 and 2 are read, below)
//!  12   4  header size u32 = 128
//!  16  24  dims u64 x 3 (samples along x, y, z of the input grid)
//!  40  24  spacing f64 x 3
//!  64  24  origin f64 x 3
//!  88   8  isovalue f64
//!  96   1  method (0 tmc, 1 mc)
//!  97   1  inside (0 high, 1 low)
//!  98   1  close (0 or 1)
//!  99   1  attributes (zero in version 1): bit 0 normals,
//!          bit 1 labels, the other bits zero
//! 100  24  zero
//! 124   4  CRC-32 of bytes 0..124
//! chunk    (one per grid plane that owns vertices or triangles, in plane order)
//!   0   4  tag "CHNK"
//!   4   4  CRC-32 of the payload
//!   8   8  plane (z index) u64
//!  16   8  vertex base u64: global index of the chunk's first vertex
//!  24   4  vertex count u32
//!  28   4  triangle count u32
//!  32   8  payload size u64 (bytes, compressed)
//!  40   4  CRC-32 of bytes 0..40
//!  44   4  zero
//!  48   .. payload: one zstd frame holding vertex count x 3 f32 (x, y, z)
//!            then triangle count x 3 u32: vertex indices relative to the
//!            vertex base; they may point into the next chunk, never beyond;
//!            then, with the normals attribute, vertex count x 3 f32
//!            (nx, ny, nz): unit outward vertex normals, or 0 0 0;
//!            then, with the labels attribute, triangle count x u32: the
//!            label of each triangle (`tmc extract --labels` into one file);
//!            in version 3 the positions, indices and labels packed
//!            (`packing.rs`), the normals as they are: the positions as
//!            the first vertex's f32 bits, then each component XOR the
//!            same component of the vertex before; the indices (as one
//!            array of 3 x triangle count) and the labels as zig-zag coded
//!            wrapping differences from the number before (the first from
//!            0); each of those arrays then as four byte planes, the
//!            lowest byte of every number first
//! index
//!   0   4  tag "INDX"
//!   4   4  CRC-32 of the entries
//!   8   8  chunk count u64
//!  16  ..  per chunk 32 bytes: file offset u64, vertex base u64,
//!          vertex count u32, triangle count u32, plane u64
//! trailer  32 bytes, the last of the file
//!   0   8  index offset u64
//!   8   8  total vertices u64
//!  16   8  total triangles u64
//!  24   8  "TMESHEND"
//! ```
//!
//! A reader refuses a header size other than 128, zero dimensions, a
//! spacing that is not finite and positive, an origin that is not finite,
//! a non-finite isovalue, option bytes
//! other than 0 and 1, nonzero reserved bytes, chunks not in increasing
//! plane order or with a plane beyond the grid (`dims[2] + 2` planes with
//! close), chunks claiming more vertices or triangles than one plane of the
//! grid can have (11 and 32 per sample of a plane, 8 times that with the
//! labels attribute: at most 8 labels meet in a cell), and non-finite vertex
//! coordinates or normals. Versions 1 and 2, which earlier builds wrote,
//! are version 3 with the arrays stored as they are (not packed):
//! version 1 has no attributes, version 2 the attribute byte. This build
//! reads all three and writes version 3, whose packed arrays compress to
//! 0.66 to 0.87 of the bytes with about half of zstd's work (cthead: zstd
//! 372 M instructions before, 189 M after). The labels
//! bit came after the normals bit without a new version: a build that
//! knows only the normals refuses a labelled file by its unknown
//! attribute bit.
//!
//! Global vertex indices are 64-bit, so a file holds more than 2^32
//! vertices; the index lets a reader seek to any chunk; the checksums let a
//! reader name the damaged chunk. `scripts/read_tmesh.py` reads the format
//! with numpy and zstandard only.

mod packing;
mod payload;
mod reader;
mod writer;

pub use payload::encode_payload;
pub use reader::TmeshReader;
pub use writer::TmeshWriter;

use crate::mesh::MeshInfo;
use crate::params::{Inside, Method};
use crate::{Error, Grid, Result};

/// The first 8 bytes of every `.tmesh` file.
pub const MAGIC: [u8; 8] = *b"\x89TMESH\r\n";
/// The format version of files without attributes and unpacked arrays,
/// which every build reads.
pub const VERSION: u32 = 1;
/// The format version of files with attributes (the normals) and unpacked
/// arrays, which this build also reads.
pub const VERSION_ATTRIBUTES: u32 = 2;
/// The format version this build writes: version 2's layout with the
/// positions, indices and labels packed (`packing.rs`), the normals as
/// they are.
pub const VERSION_PACKED: u32 = 3;
/// Bit of header byte 99 saying the chunks carry vertex normals.
pub const ATTRIBUTE_NORMALS: u8 = 1;
/// Bit of header byte 99 saying the chunks carry a label per triangle.
pub const ATTRIBUTE_LABELS: u8 = 2;
/// Bytes in the file header.
pub const HEADER_BYTES: usize = 128;
/// Bytes in a chunk header.
pub const CHUNK_HEADER_BYTES: usize = 48;
/// Bytes per index entry.
pub const INDEX_ENTRY_BYTES: usize = 32;
/// Bytes in the trailer.
pub const TRAILER_BYTES: usize = 32;
/// The last 8 bytes of a complete file.
pub const END_MAGIC: [u8; 8] = *b"TMESHEND";
/// zstd level of the payloads: packed meshes compress about 3:1 at level
/// 1; level -3 spent 3% fewer instructions on cthead for 8% more bytes,
/// level -1 more of both. Small chunks keep their literals as they are
/// (`payload.rs`).
pub const ZSTD_LEVEL: i32 = 1;

/// One entry of the index: where a chunk is and what it holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChunkEntry {
    /// File offset of the chunk header.
    pub offset: u64,
    /// Global index of the chunk's first vertex.
    pub vertex_base: u64,
    /// Vertices in the chunk.
    pub vertex_count: u32,
    /// Triangles in the chunk.
    pub triangle_count: u32,
    /// Grid plane of the chunk.
    pub plane: u64,
}

fn le_u32(b: &[u8]) -> u32 {
    u32::from_le_bytes(b[..4].try_into().expect("4 bytes"))
}

fn le_u64(b: &[u8]) -> u64 {
    u64::from_le_bytes(b[..8].try_into().expect("8 bytes"))
}

fn le_f64(b: &[u8]) -> f64 {
    f64::from_le_bytes(b[..8].try_into().expect("8 bytes"))
}

/// Encodes the file header.
fn encode_header(info: &MeshInfo) -> [u8; HEADER_BYTES] {
    let mut h = [0u8; HEADER_BYTES];
    h[0..8].copy_from_slice(&MAGIC);
    h[8..12].copy_from_slice(&VERSION_PACKED.to_le_bytes());
    h[12..16].copy_from_slice(&(HEADER_BYTES as u32).to_le_bytes());
    for i in 0..3 {
        h[16 + 8 * i..24 + 8 * i].copy_from_slice(&(info.grid.dims[i] as u64).to_le_bytes());
        h[40 + 8 * i..48 + 8 * i].copy_from_slice(&info.grid.spacing[i].to_le_bytes());
        h[64 + 8 * i..72 + 8 * i].copy_from_slice(&info.grid.origin[i].to_le_bytes());
    }
    h[88..96].copy_from_slice(&info.iso.to_le_bytes());
    h[96] = u8::from(info.method == Method::Mc);
    h[97] = u8::from(info.inside == Inside::Low);
    h[98] = u8::from(info.close);
    h[99] = if info.normals { ATTRIBUTE_NORMALS } else { 0 }
        | if info.labels { ATTRIBUTE_LABELS } else { 0 };
    let crc = crc32fast::hash(&h[..124]);
    h[124..128].copy_from_slice(&crc.to_le_bytes());
    h
}

/// Decodes and checks the file header: what the mesh is, and whether its
/// payload arrays are packed (version 3).
fn decode_header(h: &[u8]) -> Result<(MeshInfo, bool)> {
    let bad = |what: &str| Error::Format(format!("not a valid .tmesh file: {what}"));
    if h.len() < HEADER_BYTES || h[0..8] != MAGIC {
        return Err(bad("wrong magic bytes"));
    }
    let version = le_u32(&h[8..]);
    if !(VERSION..=VERSION_PACKED).contains(&version) {
        return Err(Error::Format(format!(
            ".tmesh version {version} is not supported (this build reads versions {VERSION} to {VERSION_PACKED})"
        )));
    }
    if le_u32(&h[124..]) != crc32fast::hash(&h[..124]) {
        return Err(bad("header checksum mismatch"));
    }
    let size = le_u32(&h[12..]);
    if size != HEADER_BYTES as u32 {
        return Err(bad(&format!("header size {size} is not {HEADER_BYTES}")));
    }
    let dim = |i: usize| usize::try_from(le_u64(&h[16 + 8 * i..])).unwrap_or(usize::MAX);
    if (0..3).any(|i| dim(i) == 0) {
        return Err(bad("a grid dimension is 0"));
    }
    let iso = le_f64(&h[88..]);
    if !iso.is_finite() {
        return Err(bad(&format!("the isovalue {iso} is not a finite number")));
    }
    if let Some(at) = (96..99).find(|&i| h[i] > 1) {
        let field = ["method", "inside", "close"][at - 96];
        return Err(bad(&format!("unknown {field} byte {}", h[at])));
    }
    let attributes = h[99];
    if version == VERSION && h[99..124].iter().any(|&b| b != 0) {
        return Err(bad("reserved header bytes 99..124 are not zero"));
    }
    if attributes & !(ATTRIBUTE_NORMALS | ATTRIBUTE_LABELS) != 0 {
        return Err(bad(&format!("unknown attribute bits {attributes:#04x}")));
    }
    if h[100..124].iter().any(|&b| b != 0) {
        return Err(bad("reserved header bytes 100..124 are not zero"));
    }
    // Every volume reader refuses a spacing that is not finite and
    // positive and an origin that is not finite, so no writer makes one;
    // a reader that took them would frame, scale and merge by NaN.
    let spacing = [0, 1, 2].map(|i| le_f64(&h[40 + 8 * i..]));
    if !spacing.iter().all(|s| s.is_finite() && *s > 0.0) {
        let [x, y, z] = spacing;
        return Err(bad(&format!(
            "the spacing {x} {y} {z} is not finite and positive"
        )));
    }
    let origin = [0, 1, 2].map(|i| le_f64(&h[64 + 8 * i..]));
    if !origin.iter().all(|o| o.is_finite()) {
        let [x, y, z] = origin;
        return Err(bad(&format!("the origin {x} {y} {z} is not finite")));
    }
    let info = MeshInfo {
        grid: Grid {
            dims: [dim(0), dim(1), dim(2)],
            spacing,
            origin,
            direction: crate::grid::IDENTITY,
        },
        iso,
        method: if h[96] == 1 { Method::Mc } else { Method::Tmc },
        inside: if h[97] == 1 {
            Inside::Low
        } else {
            Inside::High
        },
        close: h[98] == 1,
        normals: attributes & ATTRIBUTE_NORMALS != 0,
        labels: attributes & ATTRIBUTE_LABELS != 0,
    };
    Ok((info, version == VERSION_PACKED))
}
