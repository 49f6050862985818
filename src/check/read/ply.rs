//! PLY, ASCII and binary (either byte order): the `vertex` element's
//! `x y z` (and `nx ny nz`, when it has all three, as the mesh's normals)
//! and the `face` element's vertex index list (and an integer `label`, as
//! tmc writes a label map's surfaces into one file); other elements and
//! properties are read past.

use super::source::{parse, push_fan, Source, MAX_RESERVE, MAX_TRIANGLES};
use crate::mesh::Mesh;
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};

/// A PLY scalar type.
#[derive(Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Decodes `bytes` (exactly `self.size()` long). Every PLY type fits
    /// exactly in an `f64`.
    fn decode(self, bytes: &[u8], big_endian: bool) -> f64 {
        macro_rules! num {
            ($t:ty, $n:literal) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&bytes[..$n]);
                f64::from(if big_endian {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                })
            }};
        }
        match self {
            Scalar::I8 => f64::from(bytes[0] as i8),
            Scalar::U8 => f64::from(bytes[0]),
            Scalar::I16 => num!(i16, 2),
            Scalar::U16 => num!(u16, 2),
            Scalar::I32 => num!(i32, 4),
            Scalar::U32 => num!(u32, 4),
            Scalar::F32 => num!(f32, 4),
            Scalar::F64 => num!(f64, 8),
        }
    }
}

#[derive(Clone, Copy)]
enum PropKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// What the reader does with a property.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Skip,
    /// A number kept in slot `0..VALUES` of the record's values: a vertex's
    /// coordinates (0, 1, 2) and normal (3, 4, 5), a face's label (6).
    Value(usize),
    /// The face's vertex index list.
    Indices,
}

/// The slots of a record's kept numbers ([`Role::Value`]).
const VALUES: usize = 7;
/// The slot of a vertex's first normal component.
const NORMAL: usize = 3;
/// The slot of a face's label.
const LABEL: usize = 6;

struct Property {
    name: String,
    kind: PropKind,
}

struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
}

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Binary { big_endian: bool },
}

pub(super) fn read_ply(src: &mut Source) -> Result<Mesh> {
    let (encoding, elements) = read_ply_header(src)?;
    let vertex_count = elements
        .iter()
        .find(|e| e.name == "vertex")
        .map(|e| e.count)
        .ok_or_else(|| src.err("PLY header has no 'vertex' element"))?;
    if vertex_count > u64::from(u32::MAX) {
        return Err(src.err(format!("too many vertices ({vertex_count})")));
    }
    let mut mesh = Mesh {
        vertices: Vec::with_capacity((vertex_count as usize).min(MAX_RESERVE)),
        ..Mesh::default()
    };
    let mut scratch = Vec::new();
    let mut polygon: Vec<u32> = Vec::new();
    for elem in &elements {
        let roles = ply_roles(src, elem)?;
        if elem.props.is_empty() {
            // Records without properties occupy no bytes (or tokens).
            continue;
        }
        let is_face = roles.contains(&Role::Indices);
        let normals = roles.contains(&Role::Value(NORMAL));
        let labels = is_face && roles.contains(&Role::Value(LABEL));
        // Declared normals and labels are the mesh's, with or without
        // records (an empty mesh keeps them).
        if elem.name == "vertex" && normals {
            let room = (elem.count as usize).min(MAX_RESERVE);
            mesh.normals = Some(Vec::with_capacity(room));
        }
        if labels {
            mesh.labels.get_or_insert_with(Vec::new);
        }
        if is_face {
            mesh.triangles
                .reserve((elem.count as usize).min(MAX_RESERVE));
        }
        for record in 0..elem.count {
            let mut values = [0.0f64; VALUES];
            let mut indices: Vec<f64> = std::mem::take(&mut scratch);
            indices.clear();
            let result = match encoding {
                Encoding::Ascii => read_ascii_record(src, elem, &roles, &mut values, &mut indices),
                Encoding::Binary { big_endian } => read_binary_record(
                    &mut src.reader,
                    elem,
                    &roles,
                    big_endian,
                    &mut values,
                    &mut indices,
                ),
            };
            match result {
                Ok(()) => {}
                Err(RecordError::Eof) => {
                    return Err(src.err(format!(
                        "truncated PLY file: element '{}' ends after {record} of {} records",
                        elem.name, elem.count
                    )))
                }
                Err(RecordError::Io(e)) => return Err(src.io(e)),
                Err(RecordError::Bad(msg)) => {
                    return Err(src.err(format!(
                        "PLY element '{}' record {record}: {msg}",
                        elem.name
                    )))
                }
                Err(RecordError::Fatal(e)) => return Err(e),
            }
            if elem.name == "vertex" {
                let coords = &values[..NORMAL];
                if let Some(c) = coords.iter().find(|&&c| !(c as f32).is_finite()) {
                    return Err(src.err(format!(
                        "PLY vertex {record}: coordinate {c:e} is not a finite \
                         single-precision number"
                    )));
                }
                mesh.vertices.push([0, 1, 2].map(|i| coords[i] as f32));
                if normals {
                    let normal = &values[NORMAL..LABEL];
                    if let Some(c) = normal.iter().find(|&&c| !(c as f32).is_finite()) {
                        return Err(src.err(format!(
                            "PLY vertex {record}: normal component {c:e} is not a finite \
                             single-precision number"
                        )));
                    }
                    let normals = mesh.normals.get_or_insert_with(Vec::new);
                    normals.push([0, 1, 2].map(|i| normal[i] as f32));
                }
            }
            if is_face {
                polygon.clear();
                for &i in &indices {
                    if !(i >= 0.0 && i < vertex_count as f64 && i.fract() == 0.0) {
                        return Err(src.err(format!(
                            "PLY face {record}: vertex index {i} out of range \
                             ({vertex_count} vertices)"
                        )));
                    }
                    polygon.push(i as u32);
                }
                if polygon.len() < 3 {
                    return Err(src.err(format!(
                        "PLY face {record} has {} vertices (at least 3 needed)",
                        polygon.len()
                    )));
                }
                let before = mesh.triangles.len();
                push_fan(&mut mesh.triangles, &polygon);
                if labels {
                    let label = values[LABEL];
                    if !(label >= 0.0 && label <= f64::from(u32::MAX)) {
                        return Err(src.err(format!(
                            "PLY face {record}: label {label} is not a uint32 (0 to {})",
                            u32::MAX
                        )));
                    }
                    let added = mesh.triangles.len() - before;
                    let labels = mesh.labels.get_or_insert_with(Vec::new);
                    labels.extend(std::iter::repeat_n(label as u32, added));
                }
                if mesh.triangles.len() > MAX_TRIANGLES {
                    return Err(src.err("too many triangles"));
                }
            }
            scratch = indices;
        }
    }
    let trailing = match encoding {
        Encoding::Ascii => src.next_token()?.is_some(),
        Encoding::Binary { .. } => !src
            .reader
            .fill_buf()
            .map_err(|e| Error::io(src.path, e))?
            .is_empty(),
    };
    if trailing {
        return Err(src.err("data after the last element that the PLY header declares"));
    }
    Ok(mesh)
}

fn read_ply_header(src: &mut Source) -> Result<(Encoding, Vec<Element>)> {
    if !src.next_line()? || src.buf != b"ply" {
        return Err(src.err("not a PLY file (first line is not 'ply')"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if !src.next_line()? || !src.complete {
            return Err(src.err("truncated PLY header (no 'end_header')"));
        }
        let words: Vec<String> = src
            .words()
            .map(|w| String::from_utf8_lossy(w).into_owned())
            .collect();
        let words: Vec<&str> = words.iter().map(String::as_str).collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["end_header"] => break,
            ["format", f, _version] => {
                encoding = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Binary { big_endian: false },
                    "binary_big_endian" => Encoding::Binary { big_endian: true },
                    _ => return Err(src.err_line(format!("unknown PLY format '{f}'"))),
                })
            }
            ["element", name, count] => {
                let count = parse(count.as_bytes())
                    .ok_or_else(|| src.err_line(format!("invalid element count '{count}'")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            ["property", rest @ ..] => {
                let type_of = |name: &str| {
                    Scalar::from_name(name)
                        .ok_or_else(|| src.err_line(format!("unknown PLY type '{name}'")))
                };
                let (name, kind) = match rest {
                    ["list", count, item, name] => {
                        let count = type_of(count)?;
                        if !count.is_integer() {
                            return Err(src.err_line("PLY list count must be an integer type"));
                        }
                        (
                            name,
                            PropKind::List {
                                count,
                                item: type_of(item)?,
                            },
                        )
                    }
                    [ty, name] => (name, PropKind::Scalar(type_of(ty)?)),
                    _ => return Err(src.err_line("malformed PLY property")),
                };
                let elem = elements
                    .last_mut()
                    .ok_or_else(|| src.err_line("PLY property before any element"))?;
                elem.props.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            _ => {
                return Err(
                    src.err_line(format!("unexpected PLY header line '{}'", words.join(" ")))
                )
            }
        }
    }
    let encoding = encoding.ok_or_else(|| src.err("PLY header has no 'format' line"))?;
    // The body starts right after the header line; discard the text cursor.
    src.buf.clear();
    src.pos = 0;
    Ok((encoding, elements))
}

/// Decides which properties of `elem` the reader keeps.
fn ply_roles(src: &Source, elem: &Element) -> Result<Vec<Role>> {
    let mut roles = vec![Role::Skip; elem.props.len()];
    match elem.name.as_str() {
        "vertex" => {
            for (axis, coord) in ["x", "y", "z"].iter().enumerate() {
                let i = elem
                    .props
                    .iter()
                    .position(|p| p.name == *coord)
                    .ok_or_else(|| src.err(format!("PLY vertex has no property '{coord}'")))?;
                if !matches!(elem.props[i].kind, PropKind::Scalar(_)) {
                    return Err(src.err(format!("PLY vertex property '{coord}' is a list")));
                }
                roles[i] = Role::Value(axis);
            }
            let normal = ["nx", "ny", "nz"].map(|name| {
                elem.props
                    .iter()
                    .position(|p| p.name == name && matches!(p.kind, PropKind::Scalar(_)))
            });
            if let [Some(x), Some(y), Some(z)] = normal {
                for (axis, i) in [x, y, z].into_iter().enumerate() {
                    roles[i] = Role::Value(NORMAL + axis);
                }
            }
        }
        "face" => {
            let i = elem
                .props
                .iter()
                .position(|p| p.name == "vertex_indices" || p.name == "vertex_index")
                .ok_or_else(|| src.err("PLY face has no property 'vertex_indices'"))?;
            match elem.props[i].kind {
                PropKind::List { item, .. } if item.is_integer() => roles[i] = Role::Indices,
                _ => {
                    return Err(
                        src.err("PLY face property 'vertex_indices' must be a list of integers")
                    )
                }
            }
            let label = elem.props.iter().position(|p| {
                p.name == "label" && matches!(p.kind, PropKind::Scalar(ty) if ty.is_integer())
            });
            if let Some(i) = label {
                roles[i] = Role::Value(LABEL);
            }
        }
        _ => {}
    }
    Ok(roles)
}

/// Why a PLY record could not be read.
enum RecordError {
    /// The file ended inside the record.
    Eof,
    Io(io::Error),
    /// A malformed value.
    Bad(String),
    /// An already formatted error.
    Fatal(Error),
}

impl From<io::Error> for RecordError {
    fn from(e: io::Error) -> Self {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            RecordError::Eof
        } else {
            RecordError::Io(e)
        }
    }
}

/// Largest list a PLY record may hold (a polygon or any skipped list).
const MAX_LIST: f64 = 1e6;

fn list_len(n: f64) -> std::result::Result<usize, RecordError> {
    if (0.0..=MAX_LIST).contains(&n) && n.fract() == 0.0 {
        Ok(n as usize)
    } else {
        Err(RecordError::Bad(format!("invalid list length {n}")))
    }
}

fn read_binary_record(
    reader: &mut BufReader<File>,
    elem: &Element,
    roles: &[Role],
    big_endian: bool,
    values: &mut [f64; VALUES],
    indices: &mut Vec<f64>,
) -> std::result::Result<(), RecordError> {
    let mut bytes = [0u8; 8];
    for (prop, role) in elem.props.iter().zip(roles) {
        match prop.kind {
            PropKind::Scalar(ty) => {
                reader.read_exact(&mut bytes[..ty.size()])?;
                if let Role::Value(slot) = role {
                    values[*slot] = ty.decode(&bytes, big_endian);
                }
            }
            PropKind::List { count, item } => {
                reader.read_exact(&mut bytes[..count.size()])?;
                let n = list_len(count.decode(&bytes, big_endian))?;
                if *role == Role::Indices {
                    for _ in 0..n {
                        reader.read_exact(&mut bytes[..item.size()])?;
                        indices.push(item.decode(&bytes, big_endian));
                    }
                } else {
                    let skip = (n * item.size()) as u64;
                    let copied = io::copy(&mut reader.by_ref().take(skip), &mut io::sink())?;
                    if copied < skip {
                        return Err(RecordError::Eof);
                    }
                }
            }
        }
    }
    Ok(())
}

fn read_ascii_record(
    src: &mut Source,
    elem: &Element,
    roles: &[Role],
    values: &mut [f64; VALUES],
    indices: &mut Vec<f64>,
) -> std::result::Result<(), RecordError> {
    fn number(src: &mut Source, integer: bool) -> std::result::Result<f64, RecordError> {
        let (a, b) = src
            .next_token()
            .map_err(RecordError::Fatal)?
            .ok_or(RecordError::Eof)?;
        let word = &src.buf[a..b];
        let value = if integer {
            parse::<i64>(word).map(|v| v as f64)
        } else {
            parse::<f64>(word)
        };
        value.ok_or_else(|| {
            RecordError::Bad(format!(
                "line {}: invalid number '{}'",
                src.line,
                String::from_utf8_lossy(word)
            ))
        })
    }
    for (prop, role) in elem.props.iter().zip(roles) {
        match prop.kind {
            PropKind::Scalar(ty) => {
                let v = number(src, ty.is_integer())?;
                if let Role::Value(slot) = role {
                    values[*slot] = v;
                }
            }
            PropKind::List { item, .. } => {
                let n = list_len(number(src, true)?)?;
                for _ in 0..n {
                    let v = number(src, item.is_integer())?;
                    if *role == Role::Indices {
                        indices.push(v);
                    }
                }
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------- OBJ ----
