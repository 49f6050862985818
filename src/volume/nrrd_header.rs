//! Parsing the text header of a NRRD file (`.nrrd` or detached `.nhdr`).
//!
//! Kept apart from [`super::nrrd`], which turns a parsed header into a
//! volume, so that the field syntax (names, vectors, type spellings, the
//! three forms of `data file`) reads in one place. Field names are
//! case-sensitive, as in the NRRD format; trailing spaces are tolerated,
//! `#` lines are comments, `key:=value` pairs and unknown fields are
//! ignored.

use super::nrrd_pattern::format_number;
use super::{Endian, ScalarType};
use std::io::{self, BufRead, Read};

/// Longest header accepted (without the file names of `data file: LIST`).
pub(crate) const MAX_HEADER: u64 = 1 << 20;

/// How the samples are encoded in a data file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Encoding {
    /// Packed binary samples (memory-mapped).
    Raw,
    /// gzip-compressed samples.
    Gzip,
    /// bzip2-compressed samples.
    Bzip2,
    /// Numbers written as text, separated by whitespace.
    Ascii,
    /// The raw bytes written as pairs of hex digits, whitespace between
    /// them ignored.
    Hex,
}

impl Encoding {
    /// The canonical NRRD name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Encoding::Raw => "raw",
            Encoding::Gzip => "gzip",
            Encoding::Bzip2 => "bzip2",
            Encoding::Ascii => "ascii",
            Encoding::Hex => "hex",
        }
    }
}

/// Where the samples are, from the `data file` field.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum DataFile {
    /// One file (`data file: <name>`).
    Single(String),
    /// The file names on the lines after the header line (`data file: LIST
    /// [subdim]`), collected into `names`.
    List {
        /// Axes held by each file (default: dimension - 1).
        subdim: Option<usize>,
        /// The file names, in order.
        names: Vec<String>,
    },
    /// Names made by a printf format (`data file: <format> <min> <max>
    /// <step> [subdim]`).
    Pattern {
        /// The format, with one integer conversion such as `%03d`.
        format: String,
        /// First number.
        min: i64,
        /// Last number (inclusive, if the steps reach it).
        max: i64,
        /// Increment, positive or negative.
        step: i64,
        /// Axes held by each file (default: dimension - 1).
        subdim: Option<usize>,
    },
}

impl DataFile {
    /// How many files a pattern names (0 when the step goes the wrong way).
    pub(crate) fn pattern_count(min: i64, max: i64, step: i64) -> u64 {
        let (span, step) = (i128::from(max) - i128::from(min), i128::from(step));
        if step == 0 || (span != 0 && (span > 0) != (step > 0)) {
            return 0;
        }
        u64::try_from(span / step + 1).unwrap_or(u64::MAX)
    }
}

/// The fields of a NRRD header that the reader uses.
#[derive(Debug)]
pub(crate) struct Header {
    pub scalar: Option<ScalarType>,
    pub dimension: Option<usize>,
    pub sizes: Option<Vec<usize>>,
    pub endian: Option<Endian>,
    pub encoding: Option<Encoding>,
    /// From `spacings`, one per axis (NaN for a non-spatial one), signed:
    /// a negative spacing makes positions decrease along its axis, as teem
    /// (`nrrdSpacingCalculate` hands the value on as it is) and ITK
    /// (index-to-physical with that spacing) read it. Their count is
    /// checked against `dimension` once the header is read.
    pub spacings: Option<Vec<f64>>,
    /// From `space directions`: one entry per axis, a vector or `None` for
    /// `none` (a non-spatial axis), or why the field cannot be parsed.
    /// Checked against `dimension` and turned into a matrix once the
    /// header is read. Takes precedence over `spacings`.
    pub directions: Option<Result<Vec<Option<Vec<f64>>>, String>>,
    /// From `kinds`: one NRRD kind per axis (`domain`, `space`,
    /// `RGB-color`, `list`, ...), as written.
    pub kinds: Option<Vec<String>>,
    pub origin: Option<[f64; 3]>,
    /// From `axis mins` and `axis maxs`: one per axis, NaN where unknown.
    /// Without `space directions` they place the origin as teem's
    /// `nrrdOriginCalculate` does (the spacing never comes from them).
    pub axis_mins: Option<Vec<f64>>,
    pub axis_maxs: Option<Vec<f64>>,
    /// From `centers` (or `centerings`): `cell`, `node`, or anything else
    /// for unknown, one per axis, as written.
    pub centers: Option<Vec<String>>,
    /// The `space` name (`left-posterior-superior`, ...), recorded only.
    pub space: Option<String>,
    /// From `space units`: the unit of each space axis (of `space
    /// directions` and `space origin`), as written (`microns`, `mm`, ...).
    pub space_units: Option<Vec<String>>,
    /// From `units`: the unit of each axis (of `spacings`, `axis mins` and
    /// `axis maxs`), as written.
    pub units: Option<Vec<String>>,
    pub line_skip: u64,
    /// `None` for `byte skip: -1` (raw data ends the file).
    pub byte_skip: Option<u64>,
    pub data_file: Option<DataFile>,
}

impl Default for Header {
    fn default() -> Self {
        Header {
            scalar: None,
            dimension: None,
            sizes: None,
            endian: None,
            encoding: None,
            spacings: None,
            directions: None,
            kinds: None,
            origin: None,
            axis_mins: None,
            axis_maxs: None,
            centers: None,
            space: None,
            space_units: None,
            units: None,
            line_skip: 0,
            byte_skip: Some(0),
            data_file: None,
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
pub(crate) fn parse_line(line: &str, header: &mut Header) -> Result<(), String> {
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
    let name = line[..at].trim();
    let value = line[at + 2..].trim();
    match name {
        "type" => header.scalar = Some(scalar_type(value)?),
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
                .collect::<Result<Vec<_>, _>>()
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
                "bzip2" | "bz2" => Encoding::Bzip2,
                "ascii" | "text" | "txt" => Encoding::Ascii,
                "hex" => Encoding::Hex,
                _ => {
                    return Err(format!(
                        "encoding '{value}' is not supported (raw, gzip, bzip2, ascii or hex)"
                    ))
                }
            });
        }
        "spacings" => {
            let spacings = value
                .split_whitespace()
                .map(|v| v.parse::<f64>())
                .collect::<Result<Vec<_>, _>>()
                .map_err(|_| format!("bad 'spacings' value '{value}'"))?;
            header.spacings = Some(spacings);
        }
        "space directions" => {
            header.directions = Some(
                vectors(value)
                    .filter(|v| v.iter().flatten().all(|v| v.len() == 3))
                    .ok_or_else(|| {
                        format!("bad 'space directions' '{value}' (need 3-vectors or 'none')")
                    }),
            )
        }
        "kinds" => header.kinds = Some(value.split_whitespace().map(String::from).collect()),
        "axis mins" | "axismins" => header.axis_mins = Some(per_axis_numbers(name, value)?),
        "axis maxs" | "axismaxs" => header.axis_maxs = Some(per_axis_numbers(name, value)?),
        "centers" | "centerings" => {
            header.centers = Some(value.split_whitespace().map(String::from).collect())
        }
        "space origin" => {
            header.origin = Some(match vectors(value).as_deref() {
                Some([Some(v)]) if v.len() == 3 => [v[0], v[1], v[2]],
                _ => return Err(format!("bad 'space origin' '{value}' (need a 3-vector)")),
            });
        }
        "space" => header.space = Some(value.to_string()),
        "space units" => header.space_units = Some(quoted_strings(name, value)?),
        "units" => header.units = Some(quoted_strings(name, value)?),
        "byte skip" | "byteskip" => {
            header.byte_skip = match value.parse::<i64>() {
                Ok(-1) => None,
                Ok(s) if s >= 0 => Some(s as u64),
                _ => return Err(format!("bad 'byte skip' value '{value}'")),
            };
        }
        "line skip" | "lineskip" => {
            header.line_skip = value
                .parse()
                .map_err(|_| format!("bad 'line skip' value '{value}'"))?;
        }
        "data file" | "datafile" => header.data_file = Some(data_file(value)?),
        _ => {}
    }
    Ok(())
}

/// The numbers of a per-axis field (`axis mins`, `axis maxs`): separated
/// by whitespace or commas (as CMTK writes them, and teem's `%lf` reads
/// past), `nan` for an unknown one.
fn per_axis_numbers(name: &str, value: &str) -> Result<Vec<f64>, String> {
    value
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .map(|w| w.parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| format!("bad '{name}' value '{value}'"))
}

/// The strings of a field such as `space units: "mm" "mm" "mm"`, each in
/// double quotes as the format writes them (`""` for none); words
/// without quotes are taken too, one string each.
fn quoted_strings(name: &str, value: &str) -> Result<Vec<String>, String> {
    if !value.contains('"') {
        return Ok(value.split_whitespace().map(String::from).collect());
    }
    let mut out = Vec::new();
    let mut rest = value.trim();
    while !rest.is_empty() {
        let inner = rest
            .strip_prefix('"')
            .and_then(|r| r.find('"').map(|end| (&r[..end], &r[end + 1..])));
        let Some((text, after)) = inner else {
            return Err(format!(
                "bad '{name}' value '{value}' (need strings in double quotes)"
            ));
        };
        out.push(text.to_string());
        rest = after.trim_start();
    }
    Ok(out)
}

/// Maps a NRRD type name to a scalar type.
fn scalar_type(name: &str) -> Result<ScalarType, String> {
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
        "longlong"
        | "long long"
        | "long long int"
        | "signed long long"
        | "signed long long int"
        | "int64"
        | "int64_t" => ScalarType::I64,
        "ulonglong" | "unsigned long long" | "unsigned long long int" | "uint64" | "uint64_t" => {
            ScalarType::U64
        }
        _ => {
            return Err(format!(
                "type '{name}' is not supported (8-, 16-, 32- or 64-bit integers, float or double)"
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

/// Parses the value of `data file`: `LIST [subdim]`, a printf pattern
/// `<format> <min> <max> <step> [subdim]`, or one file name.
fn data_file(value: &str) -> Result<DataFile, String> {
    let words: Vec<&str> = value.split_whitespace().collect();
    let subdim = |s: &str| {
        s.parse::<usize>()
            .map_err(|_| format!("bad 'data file' subdimension '{s}' in '{value}'"))
    };
    match words.as_slice() {
        [] => Err("empty 'data file' field".into()),
        ["LIST"] => Ok(DataFile::List {
            subdim: None,
            names: Vec::new(),
        }),
        ["LIST", s] => Ok(DataFile::List {
            subdim: Some(subdim(s)?),
            names: Vec::new(),
        }),
        [format, rest @ ..] if format.contains('%') && (3..=4).contains(&rest.len()) => {
            let int = |s: &str| {
                s.parse::<i64>()
                    .map_err(|_| format!("bad number '{s}' in 'data file' pattern '{value}'"))
            };
            format_number(format, 0)?;
            let step = int(rest[2])?;
            if step == 0 {
                return Err(format!("'data file' pattern '{value}' has a zero step"));
            }
            Ok(DataFile::Pattern {
                format: format.to_string(),
                min: int(rest[0])?,
                max: int(rest[1])?,
                step,
                subdim: rest.get(3).map(|s| subdim(s)).transpose()?,
            })
        }
        _ => Ok(DataFile::Single(value.to_string())),
    }
}
