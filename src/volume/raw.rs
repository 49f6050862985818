//! Samples of one scalar type stored contiguously in a file after a header,
//! memory-mapped and decoded one plane at a time.
//!
//! [`RawVolume::open`] reads headerless files described by [`RawOptions`];
//! the `.npy` and `.nrrd` readers parse their headers and then build the same
//! [`RawVolume`] over the data that follows.

use super::mapped::MappedFile;
use super::scalar::{decode_samples, decode_strided};
use super::{Access, Endian, Grid, LentPlane, PlaneMemory, SampleSource, ScalarType};
use crate::{Error, Result};
use std::fmt;
use std::fs::File;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Options for raw input, which carries no header of its own.
#[derive(Debug, Clone)]
pub struct RawOptions {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// Sample type.
    pub scalar: ScalarType,
    /// Byte order of multi-byte samples.
    pub endian: Endian,
    /// Bytes to skip before the first sample.
    pub header_bytes: u64,
    /// Distance between samples.
    pub spacing: [f64; 3],
    /// Position of the first sample.
    pub origin: [f64; 3],
}

/// Memory order of the samples of a [`RawVolume`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    /// x varies fastest, then y, then z (C order of a `[z][y][x]` array).
    XFastest,
    /// z varies fastest, then y, then x (Fortran order of a `[z][y][x]` array).
    ZFastest,
}

/// Where the samples of a [`RawVolume`] live.
pub(crate) struct Layout {
    /// Grid of the samples.
    pub grid: Grid,
    /// Stored sample type.
    pub scalar: ScalarType,
    /// Byte order of the stored samples.
    pub endian: Endian,
    /// Byte offset of the first sample.
    pub offset: u64,
    /// Memory order of the samples.
    pub order: Order,
}

/// The bytes behind a [`RawVolume`].
enum Storage {
    /// A read-only memory map of the whole file.
    Mapped(MappedFile),
    /// Bytes held in memory (parsed text samples, decoded `.vti` arrays).
    Owned(Vec<u8>),
}

impl Storage {
    fn bytes(&self) -> &[u8] {
        match self {
            Storage::Mapped(map) => map.bytes(),
            Storage::Owned(bytes) => bytes,
        }
    }
}

/// A volume whose samples are read from a memory-mapped file (or, for
/// compressed input, from bytes in memory) and converted plane by plane;
/// the file is never read into memory as a whole.
pub struct RawVolume {
    grid: Grid,
    scalar: ScalarType,
    endian: Endian,
    order: Order,
    offset: usize,
    storage: Storage,
    /// The file the samples come from (mapped, decompressed or parsed).
    data_file: PathBuf,
    /// Whether the file states the grid's spacing and origin (a header
    /// does; `.npy` and headerless samples do not). Only reported.
    grid_stated: bool,
}

impl RawVolume {
    /// Bytes of the file at `path` beyond the header and the samples that
    /// `options` describe (0 when there are none, when the file is shorter
    /// or cannot be looked up). [`RawVolume::open`] ignores them; a caller
    /// that knows the file holds nothing else can take them as a sign of
    /// wrong dims or type.
    pub fn trailing_bytes(path: &Path, options: &RawOptions) -> u64 {
        let needed = data_bytes(options.dims, options.scalar)
            .and_then(|d| d.checked_add(options.header_bytes));
        match (needed, std::fs::metadata(path)) {
            (Some(needed), Ok(meta)) if meta.is_file() => meta.len().saturating_sub(needed),
            _ => 0,
        }
    }

    /// Opens a headerless file of samples described by `options`.
    ///
    /// The file must hold at least `header_bytes + dims product * sample size`
    /// bytes (trailing bytes are ignored); dims must be at least 1, spacing
    /// finite and positive, origin finite. A file named and made as
    /// compressed (`.gz`, `.bz2`, `.zst`, `.xz` with that format's magic) is
    /// refused: its bytes are no samples, and read as such they would make a
    /// mesh of noise whenever the compressed length happens to fit.
    pub fn open(path: &Path, options: &RawOptions) -> Result<RawVolume> {
        let layout = Layout {
            grid: Grid {
                dims: options.dims,
                spacing: options.spacing,
                origin: options.origin,
                direction: super::IDENTITY,
            },
            scalar: options.scalar,
            endian: options.endian,
            offset: options.header_bytes,
            order: Order::XFastest,
        };
        let mut file = File::open(path).map_err(|e| Error::io(path, e))?;
        if let Some(kind) = compressed(path, &mut file) {
            return Err(compressed_error(path, kind, "raw samples"));
        }
        Ok(RawVolume::map_file(path, &file, layout)?.without_stated_grid())
    }

    /// The same volume, reported as one whose file states no spacing or
    /// origin (see [`SampleSource::notes`]): `.npy` and headerless samples.
    pub(crate) fn without_stated_grid(self) -> RawVolume {
        RawVolume {
            grid_stated: false,
            ..self
        }
    }

    /// Maps `file` (opened from `path`) and checks that it holds the samples
    /// described by `layout`.
    pub(crate) fn map_file(path: &Path, file: &File, layout: Layout) -> Result<RawVolume> {
        check_grid(path, &layout.grid)?;
        let meta = file.metadata().map_err(|e| Error::io(path, e))?;
        if meta.is_file() {
            check_length(path, meta.len(), &layout)?;
        }
        let map = MappedFile::map(path, file)?;
        // The map may be shorter than the metadata said if the file shrank
        // in between: check again against what was actually mapped.
        check_length(path, map.bytes().len() as u64, &layout)?;
        RawVolume::with_storage(path, layout, Storage::Mapped(map))
    }

    /// Wraps samples already in memory (for example, decompressed data).
    pub(crate) fn from_bytes(path: &Path, bytes: Vec<u8>, layout: Layout) -> Result<RawVolume> {
        check_grid(path, &layout.grid)?;
        check_length(path, bytes.len() as u64, &layout)?;
        RawVolume::with_storage(path, layout, Storage::Owned(bytes))
    }

    fn with_storage(path: &Path, layout: Layout, storage: Storage) -> Result<RawVolume> {
        let offset = usize::try_from(layout.offset).map_err(|_| {
            Error::Format(format!(
                "{}: data offset {} is too large",
                path.display(),
                layout.offset
            ))
        })?;
        Ok(RawVolume {
            grid: layout.grid,
            scalar: layout.scalar,
            endian: layout.endian,
            order: layout.order,
            offset,
            storage,
            data_file: path.to_path_buf(),
            grid_stated: true,
        })
    }

    /// The stored sample type.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }

    /// The byte order of the stored samples.
    pub fn endian(&self) -> Endian {
        self.endian
    }

    /// Whether the samples are stored with z varying fastest (a Fortran-order
    /// `.npy` array) rather than x fastest.
    pub fn is_z_fastest(&self) -> bool {
        self.order == Order::ZFastest
    }
}

impl fmt::Debug for RawVolume {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RawVolume")
            .field("grid", &self.grid)
            .field("scalar", &self.scalar)
            .field("endian", &self.endian)
            .field("order", &self.order)
            .field("offset", &self.offset)
            .field(
                "storage",
                &match self.storage {
                    Storage::Mapped(_) => "mapped",
                    Storage::Owned(_) => "owned",
                },
            )
            .finish()
    }
}

impl SampleSource for RawVolume {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        // Only x-fastest data stores a plane contiguously.
        if self.order != Order::XFastest {
            return;
        }
        let Storage::Mapped(map) = &self.storage else {
            return;
        };
        let plane = self.grid.plane_len() * self.scalar.size();
        let start = self.offset + planes.start * plane;
        map.advise(start..self.offset + planes.end * plane, access);
    }

    fn data_files(&self) -> Vec<&Path> {
        vec![self.data_file.as_path()]
    }

    fn notes(&self) -> super::SourceNotes {
        if self.grid_stated {
            super::SourceNotes::default()
        } else {
            super::SourceNotes::no_grid()
        }
    }

    fn check_unchanged(&self) -> Result<()> {
        match &self.storage {
            Storage::Mapped(map) => map.check_unchanged(),
            Storage::Owned(_) => Ok(()),
        }
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let [nx, ny, nz] = self.grid.dims;
        if z >= nz {
            return Err(Error::Invalid(format!(
                "plane {z} out of range: the volume has {nz} planes"
            )));
        }
        let plane = nx * ny;
        if out.len() != plane {
            return Err(Error::Invalid(format!(
                "plane buffer holds {} samples, a plane has {plane}",
                out.len()
            )));
        }
        // The length check at construction guarantees that every index below
        // is inside the data and that no product overflows.
        let size = self.scalar.size();
        let data = &self.storage.bytes()[self.offset..];
        match self.order {
            Order::XFastest => {
                let start = z * plane * size;
                decode_samples(
                    self.scalar,
                    self.endian,
                    &data[start..start + plane * size],
                    out,
                );
            }
            Order::ZFastest => {
                for (y, row) in out.chunks_exact_mut(nx).enumerate() {
                    let start = (z + nz * y) * size;
                    decode_strided(self.scalar, self.endian, data, start, nz * ny * size, row);
                }
            }
        }
        Ok(())
    }

    /// Lends x-fastest planes as stored, at any alignment, in either byte
    /// order (the other one's samples are swapped as they are read).
    fn plane_memory(&self) -> PlaneMemory {
        match self.order {
            Order::XFastest => PlaneMemory::Lent,
            _ => PlaneMemory::Read,
        }
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        if self.order != Order::XFastest {
            return None;
        }
        let plane = self.grid.plane_len() * self.scalar.size();
        let start = self.offset + z.checked_mul(plane)?;
        let bytes = self.storage.bytes().get(start..start.checked_add(plane)?)?;
        if self.endian == Endian::native() {
            LentPlane::from_bytes(self.scalar, bytes)
        } else {
            LentPlane::from_foreign_bytes(self.scalar, bytes)
        }
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.scalar)
    }
}

/// Checks dims (at least 1), spacing (finite, positive) and origin (finite).
fn check_grid(path: &Path, grid: &Grid) -> Result<()> {
    let bad = |what: String| Err(Error::Format(format!("{}: {what}", path.display())));
    if grid.dims.contains(&0) {
        return bad(format!("dims {} contain a zero", dims_text(grid.dims)));
    }
    if grid.spacing.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return bad(format!(
            "spacing {:?} must be finite and positive",
            grid.spacing
        ));
    }
    if grid.origin.iter().any(|o| !o.is_finite()) {
        return bad(format!("origin {:?} must be finite", grid.origin));
    }
    Ok(())
}

/// Checks that `len` bytes hold the header and every sample of `layout`.
fn check_length(path: &Path, len: u64, layout: &Layout) -> Result<()> {
    let dims = layout.grid.dims;
    let Some(data) = data_bytes(dims, layout.scalar) else {
        return Err(Error::Format(format!(
            "{}: dims {} {} are too large",
            path.display(),
            dims_text(dims),
            layout.scalar
        )));
    };
    match data.checked_add(layout.offset) {
        Some(needed) if needed <= len && usize::try_from(needed).is_ok() => Ok(()),
        _ => Err(Error::Format(format!(
            "{}: file has {len} bytes, dims {} {} need {data} after a {}-byte header",
            path.display(),
            dims_text(dims),
            layout.scalar,
            layout.offset
        ))),
    }
}

/// Bytes taken by the samples of `dims`, or `None` on overflow.
pub(crate) fn data_bytes(dims: [usize; 3], scalar: ScalarType) -> Option<u64> {
    dims.iter().try_fold(scalar.size() as u64, |acc, &d| {
        acc.checked_mul(u64::try_from(d).ok()?)
    })
}

/// The compressed formats tmc recognises by their first bytes, with the
/// extension that names them.
const COMPRESSED: [(&str, &str, &[u8]); 4] = [
    ("gz", "gzip", b"\x1f\x8b"),
    ("bz2", "bzip2", b"BZh"),
    ("zst", "zstd", b"\x28\xb5\x2f\xfd"),
    ("xz", "xz", b"\xfd7zXZ\x00"),
];

/// The compression whose magic starts `head` (`gzip`, `bzip2`, `zstd`,
/// `xz`), if any.
pub(crate) fn compression_magic(head: &[u8]) -> Option<&'static str> {
    COMPRESSED
        .iter()
        .find(|(_, _, magic)| head.starts_with(magic))
        .map(|(_, kind, _)| *kind)
}

/// The error for `path`, which holds `kind`-compressed data (see
/// [`compression_magic`]) where `expected` was to be: what it is, and the
/// command that decompresses it (keeping the file: `-k`, or `-c` into a
/// new file when the name lacks the format's extension, which the tools
/// would refuse).
pub(crate) fn compressed_error(path: &Path, kind: &str, expected: &str) -> Error {
    let (extension, tool) = match kind {
        "gzip" => ("gz", "gunzip"),
        "bzip2" => ("bz2", "bunzip2"),
        "zstd" => ("zst", "unzstd"),
        _ => ("xz", "unxz"),
    };
    let name = path.display();
    let command = if crate::files::lowercase_extension(path) == extension {
        format!("{tool} -k {name}")
    } else {
        format!("{tool} -c {name} > decompressed-file")
    };
    Error::Format(format!(
        "{name}: {kind}-compressed data, not {expected}: decompress it first (e.g. {command})"
    ))
}

/// The compression of `file` when its name's extension says it and its
/// first bytes agree (`gzip`, `bzip2`, `zstd`, `xz`); `None` otherwise, the
/// file read from its start again.
fn compressed(path: &Path, file: &mut File) -> Option<&'static str> {
    use std::io::{Read, Seek};
    let extension = crate::files::lowercase_extension(path);
    let (_, kind, _) = COMPRESSED.iter().find(|(e, _, _)| *e == extension)?;
    let mut head = [0u8; 6];
    let n = file.read(&mut head).ok()?;
    file.rewind().ok()?;
    (compression_magic(&head[..n]) == Some(*kind)).then_some(*kind)
}

/// `dims` as `XxYxZ`.
pub(crate) fn dims_text(dims: [usize; 3]) -> String {
    format!("{}x{}x{}", dims[0], dims[1], dims[2])
}
