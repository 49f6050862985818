//! The `.nrrd` reader (attached header, 3-D, raw or gzip encoding).
//!
//! Understood fields: `type` (all the NRRD names of 8-, 16- and 32-bit
//! integers, `float`, `double`), `dimension` (must be 3), `sizes`, `endian`,
//! `encoding` (`raw`, memory-mapped; `gzip`, decompressed into memory),
//! `spacings` or `space directions`, `space origin`, `line skip` and
//! `byte skip` (`-1` for raw data at the end of the file). Other fields and
//! `key:=value` pairs are ignored.
//!
//! The spacing along each axis is the norm of its `space directions` vector
//! and its direction the unit vector, so the mesh lives in the NRRD's space,
//! rotation or axis flip included, shifted by `space origin`. Detached
//! headers (`data file`) are not supported.

use super::raw::{data_bytes, dims_text, Layout, Order, RawVolume};
use super::{Endian, Grid, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// Longest header accepted.
pub(crate) const MAX_HEADER: u64 = 1 << 20;

/// How the data after the header is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Raw,
    Gzip,
}

/// The fields of a NRRD header that the reader uses.
#[derive(Debug, Default)]
struct Header {
    scalar: Option<ScalarType>,
    dimension: Option<usize>,
    sizes: Option<Vec<usize>>,
    endian: Option<Endian>,
    encoding: Option<Encoding>,
    spacing: Option<[f64; 3]>,
    /// Unit vectors of the `space directions`, as columns.
    direction: Option<[[f64; 3]; 3]>,
    origin: Option<[f64; 3]>,
    line_skip: u64,
    /// `None` for `byte skip: -1` (raw data ends the file).
    byte_skip: Option<u64>,
}

/// Opens a 3-D NRRD file with an attached header.
pub fn open(path: &Path) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = BufReader::new(file);
    let mut consumed = 0u64;

    let first = read_line(&mut reader, &mut consumed)
        .map_err(|e| Error::io(path, e))?
        .ok_or_else(|| fail("empty file, not a NRRD".into()))?;
    if !first.starts_with("NRRD") {
        return Err(fail("not a NRRD file (no NRRD magic)".into()));
    }

    let mut header = Header {
        byte_skip: Some(0),
        ..Header::default()
    };
    loop {
        if consumed > MAX_HEADER {
            return Err(fail("NRRD header too long".into()));
        }
        let Some(line) = read_line(&mut reader, &mut consumed).map_err(|e| Error::io(path, e))?
        else {
            return Err(fail(
                "the NRRD header does not end with a blank line (no attached data)".into(),
            ));
        };
        if line.is_empty() {
            break;
        }
        parse_line(&line, &mut header).map_err(fail)?;
    }
    for _ in 0..header.line_skip {
        read_line(&mut reader, &mut consumed)
            .map_err(|e| Error::io(path, e))?
            .ok_or_else(|| fail("'line skip' goes past the end of the file".into()))?;
    }

    let scalar = header
        .scalar
        .ok_or_else(|| fail("missing 'type' field".into()))?;
    match header.dimension {
        Some(3) => {}
        Some(d) => return Err(fail(format!("dimension {d} is not supported (need 3)"))),
        None => return Err(fail("missing 'dimension' field".into())),
    }
    let dims = match header.sizes.as_deref() {
        Some(&[x, y, z]) => [x, y, z],
        Some(s) => return Err(fail(format!("'sizes' has {} values, need 3", s.len()))),
        None => return Err(fail("missing 'sizes' field".into())),
    };
    let encoding = header
        .encoding
        .ok_or_else(|| fail("missing 'encoding' field".into()))?;
    let endian = match (header.endian, scalar.size()) {
        (Some(e), _) => e,
        (None, 1) => Endian::Little,
        (None, _) => return Err(fail(format!("missing 'endian' field for type {scalar}"))),
    };
    let grid = Grid {
        dims,
        spacing: header.spacing.unwrap_or([1.0; 3]),
        origin: header.origin.unwrap_or([0.0; 3]),
        direction: header.direction.unwrap_or(super::IDENTITY),
    };
    let data_len = data_bytes(dims, scalar)
        .ok_or_else(|| fail(format!("sizes {} are too large", dims_text(dims))))?;

    match encoding {
        Encoding::Raw => {
            let file = reader.into_inner();
            let offset = match header.byte_skip {
                Some(skip) => consumed
                    .checked_add(skip)
                    .ok_or_else(|| fail("'byte skip' is too large".into()))?,
                None => {
                    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
                    len.checked_sub(data_len).ok_or_else(|| {
                        fail(format!(
                            "file has {len} bytes, sizes {} {scalar} need {data_len}",
                            dims_text(dims)
                        ))
                    })?
                }
            };
            let layout = Layout {
                grid,
                scalar,
                endian,
                offset,
                order: Order::XFastest,
            };
            RawVolume::map_file(path, &file, layout)
        }
        Encoding::Gzip => {
            let skip = header
                .byte_skip
                .ok_or_else(|| fail("'byte skip: -1' is only allowed with raw encoding".into()))?;
            let mut file = reader.into_inner();
            file.seek(SeekFrom::Start(consumed))
                .map_err(|e| Error::io(path, e))?;
            let bytes = gunzip(file, skip, data_len).map_err(|e| match e {
                GunzipError::Short(n) => fail(format!(
                    "gzip data holds {n} bytes, sizes {} {scalar} need {data_len} after a {skip}-byte skip",
                    dims_text(dims)
                )),
                GunzipError::Memory => fail(format!(
                    "not enough memory to decompress {data_len} bytes"
                )),
                GunzipError::Io(e) => fail(format!("bad gzip data: {e}")),
            })?;
            let layout = Layout {
                grid,
                scalar,
                endian,
                offset: 0,
                order: Order::XFastest,
            };
            RawVolume::from_bytes(path, bytes, layout)
        }
    }
}

/// Reads one line (without `\n` or `\r\n`), counting the bytes consumed;
/// `None` at the end of the file.
pub(crate) fn read_line(
    reader: &mut impl BufRead,
    consumed: &mut u64,
) -> io::Result<Option<String>> {
    let mut buf = Vec::new();
    let n = reader
        .by_ref()
        .take(MAX_HEADER)
        .read_until(b'\n', &mut buf)?;
    if n == 0 {
        return Ok(None);
    }
    *consumed += n as u64;
    if buf.last() == Some(&b'\n') {
        buf.pop();
        if buf.last() == Some(&b'\r') {
            buf.pop();
        }
    }
    Ok(Some(String::from_utf8_lossy(&buf).into_owned()))
}

/// Parses one header line (a comment, a `key:=value` pair or a field) into
/// `header`.
fn parse_line(line: &str, header: &mut Header) -> std::result::Result<(), String> {
    if line.starts_with('#') {
        return Ok(());
    }
    let field_at = line.find(": ");
    let pair_at = line.find(":=");
    let at = match (field_at, pair_at) {
        (Some(f), Some(p)) if p < f => return Ok(()),
        (Some(f), _) => f,
        (None, Some(_)) => return Ok(()),
        (None, None) => return Err(format!("bad header line '{line}'")),
    };
    let name = line[..at].trim().to_ascii_lowercase();
    let value = line[at + 2..].trim();
    match name.as_str() {
        "type" => {
            header.scalar = Some(scalar_type(value)?);
        }
        "dimension" => {
            header.dimension = Some(
                value
                    .parse()
                    .map_err(|_| format!("bad 'dimension' value '{value}'"))?,
            );
        }
        "sizes" => {
            let sizes = value
                .split_whitespace()
                .map(|s| s.parse::<usize>())
                .collect::<std::result::Result<Vec<_>, _>>()
                .map_err(|_| format!("bad 'sizes' value '{value}'"))?;
            header.sizes = Some(sizes);
        }
        "endian" => {
            header.endian = Some(match value.to_ascii_lowercase().as_str() {
                "little" => Endian::Little,
                "big" => Endian::Big,
                _ => return Err(format!("bad 'endian' value '{value}'")),
            });
        }
        "encoding" => {
            header.encoding = Some(match value.to_ascii_lowercase().as_str() {
                "raw" => Encoding::Raw,
                "gzip" | "gz" => Encoding::Gzip,
                other => {
                    return Err(format!(
                        "encoding '{other}' is not supported (use raw or gzip)"
                    ))
                }
            });
        }
        "spacings" => {
            let mut spacing = [1.0; 3];
            let values: Vec<&str> = value.split_whitespace().collect();
            if values.len() != 3 {
                return Err(format!("'spacings' has {} values, need 3", values.len()));
            }
            for (s, v) in spacing.iter_mut().zip(values) {
                let x: f64 = v
                    .parse()
                    .map_err(|_| format!("bad 'spacings' value '{value}'"))?;
                *s = x.abs();
            }
            if header.spacing.is_none() {
                header.spacing = Some(spacing);
            }
        }
        "space directions" => {
            let vectors =
                vectors(value).ok_or_else(|| format!("bad 'space directions' '{value}'"))?;
            if vectors.len() != 3 {
                return Err(format!(
                    "'space directions' has {} vectors, need 3",
                    vectors.len()
                ));
            }
            let mut spacing = [1.0; 3];
            let mut direction = super::IDENTITY;
            for (j, v) in vectors.iter().enumerate() {
                if let Some(v) = v {
                    if v.len() != 3 {
                        return Err(format!("bad 'space directions' '{value}' (need 3-vectors)"));
                    }
                    let norm = v.iter().map(|c| c * c).sum::<f64>().sqrt();
                    if !(norm.is_finite() && norm > 0.0) {
                        return Err(format!("'space directions' vector {} has no length", j + 1));
                    }
                    spacing[j] = norm;
                    for i in 0..3 {
                        direction[i][j] = v[i] / norm;
                    }
                }
            }
            // Directions take precedence over `spacings`.
            header.spacing = Some(spacing);
            header.direction = Some(direction);
        }
        "space origin" => {
            let origin = match vectors(value).as_deref() {
                Some([Some(v)]) if v.len() == 3 => [v[0], v[1], v[2]],
                _ => return Err(format!("bad 'space origin' '{value}' (need a 3-vector)")),
            };
            header.origin = Some(origin);
        }
        "byte skip" | "byteskip" => {
            let skip: i64 = value
                .parse()
                .map_err(|_| format!("bad 'byte skip' value '{value}'"))?;
            header.byte_skip = match skip {
                -1 => None,
                s if s >= 0 => Some(s as u64),
                _ => return Err(format!("bad 'byte skip' value '{value}'")),
            };
        }
        "line skip" | "lineskip" => {
            header.line_skip = value
                .parse()
                .map_err(|_| format!("bad 'line skip' value '{value}'"))?;
        }
        "data file" | "datafile" => {
            return Err("detached data ('data file') is not supported".into());
        }
        _ => {}
    }
    Ok(())
}

/// Maps a NRRD type name to a scalar type.
fn scalar_type(name: &str) -> std::result::Result<ScalarType, String> {
    let t = match name.to_ascii_lowercase().as_str() {
        "signed char" | "int8" | "int8_t" => ScalarType::I8,
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => ScalarType::U8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
            ScalarType::I16
        }
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
            ScalarType::U16
        }
        "int" | "signed int" | "int32" | "int32_t" => ScalarType::I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => ScalarType::U32,
        "float" => ScalarType::F32,
        "double" => ScalarType::F64,
        _ => {
            return Err(format!(
                "type '{name}' is not supported (8-, 16- or 32-bit integers, float or double)"
            ))
        }
    };
    Ok(t)
}

/// Parses a list of vectors `(a,b,c) (d,e,f) none ...`; `none` gives `None`.
#[allow(clippy::type_complexity)]
fn vectors(text: &str) -> Option<Vec<Option<Vec<f64>>>> {
    let mut out = Vec::new();
    let mut rest = text.trim();
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("none") {
            out.push(None);
            rest = after.trim_start();
        } else if let Some(after) = rest.strip_prefix('(') {
            let close = after.find(')')?;
            let v = after[..close]
                .split(',')
                .map(|c| c.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect::<Option<Vec<f64>>>()?;
            out.push(Some(v));
            rest = after[close + 1..].trim_start();
        } else {
            return None;
        }
    }
    Some(out)
}

/// Why decompression failed.
enum GunzipError {
    /// The stream ended after this many bytes.
    Short(u64),
    /// The buffer could not be allocated.
    Memory,
    /// The stream is corrupt or unreadable.
    Io(io::Error),
}

/// Decompresses `skip + len` bytes of gzip data from `file` and returns the
/// last `len`.
fn gunzip(file: File, skip: u64, len: u64) -> std::result::Result<Vec<u8>, GunzipError> {
    let mut decoder = flate2::read::MultiGzDecoder::new(BufReader::new(file));
    let skipped =
        io::copy(&mut decoder.by_ref().take(skip), &mut io::sink()).map_err(GunzipError::Io)?;
    if skipped < skip {
        return Err(GunzipError::Short(skipped));
    }
    let want = usize::try_from(len).map_err(|_| GunzipError::Memory)?;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(want)
        .map_err(|_| GunzipError::Memory)?;
    let got = decoder
        .by_ref()
        .take(len)
        .read_to_end(&mut bytes)
        .map_err(GunzipError::Io)? as u64;
    if got < len {
        return Err(GunzipError::Short(skip + got));
    }
    // Read to the end of the stream so that its checksum is verified.
    io::copy(&mut decoder, &mut io::sink()).map_err(GunzipError::Io)?;
    Ok(bytes)
}
