//! The `.npy` reader (numpy's array format, versions 1, 2 and 3).
//!
//! The array must be 3-D with shape `(nz, ny, nx)`, or have leading axes of
//! size 1 before those three (`(1, nz, ny, nx)` from a batch or channel
//! axis, as NIfTI readers take a 4-D file of one time point): the logical
//! array is indexed `[z][y][x]`, and unit axes change no byte's place in
//! either order. In C order x varies fastest in memory; in Fortran order
//! (`fortran_order: True`) z varies fastest, and planes are gathered with a
//! stride from the memory map. Supported dtypes: `u1 i1 u2 i2 u4 i4 f4 f8`
//! in either byte order, read in their own type; `b1` (a mask) as `u1`;
//! `i8 u8 f2` read as `f64` (64-bit integers exactly within ±2^53). The grid has unit spacing and zero origin.

use super::raw::{compressed_error, compression_magic, Layout, Order, RawVolume};
use super::{Grid, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// The magic string that starts every `.npy` file.
const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// Longest header accepted (numpy itself refuses headers over 10 000 bytes
/// by default).
const MAX_HEADER: usize = 1 << 20;

/// Opens a 3-D `.npy` array as a memory-mapped volume.
pub fn open(path: &Path) -> Result<RawVolume> {
    let mut file = File::open(path).map_err(|e| Error::io(path, e))?;
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let read_err = |e: io::Error| {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            fail("truncated .npy header".into())
        } else {
            Error::io(path, e)
        }
    };

    let mut preamble = [0u8; 8];
    file.read_exact(&mut preamble).map_err(|e| {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            fail("not a .npy file (too short)".into())
        } else {
            Error::io(path, e)
        }
    })?;
    if &preamble[..6] != MAGIC {
        if let Some(kind) = compression_magic(&preamble) {
            return Err(compressed_error(path, kind, "a .npy file"));
        }
        return Err(fail("not a .npy file (bad magic)".into()));
    }
    let (major, minor) = (preamble[6], preamble[7]);
    let (header_len, prefix_len) = match major {
        1 => {
            let mut len = [0u8; 2];
            file.read_exact(&mut len).map_err(read_err)?;
            (usize::from(u16::from_le_bytes(len)), 10u64)
        }
        2 | 3 => {
            let mut len = [0u8; 4];
            file.read_exact(&mut len).map_err(read_err)?;
            let len = usize::try_from(u32::from_le_bytes(len)).unwrap_or(usize::MAX);
            (len, 12u64)
        }
        _ => {
            return Err(fail(format!(
                "unsupported .npy version {major}.{minor} (expected 1.0, 2.0 or 3.0)"
            )))
        }
    };
    if header_len > MAX_HEADER {
        return Err(fail(format!(
            ".npy header of {header_len} bytes is too long"
        )));
    }
    let mut header = vec![0u8; header_len];
    file.read_exact(&mut header).map_err(read_err)?;
    let header = String::from_utf8_lossy(&header);
    let header = parse_header(&header).map_err(|e| fail(format!("bad .npy header: {e}")))?;

    let (scalar, endian) = ScalarType::from_numpy_descr(&header.descr).ok_or_else(|| {
        fail(format!(
            "unsupported dtype '{}' (expected b1, u1, i1, u2, i2, u4, i4, u8, i8, f2, f4 or f8)",
            header.descr
        ))
    })?;
    let [nz, ny, nx] = volume_shape(&header.shape).map_err(fail)?;
    let layout = Layout {
        grid: Grid::unit([nx, ny, nz]),
        scalar,
        endian,
        offset: prefix_len + header_len as u64,
        order: if header.fortran_order {
            Order::ZFastest
        } else {
            Order::XFastest
        },
    };
    Ok(RawVolume::map_file(path, &file, layout)?.without_stated_grid())
}

/// The fields of a `.npy` header that the reader uses.
#[derive(Debug)]
struct Header {
    descr: String,
    fortran_order: bool,
    shape: Vec<usize>,
}

/// A value of the header's Python dict literal.
#[derive(Debug)]
enum Value {
    Str(String),
    Bool(bool),
    Tuple(Vec<usize>),
}

/// Parses the header dict, e.g.
/// `{'descr': '<u2', 'fortran_order': False, 'shape': (93, 64, 64), }`.
fn parse_header(text: &str) -> std::result::Result<Header, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
    };
    let (mut descr, mut fortran_order, mut shape) = (None, None, None);
    p.expect(b'{')?;
    loop {
        p.skip_ws();
        if p.eat(b'}') {
            break;
        }
        let key = p.string()?;
        p.skip_ws();
        p.expect(b':')?;
        p.skip_ws();
        let value = p.value()?;
        match (key.as_str(), value) {
            ("descr", Value::Str(s)) => descr = Some(s),
            ("descr", _) => return Err("structured dtypes are not supported".into()),
            ("fortran_order", Value::Bool(b)) => fortran_order = Some(b),
            ("fortran_order", _) => return Err("'fortran_order' is not True or False".into()),
            ("shape", Value::Tuple(t)) => shape = Some(t),
            ("shape", _) => return Err("'shape' is not a tuple".into()),
            _ => {}
        }
        p.skip_ws();
        if p.eat(b',') {
            continue;
        }
        p.skip_ws();
        p.expect(b'}')?;
        break;
    }
    Ok(Header {
        descr: descr.ok_or("missing 'descr'")?,
        fortran_order: fortran_order.ok_or("missing 'fortran_order'")?,
        shape: shape.ok_or("missing 'shape'")?,
    })
}

/// A cursor over the header text.
struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn skip_ws(&mut self) {
        while self.peek().is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: u8) -> std::result::Result<(), String> {
        self.skip_ws();
        if self.eat(c) {
            Ok(())
        } else {
            Err(format!("expected '{}' at byte {}", c as char, self.i))
        }
    }

    fn string(&mut self) -> std::result::Result<String, String> {
        let quote = match self.peek() {
            Some(q @ (b'\'' | b'"')) => q,
            _ => return Err(format!("expected a quoted string at byte {}", self.i)),
        };
        self.i += 1;
        let start = self.i;
        while let Some(c) = self.peek() {
            if c == quote {
                let s = String::from_utf8_lossy(&self.s[start..self.i]).into_owned();
                self.i += 1;
                return Ok(s);
            }
            self.i += 1;
        }
        Err("unterminated string".into())
    }

    fn word(&mut self) -> &[u8] {
        let start = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_alphanumeric()) {
            self.i += 1;
        }
        &self.s[start..self.i]
    }

    fn value(&mut self) -> std::result::Result<Value, String> {
        match self.peek() {
            Some(b'\'' | b'"') => Ok(Value::Str(self.string()?)),
            Some(b'(') => {
                self.i += 1;
                let mut items = Vec::new();
                loop {
                    self.skip_ws();
                    if self.eat(b')') {
                        break;
                    }
                    let at = self.i;
                    let word = self.word();
                    // Python 2 wrote long integers with an `L` suffix.
                    let digits = word.strip_suffix(b"L").unwrap_or(word);
                    let n = std::str::from_utf8(digits)
                        .ok()
                        .filter(|d| !d.is_empty() && d.bytes().all(|c| c.is_ascii_digit()))
                        .and_then(|d| d.parse::<usize>().ok())
                        .ok_or_else(|| format!("bad shape entry at byte {at}"))?;
                    items.push(n);
                    self.skip_ws();
                    if !self.eat(b',') {
                        self.expect(b')')?;
                        break;
                    }
                }
                Ok(Value::Tuple(items))
            }
            Some(b'[') => Err("structured dtypes are not supported".into()),
            _ => {
                let at = self.i;
                match self.word() {
                    b"True" => Ok(Value::Bool(true)),
                    b"False" => Ok(Value::Bool(false)),
                    _ => Err(format!("unexpected value at byte {at}")),
                }
            }
        }
    }
}

/// The `[nz, ny, nx]` of `shape`: its last three axes, any axes before
/// them of size 1 (an error naming the first that is not, and what to do).
fn volume_shape(shape: &[usize]) -> std::result::Result<[usize; 3], String> {
    let Some((extra, &[nz, ny, nx])) = shape.split_last_chunk::<3>() else {
        return Err(format!(
            "expected a 3-D array of shape (nz, ny, nx), found shape {}",
            shape_text(shape)
        ));
    };
    // A channel axis last, (nz, ny, nx, 1): the volume is a[..., 0], where
    // a[0] would be a plane and its channels.
    let channel_last = nx == 1
        && extra
            .split_last()
            .is_some_and(|(_, e)| e.iter().all(|&n| n == 1));
    let volume = if channel_last { "a[..., 0]" } else { "a[0]" };
    match extra.iter().position(|&n| n != 1) {
        None => Ok([nz, ny, nx]),
        Some(axis) => Err(format!(
            "shape {} is not one volume: axis {axis} has size {}, not 1 (only axes of size 1 may come before (nz, ny, nx)); save one 3-D volume, e.g. np.save(path, {volume})",
            shape_text(shape),
            extra[axis]
        )),
    }
}

/// `shape` as Python prints it.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => {
            let items: Vec<String> = shape.iter().map(|n| n.to_string()).collect();
            format!("({})", items.join(", "))
        }
    }
}
