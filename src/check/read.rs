//! Reading triangle meshes (PLY, OBJ, OFF, `.tmesh`) for the checker.
//!
//! The readers keep exactly the connectivity that the file states: vertices
//! are never welded, polygons are fan-triangulated (`v0 vi vi+1`). Every
//! malformed input is reported as one line, [`Error::Format`], prefixed with
//! the file name. Malformed includes content that the format does not allow:
//! an OBJ line that is not an OBJ statement (or not UTF-8 text), an OFF
//! vertex line with other columns than its header keyword declares (see
//! [`OffLayout`]), an OFF face line with anything but 0, 1, 3 or 4 numbers
//! (a colour) after its vertex indices, anything but blank lines and
//! comments after the faces an
//! OFF header declares, anything after the last element a PLY header
//! declares, and vertex coordinates that are not finite `f32` numbers.
//! `.tmesh` files are read with [`TmeshReader`], which verifies every
//! checksum and names a damaged chunk.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;

use crate::export::replay;
use crate::mesh::MeshBuilder;
use crate::meshfile::{TmeshReader, MAGIC};
use crate::{Error, Mesh, Result};

/// Most triangles a mesh may have (indices of triangles are `u32`).
const MAX_TRIANGLES: usize = u32::MAX as usize - 1;
/// Pre-allocation cap, so that a lying header cannot exhaust memory.
const MAX_RESERVE: usize = 1 << 22;

/// Reads a mesh from a PLY (ASCII or binary), OBJ, OFF or `.tmesh` file,
/// chosen by the extension or, failing that, by the first bytes of the file.
///
/// Content that the format does not allow is refused: an OBJ line that is
/// not an OBJ statement, data after what an OFF or PLY header declares, a
/// vertex coordinate that is not a finite `f32` number. So are STL files:
/// STL repeats the corners of every triangle instead of sharing vertices,
/// so it carries no connectivity to check. A `.tmesh` file must fit a
/// [`Mesh`] (at most `u32::MAX` vertices).
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("stl") => return Err(stl_error(path)),
        Some("tmesh") => return read_tmesh(path),
        _ => {}
    }
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut src = Source {
        path,
        reader: BufReader::with_capacity(1 << 20, file),
        buf: Vec::new(),
        pos: 0,
        line: 0,
        complete: false,
    };
    let format = match ext.as_deref() {
        Some("ply") => Format::Ply,
        Some("obj") => Format::Obj,
        Some("off") => Format::Off,
        _ => src.sniff()?,
    };
    match format {
        Format::Ply => read_ply(&mut src),
        Format::Obj => read_obj(&mut src),
        Format::Off => read_off(&mut src),
        Format::Tmesh => read_tmesh(path),
    }
}

/// Reads a whole `.tmesh` file, chunk by chunk, into a [`Mesh`].
fn read_tmesh(path: &Path) -> Result<Mesh> {
    crate::part::PartRecord::refuse_part(path)?;
    let mut reader = TmeshReader::open(path)?;
    let (vertices, triangles) = (reader.vertices(), reader.triangles());
    if vertices > u64::from(u32::MAX) || triangles > MAX_TRIANGLES as u64 {
        return Err(Error::Format(format!(
            "{}: {vertices} vertices and {triangles} triangles are more than a mesh in memory holds (at most {} vertices and {MAX_TRIANGLES} triangles)",
            path.display(),
            u32::MAX
        )));
    }
    let mut builder = MeshBuilder::with_room(vertices as usize, triangles as usize)?;
    replay(&mut reader, &mut builder)?;
    Ok(builder.into_mesh())
}

fn stl_error(path: &Path) -> Error {
    Error::Format(format!(
        "{}: STL does not share vertices between triangles, so its topology cannot be \
         checked; write PLY, OBJ or OFF instead",
        path.display()
    ))
}

enum Format {
    Ply,
    Obj,
    Off,
    Tmesh,
}

/// A buffered file with a current line and a token cursor in it.
struct Source<'a> {
    path: &'a Path,
    reader: BufReader<File>,
    /// The current line (for the text formats).
    buf: Vec<u8>,
    /// Cursor of [`Source::next_token`] in `buf`.
    pos: usize,
    /// 1-based number of the line in `buf`.
    line: usize,
    /// Whether the line in `buf` ended with a line break (not the file's end).
    complete: bool,
}

impl Source<'_> {
    /// An error about the file, without position.
    fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::Format(format!("{}: {msg}", self.path.display()))
    }

    /// An error about the current line.
    fn err_line(&self, msg: impl std::fmt::Display) -> Error {
        Error::Format(format!(
            "{}: line {}: {msg}",
            self.path.display(),
            self.line
        ))
    }

    fn io(&self, e: io::Error) -> Error {
        Error::io(self.path, e)
    }

    /// Guesses the format from the first bytes.
    fn sniff(&mut self) -> Result<Format> {
        let head = self
            .reader
            .fill_buf()
            .map_err(|e| Error::io(self.path, e))?;
        let head = &head[..head.len().min(512)];
        if head.starts_with(&MAGIC) {
            return Ok(Format::Tmesh);
        }
        let text = String::from_utf8_lossy(head);
        let first = text
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !l.starts_with('#'))
            .unwrap_or("");
        let word = first.split_ascii_whitespace().next().unwrap_or("");
        if word == "ply" {
            Ok(Format::Ply)
        } else if word.ends_with("OFF") {
            Ok(Format::Off)
        } else if word == "solid" || (head.len() >= 84 && !text.is_ascii()) {
            Err(stl_error(self.path))
        } else if ["v", "vn", "vt", "f", "o", "g", "s", "mtllib", "usemtl"].contains(&word) {
            Ok(Format::Obj)
        } else {
            Err(self.err("unrecognised mesh format (expected a .ply, .obj, .off or .tmesh file)"))
        }
    }

    /// Reads the next line into `buf` (without the line break); false at the
    /// end of the file.
    fn next_line(&mut self) -> Result<bool> {
        self.buf.clear();
        self.pos = 0;
        let n = self
            .reader
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| Error::io(self.path, e))?;
        if n == 0 {
            return Ok(false);
        }
        self.line += 1;
        self.complete = self.buf.last() == Some(&b'\n');
        while matches!(self.buf.last(), Some(b'\n' | b'\r')) {
            self.buf.pop();
        }
        Ok(true)
    }

    /// Reads the next line that is not empty once `#` comments are removed;
    /// false at the end of the file.
    fn next_content_line(&mut self) -> Result<bool> {
        while self.next_line()? {
            if self.strip_comment() {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Removes a `#` comment from the current line; true when anything but
    /// whitespace remains.
    fn strip_comment(&mut self) -> bool {
        if let Some(hash) = self.buf.iter().position(|&b| b == b'#') {
            self.buf.truncate(hash);
        }
        self.buf.iter().any(|b| !b.is_ascii_whitespace())
    }

    /// The whitespace-separated words of the current line.
    fn words(&self) -> impl Iterator<Item = &[u8]> {
        self.buf
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty())
    }

    /// The next whitespace-separated token, reading further lines as needed;
    /// `None` at the end of the file. Returns the token's range in `buf`.
    fn next_token(&mut self) -> Result<Option<(usize, usize)>> {
        loop {
            while self.pos < self.buf.len() && self.buf[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if self.pos < self.buf.len() {
                let start = self.pos;
                while self.pos < self.buf.len() && !self.buf[self.pos].is_ascii_whitespace() {
                    self.pos += 1;
                }
                return Ok(Some((start, self.pos)));
            }
            if !self.next_line()? {
                return Ok(None);
            }
        }
    }
}

fn parse<T: std::str::FromStr>(word: &[u8]) -> Option<T> {
    std::str::from_utf8(word).ok()?.parse().ok()
}

/// `word` as a finite number (`nan` and `inf` parse as `f64`, but are no
/// normal, colour or texture coordinate).
fn finite(word: &[u8]) -> Option<f64> {
    parse::<f64>(word).filter(|v| v.is_finite())
}

/// The three coordinates that follow the first `skip` words of the current
/// line (of an OBJ or OFF file), which must be finite `f32` numbers.
fn point(src: &Source, skip: usize) -> Result<[f32; 3]> {
    let mut words = src.words().skip(skip);
    let mut p = [0.0f32; 3];
    for c in &mut p {
        let word = words
            .next()
            .ok_or_else(|| src.err_line("vertex needs three coordinates"))?;
        *c = parse(word).ok_or_else(|| src.err_line("vertex needs three coordinates"))?;
        if !c.is_finite() {
            return Err(src.err_line(format!(
                "vertex coordinate '{}' is not a finite number",
                String::from_utf8_lossy(word)
            )));
        }
    }
    Ok(p)
}

/// Appends the fan triangulation of `polygon` to `triangles`.
fn push_fan(triangles: &mut Vec<[u32; 3]>, polygon: &[u32]) {
    for i in 1..polygon.len().saturating_sub(1) {
        triangles.push([polygon[0], polygon[i], polygon[i + 1]]);
    }
}

// ---------------------------------------------------------------- PLY ----

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
    /// Vertex coordinate 0, 1 or 2.
    Coord(usize),
    /// The face's vertex index list.
    Indices,
}

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

fn read_ply(src: &mut Source) -> Result<Mesh> {
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
        triangles: Vec::new(),
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
        if is_face {
            mesh.triangles
                .reserve((elem.count as usize).min(MAX_RESERVE));
        }
        for record in 0..elem.count {
            let mut coords = [0.0f64; 3];
            let mut indices: Vec<f64> = std::mem::take(&mut scratch);
            indices.clear();
            let result = match encoding {
                Encoding::Ascii => read_ascii_record(src, elem, &roles, &mut coords, &mut indices),
                Encoding::Binary { big_endian } => read_binary_record(
                    &mut src.reader,
                    elem,
                    &roles,
                    big_endian,
                    &mut coords,
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
                if let Some(c) = coords.iter().find(|&&c| !(c as f32).is_finite()) {
                    return Err(src.err(format!(
                        "PLY vertex {record}: coordinate {c:e} is not a finite \
                         single-precision number"
                    )));
                }
                mesh.vertices.push(coords.map(|c| c as f32));
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
                push_fan(&mut mesh.triangles, &polygon);
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
                roles[i] = Role::Coord(axis);
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
    coords: &mut [f64; 3],
    indices: &mut Vec<f64>,
) -> std::result::Result<(), RecordError> {
    let mut bytes = [0u8; 8];
    for (prop, role) in elem.props.iter().zip(roles) {
        match prop.kind {
            PropKind::Scalar(ty) => {
                reader.read_exact(&mut bytes[..ty.size()])?;
                if let Role::Coord(axis) = role {
                    coords[*axis] = ty.decode(&bytes, big_endian);
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
    coords: &mut [f64; 3],
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
                if let Role::Coord(axis) = role {
                    coords[*axis] = v;
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

/// The statement keywords of OBJ: every line with content must start with
/// one. Only `v` and `f` are read; the others (texture coordinates, normals,
/// groups, materials, free-form geometry...) are skipped.
const OBJ_KEYWORDS: &str = "v vt vn vp f l p g o s mg mtllib usemtl maplib usemap \
    cstype deg bmat step curv curv2 surf parm trim hole scrv sp end con bevel c_interp d_interp \
    lod shadow_obj trace_obj ctech stech call csh";

fn read_obj(src: &mut Source) -> Result<Mesh> {
    let mut mesh = Mesh::default();
    let mut polygon: Vec<u32> = Vec::new();
    // The largest positive index seen and its line, checked at the end
    // (positive indices may refer to vertices defined later).
    let mut max_index: Option<(u32, usize)> = None;
    // Whether the previous line ended with a backslash: this one continues it.
    let mut continued = false;
    while src.next_line()? {
        if src.buf.contains(&0) || std::str::from_utf8(&src.buf).is_err() {
            return Err(src.err_line("not an OBJ file: NUL or non-UTF-8 bytes"));
        }
        let has_content = src.strip_comment();
        let continuation = continued;
        continued = src.buf.trim_ascii_end().ends_with(b"\\");
        if continuation || !has_content {
            continue;
        }
        let mut words = src.words();
        let keyword = words.next().unwrap_or_default();
        if !OBJ_KEYWORDS
            .split_ascii_whitespace()
            .any(|k| k.as_bytes() == keyword)
        {
            let keyword: String = String::from_utf8_lossy(keyword).chars().take(40).collect();
            return Err(src.err_line(format!(
                "not an OBJ file: '{keyword}' is not an OBJ statement"
            )));
        }
        match keyword {
            b"v" => {
                let p = point(src, 1)?;
                if mesh.vertices.len() >= u32::MAX as usize {
                    return Err(src.err("too many vertices"));
                }
                mesh.vertices.push(p);
            }
            b"f" => {
                polygon.clear();
                for word in words {
                    let first = word.split(|&b| b == b'/').next().unwrap_or(word);
                    let index: i64 = parse(first).ok_or_else(|| {
                        src.err_line(format!(
                            "invalid face vertex '{}'",
                            String::from_utf8_lossy(word)
                        ))
                    })?;
                    let resolved = match index {
                        0 => return Err(src.err_line("vertex index 0 (OBJ counts from 1)")),
                        i if i > 0 => i - 1,
                        i => mesh.vertices.len() as i64 + i,
                    };
                    if resolved < 0 || resolved >= i64::from(u32::MAX) {
                        return Err(src.err_line(format!(
                            "vertex index {index} out of range ({} vertices so far)",
                            mesh.vertices.len()
                        )));
                    }
                    let resolved = resolved as u32;
                    if max_index.is_none_or(|(m, _)| resolved > m) {
                        max_index = Some((resolved, src.line));
                    }
                    polygon.push(resolved);
                }
                if polygon.len() < 3 {
                    return Err(src.err_line(format!(
                        "face has {} vertices (at least 3 needed)",
                        polygon.len()
                    )));
                }
                push_fan(&mut mesh.triangles, &polygon);
                if mesh.triangles.len() > MAX_TRIANGLES {
                    return Err(src.err("too many triangles"));
                }
            }
            _ => {}
        }
    }
    if let Some((index, line)) = max_index {
        if index as usize >= mesh.vertices.len() {
            return Err(src.err(format!(
                "line {line}: vertex index {} out of range ({} vertices)",
                u64::from(index) + 1,
                mesh.vertices.len()
            )));
        }
    }
    Ok(mesh)
}

// ---------------------------------------------------------------- OFF ----

/// The columns of an OFF vertex line, which the header keyword
/// `[ST][C][N]OFF` declares (Geomview's OFF; the prefixes in any order,
/// each at most once): `x y z`, then with `N` a normal `nx ny nz`, with `C`
/// a colour `r g b` or `r g b a`, with `ST` texture coordinates `s t`.
/// Every column must be a number; a line with fewer or more columns is
/// refused (so that a colour, say, is never taken for part of the next
/// vertex or silently dropped).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct OffLayout {
    normal: bool,
    colour: bool,
    texture: bool,
}

impl OffLayout {
    /// The layout the prefix of `OFF` declares; `None` for an unknown or
    /// repeated prefix.
    fn parse(mut prefix: &str) -> Option<OffLayout> {
        let mut layout = OffLayout::default();
        while !prefix.is_empty() {
            let (flag, len) = match prefix.as_bytes()[0] {
                b'S' if prefix.starts_with("ST") => (&mut layout.texture, 2),
                b'C' => (&mut layout.colour, 1),
                b'N' => (&mut layout.normal, 1),
                _ => return None,
            };
            if std::mem::replace(flag, true) {
                return None;
            }
            prefix = &prefix[len..];
        }
        Some(layout)
    }

    /// The fewest and most columns of a vertex line.
    fn columns(self) -> (usize, usize) {
        let least = 3
            + 3 * usize::from(self.normal)
            + 3 * usize::from(self.colour)
            + 2 * usize::from(self.texture);
        (least, least + usize::from(self.colour))
    }

    /// The columns, for messages: `x y z nx ny nz r g b [a] s t`.
    fn describe(self) -> String {
        let mut s = String::from("x y z");
        for (on, what) in [
            (self.normal, " nx ny nz"),
            (self.colour, " r g b [a]"),
            (self.texture, " s t"),
        ] {
            if on {
                s += what;
            }
        }
        s
    }

    /// Checks the columns of the vertex line in `src` against the layout.
    fn check(self, src: &Source, keyword: &str) -> Result<()> {
        let (least, most) = self.columns();
        let mut n = 0;
        for word in src.words() {
            n += 1;
            if n > 3 && n <= most && finite(word).is_none() {
                return Err(src.err_line(format!(
                    "vertex column {n} '{}' is not a finite number",
                    String::from_utf8_lossy(word)
                )));
            }
        }
        // Fewer than three: `point` names the missing coordinate.
        if n >= 3 && !(least..=most).contains(&n) {
            let count = if least == most {
                least.to_string()
            } else {
                format!("{least} or {most}")
            };
            return Err(src.err_line(format!(
                "vertex has {n} columns; the header '{keyword}' declares {count} ({})",
                self.describe()
            )));
        }
        Ok(())
    }
}

/// Checks what follows the `n` vertex indices of an OFF face line: nothing,
/// a colour index (as some writers emit), or an RGB or RGBA colour, every
/// column a number. Anything else is refused, so that a face with more
/// indices than its count says, or a line run together with the next, is
/// never read as a smaller face with a "colour".
fn check_face_colour<'a>(
    src: &Source,
    rest: impl Iterator<Item = &'a [u8]>,
    n: usize,
) -> Result<()> {
    let mut extra = 0;
    for word in rest {
        extra += 1;
        if finite(word).is_none() {
            return Err(src.err_line(format!(
                "face column {} '{}' is not a finite number (a face's colour follows its {n} vertex indices)",
                1 + n + extra,
                String::from_utf8_lossy(word)
            )));
        }
    }
    if matches!(extra, 0 | 1 | 3 | 4) {
        return Ok(());
    }
    Err(src.err_line(format!(
        "face has {extra} numbers after its {n} vertex indices; OFF allows 0, 1 (a colour index), 3 (r g b) or 4 (r g b a)"
    )))
}

fn read_off(src: &mut Source) -> Result<Mesh> {
    if !src.next_content_line()? {
        return Err(src.err("empty OFF file"));
    }
    let words: Vec<Vec<u8>> = src.words().map(<[u8]>::to_vec).collect();
    let keyword = String::from_utf8_lossy(&words[0]).into_owned();
    let prefix = keyword
        .strip_suffix("OFF")
        .ok_or_else(|| src.err_line(format!("not an OFF file (header '{keyword}')")))?;
    if prefix.contains('4') || prefix.contains('n') {
        return Err(src.err_line(format!("{keyword} files (not 3-D) are not supported")));
    }
    let layout = OffLayout::parse(prefix).ok_or_else(|| {
        src.err_line(format!(
            "unknown OFF header keyword '{keyword}' (expected OFF with prefixes ST, C or N)"
        ))
    })?;
    let mut counts: Vec<Vec<u8>> = words[1..].to_vec();
    if counts.first().is_some_and(|w| w == b"BINARY") {
        return Err(src.err_line("binary OFF files are not supported"));
    }
    if counts.is_empty() {
        if !src.next_content_line()? {
            return Err(src.err("truncated OFF file: no vertex and face counts"));
        }
        counts = src.words().map(<[u8]>::to_vec).collect();
    }
    let count = |i: usize| -> Result<usize> {
        counts
            .get(i)
            .and_then(|w| parse::<usize>(w))
            .ok_or_else(|| src.err_line("invalid OFF counts (expected 'vertices faces edges')"))
    };
    let (nv, nf) = (count(0)?, count(1)?);
    if nv > u32::MAX as usize {
        return Err(src.err(format!("too many vertices ({nv})")));
    }
    let mut mesh = Mesh {
        vertices: Vec::with_capacity(nv.min(MAX_RESERVE)),
        triangles: Vec::with_capacity(nf.min(MAX_RESERVE)),
    };
    for i in 0..nv {
        if !src.next_content_line()? {
            return Err(src.err(format!("truncated OFF file: {i} of {nv} vertices")));
        }
        layout.check(src, &keyword)?;
        mesh.vertices.push(point(src, 0)?);
    }
    let mut polygon: Vec<u32> = Vec::new();
    for i in 0..nf {
        if !src.next_content_line()? {
            return Err(src.err(format!("truncated OFF file: {i} of {nf} faces")));
        }
        let mut words = src.words();
        let n: usize = words
            .next()
            .and_then(parse)
            .ok_or_else(|| src.err_line("invalid face vertex count"))?;
        if n < 3 {
            return Err(src.err_line(format!("face has {n} vertices (at least 3 needed)")));
        }
        polygon.clear();
        for _ in 0..n {
            let index: u32 = words
                .next()
                .and_then(parse)
                .filter(|&k: &u32| (k as usize) < nv)
                .ok_or_else(|| {
                    src.err_line(format!(
                        "missing or out-of-range vertex index ({nv} vertices)"
                    ))
                })?;
            polygon.push(index);
        }
        check_face_colour(src, words, n)?;
        push_fan(&mut mesh.triangles, &polygon);
        if mesh.triangles.len() > MAX_TRIANGLES {
            return Err(src.err("too many triangles"));
        }
    }
    if src.next_content_line()? {
        return Err(src.err_line(format!(
            "content after the {nv} vertices and {nf} faces that the OFF header declares"
        )));
    }
    Ok(mesh)
}
