//! Opening the samples of one NRRD data file (or the data attached to a
//! `.nrrd` header) as a [`RawVolume`]: `line skip` and `byte skip` applied,
//! then raw data memory-mapped, compressed and hex data decoded into a
//! mapped temporary file, ascii text parsed.
//!
//! Every data file of a multi-file NRRD goes through [`open_data`] on its
//! own, so the skips apply to each file, as the format says.

use super::ascii::read_ascii;
use super::nrrd_header::{read_line, Encoding};
use super::raw::{data_bytes, dims_text, Layout, Order, RawVolume};
use super::{Endian, Grid, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// How the samples are stored in every data file.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DataFormat {
    pub scalar: ScalarType,
    pub endian: Endian,
    pub encoding: Encoding,
    /// Lines to skip before the byte skip.
    pub line_skip: u64,
    /// Bytes to skip after the lines (decompressed bytes for compressed
    /// data); `None`: raw data ends the file.
    pub byte_skip: Option<u64>,
}

/// Opens the samples of `grid` stored in `path` from byte `start` on (the
/// end of the header for attached data, else 0). Errors name `path` only
/// (the caller names the header first, see [`Error::in_data_file`]).
pub(crate) fn open_data(
    path: &Path,
    start: u64,
    grid: Grid,
    format: &DataFormat,
    cancel: &AtomicBool,
) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    // A FIFO data file would block the open below.
    super::check_input_kind(path)?;
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let scalar = format.scalar;
    let data_len = data_bytes(grid.dims, scalar)
        .ok_or_else(|| fail(format!("sizes {} are too large", dims_text(grid.dims))))?;
    let mut reader = BufReader::new(file);
    reader
        .seek(SeekFrom::Start(start))
        .map_err(|e| Error::io(path, e))?;
    let mut offset = start;
    for _ in 0..format.line_skip {
        read_line(&mut reader, &mut offset)
            .map_err(|e| Error::io(path, e))?
            .ok_or_else(|| fail("'line skip' goes past the end of the file".into()))?;
    }
    let layout = |offset: u64| Layout {
        grid,
        scalar,
        endian: format.endian,
        offset,
        order: Order::XFastest,
    };
    let skip = || {
        format
            .byte_skip
            .ok_or_else(|| fail("'byte skip: -1' is only allowed with raw encoding".into()))
    };
    match format.encoding {
        Encoding::Raw => {
            let file = reader.into_inner();
            let offset = match format.byte_skip {
                Some(skip) => offset
                    .checked_add(skip)
                    .ok_or_else(|| fail("'byte skip' is too large".into()))?,
                None => {
                    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
                    len.checked_sub(data_len).ok_or_else(|| {
                        fail(format!(
                            "file has {len} bytes, sizes {} {scalar} need {data_len}",
                            dims_text(grid.dims)
                        ))
                    })?
                }
            };
            RawVolume::map_file(path, &file, layout(offset))
        }
        Encoding::Gzip | Encoding::Bzip2 => {
            let skip = skip()?;
            let mut file = reader.into_inner();
            file.seek(SeekFrom::Start(offset))
                .map_err(|e| Error::io(path, e))?;
            decompressed(path, format.encoding, file, skip, layout(0), cancel)
        }
        Encoding::Ascii => {
            let skip = skip()?;
            skip_text(path, &mut reader, skip)?;
            read_ascii(path, reader, layout(0), false)
        }
        Encoding::Hex => {
            let skip = skip()?;
            skip_text(path, &mut reader, skip)?;
            let bad = |got: u64| {
                fail(format!(
                    "hex data holds {got} bytes, sizes {} {scalar} need {data_len}",
                    dims_text(grid.dims)
                ))
            };
            let hex = HexBytes { inner: reader };
            let (samples, got) = super::spill::spill(path, "hex", &[], hex, data_len, cancel)?;
            if got < data_len {
                return Err(bad(got));
            }
            RawVolume::map_file(path, &samples, layout(0))
        }
    }
}

/// The bytes that `hex` data spells: two hex digits a byte, either case,
/// whitespace anywhere between digits ignored (as teem reads it); another
/// character, or a lone last digit, is an error.
struct HexBytes<R> {
    inner: R,
}

impl<R: BufRead> HexBytes<R> {
    /// The next hex digit's value, `None` at the end of the data.
    fn digit(&mut self) -> io::Result<Option<u8>> {
        loop {
            let Some(&c) = self.inner.fill_buf()?.first() else {
                return Ok(None);
            };
            self.inner.consume(1);
            if c.is_ascii_whitespace() {
                continue;
            }
            return match (c as char).to_digit(16) {
                Some(d) => Ok(Some(d as u8)),
                None => Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!("'{}' is not a hex digit", c.escape_ascii()),
                )),
            };
        }
    }
}

impl<R: BufRead> Read for HexBytes<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        for (n, byte) in buf.iter_mut().enumerate() {
            let Some(high) = self.digit()? else {
                return Ok(n);
            };
            let Some(low) = self.digit()? else {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    "the data ends in the middle of a byte (an odd number of hex digits)",
                ));
            };
            *byte = high << 4 | low;
        }
        Ok(buf.len())
    }
}

/// Decompresses the `encoding` stream that starts at the current position
/// of `file`, drops its first `skip` bytes and wraps the next ones as the
/// samples of `layout` (whose offset must be 0).
///
/// The samples go to a temporary file that is then memory-mapped (see
/// [`super::spill`]), so the volume is never held in memory.
pub(crate) fn decompressed(
    path: &Path,
    encoding: Encoding,
    file: File,
    skip: u64,
    layout: Layout,
    cancel: &AtomicBool,
) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let name = encoding.name();
    let bad = |e: io::Error| fail(format!("bad {name} data: {e}"));
    let len = data_bytes(layout.grid.dims, layout.scalar).ok_or_else(|| {
        fail(format!(
            "sizes {} are too large",
            dims_text(layout.grid.dims)
        ))
    })?;
    let input = BufReader::new(file);
    let mut decoder: Box<dyn Read> = match encoding {
        Encoding::Bzip2 => Box::new(bzip2::read::MultiBzDecoder::new(input)),
        _ => Box::new(flate2::read::MultiGzDecoder::new(input)),
    };
    let short = |got: u64| {
        fail(format!(
            "{name} data holds {got} bytes, sizes {} {} need {len} after a {skip}-byte skip",
            dims_text(layout.grid.dims),
            layout.scalar
        ))
    };
    let skipped = io::copy(&mut decoder.by_ref().take(skip), &mut io::sink()).map_err(bad)?;
    if skipped < skip {
        return Err(short(skipped));
    }
    let (samples, got) = super::spill::spill(path, name, &[], decoder, len, cancel)?;
    if got < len {
        return Err(short(skip + got));
    }
    RawVolume::map_file(path, &samples, layout)
}

/// Skips the first `skip` bytes of text data (`ascii` or `hex`: the file's
/// bytes, not decoded ones, as teem skips them).
fn skip_text(path: &Path, reader: &mut impl BufRead, skip: u64) -> Result<()> {
    let skipped = io::copy(&mut reader.by_ref().take(skip), &mut io::sink())
        .map_err(|e| Error::io(path, e))?;
    if skipped < skip {
        return Err(Error::Format(format!(
            "{}: 'byte skip' goes past the end of the file",
            path.display()
        )));
    }
    Ok(())
}
