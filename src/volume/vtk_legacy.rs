//! The legacy VTK reader (`.vtk`, `DATASET STRUCTURED_POINTS`).
//!
//! Understood: `DIMENSIONS`, `SPACING` (or `ASPECT_RATIO`), `ORIGIN`,
//! `POINT_DATA n`, `SCALARS name type [1]`, `LOOKUP_TABLE`; types
//! `unsigned_char`, `char`, `unsigned_short`, `short`, `unsigned_int`, `int`,
//! `float`, `double`. `BINARY` data is big-endian (as the VTK spec says) and
//! memory-mapped; `ASCII` data is parsed into memory (meant for small files)
//! as NRRD ascii data is, each value checked against the type.
//! Only the first `SCALARS` array of the point data is read. `CELL_DATA`
//! and its arrays (scalars, vectors, fields ... in either encoding) before
//! the point scalars are skipped, as VTK's reader leaves them aside when
//! the point scalars are asked for.

use super::ascii::read_ascii;
use super::raw::{Layout, Order, RawVolume};
use super::{Endian, Grid, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
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
        "vtktypeint64" => ScalarType::I64,
        "vtktypeuint64" => ScalarType::U64,
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

/// The header lines of a legacy VTK file, read from its start, with the
/// bytes consumed (where binary point data starts) and, of those, the
/// bytes of skipped cell data (not counted against [`MAX_HEADER`]).
struct Lines<'a> {
    path: &'a Path,
    reader: BufReader<File>,
    consumed: u64,
    skipped: u64,
}

impl Lines<'_> {
    fn fail(&self, what: String) -> Error {
        Error::Format(format!("{}: {what}", self.path.display()))
    }

    /// The next line, trimmed; `None` at the end of the file.
    fn next(&mut self) -> Result<Option<String>> {
        let mut buf = Vec::new();
        let n = self
            .reader
            .read_until(b'\n', &mut buf)
            .map_err(|e| Error::io(self.path, e))?;
        self.consumed += n as u64;
        if n == 0 {
            return Ok(None);
        }
        if self.consumed - self.skipped > MAX_HEADER {
            return Err(self.fail("legacy VTK header too long".into()));
        }
        Ok(Some(String::from_utf8_lossy(&buf).trim().to_string()))
    }

    /// The next line that is not blank (binary data ends with a line
    /// break before the next header line); `None` at the end of the file.
    fn next_filled(&mut self) -> Result<Option<String>> {
        while let Some(line) = self.next()? {
            if !line.is_empty() {
                return Ok(Some(line));
            }
        }
        Ok(None)
    }

    /// Skips the `count` values of `size` bytes each (binary) or `count`
    /// words (ascii) of an array of `what` that follow its header line.
    fn skip(&mut self, binary: bool, count: u64, size: u64, what: &str) -> Result<()> {
        let short = |lines: &Self| lines.fail(format!("the file ends inside {what}"));
        if binary {
            let bytes = count.checked_mul(size).ok_or_else(|| short(self))?;
            let got = std::io::copy(&mut (&mut self.reader).take(bytes), &mut std::io::sink())
                .map_err(|e| Error::io(self.path, e))?;
            self.consumed += got;
            self.skipped += got;
            return if got < bytes {
                Err(short(self))
            } else {
                Ok(())
            };
        }
        let mut left = count;
        while left > 0 {
            let before = self.consumed;
            let line = self.next()?.ok_or_else(|| short(self))?;
            self.skipped += self.consumed - before;
            let words = line.split_whitespace().count() as u64;
            if words > left {
                return Err(self.fail(format!(
                    "{what} has more values than its header says ({count})"
                )));
            }
            left -= words;
        }
        Ok(())
    }
}

/// Bytes of one value of a legacy VTK data type in binary files, for the
/// arrays that are skipped (`bit` and `string` arrays have none).
fn type_size(name: &str) -> Option<u64> {
    Some(match name.to_ascii_lowercase().as_str() {
        "unsigned_char" | "char" => 1,
        "unsigned_short" | "short" => 2,
        "unsigned_int" | "int" | "float" | "vtkidtype" => 4,
        "unsigned_long" | "long" | "double" | "vtktypeint64" | "vtktypeuint64" => 8,
        _ => return None,
    })
}

/// Skips the arrays of a `CELL_DATA` section (`cells` values per
/// component) up to the `POINT_DATA` line, returned (`None` at the end of
/// the file), as VTK's reader leaves cell data aside when it reads the
/// point scalars.
fn skip_cell_data(lines: &mut Lines, binary: bool, cells: u64) -> Result<Option<String>> {
    let fail = |lines: &Lines, line: &str| lines.fail(format!("bad CELL_DATA array line '{line}'"));
    loop {
        let Some(line) = lines.next()? else {
            return Ok(None);
        };
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(key) = words.first().map(|k| k.to_ascii_uppercase()) else {
            continue;
        };
        let number = |i: usize| words.get(i).and_then(|w| w.parse::<u64>().ok());
        let size = |i: usize| words.get(i).and_then(|w| type_size(w));
        let what = format!("the CELL_DATA array '{line}'");
        let (count, bytes) = match key.as_str() {
            "POINT_DATA" => return Ok(Some(line.clone())),
            "SCALARS" => {
                let components = if words.len() > 3 { number(3) } else { Some(1) };
                let (Some(size), Some(components)) = (size(2), components) else {
                    return Err(fail(lines, &line));
                };
                let table = lines.next_filled()?.unwrap_or_default();
                if !table.to_ascii_uppercase().starts_with("LOOKUP_TABLE") {
                    return Err(lines.fail(format!(
                        "expected LOOKUP_TABLE after '{line}', got '{table}'"
                    )));
                }
                (cells.saturating_mul(components), size)
            }
            "COLOR_SCALARS" => {
                let n = number(2).ok_or_else(|| fail(lines, &line))?;
                (cells.saturating_mul(n), 1)
            }
            "LOOKUP_TABLE" => {
                let n = number(2).ok_or_else(|| fail(lines, &line))?;
                (n.saturating_mul(4), 1)
            }
            "VECTORS" | "NORMALS" => (
                cells.saturating_mul(3),
                size(2).ok_or_else(|| fail(lines, &line))?,
            ),
            "TENSORS" => (
                cells.saturating_mul(9),
                size(2).ok_or_else(|| fail(lines, &line))?,
            ),
            "TENSORS6" => (
                cells.saturating_mul(6),
                size(2).ok_or_else(|| fail(lines, &line))?,
            ),
            "GLOBAL_IDS" => (cells, size(2).ok_or_else(|| fail(lines, &line))?),
            "TEXTURE_COORDINATES" => {
                let (Some(dim), Some(size)) = (number(2), size(3)) else {
                    return Err(fail(lines, &line));
                };
                (cells.saturating_mul(dim), size)
            }
            "FIELD" => {
                let arrays = number(2).ok_or_else(|| fail(lines, &line))?;
                for _ in 0..arrays {
                    let array = lines.next_filled()?.unwrap_or_default();
                    let w: Vec<&str> = array.split_whitespace().collect();
                    let num = |i: usize| w.get(i).and_then(|x| x.parse::<u64>().ok());
                    let (Some(components), Some(tuples), Some(size)) =
                        (num(1), num(2), w.get(3).and_then(|t| type_size(t)))
                    else {
                        return Err(fail(lines, &array));
                    };
                    let what = format!("the CELL_DATA field array '{array}'");
                    lines.skip(binary, components.saturating_mul(tuples), size, &what)?;
                }
                continue;
            }
            "METADATA" | "INFORMATION" | "NAME" | "DATA" => continue,
            _ => return Err(fail(lines, &line)),
        };
        // ASCII color scalars and lookup tables are floats, one word each.
        lines.skip(binary, count, bytes, &what)?;
    }
}

/// Opens a legacy VTK `STRUCTURED_POINTS` file with one scalar component.
pub fn open(path: &Path) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut lines = Lines {
        path,
        reader: BufReader::new(file),
        consumed: 0,
        skipped: 0,
    };
    let magic = lines.next()?.unwrap_or_default();
    if !magic.starts_with("# vtk DataFile") {
        return Err(fail(
            "not a legacy VTK file (no '# vtk DataFile' line)".into(),
        ));
    }
    let _title = lines.next()?;
    let binary = match lines
        .next()?
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
    let mut pending: Option<String> = None;
    loop {
        let Some(line) = (match pending.take() {
            Some(line) => Some(line),
            None => lines.next()?,
        }) else {
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
            "CELL_DATA" => {
                // Cell data (before the point scalars) is left aside, as
                // VTK's reader does when it reads the point scalars.
                let cells = words
                    .get(1)
                    .and_then(|w| w.parse().ok())
                    .ok_or_else(|| fail(format!("bad CELL_DATA line '{line}'")))?;
                pending = skip_cell_data(&mut lines, binary, cells)?;
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
    let (consumed, reader) = (lines.consumed, lines.reader);
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
