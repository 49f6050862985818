//! A check of a DICOM file's element lengths against its size, made before
//! the file is parsed.
//!
//! The DICOM parser allocates (and zero-fills) a value of the length an
//! element claims before it reads it, so a damaged file of a few hundred
//! bytes claiming a 4 GiB value costs gigabytes and seconds before the
//! error. This walk reads only element headers (seeking over the values)
//! and refuses a value that runs past the end of the file. It descends
//! into sequences and items, so nested elements are checked too, and skips
//! the fragments of encapsulated pixel data. It refuses sequences nested
//! deeper than [`MAX_DEPTH`], which the parser would follow by recursion
//! until the stack overflows, and it reports what it saw of the pixel data
//! so that the header's image size can be checked against it.
//!
//! A deflated data set is inflated twice, without being kept: once to learn
//! its size (refusing one that inflates beyond [`inflate_cap`]), once to
//! walk it against that size. (Deflated frames, [`DEFLATED_FRAMES`], are
//! fragments of an ordinary data set; [`inflates_beyond`] bounds each one.)
//! What it does not check is
//! left to the parser: a file without the `DICM` magic, a data set it cannot
//! inflate and a header cut short by the end of the file.

use super::walker::{is_sequence, Encoding, Walker};
use dicom_core::Tag;
use flate2::read::DeflateDecoder;
use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

/// An undefined length: a sequence, an item or encapsulated pixel data
/// ends at a delimitation item instead.
const UNDEFINED: u32 = 0xFFFF_FFFF;
const ITEM: Tag = Tag(0xFFFE, 0xE000);
const ITEM_DELIMITER: Tag = Tag(0xFFFE, 0xE00D);
const SEQUENCE_DELIMITER: Tag = Tag(0xFFFE, 0xE0DD);
const PIXEL_DATA: Tag = Tag(0x7FE0, 0x0010);
/// The transfer syntaxes whose data set is not explicit VR little endian.
const IMPLICIT_VR_LE: &str = "1.2.840.10008.1.2";
const EXPLICIT_VR_BE: &str = "1.2.840.10008.1.2.2";
/// Deflated explicit VR little endian: the data set is a raw deflate stream.
const DEFLATED: &str = "1.2.840.10008.1.2.1.99";
/// Deflated Image Frame Compression: an explicit VR little endian data set
/// whose encapsulated pixel data holds one raw deflate stream per frame.
/// The data set is walked like any explicit VR little endian one; each
/// frame is checked with [`inflates_beyond`] before it is decoded.
pub const DEFLATED_FRAMES: &str = "1.2.840.10008.1.2.8.1";

/// A UID or code string without the padding DICOM adds to reach an even
/// length (a NUL or a space).
pub fn unpadded(value: &str) -> &str {
    value.trim_end_matches(['\0', ' '])
}

/// The least [`inflate_cap`] allows a deflated data set, whatever the file
/// size: 256 MiB.
pub const INFLATE_FLOOR: u64 = 256 << 20;

/// The most bytes [`inflate_cap`] allows a deflated data set per byte of
/// its file, above [`INFLATE_FLOOR`].
pub const INFLATE_RATIO: u64 = 64;

/// The most bytes the deflated data set of a file of `file_size` bytes may
/// inflate to: the larger of [`INFLATE_FLOOR`] and [`INFLATE_RATIO`] times
/// the file size.
///
/// Deflate inflates up to 1032 bytes per byte, so the file size alone lets
/// a 4 MB file claim a 4 GB data set, which the parser would hold in memory
/// (it keeps every value it reads) after this walk inflated it twice. Image
/// data deflates about 2-4:1 (CT, MR); only constant regions deflate much
/// better, so 64:1 leaves a wide margin for a real series, and the floor
/// admits any single slice however uniform (a 4096x4096 slice of 32-bit
/// samples is 64 MiB) and a multi-frame file of 256 MiB. A file beyond the
/// cap is refused after inflating the cap plus one byte, in one streaming
/// pass that keeps nothing, before the parser sees it.
pub fn inflate_cap(file_size: u64) -> u64 {
    INFLATE_FLOOR.max(file_size.saturating_mul(INFLATE_RATIO))
}

/// The deepest nesting of sequences and items (each counts one level)
/// that is walked. Real files nest a few levels; the parser recurses once
/// per level, and ten thousand levels overflow the main thread's stack.
pub const MAX_DEPTH: usize = 256;

/// The pixel data element of the top level data set, as the walk saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelData {
    /// Native (uncompressed) pixel data of this many bytes.
    Native(u64),
    /// Encapsulated pixel data: this many fragments after the offset table
    /// (each frame takes at least one).
    Fragments(u64),
}

/// How the data set after the meta group is stored.
#[derive(Clone, Copy)]
enum Stored {
    /// As it is, in this encoding.
    Plain(Encoding),
    /// Deflated, explicit VR little endian once inflated.
    Deflated,
}

/// Checks every element length of the DICOM file at `path` against the
/// file size, and the nesting of its sequences against [`MAX_DEPTH`].
/// `Err` holds a message (without the path) for a value that runs past the
/// end or too deep a nesting; a file this walk cannot follow is left to the
/// parser. `Ok` holds the top level pixel data, if the walk reached it.
pub fn check(path: &Path) -> Result<Option<PixelData>, String> {
    let Ok(file) = File::open(path) else {
        return Ok(None);
    };
    let Ok(size) = file.metadata().map(|m| m.len()) else {
        return Ok(None);
    };
    check_reader(BufReader::with_capacity(4096, file), size)
}

/// [`check`] on any seekable input of `size` bytes.
fn check_reader<R: Read + Seek>(input: R, size: u64) -> Result<Option<PixelData>, String> {
    let mut w = Walker {
        input,
        pos: 0,
        size,
        what: "the file",
    };
    // The preamble and magic; a file without them is left to the parser.
    match w.bytes::<132>() {
        Some(head) if &head[128..] == b"DICM" => {}
        _ => return Ok(None),
    }
    match meta_group(&mut w)? {
        None => Ok(None),
        Some(Stored::Plain(encoding)) => data_set(&mut w, encoding),
        Some(Stored::Deflated) => deflated_data_set(w, inflate_cap(size)),
    }
}

/// Walks a deflated data set, which starts at the walker's position, if it
/// inflates to `cap` bytes at most.
fn deflated_data_set<R: Read + Seek>(
    mut w: Walker<R>,
    cap: u64,
) -> Result<Option<PixelData>, String> {
    let start = w.pos;
    // A stream that does not inflate is the parser's to report, unless it
    // inflates beyond the cap before it fails: the parser would too.
    let size = inflate_from(&mut w.input, start).and_then(|d| count_up_to(d, cap));
    if size.as_ref().is_ok_and(|&n| n > cap) {
        return Err(format!(
            "not a readable DICOM file: its deflated data set inflates to more than {cap} bytes, the most tmc inflates from a file of {} bytes (the larger of {} MiB and {INFLATE_RATIO} times the file size; a decompression bomb or damaged: store it uncompressed to read it)",
            w.size,
            INFLATE_FLOOR >> 20
        ));
    }
    let (Ok(size), Ok(decoder)) = (size, inflate_from(&mut w.input, start)) else {
        return Ok(None);
    };
    let mut inflated = Walker {
        input: Forward(decoder),
        pos: 0,
        size,
        what: "the inflated data set",
    };
    let explicit_le = Encoding {
        explicit_vr: true,
        big_endian: false,
    };
    data_set(&mut inflated, explicit_le)
}

/// The bytes `input` yields, counted (and dropped) up to `cap + 1`: more
/// than `cap` means beyond the cap, whatever follows.
fn count_up_to(input: impl Read, cap: u64) -> io::Result<u64> {
    io::copy(&mut input.take(cap.saturating_add(1)), &mut io::sink())
}

/// Does the raw deflate stream `compressed` inflate to more than `cap`
/// bytes? Inflated in one streaming pass that keeps nothing and stops one
/// byte past the cap. A stream that fails to inflate before the cap is not
/// beyond it (`false`): its error is the decoder's to report.
pub fn inflates_beyond(compressed: &[u8], cap: u64) -> bool {
    count_up_to(DeflateDecoder::new(compressed), cap).is_ok_and(|n| n > cap)
}

/// A raw deflate decoder of `input` from byte `start` on.
fn inflate_from<R: Read + Seek>(input: &mut R, start: u64) -> io::Result<DeflateDecoder<&mut R>> {
    input.seek(SeekFrom::Start(start))?;
    Ok(DeflateDecoder::new(input))
}

/// A stream that can only skip forward, which is all the walk asks of
/// [`Seek`].
struct Forward<R>(R);

impl<R: Read> Read for Forward<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.0.read(buf)
    }
}

impl<R: Read> Seek for Forward<R> {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        match to {
            SeekFrom::Current(n) if n >= 0 => {
                let n = n as u64;
                let skipped = io::copy(&mut (&mut self.0).take(n), &mut io::sink())?;
                if skipped < n {
                    return Err(io::ErrorKind::UnexpectedEof.into());
                }
                Ok(skipped)
            }
            _ => Err(io::ErrorKind::Unsupported.into()),
        }
    }
}

/// Walks the meta group (explicit VR little endian) and returns how the
/// data set is stored, `None` when it cannot be checked. Like the parser, it
/// reads the group length (0002,0000) first and then elements, whatever
/// their tags, until that many bytes are read.
fn meta_group<R: Read + Seek>(w: &mut Walker<R>) -> Result<Option<Stored>, String> {
    let meta = Encoding {
        explicit_vr: true,
        big_endian: false,
    };
    // The parser refuses any other first element before reading a value.
    match w.header(meta) {
        Some((Tag(0x0002, 0x0000), _, 4)) => {}
        _ => return Ok(None),
    }
    let Some(group_length) = w.u32(false) else {
        return Ok(None);
    };
    let end = w.pos + u64::from(group_length);
    let mut syntax = None;
    while w.pos < end {
        let Some((tag, _, len)) = w.header(meta) else {
            return Ok(None);
        };
        if len == UNDEFINED {
            return Ok(None); // refused by the parser
        }
        w.fits(tag, len)?;
        if tag == Tag(0x0002, 0x0010) {
            let mut uid = vec![0u8; len as usize];
            if w.input.read_exact(&mut uid).is_err() {
                return Ok(None);
            }
            w.pos += u64::from(len);
            let uid = String::from_utf8_lossy(&uid);
            syntax = Some(unpadded(&uid).to_string());
        } else if w.skip(len).is_none() {
            return Ok(None);
        }
    }
    let Some(syntax) = syntax else {
        return Ok(None);
    };
    match syntax.as_str() {
        DEFLATED => Ok(Some(Stored::Deflated)),
        _ => Ok(Some(Stored::Plain(Encoding {
            explicit_vr: syntax != IMPLICIT_VR_LE,
            big_endian: syntax == EXPLICIT_VR_BE,
        }))),
    }
}

/// Walks the data set to the end of the file. Values of sequences and of
/// their items are walked into (their lengths only checked); fragments of
/// encapsulated pixel data are skipped, and counted.
fn data_set<R: Read + Seek>(w: &mut Walker<R>, enc: Encoding) -> Result<Option<PixelData>, String> {
    // The sequences and items walked into, innermost last: where each ends
    // (`None`: at its delimiter). At most MAX_DEPTH + 1 entries.
    let mut open: Vec<Option<u64>> = Vec::new();
    let mut pixels = None;
    let mut in_fragments = false;
    let mut seen_table = false;
    loop {
        let start = w.pos;
        while open
            .last()
            .is_some_and(|end| end.is_some_and(|e| e <= start))
        {
            open.pop();
        }
        let Some((tag, vr, len)) = w.header(enc) else {
            break;
        };
        if tag == SEQUENCE_DELIMITER || tag == ITEM_DELIMITER {
            // Closes the innermost container of undefined length.
            while let Some(Some(_)) = open.last() {
                open.pop();
            }
            open.pop();
        }
        if tag == SEQUENCE_DELIMITER {
            in_fragments = false;
        }
        if tag.0 == 0xFFFE && tag != ITEM {
            continue; // delimiters have no value
        }
        if in_fragments && tag == ITEM {
            // An item of the top level pixel data: the basic offset table
            // first, then the fragments.
            if let Some(PixelData::Fragments(n)) = &mut pixels {
                *n += u64::from(open.len() == 1 && seen_table);
                seen_table |= open.len() == 1;
            }
        }
        if len == UNDEFINED {
            if tag == PIXEL_DATA {
                // Encapsulated pixel data: fragment items to skip.
                in_fragments = true;
                if open.is_empty() {
                    pixels = Some(PixelData::Fragments(0));
                }
            } else if tag != ITEM && !is_sequence(tag, vr) {
                // UN of undefined length (a sequence in implicit VR inside
                // an explicit VR data set): left to the parser.
                return Ok(pixels);
            }
            open.push(None);
            if open.len() > MAX_DEPTH {
                return Err(too_deep(tag, start));
            }
            continue; // walk into the sequence or item
        }
        w.fits(tag, len)?;
        if tag == PIXEL_DATA && open.is_empty() {
            pixels = Some(PixelData::Native(u64::from(len)));
        }
        let walk_into = !in_fragments && (tag == ITEM || is_sequence(tag, vr));
        if walk_into {
            open.push(Some(w.pos + u64::from(len)));
            if open.len() > MAX_DEPTH {
                return Err(too_deep(tag, start));
            }
        } else if w.skip(len).is_none() {
            break;
        }
    }
    Ok(pixels)
}

/// The message for a container opened beyond [`MAX_DEPTH`].
fn too_deep(tag: Tag, at: u64) -> String {
    format!(
        "not a readable DICOM file: element ({:04X},{:04X}) at byte {at} opens a sequence or item nested more than {MAX_DEPTH} deep (damaged or hostile)",
        tag.0, tag.1
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// A file: preamble, magic, a transfer syntax element, then `body`.
    fn file(syntax: &str, body: &[u8]) -> Vec<u8> {
        let mut f = vec![0u8; 128];
        f.extend_from_slice(b"DICM");
        let mut uid = syntax.as_bytes().to_vec();
        if uid.len() % 2 == 1 {
            uid.push(0);
        }
        // Group length: the transfer syntax element that follows.
        f.extend_from_slice(&[0x02, 0x00, 0x00, 0x00, b'U', b'L', 4, 0]);
        f.extend_from_slice(&(8 + uid.len() as u32).to_le_bytes());
        f.extend_from_slice(&[0x02, 0x00, 0x10, 0x00, b'U', b'I']);
        f.extend_from_slice(&(uid.len() as u16).to_le_bytes());
        f.extend_from_slice(&uid);
        f.extend_from_slice(body);
        f
    }

    fn run(f: &[u8]) -> Result<(), String> {
        walk(f).map(|_| ())
    }

    fn walk(f: &[u8]) -> Result<Option<PixelData>, String> {
        check_reader(Cursor::new(f), f.len() as u64)
    }

    /// An implicit VR element: tag and a 4-byte length.
    fn implicit(g: u16, e: u16, len: u32, value: &[u8]) -> Vec<u8> {
        let mut v = Vec::new();
        v.extend_from_slice(&g.to_le_bytes());
        v.extend_from_slice(&e.to_le_bytes());
        v.extend_from_slice(&len.to_le_bytes());
        v.extend_from_slice(value);
        v
    }

    #[test]
    fn a_short_value_that_fits_passes() {
        let body = implicit(0x0010, 0x0010, 4, b"DOE ");
        assert_eq!(run(&file(IMPLICIT_VR_LE, &body)), Ok(()));
    }

    #[test]
    fn a_value_past_the_end_is_refused() {
        let body = implicit(0x0028, 0x1052, 0xFFFF_FFF0, b"1.0 ");
        let e = run(&file(IMPLICIT_VR_LE, &body)).unwrap_err();
        assert!(e.contains("(0028,1052)") && e.contains("4294967280"), "{e}");
    }

    #[test]
    fn an_element_nested_in_a_sequence_is_checked() {
        // (0008,1140) Referenced Image Sequence, undefined length, one item
        // of undefined length holding a damaged element.
        let mut body = implicit(0x0008, 0x1140, UNDEFINED, &[]);
        body.extend(implicit(0xFFFE, 0xE000, UNDEFINED, &[]));
        body.extend(implicit(0x0008, 0x1150, 0x7000_0000, b"1.2"));
        let e = run(&file(IMPLICIT_VR_LE, &body)).unwrap_err();
        assert!(e.contains("(0008,1150)"), "{e}");
        // A defined-length sequence is walked into as well.
        let mut body = implicit(0x0008, 0x1140, 16, &[]);
        body.extend(implicit(0xFFFE, 0xE000, 8, &[]));
        body.extend(implicit(0x0008, 0x1150, 0x7000_0000, &[]));
        let e = run(&file(IMPLICIT_VR_LE, &body)).unwrap_err();
        assert!(e.contains("(0008,1150)"), "{e}");
    }

    #[test]
    fn encapsulated_fragments_are_skipped() {
        // Explicit VR: pixel data OB of undefined length, an empty offset
        // table, one fragment whose bytes look like a huge element header.
        let mut body = vec![0xE0, 0x7F, 0x10, 0x00, b'O', b'B', 0, 0];
        body.extend_from_slice(&UNDEFINED.to_le_bytes());
        body.extend(implicit(0xFFFE, 0xE000, 0, &[]));
        body.extend(implicit(
            0xFFFE,
            0xE000,
            8,
            &[0x10, 0x00, 0x10, 0x00, 0xF0, 0xFF, 0xFF, 0xFF],
        ));
        body.extend(implicit(0xFFFE, 0xE0DD, 0, &[]));
        assert_eq!(run(&file("1.2.840.10008.1.2.4.50", &body)), Ok(()));
    }

    #[test]
    fn encapsulated_fragments_are_counted_without_the_offset_table() {
        let mut body = vec![0xE0, 0x7F, 0x10, 0x00, b'O', b'B', 0, 0];
        body.extend_from_slice(&UNDEFINED.to_le_bytes());
        body.extend(implicit(0xFFFE, 0xE000, 0, &[]));
        for _ in 0..3 {
            body.extend(implicit(0xFFFE, 0xE000, 2, &[1, 2]));
        }
        body.extend(implicit(0xFFFE, 0xE0DD, 0, &[]));
        let syntax = "1.2.840.10008.1.2.4.50";
        assert_eq!(
            walk(&file(syntax, &body)),
            Ok(Some(PixelData::Fragments(3)))
        );
    }

    #[test]
    fn native_pixel_data_reports_its_length() {
        let body = implicit(0x7FE0, 0x0010, 6, &[0; 6]);
        assert_eq!(
            walk(&file(IMPLICIT_VR_LE, &body)),
            Ok(Some(PixelData::Native(6)))
        );
        // Pixel data inside an item (an icon) is not the image's.
        let mut body = implicit(0x0088, 0x0200, UNDEFINED, &[]);
        body.extend(implicit(0xFFFE, 0xE000, UNDEFINED, &[]));
        body.extend(implicit(0x7FE0, 0x0010, 2, &[0; 2]));
        body.extend(implicit(0xFFFE, 0xE00D, 0, &[]));
        body.extend(implicit(0xFFFE, 0xE0DD, 0, &[]));
        assert_eq!(walk(&file(IMPLICIT_VR_LE, &body)), Ok(None));
        body.extend(implicit(0x7FE0, 0x0010, 4, &[0; 4]));
        assert_eq!(
            walk(&file(IMPLICIT_VR_LE, &body)),
            Ok(Some(PixelData::Native(4)))
        );
    }

    /// `depth` nested (0008,1140) sequences with one item each, undefined
    /// lengths (`defined`: lengths given instead), around one element.
    fn nested(depth: usize, defined: bool) -> Vec<u8> {
        let mut inner = implicit(0x0008, 0x1150, 4, b"1.2 ");
        for _ in 0..depth {
            let mut item = Vec::new();
            if defined {
                item.extend(implicit(0xFFFE, 0xE000, inner.len() as u32, &inner));
                inner = implicit(0x0008, 0x1140, item.len() as u32, &item);
            } else {
                item.extend(implicit(0xFFFE, 0xE000, UNDEFINED, &inner));
                item.extend(implicit(0xFFFE, 0xE00D, 0, &[]));
                let mut seq = implicit(0x0008, 0x1140, UNDEFINED, &item);
                seq.extend(implicit(0xFFFE, 0xE0DD, 0, &[]));
                inner = seq;
            }
        }
        inner
    }

    #[test]
    fn nesting_deeper_than_the_limit_is_refused() {
        for defined in [false, true] {
            // Two levels a sequence: 128 sequences are 256 levels.
            let ok = nested(MAX_DEPTH / 2, defined);
            assert_eq!(run(&file(IMPLICIT_VR_LE, &ok)), Ok(()), "{defined}");
            let deep = nested(MAX_DEPTH / 2 + 1, defined);
            let e = run(&file(IMPLICIT_VR_LE, &deep)).unwrap_err();
            assert!(e.contains("nested more than 256"), "{e}");
        }
        // Many sequences one after the other are not nested.
        let mut body = Vec::new();
        for _ in 0..2 * MAX_DEPTH {
            body.extend(nested(1, false));
            body.extend(nested(1, true));
        }
        assert_eq!(run(&file(IMPLICIT_VR_LE, &body)), Ok(()));
    }

    #[test]
    fn the_meta_group_is_walked_as_far_as_its_length_says() {
        // The group length covers a foreign tag and then an element with an
        // unknown VR, read (like UN) with a 4-byte length of about 4 GB.
        let mut f = vec![0u8; 128];
        f.extend_from_slice(b"DICM");
        f.extend_from_slice(&[0x02, 0x00, 0x00, 0x00, b'U', b'L', 4, 0]);
        f.extend_from_slice(&28u32.to_le_bytes());
        f.extend_from_slice(&[0x02, 0x9A, 0x03, 0x00, b'U', b'I', 4, 0]);
        f.extend_from_slice(b"1.2\0");
        f.extend_from_slice(&[0x02, 0x00, 0x13, 0x00, b'S', b'b', 0, 0]);
        f.extend_from_slice(&0xFF59_5000u32.to_le_bytes());
        f.extend_from_slice(&[0; 16]);
        let e = run(&f).unwrap_err();
        assert!(e.contains("(0002,0013)") && e.contains("4284043264"), "{e}");
    }

    #[test]
    fn a_data_set_with_deflated_frames_is_walked() {
        // Explicit VR little endian like any other: the RescaleIntercept
        // below, read as DS with a 2-byte length, fits; a UT past the end
        // does not.
        let body = [
            0x28, 0x00, 0x52, 0x10, b'D', b'S', 4, 0, b'1', b'.', b'0', b' ',
        ];
        assert_eq!(run(&file(DEFLATED_FRAMES, &body)), Ok(()));
        let mut body = vec![0x08, 0x00, 0x19, 0x01, b'U', b'T', 0, 0];
        body.extend_from_slice(&0x4000_0000u32.to_le_bytes());
        let e = run(&file(DEFLATED_FRAMES, &body)).unwrap_err();
        assert!(e.contains("(0008,0119)") && e.contains("1073741824"), "{e}");
    }

    #[test]
    fn a_deflated_frame_is_measured_against_its_cap() {
        let frame = deflate(&[7; 126]);
        assert!(!inflates_beyond(&frame, 126));
        assert!(inflates_beyond(&frame, 125));
        // Not a deflate stream: left to the decoder.
        assert!(!inflates_beyond(&[0xFF; 16], 0));
    }

    #[test]
    fn big_endian_lengths_are_read_big_endian() {
        // (0010,0010) PN, 4 bytes, big endian: a little-endian reading
        // would claim 1024 bytes.
        let body = [
            0x00, 0x10, 0x00, 0x10, b'P', b'N', 0x00, 0x04, b'D', b'O', b'E', b' ',
        ];
        assert_eq!(run(&file(EXPLICIT_VR_BE, &body)), Ok(()));
    }

    #[test]
    fn files_it_cannot_follow_are_left_to_the_parser() {
        assert_eq!(run(b"not dicom"), Ok(()));
        // Not a deflate stream.
        assert_eq!(run(&file(DEFLATED, &[0xFF; 16])), Ok(()));
    }

    /// `bytes` as a raw deflate stream.
    fn deflate(bytes: &[u8]) -> Vec<u8> {
        use std::io::Write;
        let mut e = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(bytes).unwrap();
        e.finish().unwrap()
    }

    #[test]
    fn a_deflated_data_set_is_checked_once_inflated() {
        // Explicit VR little endian: (0010,0010) PN "DOE ", then a UT value
        // claiming more bytes than the inflated stream holds.
        let mut body = vec![0x10, 0x00, 0x10, 0x00, b'P', b'N', 4, 0];
        body.extend_from_slice(b"DOE ");
        assert_eq!(run(&file(DEFLATED, &deflate(&body))), Ok(()));
        body.extend_from_slice(&[0x08, 0x00, 0x19, 0x01, b'U', b'T', 0, 0]);
        body.extend_from_slice(&0x4000_0000u32.to_le_bytes());
        body.extend_from_slice(&[b'x'; 32]);
        let e = run(&file(DEFLATED, &deflate(&body))).unwrap_err();
        assert!(
            e.contains("(0008,0119)") && e.contains("inflated data set"),
            "{e}"
        );
    }

    #[test]
    fn a_deflated_data_set_beyond_the_cap_is_refused() {
        // (0042,0011) OB of 4000 zero bytes: 4012 bytes inflated.
        let mut body = vec![0x42, 0x00, 0x11, 0x00, b'O', b'B', 0, 0];
        body.extend_from_slice(&4000u32.to_le_bytes());
        body.resize(body.len() + 4000, 0);
        let stream = deflate(&body);
        let walk = |cap| {
            let w = Walker {
                input: Cursor::new(&stream),
                pos: 0,
                size: stream.len() as u64,
                what: "the file",
            };
            deflated_data_set(w, cap)
        };
        assert_eq!(walk(4012), Ok(None));
        let e = walk(4011).unwrap_err();
        assert!(e.contains("inflates to more than 4011 bytes"), "{e}");
        assert_eq!(inflate_cap(1000), INFLATE_FLOOR);
        assert_eq!(inflate_cap(1 << 30), INFLATE_RATIO << 30);
    }
}
