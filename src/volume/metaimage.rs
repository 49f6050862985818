//! The MetaImage reader (`.mhd` header + data file, `.mha` attached data).
//!
//! Understood keys: `ObjectType` (must be `Image`), `NDims` (3, or more
//! when every axis after the third has size 1, as NIfTI readers take a 4-D
//! file of one time point: the first three values of `ElementSpacing` and
//! `Offset` and the 3x3 of `TransformMatrix` on those axes are used),
//! `DimSize`, `ElementType` (`MET_UCHAR`, `MET_CHAR`, `MET_USHORT`,
//! `MET_SHORT`, `MET_UINT`, `MET_INT`, `MET_ULONG`, `MET_LONG` (4 bytes,
//! as MetaIO sizes them), `MET_LONG_LONG`, `MET_ULONG_LONG`, `MET_FLOAT`,
//! `MET_DOUBLE`),
//! `ElementNumberOfChannels` (must be 1), `ElementSpacing` (else
//! `ElementSize`), `Offset` / `Origin` / `Position`, `TransformMatrix` /
//! `Rotation` / `Orientation`, `BinaryDataByteOrderMSB` /
//! `ElementByteOrderMSB`, `CompressedData` (zlib, decompressed into a temporary file),
//! `BinaryData` (`False`: the samples are numbers written as text, read by
//! the shared ascii parser; not with `CompressedData` or `HeaderSize = -1`),
//! `HeaderSize` (`-1`: the data ends the file) and `ElementDataFile`, which
//! ends the header: `LOCAL` (data follows the header), a file name relative
//! to the header, or `LIST` / `LIST 2D` followed by one file name per z
//! slice. File name patterns (`%03d.raw 1 10 1`) are not supported.
//!
//! The `TransformMatrix` goes into the [`Grid`] with the spacing and
//! origin, so vertices are in the image's world frame (ITK's LPS
//! millimetres as written by ITK); a mirroring matrix flips the winding.

use super::ascii::read_ascii;
use super::raw::{data_bytes, dims_text, Layout, Order, RawVolume};
use super::spill::spill;
use super::{set_direction, Access, Endian, Grid, LentPlane, SampleSource, ScalarType};
// One line reader and one header limit (1 MiB, without the file list of
// `LIST`) for both text-header formats.
use super::nrrd::{read_line, MAX_HEADER};
use crate::{Error, Result};
use std::fs::File;
use std::io::{BufReader, Seek, SeekFrom};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A MetaImage volume.
#[derive(Debug)]
pub struct MetaImageVolume {
    grid: Grid,
    data: Data,
}

/// Where the samples of a [`MetaImageVolume`] are.
#[derive(Debug)]
enum Data {
    /// One data file (or the attached data, or text samples parsed into memory).
    Volume(Box<RawVolume>),
    /// One single-plane volume per z slice (`ElementDataFile = LIST`).
    Slices(Vec<RawVolume>),
}

impl MetaImageVolume {
    /// The direction cosines: `direction()[r][c]` is component `r` of the
    /// unit vector of index axis `c` (from `TransformMatrix`, whose
    /// consecutive triples are the axis vectors, as ITK writes it; the
    /// identity when absent); the same as the grid's.
    pub fn direction(&self) -> [[f64; 3]; 3] {
        self.grid.direction
    }

    /// Whether the samples come from one file per slice (`LIST`).
    pub fn is_slice_list(&self) -> bool {
        matches!(self.data, Data::Slices(_))
    }
}

impl SampleSource for MetaImageVolume {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        match &self.data {
            Data::Volume(v) => v.read_plane(z, out),
            Data::Slices(slices) => {
                let slice = slices.get(z).ok_or_else(|| {
                    Error::Invalid(format!(
                        "plane {z} out of range: the volume has {} planes",
                        slices.len()
                    ))
                })?;
                slice.read_plane(0, out)
            }
        }
    }

    /// Lends the stored plane as `RawVolume` does (native byte order,
    /// aligned): the slab loop then holds no `f64` copy of it.
    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        match &self.data {
            Data::Volume(v) => v.lend_plane(z),
            Data::Slices(slices) => slices.get(z)?.lend_plane(0),
        }
    }

    fn plane_memory(&self) -> super::PlaneMemory {
        match &self.data {
            Data::Volume(v) => v.plane_memory(),
            Data::Slices(slices) => slices
                .first()
                .map_or(super::PlaneMemory::Read, |s| s.plane_memory()),
        }
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        match &self.data {
            Data::Volume(v) => v.advise(planes, access),
            Data::Slices(slices) => {
                let end = planes.end.min(slices.len());
                for s in slices.get(planes.start..end).unwrap_or_default() {
                    s.advise(0..1, access);
                }
            }
        }
    }

    fn check_unchanged(&self) -> Result<()> {
        match &self.data {
            Data::Volume(v) => v.check_unchanged(),
            Data::Slices(slices) => slices.iter().try_for_each(|s| s.check_unchanged()),
        }
    }

    fn data_files(&self) -> Vec<&Path> {
        match &self.data {
            Data::Volume(v) => v.data_files(),
            Data::Slices(slices) => slices.iter().flat_map(|s| s.data_files()).collect(),
        }
    }

    fn sample_bytes(&self) -> usize {
        match &self.data {
            Data::Volume(v) => v.sample_bytes(),
            Data::Slices(s) => s.first().map_or(8, |v| v.sample_bytes()),
        }
    }

    fn stored_type(&self) -> Option<ScalarType> {
        match &self.data {
            Data::Volume(v) => v.stored_type(),
            Data::Slices(s) => s.first().and_then(|v| v.stored_type()),
        }
    }
}

/// The keys of a MetaImage header that the reader uses.
#[derive(Debug, Default)]
struct Header {
    /// `NDims` (3 when absent); the vectors below have as many values
    /// (`matrix` its square), checked once the header is read.
    ndims: Option<usize>,
    dims: Option<Vec<usize>>,
    scalar: Option<ScalarType>,
    spacing: Option<Vec<f64>>,
    size: Option<Vec<f64>>,
    origin: Option<Vec<f64>>,
    matrix: Option<Vec<f64>>,
    big_endian: bool,
    compressed: bool,
    /// `BinaryData = False`: the samples are written as text.
    ascii: bool,
    /// `Some(-1)` means the data ends the file.
    header_size: Option<i64>,
    data_file: Option<String>,
}

/// Opens a MetaImage volume (`.mhd` or `.mha`).
pub fn open(path: &Path) -> Result<MetaImageVolume> {
    open_cancellable(path, &AtomicBool::new(false))
}

/// [`open`] that stops with [`Error::Interrupted`] once `cancel` is set
/// while compressed samples are decompressed (it is looked at every MiB).
pub fn open_cancellable(path: &Path, cancel: &AtomicBool) -> Result<MetaImageVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = BufReader::new(file);
    let mut consumed = 0u64;
    let mut header = Header::default();
    while header.data_file.is_none() {
        if consumed > MAX_HEADER {
            return Err(fail("MetaImage header too long".into()));
        }
        let line = read_line(&mut reader, &mut consumed)
            .map_err(|e| Error::io(path, e))?
            .ok_or_else(|| fail("the header has no ElementDataFile line".into()))?;
        parse_line(&line, &mut header).map_err(fail)?;
    }

    let n = header.ndims.unwrap_or(3);
    let dims = header
        .dims
        .as_deref()
        .ok_or_else(|| fail("missing DimSize".into()))?;
    let dims = volume_dims(n, dims).map_err(&fail)?;
    let first3 = |key: &str, v: &Option<Vec<f64>>| {
        v.as_deref()
            .map(|v| axes3(key, n, v))
            .transpose()
            .map_err(&fail)
    };
    let spacing = first3("ElementSpacing", &header.spacing)?;
    let size = first3("ElementSize", &header.size)?;
    let origin = first3("Offset", &header.origin)?;
    let scalar = header
        .scalar
        .ok_or_else(|| fail("missing ElementType".into()))?;
    if header.ascii && header.compressed {
        return Err(fail(
            "BinaryData = False with CompressedData = True (compressed text) is not supported"
                .into(),
        ));
    }
    if header.ascii && header.header_size == Some(-1) {
        return Err(fail(
            "BinaryData = False with HeaderSize = -1 is not supported (text samples have no fixed size)"
                .into(),
        ));
    }
    let spacing = spacing.or(size).unwrap_or([1.0; 3]);
    let mut grid = Grid {
        dims,
        spacing,
        origin: origin.unwrap_or([0.0; 3]),
        direction: super::IDENTITY,
    };
    let endian = if header.big_endian {
        Endian::Big
    } else {
        Endian::Little
    };
    if let Some(m) = &header.matrix {
        if m.len() != n * n {
            return Err(fail(format!(
                "bad TransformMatrix (need {} numbers for NDims {n}, found {})",
                n * n,
                m.len()
            )));
        }
        // Consecutive n-tuples are the axis vectors (columns).
        let matrix = [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[n * c + r]));
        set_direction(&mut grid, matrix).map_err(|e| fail(format!("TransformMatrix: {e}")))?;
    }
    let data_len = data_bytes(dims, scalar)
        .ok_or_else(|| fail(format!("DimSize {} is too large", dims_text(dims))))?;
    let layout = |offset: u64| Layout {
        grid,
        scalar,
        endian,
        offset,
        order: Order::XFastest,
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let data_file = header.data_file.clone().unwrap_or_default();
    let words: Vec<&str> = data_file.split_whitespace().collect();

    let data = match words.as_slice() {
        ["LOCAL"] => {
            let mut file = reader.into_inner();
            if header.compressed {
                file.seek(SeekFrom::Start(consumed))
                    .map_err(|e| Error::io(path, e))?;
                let samples = inflate(path, file, data_len, cancel)?;
                Data::Volume(Box::new(RawVolume::map_file(path, &samples, layout(0))?))
            } else {
                Data::Volume(Box::new(samples(
                    path,
                    &file,
                    layout(consumed),
                    header.ascii,
                )?))
            }
        }
        ["LIST"] | ["LIST", "2D" | "2d"] => {
            if header.compressed {
                return Err(fail(
                    "CompressedData with ElementDataFile = LIST is not supported".into(),
                ));
            }
            let mut names = Vec::new();
            while names.len() < dims[2] {
                match read_line(&mut reader, &mut consumed).map_err(|e| Error::io(path, e))? {
                    Some(line) if line.trim().is_empty() => {}
                    Some(line) => names.push(line.trim().to_string()),
                    None => {
                        return Err(fail(format!(
                            "ElementDataFile = LIST names {} files, DimSize needs {} slices",
                            names.len(),
                            dims[2]
                        )))
                    }
                }
            }
            let plane = Grid {
                dims: [dims[0], dims[1], 1],
                ..grid
            };
            let plane_len = data_len / dims[2] as u64;
            let mut slices = Vec::with_capacity(names.len());
            for name in names {
                let slice_path = dir.join(name);
                let slice = || {
                    super::check_input_kind(&slice_path)?;
                    let file = File::open(&slice_path).map_err(|e| Error::io(&slice_path, e))?;
                    let offset = data_offset(&slice_path, &file, header.header_size, plane_len)?;
                    let slice_layout = Layout {
                        grid: plane,
                        ..layout(offset)
                    };
                    samples(&slice_path, &file, slice_layout, header.ascii)
                };
                slices.push(slice().map_err(|e| e.in_data_file(path, &slice_path))?);
            }
            Data::Slices(slices)
        }
        ["LIST", other] => {
            return Err(fail(format!(
                "ElementDataFile = LIST {other} is not supported (only one 2-D file per slice)"
            )))
        }
        [_, _, ..] if data_file.contains('%') => {
            return Err(fail(format!(
                "ElementDataFile pattern '{data_file}' is not supported"
            )))
        }
        _ => {
            let data_path: PathBuf = dir.join(data_file.trim());
            let volume = || {
                // A FIFO data file would block the open below.
                super::check_input_kind(&data_path)?;
                let file = File::open(&data_path).map_err(|e| Error::io(&data_path, e))?;
                if header.compressed {
                    let samples = inflate(&data_path, file, data_len, cancel)?;
                    RawVolume::map_file(&data_path, &samples, layout(0))
                } else {
                    let offset = data_offset(&data_path, &file, header.header_size, data_len)?;
                    samples(&data_path, &file, layout(offset), header.ascii)
                }
            };
            let volume = volume().map_err(|e| e.in_data_file(path, &data_path))?;
            Data::Volume(Box::new(volume))
        }
    };
    Ok(MetaImageVolume { grid, data })
}

/// The samples of `layout` in `file` (opened from `path`): mapped, or
/// parsed from the text that starts at the layout's offset when `ascii`.
fn samples(path: &Path, mut file: &File, layout: Layout, ascii: bool) -> Result<RawVolume> {
    if !ascii {
        return RawVolume::map_file(path, file, layout);
    }
    file.seek(SeekFrom::Start(layout.offset))
        .map_err(|e| Error::io(path, e))?;
    read_ascii(
        path,
        BufReader::new(file),
        Layout {
            offset: 0,
            ..layout
        },
        false,
    )
}

/// The offset of `len` bytes of samples in `file`, after `HeaderSize` bytes
/// (`-1`: at the end of the file).
fn data_offset(path: &Path, file: &File, header_size: Option<i64>, len: u64) -> Result<u64> {
    match header_size {
        None => Ok(0),
        Some(-1) => {
            let size = file.metadata().map_err(|e| Error::io(path, e))?.len();
            size.checked_sub(len).ok_or_else(|| {
                Error::Format(format!(
                    "{}: file has {size} bytes, the samples need {len}",
                    path.display()
                ))
            })
        }
        Some(n) => Ok(n as u64),
    }
}

/// Decompresses the zlib data in `file`, which must hold at least `len`
/// bytes, into a temporary file to be mapped (see [`super::spill`]).
fn inflate(path: &Path, file: File, len: u64, cancel: &AtomicBool) -> Result<File> {
    let decoder = flate2::read::ZlibDecoder::new(BufReader::new(file));
    let (samples, got) = spill(path, "zlib", &[], decoder, len, cancel)?;
    if got < len {
        return Err(Error::Format(format!(
            "{}: compressed data holds {got} bytes, DimSize and ElementType need {len}",
            path.display()
        )));
    }
    Ok(samples)
}

/// Parses finite numbers (as many as there are; their count is checked
/// against `NDims` once the header is read).
fn numbers(key: &str, value: &str) -> std::result::Result<Vec<f64>, String> {
    let parsed: Option<Vec<f64>> = value
        .split_whitespace()
        .map(|s| s.parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect();
    parsed
        .filter(|v| !v.is_empty())
        .ok_or_else(|| format!("bad {key} '{value}' (need finite numbers)"))
}

/// The values of the first three axes of a per-axis vector of `NDims` = `n`
/// values.
fn axes3(key: &str, n: usize, v: &[f64]) -> std::result::Result<[f64; 3], String> {
    match v {
        [x, y, z, ..] if v.len() == n => Ok([*x, *y, *z]),
        _ => Err(format!(
            "bad {key} (need {n} numbers for NDims {n}, found {})",
            v.len()
        )),
    }
}

/// The `[nx, ny, nz]` of a `DimSize` of `n` values (`NDims`): its first
/// three, every later axis of size 1 (an error naming the first that is
/// not, and what to do).
fn volume_dims(n: usize, dims: &[usize]) -> std::result::Result<[usize; 3], String> {
    let text = || {
        let v: Vec<String> = dims.iter().map(usize::to_string).collect();
        v.join(" ")
    };
    if dims.len() != n {
        return Err(format!(
            "bad DimSize '{}' (need {n} positive integers for NDims {n})",
            text()
        ));
    }
    if let Some(axis) = (3..n).find(|&a| dims[a] != 1) {
        return Err(format!(
            "DimSize '{}' is not one volume: axis {} has size {}, not 1 (only axes of size 1 may follow x, y, z); write one 3-D volume (e.g. a time point with SimpleITK's image[:, :, :, 0])",
            text(),
            axis + 1,
            dims[axis]
        ));
    }
    Ok([dims[0], dims[1], dims[2]])
}

/// Parses a boolean value (`True` / `False`, `1` / `0`).
fn boolean(key: &str, value: &str) -> std::result::Result<bool, String> {
    match value.to_ascii_lowercase().as_str() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        _ => Err(format!("bad {key} '{value}' (need True or False)")),
    }
}

/// Parses one `Key = Value` header line into `header`.
fn parse_line(line: &str, header: &mut Header) -> std::result::Result<(), String> {
    if line.trim().is_empty() {
        return Ok(());
    }
    let Some((key, value)) = line.split_once('=') else {
        return Err(format!("bad header line '{line}' (need 'Key = Value')"));
    };
    let key = key.trim();
    let value = value.trim();
    match key.to_ascii_lowercase().as_str() {
        "objecttype" if !value.eq_ignore_ascii_case("image") => {
            return Err(format!(
                "ObjectType '{value}' is not supported (need Image)"
            ))
        }
        "ndims" => {
            header.ndims = Some(
                value
                    .parse()
                    .ok()
                    .filter(|n| (3..=16).contains(n))
                    .ok_or_else(|| {
                        format!(
                        "NDims {value} is not supported (need 3, or 4 with a 4th axis of size 1)"
                    )
                    })?,
            )
        }
        "dimsize" => {
            let parsed: Option<Vec<usize>> = value
                .split_whitespace()
                .map(|s| s.parse().ok().filter(|&n| n > 0))
                .collect();
            header.dims = Some(
                parsed
                    .filter(|v| !v.is_empty())
                    .ok_or_else(|| format!("bad DimSize '{value}' (need positive integers)"))?,
            );
        }
        "elementtype" => {
            header.scalar = Some(match value {
                "MET_UCHAR" => ScalarType::U8,
                "MET_CHAR" => ScalarType::I8,
                "MET_USHORT" => ScalarType::U16,
                "MET_SHORT" => ScalarType::I16,
                "MET_UINT" => ScalarType::U32,
                "MET_INT" => ScalarType::I32,
                // MetaIO's long types have 4 bytes (`MET_ValueTypeSize`),
                // whatever C's `long` has where the file was written.
                "MET_LONG" => ScalarType::I32,
                "MET_ULONG" => ScalarType::U32,
                "MET_FLOAT" => ScalarType::F32,
                "MET_DOUBLE" => ScalarType::F64,
                "MET_LONG_LONG" => ScalarType::I64,
                "MET_ULONG_LONG" => ScalarType::U64,
                _ => return Err(format!(
                    "ElementType '{value}' is not supported (MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT, MET_INT, MET_ULONG, MET_LONG, MET_LONG_LONG, MET_ULONG_LONG, MET_FLOAT, MET_DOUBLE)"
                )),
            });
        }
        "elementnumberofchannels" if value != "1" => {
            return Err(format!(
                "ElementNumberOfChannels {value} is not supported (need 1)"
            ))
        }
        "elementspacing" => header.spacing = Some(numbers(key, value)?),
        "elementsize" => header.size = Some(numbers(key, value)?),
        "offset" | "origin" | "position" => header.origin = Some(numbers(key, value)?),
        "transformmatrix" | "rotation" | "orientation" => {
            header.matrix = Some(numbers(key, value)?)
        }
        "binarydatabyteordermsb" | "elementbyteordermsb" => {
            header.big_endian = boolean(key, value)?
        }
        "compresseddata" => header.compressed = boolean(key, value)?,
        "binarydata" => header.ascii = !boolean(key, value)?,
        "headersize" => {
            let n: i64 = value
                .parse()
                .ok()
                .filter(|&n| n >= -1)
                .ok_or_else(|| format!("bad HeaderSize '{value}'"))?;
            header.header_size = Some(n);
        }
        "elementdatafile" => {
            if value.is_empty() {
                return Err("empty ElementDataFile".into());
            }
            header.data_file = Some(value.to_string());
        }
        _ => {}
    }
    Ok(())
}
