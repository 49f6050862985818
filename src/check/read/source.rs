//! What the mesh readers share: a buffered file read line by line and word
//! by word, with line numbers in its errors, and the limits a lying header
//! cannot get past.

use crate::meshfile::MAGIC;
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::Path;

/// Most triangles a mesh may have (indices of triangles are `u32`).
pub(super) const MAX_TRIANGLES: usize = u32::MAX as usize - 1;
/// Pre-allocation cap, so that a lying header cannot exhaust memory.
pub(super) const MAX_RESERVE: usize = 1 << 22;

/// The mesh formats the checker reads, as told by an extension or the
/// first bytes of a file.
pub(super) enum Format {
    Ply,
    Obj,
    Off,
    Tmesh,
    /// STL, binary (`true`: the file's length is that of the facet count
    /// at bytes 80..84) or ASCII.
    Stl(bool),
}

/// A buffered file with a current line and a token cursor in it.
pub(super) struct Source<'a> {
    pub(super) path: &'a Path,
    pub(super) reader: BufReader<File>,
    /// The current line (for the text formats).
    pub(super) buf: Vec<u8>,
    /// Cursor of [`Source::next_token`] in `buf`.
    pub(super) pos: usize,
    /// 1-based number of the line in `buf`.
    pub(super) line: usize,
    /// Whether the line in `buf` ended with a line break (not the file's end).
    pub(super) complete: bool,
}

impl Source<'_> {
    /// An error about the file, without position.
    pub(super) fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::Format(format!("{}: {msg}", self.path.display()))
    }

    /// An error about the current line.
    pub(super) fn err_line(&self, msg: impl std::fmt::Display) -> Error {
        Error::Format(format!(
            "{}: line {}: {msg}",
            self.path.display(),
            self.line
        ))
    }

    pub(super) fn io(&self, e: io::Error) -> Error {
        Error::io(self.path, e)
    }

    /// Guesses the format from the first bytes.
    pub(super) fn sniff(&mut self) -> Result<Format> {
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
            .map(|l| l.trim_start_matches('\u{feff}').trim())
            .find(|l| !l.is_empty() && !l.starts_with('#'))
            .unwrap_or("");
        let word = first.split_ascii_whitespace().next().unwrap_or("");
        if word == "ply" {
            Ok(Format::Ply)
        } else if word.ends_with("OFF") {
            Ok(Format::Off)
        } else if binary_stl(self.path, head) {
            Ok(Format::Stl(true))
        } else if word == "solid" {
            Ok(Format::Stl(false))
        } else if ["v", "vn", "vt", "f", "o", "g", "s", "mtllib", "usemtl"].contains(&word) {
            Ok(Format::Obj)
        } else {
            Err(self.err("unrecognised mesh format (expected a .ply, .obj, .off or .tmesh file)"))
        }
    }

    /// Reads the next line into `buf` (without the line break); false at the
    /// end of the file.
    pub(super) fn next_line(&mut self) -> Result<bool> {
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
    pub(super) fn next_content_line(&mut self) -> Result<bool> {
        while self.next_line()? {
            if self.strip_comment() {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Removes a `#` comment from the current line; true when anything but
    /// whitespace remains.
    pub(super) fn strip_comment(&mut self) -> bool {
        if let Some(hash) = self.buf.iter().position(|&b| b == b'#') {
            self.buf.truncate(hash);
        }
        self.buf.iter().any(|b| !b.is_ascii_whitespace())
    }

    /// The whitespace-separated words of the current line.
    pub(super) fn words(&self) -> impl Iterator<Item = &[u8]> {
        self.buf
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty())
    }

    /// The next whitespace-separated token, reading further lines as needed;
    /// `None` at the end of the file. Returns the token's range in `buf`.
    pub(super) fn next_token(&mut self) -> Result<Option<(usize, usize)>> {
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

pub(super) fn parse<T: std::str::FromStr>(word: &[u8]) -> Option<T> {
    std::str::from_utf8(word).ok()?.parse().ok()
}

/// `word` as a finite number (`nan` and `inf` parse as `f64`, but are no
/// normal, colour or texture coordinate).
pub(super) fn finite(word: &[u8]) -> Option<f64> {
    parse::<f64>(word).filter(|v| v.is_finite())
}

/// The three coordinates that follow the first `skip` words of the current
/// line (of an OBJ or OFF file), which must be finite `f32` numbers.
pub(super) fn point(src: &Source, skip: usize) -> Result<[f32; 3]> {
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
pub(super) fn push_fan(triangles: &mut Vec<[u32; 3]>, polygon: &[u32]) {
    for i in 1..polygon.len().saturating_sub(1) {
        triangles.push([polygon[0], polygon[i], polygon[i + 1]]);
    }
}

/// Whether the file at `path`, whose first bytes are `head`, is a binary
/// STL: an 80-byte header, a triangle count `n` and `n` records of 50
/// bytes, so the file is exactly `84 + 50 n` bytes long. Any other binary
/// file (a volume given by mistake, say) is an unknown format, not STL.
pub(super) fn binary_stl(path: &Path, head: &[u8]) -> bool {
    let Some(count) = head.get(80..84) else {
        return false;
    };
    let count = u32::from_le_bytes(count.try_into().expect("four bytes"));
    std::fs::metadata(path).is_ok_and(|m| m.len() == 84 + 50 * u64::from(count))
}

/// The error for an STL file given to an extension's reader of `.stl`
/// that is neither binary nor ASCII STL.
pub(super) fn not_stl(path: &Path) -> Error {
    Error::Format(format!(
        "{}: not an STL file: neither a binary STL (84 bytes and 50 a facet) nor ASCII \
         (starting with 'solid')",
        path.display()
    ))
}

/// The error for an STL file, which the checker does not read.
pub(super) fn stl_error(path: &Path) -> Error {
    Error::Format(format!(
        "{}: STL does not share vertices between triangles, so its topology cannot be \
         checked; write PLY, OBJ or OFF instead",
        path.display()
    ))
}
