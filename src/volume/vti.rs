//! The VTK XML image reader (`.vti`, `ImageData`).
//!
//! Reads `WholeExtent`, `Spacing`, `Origin` and `Direction`, and the first
//! `PointData` `DataArray` (the one named by the `Scalars` attribute if
//! there is one), one component of type `Int8` .. `Float64` (no 64-bit
//! integers). Formats: `ascii`, `binary` (base64 with a `UInt32` or `UInt64`
//! header per `header_type`, optionally compressed by
//! `vtkZLibDataCompressor`) and `appended` (raw or base64 after the `_`),
//! in either `byte_order`. Raw uncompressed appended data is memory-mapped;
//! everything else is decoded into memory.
//!
//! As in VTK, sample index `(i, j, k)` of `WholeExtent = x0 x1 y0 y1 z0 z1`
//! sits at `Origin + Direction * ((x0 + i, y0 + j, z0 + k) * Spacing)`
//! (`Direction` row-major, the identity when absent); the whole map goes
//! into the [`Grid`], a mirroring `Direction` flipping the winding.

use super::ascii::read_ascii;
use super::raw::{Layout, Order, RawVolume};
use super::{Access, Endian, Grid, SampleSource, ScalarType};
use crate::{Error, Result};
use base64::Engine;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::ops::Range;
use std::path::Path;

/// Longest XML text before the appended data (or the whole file without it)
/// that is read into memory.
const MAX_XML: usize = 1 << 30;

/// A `.vti` volume: the samples plus the image orientation.
#[derive(Debug)]
pub struct VtiVolume {
    inner: RawVolume,
}

impl VtiVolume {
    /// The `Direction` matrix of the image (identity if absent); the same
    /// as the grid's.
    pub fn direction(&self) -> [[f64; 3]; 3] {
        self.inner.grid().direction
    }

    /// The stored sample type.
    pub fn scalar(&self) -> ScalarType {
        self.inner.scalar()
    }
}

impl SampleSource for VtiVolume {
    fn grid(&self) -> &Grid {
        self.inner.grid()
    }
    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        self.inner.read_plane(z, out)
    }
    fn advise(&self, planes: Range<usize>, access: Access) {
        self.inner.advise(planes, access)
    }
    fn check_unchanged(&self) -> Result<()> {
        self.inner.check_unchanged()
    }
    fn data_files(&self) -> Vec<&Path> {
        self.inner.data_files()
    }
    fn sample_bytes(&self) -> usize {
        self.inner.sample_bytes()
    }
    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.inner.scalar())
    }
}

/// The `key="value"` attributes of an XML tag.
type Attrs = Vec<(String, String)>;

/// The attributes of the XML start tag `<name ...>` found at or after
/// `from` in `text`, with the position just after its `>`.
fn find_tag(text: &str, name: &str, from: usize) -> Option<(Attrs, usize, usize)> {
    let pat = format!("<{name}");
    let mut at = from;
    loop {
        let start = at + text.get(at..)?.find(&pat)?;
        let after = start + pat.len();
        let c = text[after..].chars().next()?;
        if c.is_whitespace() || c == '>' || c == '/' {
            let end = after + text[after..].find('>')?;
            return Some((attributes(&text[after..end]), start, end + 1));
        }
        at = after;
    }
}

/// Parses `key="value"` pairs.
fn attributes(s: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = s;
    while let Some(eq) = rest.find('=') {
        let key = rest[..eq].trim().trim_end_matches('/').to_string();
        let after = rest[eq + 1..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            break;
        };
        let Some(close) = after[1..].find(q) else {
            break;
        };
        out.push((key, after[1..1 + close].to_string()));
        rest = &after[close + 2..];
    }
    out
}

fn attr<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn numbers<T: std::str::FromStr>(
    s: &str,
    n: usize,
    what: &str,
) -> std::result::Result<Vec<T>, String> {
    let v: Option<Vec<T>> = s.split_whitespace().map(|w| w.parse().ok()).collect();
    match v {
        Some(v) if v.len() == n => Ok(v),
        _ => Err(format!("{what} needs {n} numbers, got '{s}'")),
    }
}

/// The sample type of a VTK XML type name.
fn xml_type(name: &str) -> std::result::Result<ScalarType, String> {
    Ok(match name {
        "Int8" | "Char" => ScalarType::I8,
        "UInt8" => ScalarType::U8,
        "Int16" => ScalarType::I16,
        "UInt16" => ScalarType::U16,
        "Int32" => ScalarType::I32,
        "UInt32" => ScalarType::U32,
        "Float32" => ScalarType::F32,
        "Float64" => ScalarType::F64,
        "Int64" => ScalarType::I64,
        "UInt64" => ScalarType::U64,
        other => return Err(format!("unsupported DataArray type '{other}'")),
    })
}

/// Where and how the samples of the chosen array are stored.
struct Header {
    grid: Grid,
    scalar: ScalarType,
    endian: Endian,
    /// Width of a binary header integer (4 or 8).
    word: usize,
    compressed: bool,
    format: String,
    /// Inline content (ascii or binary format).
    content: String,
    /// Offset into the appended data (appended format).
    offset: usize,
}

/// Reads the `UInt32`/`UInt64` word `i` of `bytes`.
fn word(bytes: &[u8], i: usize, w: usize, endian: Endian) -> Option<u64> {
    let b = bytes.get(i * w..(i + 1) * w)?;
    Some(match (w, endian) {
        (4, Endian::Little) => u32::from_le_bytes(b.try_into().ok()?) as u64,
        (4, Endian::Big) => u32::from_be_bytes(b.try_into().ok()?) as u64,
        (_, Endian::Little) => u64::from_le_bytes(b.try_into().ok()?),
        (_, Endian::Big) => u64::from_be_bytes(b.try_into().ok()?),
    })
}

/// Decodes base64 `chars` (no whitespace), reporting errors as text.
fn b64(chars: &[u8]) -> std::result::Result<Vec<u8>, String> {
    base64::engine::general_purpose::STANDARD
        .decode(chars)
        .map_err(|e| format!("bad base64 data: {e}"))
}

/// Characters that encode `n` bytes in padded base64.
fn b64_len(n: usize) -> usize {
    n.div_ceil(3) * 4
}

/// The sizes in a compression header: block size, last block size and the
/// compressed size of each block.
struct Blocks {
    block: usize,
    last: usize,
    sizes: Vec<usize>,
}

fn parse_blocks(hdr: &[u8], w: usize, e: Endian) -> std::result::Result<Blocks, String> {
    let bad = || "truncated compression header".to_string();
    let n = word(hdr, 0, w, e).ok_or_else(bad)? as usize;
    let block = word(hdr, 1, w, e).ok_or_else(bad)? as usize;
    let last = word(hdr, 2, w, e).ok_or_else(bad)? as usize;
    let mut sizes = Vec::with_capacity(n.min(1 << 20));
    for i in 0..n {
        sizes.push(word(hdr, 3 + i, w, e).ok_or_else(bad)? as usize);
    }
    Ok(Blocks { block, last, sizes })
}

/// Inflates the zlib blocks of `data` described by `blocks`.
fn inflate(blocks: &Blocks, data: &[u8], expect: usize) -> std::result::Result<Vec<u8>, String> {
    let n = blocks.sizes.len();
    let mut out = Vec::with_capacity(expect);
    let mut at = 0usize;
    for (i, &size) in blocks.sizes.iter().enumerate() {
        let chunk = at
            .checked_add(size)
            .and_then(|end| data.get(at..end))
            .ok_or_else(|| format!("compressed block {i} runs past the end of the data"))?;
        at += size;
        let want = if i + 1 == n && blocks.last != 0 {
            blocks.last
        } else {
            blocks.block
        };
        let before = out.len();
        flate2::read::ZlibDecoder::new(chunk)
            .take(want as u64 + 1)
            .read_to_end(&mut out)
            .map_err(|e| format!("compressed block {i}: {e}"))?;
        if out.len() - before != want {
            return Err(format!(
                "compressed block {i} inflates to {} bytes, expected {want}",
                out.len() - before
            ));
        }
    }
    Ok(out)
}

/// Decodes a binary block (header + data) given as raw bytes.
fn raw_block(h: &Header, bytes: &[u8]) -> std::result::Result<Vec<u8>, String> {
    let (w, e) = (h.word, h.endian);
    if !h.compressed {
        let len = word(bytes, 0, w, e).ok_or("truncated data header")? as usize;
        return bytes
            .get(w..w.saturating_add(len))
            .map(<[u8]>::to_vec)
            .ok_or_else(|| format!("data header says {len} bytes, fewer are present"));
    }
    let n = word(bytes, 0, w, e).ok_or("truncated compression header")? as usize;
    let hlen = n.saturating_add(3).saturating_mul(w);
    let hdr = bytes.get(..hlen).ok_or("truncated compression header")?;
    let blocks = parse_blocks(hdr, w, e)?;
    inflate(&blocks, &bytes[hlen..], 0)
}

/// Decodes a binary block given as base64 (whitespace already removed);
/// VTK encodes the header and the data either as one stream or as two.
fn b64_block(h: &Header, chars: &[u8]) -> std::result::Result<Vec<u8>, String> {
    let (w, e) = (h.word, h.endian);
    let first = |n: usize| chars.get(..n).ok_or("truncated base64 data".to_string());
    if !h.compressed {
        let head = b64(first(b64_len(w))?)?;
        let len = word(&head, 0, w, e).ok_or("truncated data header")? as usize;
        let separate = first(b64_len(w))?.contains(&b'=');
        let bytes = if separate {
            let start = b64_len(w);
            let data = chars
                .get(start..start.saturating_add(b64_len(len)))
                .ok_or("truncated base64 data")?;
            let mut v = head[..w].to_vec();
            v.extend(b64(data)?);
            v
        } else {
            b64(first(b64_len(w.saturating_add(len)))?)?
        };
        return raw_block(h, &bytes);
    }
    let fixed = b64(first(b64_len(3 * w))?)?;
    let n = word(&fixed, 0, w, e).ok_or("truncated compression header")? as usize;
    let hlen = n.saturating_add(3).saturating_mul(w);
    let hchars = b64_len(hlen);
    let hdr = b64(first(hchars)?)?;
    let blocks = parse_blocks(&hdr, w, e)?;
    let total = blocks
        .sizes
        .iter()
        .try_fold(0usize, |a, &s| a.checked_add(s));
    let total = total.ok_or("compressed sizes overflow")?;
    let data = chars
        .get(hchars..hchars.saturating_add(b64_len(total)))
        .ok_or("truncated base64 data")?;
    inflate(&blocks, &b64(data)?, 0)
}

/// Opens a `.vti` file.
pub fn open(path: &Path) -> Result<VtiVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    // Read the XML up to the appended data (or the whole file).
    let mut reader = BufReader::new(file);
    let mut xml = Vec::new();
    let mut data_start = None;
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = reader.read(&mut chunk).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        let scan_from = xml.len().saturating_sub(16);
        xml.extend_from_slice(&chunk[..n]);
        if let Some(p) = find_bytes(&xml[scan_from..], b"<AppendedData") {
            let tag = scan_from + p;
            if let Some(gt) = xml[tag..].iter().position(|&b| b == b'>') {
                if let Some(us) = xml[tag + gt..].iter().position(|&b| b == b'_') {
                    data_start = Some(tag + gt + us + 1);
                    break;
                }
            }
        }
        if xml.len() > MAX_XML {
            return Err(fail("XML text too long".into()));
        }
    }
    let text_end = match data_start {
        Some(d) => find_bytes(&xml, b"<AppendedData").unwrap_or(d),
        None => xml.len(),
    };
    let text = String::from_utf8_lossy(&xml[..text_end]).into_owned();
    let h = parse_header(&text).map_err(fail)?;
    let layout = |scalar, endian| Layout {
        grid: h.grid,
        scalar,
        endian,
        offset: 0,
        order: Order::XFastest,
    };
    let count = h.grid.dims.iter().product::<usize>();
    let bytes = match h.format.as_str() {
        "ascii" => {
            let layout = layout(h.scalar, Endian::Little);
            let inner = read_ascii(path, h.content.as_bytes(), layout, false)?;
            return Ok(VtiVolume { inner });
        }
        "binary" => {
            let chars: Vec<u8> = h
                .content
                .bytes()
                .filter(|b| !b.is_ascii_whitespace())
                .collect();
            b64_block(&h, &chars).map_err(fail)?
        }
        "appended" => {
            let start = data_start
                .ok_or_else(|| fail("format=\"appended\" but no <AppendedData> with '_'".into()))?;
            let encoding = find_tag(
                &String::from_utf8_lossy(&xml[text_end..start]),
                "AppendedData",
                0,
            )
            .and_then(|(a, _, _)| attr(&a, "encoding").map(str::to_string))
            .unwrap_or_else(|| "raw".into());
            let at = (start as u64)
                .checked_add(h.offset as u64)
                .ok_or_else(|| fail("offset too large".into()))?;
            let mut file = reader.into_inner();
            match encoding.as_str() {
                "raw" if !h.compressed => {
                    let mut head = vec![0u8; h.word];
                    file.seek(SeekFrom::Start(at))
                        .and_then(|_| file.read_exact(&mut head))
                        .map_err(|_| fail("appended data truncated (no data header)".into()))?;
                    let len = word(&head, 0, h.word, h.endian).unwrap_or(0);
                    let need =
                        crate::volume::raw::data_bytes(h.grid.dims, h.scalar).unwrap_or(u64::MAX);
                    if len != need {
                        return Err(fail(format!(
                            "DataArray holds {len} bytes, the extent needs {need}"
                        )));
                    }
                    let mut l = layout(h.scalar, h.endian);
                    l.offset = at + h.word as u64;
                    let inner = RawVolume::map_file(path, &file, l)?;
                    return Ok(VtiVolume { inner });
                }
                "raw" => {
                    let mut rest = Vec::new();
                    file.seek(SeekFrom::Start(at))
                        .and_then(|_| file.read_to_end(&mut rest))
                        .map_err(|e| Error::io(path, e))?;
                    raw_block(&h, &rest).map_err(fail)?
                }
                "base64" => {
                    let mut rest = Vec::new();
                    file.seek(SeekFrom::Start(at))
                        .and_then(|_| file.read_to_end(&mut rest))
                        .map_err(|e| Error::io(path, e))?;
                    let end = rest
                        .iter()
                        .position(|&b| b == b'<' || b.is_ascii_whitespace())
                        .unwrap_or(rest.len());
                    b64_block(&h, &rest[..end]).map_err(fail)?
                }
                other => return Err(fail(format!("unknown AppendedData encoding '{other}'"))),
            }
        }
        other => return Err(fail(format!("unknown DataArray format '{other}'"))),
    };
    let need = count * h.scalar.size();
    if bytes.len() != need {
        return Err(fail(format!(
            "DataArray holds {} bytes, the extent needs {need}",
            bytes.len()
        )));
    }
    let inner = RawVolume::from_bytes(path, bytes, layout(h.scalar, h.endian))?;
    Ok(VtiVolume { inner })
}

fn find_bytes(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Parses the XML text before the appended data.
fn parse_header(text: &str) -> std::result::Result<Header, String> {
    let (file_attrs, _, _) =
        find_tag(text, "VTKFile", 0).ok_or("not a VTK XML file (no <VTKFile>)")?;
    if attr(&file_attrs, "type") != Some("ImageData") {
        return Err(format!(
            "VTKFile type {:?} is not supported (need ImageData)",
            attr(&file_attrs, "type").unwrap_or("")
        ));
    }
    let endian = match attr(&file_attrs, "byte_order").unwrap_or("LittleEndian") {
        "LittleEndian" => Endian::Little,
        "BigEndian" => Endian::Big,
        other => return Err(format!("unknown byte_order '{other}'")),
    };
    let word = match attr(&file_attrs, "header_type").unwrap_or("UInt32") {
        "UInt32" => 4,
        "UInt64" => 8,
        other => return Err(format!("unknown header_type '{other}'")),
    };
    let compressed = match attr(&file_attrs, "compressor") {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => {
            return Err(format!(
                "compressor '{other}' is not supported (only vtkZLibDataCompressor)"
            ))
        }
    };
    let (img, _, _) = find_tag(text, "ImageData", 0).ok_or("no <ImageData> element")?;
    let ext: Vec<i64> = numbers(
        attr(&img, "WholeExtent").ok_or("missing WholeExtent")?,
        6,
        "WholeExtent",
    )?;
    let mut dims = [0usize; 3];
    for a in 0..3 {
        let n = ext[2 * a + 1] - ext[2 * a] + 1;
        if n < 1 {
            return Err(format!("WholeExtent {ext:?} is empty"));
        }
        dims[a] = n as usize;
    }
    let spacing: Vec<f64> = match attr(&img, "Spacing") {
        Some(s) => numbers(s, 3, "Spacing")?,
        None => vec![1.0; 3],
    };
    let origin: Vec<f64> = match attr(&img, "Origin") {
        Some(s) => numbers(s, 3, "Origin")?,
        None => vec![0.0; 3],
    };
    let mut direction = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    if let Some(s) = attr(&img, "Direction") {
        let d: Vec<f64> = numbers(s, 9, "Direction")?;
        for r in 0..3 {
            direction[r].copy_from_slice(&d[3 * r..3 * r + 3]);
        }
    }
    let mut grid = Grid {
        dims,
        spacing: [spacing[0], spacing[1], spacing[2]],
        origin: [origin[0], origin[1], origin[2]],
        direction: super::IDENTITY,
    };
    super::set_direction(&mut grid, direction).map_err(|e| format!("Direction: {e}"))?;
    // The grid starts at the extent's first sample.
    grid.origin = grid.world([ext[0] as f64, ext[2] as f64, ext[4] as f64]);
    let pieces = text.matches("<Piece").count();
    if pieces > 1 {
        return Err(format!("{pieces} pieces are not supported (need 1)"));
    }
    if let Some((piece, _, _)) = find_tag(text, "Piece", 0) {
        if let Some(pe) = attr(&piece, "Extent") {
            let pe: Vec<i64> = numbers(pe, 6, "Piece Extent")?;
            if pe != ext {
                return Err(format!(
                    "Piece Extent {pe:?} differs from WholeExtent {ext:?}"
                ));
            }
        }
    }
    let (pd, _, pd_end) = find_tag(text, "PointData", 0).ok_or("no <PointData> element")?;
    let pd_close = text[pd_end..]
        .find("</PointData>")
        .map_or(text.len(), |p| pd_end + p);
    let wanted = attr(&pd, "Scalars");
    let mut arrays = Vec::new();
    let mut at = pd_end;
    while let Some((a, _, end)) = find_tag(text, "DataArray", at) {
        if end > pd_close {
            break;
        }
        arrays.push((a, end));
        at = end;
    }
    let (a, end) = wanted
        .and_then(|w| arrays.iter().find(|(a, _)| attr(a, "Name") == Some(w)))
        .or(arrays.first())
        .cloned()
        .ok_or("no DataArray in <PointData>")?;
    let scalar = xml_type(attr(&a, "type").ok_or("DataArray without type")?)?;
    let comps = attr(&a, "NumberOfComponents").unwrap_or("1");
    if comps != "1" {
        return Err(format!(
            "DataArray with {comps} components is not supported (need 1)"
        ));
    }
    let format = attr(&a, "format")
        .ok_or("DataArray without format")?
        .to_string();
    let content = if text[..end].ends_with("/>") {
        String::new()
    } else {
        let close = text[end..]
            .find("</DataArray>")
            .ok_or("DataArray not closed")?;
        text[end..end + close].to_string()
    };
    let offset = match attr(&a, "offset") {
        Some(o) => o
            .trim()
            .parse()
            .map_err(|_| format!("bad DataArray offset '{o}'"))?,
        None => 0,
    };
    Ok(Header {
        grid,
        scalar,
        endian,
        word,
        compressed,
        format,
        content,
        offset,
    })
}
