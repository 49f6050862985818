//! The legacy VTK reader (`.vtk`, `DATASET STRUCTURED_POINTS`).
//!
//! Understood: `DIMENSIONS`, `SPACING` (or `ASPECT_RATIO`), `ORIGIN`,
//! `POINT_DATA n`, `SCALARS name type [1]`, `LOOKUP_TABLE`; types
//! `unsigned_char`, `char`, `unsigned_short`, `short`, `unsigned_int`, `int`,
//! `float`, `double`. `BINARY` data is big-endian (as the VTK spec says) and
//! memory-mapped; `ASCII` data is parsed into memory (meant for small files)
//! as NRRD ascii data is, each value checked against the type.
//! Only the first `SCALARS` array of the point data is read.

use super::ascii::read_ascii;
use super::raw::{Layout, Order, RawVolume};
use super::{Endian, Grid, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

/// Longest header accepted.
const MAX_HEADER: u64 = 1 << 20;

/// The sample type of a legacy VTK type name, if supported.
pub(crate) fn legacy_type(name: &str) -> Option<ScalarType> {
    Some(match name.to_ascii_lowercase().as_str() {
        "unsigned_char" => ScalarType::U8,
        "char" => ScalarType::I8,
        "unsigned_short" => ScalarType::U16,
        "short" => ScalarType::I16,
        "unsigned_int" => ScalarType::U32,
        "int" => ScalarType::I32,
        "float" => ScalarType::F32,
        "double" => ScalarType::F64,
        _ => return None,
    })
}

/// Parses three numbers of a header line.
fn three<T: std::str::FromStr>(words: &[&str], key: &str) -> std::result::Result<[T; 3], String> {
    let bad = || format!("{key} needs 3 numbers, got '{}'", words[1..].join(" "));
    if words.len() != 4 {
        return Err(bad());
    }
    let mut out = Vec::with_capacity(3);
    for w in &words[1..] {
        out.push(w.parse::<T>().map_err(|_| bad())?);
    }
    out.try_into().map_err(|_| bad())
}

/// Opens a legacy VTK `STRUCTURED_POINTS` file with one scalar component.
pub fn open(path: &Path) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = BufReader::new(file);
    let mut consumed = 0u64;
    let mut next_line = |reader: &mut BufReader<File>| -> Result<Option<String>> {
        let mut buf = Vec::new();
        let n = reader
            .read_until(b'\n', &mut buf)
            .map_err(|e| Error::io(path, e))?;
        consumed += n as u64;
        if n == 0 {
            return Ok(None);
        }
        if consumed > MAX_HEADER {
            return Err(fail("legacy VTK header too long".into()));
        }
        Ok(Some(String::from_utf8_lossy(&buf).trim().to_string()))
    };
    let magic = next_line(&mut reader)?.unwrap_or_default();
    if !magic.starts_with("# vtk DataFile") {
        return Err(fail(
            "not a legacy VTK file (no '# vtk DataFile' line)".into(),
        ));
    }
    let _title = next_line(&mut reader)?;
    let binary = match next_line(&mut reader)?
        .unwrap_or_default()
        .to_ascii_uppercase()
        .as_str()
    {
        "BINARY" => true,
        "ASCII" => false,
        other => return Err(fail(format!("expected ASCII or BINARY, got '{other}'"))),
    };
    let mut dataset = None;
    let mut dims: Option<[usize; 3]> = None;
    let mut spacing = [1.0; 3];
    let mut origin = [0.0; 3];
    let mut point_data: Option<usize> = None;
    let mut scalar: Option<ScalarType> = None;
    loop {
        let Some(line) = next_line(&mut reader)? else {
            return Err(fail(
                "no SCALARS / LOOKUP_TABLE before the end of the file".into(),
            ));
        };
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(key) = words.first() else { continue };
        match key.to_ascii_uppercase().as_str() {
            "DATASET" => dataset = words.get(1).map(|s| s.to_ascii_uppercase()),
            "DIMENSIONS" => dims = Some(three(&words, "DIMENSIONS").map_err(fail)?),
            "SPACING" | "ASPECT_RATIO" => spacing = three(&words, key).map_err(fail)?,
            "ORIGIN" => origin = three(&words, "ORIGIN").map_err(fail)?,
            "POINT_DATA" => {
                point_data = Some(
                    words
                        .get(1)
                        .and_then(|w| w.parse().ok())
                        .ok_or_else(|| fail(format!("bad POINT_DATA line '{line}'")))?,
                )
            }
            "CELL_DATA" if point_data.is_none() => {
                return Err(fail(
                    "CELL_DATA is not supported (need POINT_DATA scalars)".into(),
                ))
            }
            "SCALARS" => {
                if point_data.is_none() {
                    return Err(fail("SCALARS before POINT_DATA".into()));
                }
                let name = words
                    .get(2)
                    .ok_or_else(|| fail(format!("bad SCALARS line '{line}'")))?;
                scalar = Some(
                    legacy_type(name)
                        .ok_or_else(|| fail(format!("unsupported scalar type '{name}'")))?,
                );
                if let Some(n) = words.get(3) {
                    if *n != "1" {
                        return Err(fail(format!(
                            "SCALARS with {n} components are not supported (need 1)"
                        )));
                    }
                }
            }
            "LOOKUP_TABLE" if scalar.is_some() => break,
            "FIELD" | "VECTORS" | "NORMALS" | "TENSORS" | "COLOR_SCALARS" => {
                return Err(fail(format!(
                    "{key} before SCALARS is not supported (the scalars must come first)"
                )))
            }
            _ => {}
        }
    }
    match dataset.as_deref() {
        Some("STRUCTURED_POINTS") => {}
        Some(d) => {
            return Err(fail(format!(
                "DATASET {d} is not supported (need STRUCTURED_POINTS)"
            )))
        }
        None => return Err(fail("missing DATASET line".into())),
    }
    let dims = dims.ok_or_else(|| fail("missing DIMENSIONS".into()))?;
    let scalar = scalar.ok_or_else(|| fail("missing SCALARS".into()))?;
    let count = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| fail("DIMENSIONS too large".into()))?;
    let n = point_data.unwrap_or(count);
    if n != count {
        return Err(fail(format!(
            "POINT_DATA {n} does not match DIMENSIONS {}x{}x{} ({count} points)",
            dims[0], dims[1], dims[2]
        )));
    }
    let grid = Grid {
        dims,
        spacing,
        origin,
        direction: super::IDENTITY,
    };
    if binary {
        let file = reader.into_inner();
        let layout = Layout {
            grid,
            scalar,
            endian: Endian::Big,
            offset: consumed,
            order: Order::XFastest,
        };
        return RawVolume::map_file(path, &file, layout);
    }
    let layout = Layout {
        grid,
        scalar,
        endian: Endian::Little,
        offset: 0,
        order: Order::XFastest,
    };
    // Other arrays may follow the scalars.
    read_ascii(path, reader, layout, true)
}
