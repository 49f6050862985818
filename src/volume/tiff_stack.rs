//! TIFF stacks: one multi-page TIFF (page `k` = plane `z = k`), a directory
//! of single-page TIFFs, or a glob pattern (`*`, `?` in the file name) naming
//! single-page TIFFs. Files are sorted by name in natural order (`slice_2`
//! before `slice_10`). A directory or glob that finds one file reads all
//! its pages; one that finds several refuses a multi-page file among them
//! rather than read only its first page. A multi-page file whose ImageJ
//! or OME metadata says its pages run over channels or time points as
//! well as z slices (a hyperstack) is refused: stacked as z planes they
//! would interleave.
//!
//! Greyscale pages of 8-, 16-, 32- or 64-bit unsigned or signed integers or
//! 16-, 32- or 64-bit floats are read (64-bit integers and half floats
//! converted to `f64` plane by plane, never lent), classic TIFF or BigTIFF;
//! every page must have
//! the same size and type. At open only the page directories are read; a
//! page is decoded when its plane is asked for, and only the last decoded
//! page is kept, with the decoder of its file: the decoder remembers where
//! the pages it has passed start, so the pages of a multi-page file are
//! found in one walk of its page list, not one walk each (4,096 pages of
//! 64x64 took 20.7 s that way). The spacing is the voxel size of the
//! first page's ImageJ or OME metadata, in millimetres (see
//! `tiff_meta.rs`), or unit spacing without it; the origin is zero unless
//! ImageJ's `xorigin=` ... place it.
//!
//! Pages stored as plain samples (uncompressed strips in the machine's byte
//! order, the usual micro-CT slice) are not decoded at all: they are lent
//! from a memory map of their file (`tiff_pages.rs`). Other pages
//! (compressed, tiled, the other byte order) are decoded into a buffer of
//! their own type that the slab holds ([`SharedPlane`]): 2 bytes a sample
//! for 16-bit pages instead of the 8 of `f64`s, and the decoding of two
//! workers runs side by side (the decoder is taken out of the cache while
//! it decodes).

use super::tiff_meta::{several_volumes, voxel_size};
use super::tiff_pages::{plain_bytes, MappedPages};
use super::{
    Access, Grid, LentPlane, SampleSource, ScalarType, SharedPlane, SourceNotes, ValueFrom,
};
use crate::{Error, Result};
use std::cmp::Ordering;
use std::fs::File;
use std::io::BufReader;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use tiff::decoder::ifd::Value;
use tiff::decoder::{Decoder, Limits};
use tiff::tags::{SampleFormat, Tag};
use tiff::ColorType;

/// A stack of TIFF pages read one plane at a time.
#[derive(Debug)]
pub struct TiffStack {
    grid: Grid,
    scalar: ScalarType,
    /// The file and page index of each plane.
    pages: Vec<(PathBuf, usize)>,
    /// The last decoded plane, and the decoder of its file.
    cache: Mutex<Cache>,
    /// Where the spacing came from: the metadata, or `None` (unit spacing).
    spacing_from: Option<String>,
    /// Where the origin came from: ImageJ's `xorigin=` ..., or `None`
    /// (zero).
    origin_from: Option<String>,
    /// The pages stored as plain samples, lent from maps of their files.
    mapped: MappedPages,
}

/// What a [`TiffStack`] keeps between planes.
#[derive(Debug, Default)]
struct Cache {
    /// The last plane decoded, in its own type.
    shared: Option<(usize, SharedPlane)>,
    /// The decoder of the last file read, and that file.
    decoder: Option<(PathBuf, Decoder<BufReader<File>>)>,
}

impl TiffStack {
    /// The sample type of the pages.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }
}

fn decoder(path: &Path) -> Result<Decoder<BufReader<File>>> {
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
    Decoder::new(BufReader::new(file))
        .map(|d| d.with_limits(limits(len)))
        .map_err(|e| Error::Format(format!("{}: not a readable TIFF: {e}", path.display())))
}

/// Decoder limits for a file of `len` bytes. The decoder sizes tag value
/// lists and page buffers by this limit before reading them, so it must not
/// be unlimited: a tag claiming 2^31 values in a 2 KB file would allocate
/// 32 GiB. A page holds at most what its bytes can expand to (1024 times
/// for deflate and LZW), and never less than the decoder's defaults.
fn limits(len: u64) -> Limits {
    let defaults = Limits::default();
    let cap = usize::try_from(len.saturating_mul(1024)).unwrap_or(usize::MAX);
    let mut limits = Limits::default();
    limits.decoding_buffer_size = cap.max(defaults.decoding_buffer_size);
    limits.intermediate_buffer_size = cap.max(defaults.intermediate_buffer_size);
    limits
}

/// Size and sample type of the current page of `dec`.
fn page_info(
    dec: &mut Decoder<BufReader<File>>,
) -> std::result::Result<((u32, u32), ScalarType), String> {
    let dims = dec.dimensions().map_err(|e| e.to_string())?;
    let color = dec.colortype().map_err(|e| e.to_string())?;
    let ColorType::Gray(bits) = color else {
        return Err(format!(
            "colour type {color:?} is not supported (need greyscale)"
        ));
    };
    let format = dec
        .find_tag_unsigned::<u16>(Tag::SampleFormat)
        .map_err(|e| e.to_string())?
        .map_or(SampleFormat::Uint, SampleFormat::from_u16_exhaustive);
    let scalar = match (format, bits) {
        (SampleFormat::Uint, 8) => ScalarType::U8,
        (SampleFormat::Uint, 16) => ScalarType::U16,
        (SampleFormat::Uint, 32) => ScalarType::U32,
        (SampleFormat::Int, 8) => ScalarType::I8,
        (SampleFormat::Int, 16) => ScalarType::I16,
        (SampleFormat::Int, 32) => ScalarType::I32,
        (SampleFormat::IEEEFP, 32) => ScalarType::F32,
        (SampleFormat::IEEEFP, 64) => ScalarType::F64,
        // Read by converting each plane to f64 (see `read_plane`).
        (SampleFormat::Uint, 64) => ScalarType::U64,
        (SampleFormat::Int, 64) => ScalarType::I64,
        (SampleFormat::IEEEFP, 16) => ScalarType::F16,
        (f, b) => return Err(format!("{b}-bit {f:?} samples are not supported")),
    };
    Ok((dims, scalar))
}

/// Compares names in natural order: digit runs compare as numbers.
fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut a, mut b) = (a.as_bytes(), b.as_bytes());
    loop {
        match (a.first(), b.first()) {
            (None, None) => return Ordering::Equal,
            (None, _) => return Ordering::Less,
            (_, None) => return Ordering::Greater,
            (Some(x), Some(y)) if x.is_ascii_digit() && y.is_ascii_digit() => {
                let da = a.iter().take_while(|c| c.is_ascii_digit()).count();
                let db = b.iter().take_while(|c| c.is_ascii_digit()).count();
                let (na, nb) = (&a[..da], &b[..db]);
                let ta = trim_zeros(na);
                let tb = trim_zeros(nb);
                let ord = ta.len().cmp(&tb.len()).then(ta.cmp(tb)).then(da.cmp(&db));
                if ord != Ordering::Equal {
                    return ord;
                }
                a = &a[da..];
                b = &b[db..];
            }
            (Some(x), Some(y)) => {
                if x != y {
                    return x.cmp(y);
                }
                a = &a[1..];
                b = &b[1..];
            }
        }
    }
}

fn trim_zeros(d: &[u8]) -> &[u8] {
    let z = d.iter().take_while(|&&c| c == b'0').count();
    &d[z..]
}

/// Whether `name` matches the glob `pattern` (`*` any run, `?` one char).
fn glob_match(pattern: &[char], name: &[char]) -> bool {
    match pattern.first() {
        None => name.is_empty(),
        Some('*') => (0..=name.len()).any(|i| glob_match(&pattern[1..], &name[i..])),
        Some('?') => !name.is_empty() && glob_match(&pattern[1..], &name[1..]),
        Some(c) => name.first() == Some(c) && glob_match(&pattern[1..], &name[1..]),
    }
}

/// Whether `path` is a glob pattern: its file name holds `*` or `?`, and
/// no file or directory has that very name (a file named `b*.nrrd` is
/// read as itself).
pub fn is_pattern(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.contains(['*', '?']))
        && std::fs::symlink_metadata(path).is_err()
}

/// Opens a TIFF stack: a multi-page file, a directory of single-page TIFFs
/// (`.tif`/`.tiff`), or a glob pattern in the file name.
pub fn open(path: &Path) -> Result<TiffStack> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let files: Vec<PathBuf> = if path.is_dir() || is_pattern(path) {
        let (dir, pattern) = if path.is_dir() {
            (path.to_path_buf(), None)
        } else {
            let dir = path
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            let pat: Vec<char> = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or("")
                .chars()
                .collect();
            (dir.to_path_buf(), Some(pat))
        };
        let entries = std::fs::read_dir(&dir).map_err(|e| Error::io(&dir, e))?;
        let mut names = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| Error::io(&dir, e))?;
            let Ok(name) = entry.file_name().into_string() else {
                continue;
            };
            let keep = match &pattern {
                Some(p) => glob_match(p, &name.chars().collect::<Vec<_>>()),
                None => {
                    let lower = name.to_ascii_lowercase();
                    lower.ends_with(".tif") || lower.ends_with(".tiff")
                }
            };
            if keep && entry.path().is_file() {
                names.push(name);
            }
        }
        if names.is_empty() {
            return Err(fail(match pattern {
                Some(_) => "no TIFF files match the pattern".into(),
                // A directory comes here when it holds no DICOM file either
                // (see `Format::detect`).
                None => "a directory is read as a TIFF stack (files ending in .tif or .tiff) or a DICOM series (files ending in .dcm, or with 'DICM' at byte 128), and this one holds neither".into(),
            }));
        }
        names.sort_by(|a, b| natural_cmp(a, b));
        names.into_iter().map(|n| dir.join(n)).collect()
    } else {
        vec![path.to_path_buf()]
    };
    let all_pages = files.len() == 1;
    let voxel = {
        let mut dec = decoder(&files[0])?;
        let description = dec.get_tag_ascii_string(Tag::ImageDescription).ok();
        let mut resolution = |tag| match dec.find_tag(tag) {
            Ok(Some(Value::Rational(n, d))) if d != 0 => Some(f64::from(n) / f64::from(d)),
            _ => None,
        };
        let xy = resolution(Tag::XResolution).zip(resolution(Tag::YResolution));
        if all_pages {
            if let Some(why) = several_volumes(description.as_deref()) {
                return Err(fail(why));
            }
        }
        voxel_size(description.as_deref(), xy)
    };
    let mut pages = Vec::new();
    let mut mapped = MappedPages::default();
    let mut first: Option<((u32, u32), ScalarType)> = None;
    for file in &files {
        let mut dec = decoder(file)?;
        let mut index = 0usize;
        loop {
            let info = page_info(&mut dec)
                .map_err(|e| Error::Format(format!("{} page {index}: {e}", file.display())))?;
            match first {
                None => first = Some(info),
                Some(f) if f != info => {
                    return Err(Error::Format(format!(
                        "{} page {index}: {}x{} {} differs from the first page ({}x{} {})",
                        file.display(),
                        info.0 .0,
                        info.0 .1,
                        info.1,
                        f.0 .0,
                        f.0 .1,
                        f.1
                    )))
                }
                Some(_) => {}
            }
            mapped.push(file, plain_bytes(&mut dec, info.0, info.1));
            pages.push((file.clone(), index));
            if !dec.more_images() {
                break;
            }
            if !all_pages {
                return Err(Error::Format(format!(
                    "{}: has more than one page; the files of a TIFF stack directory or glob must be single pages (open a multi-page TIFF on its own)",
                    file.display()
                )));
            }
            dec.next_image().map_err(|e| {
                Error::Format(format!("{} page {}: {e}", file.display(), index + 1))
            })?;
            index += 1;
        }
    }
    let ((w, h), scalar) = first.ok_or_else(|| fail("no pages".into()))?;
    let mut grid = Grid::unit([w as usize, h as usize, pages.len()]);
    if grid.dims.contains(&0) {
        return Err(fail("empty pages".into()));
    }
    let mut origin_from = None;
    if let Some(v) = &voxel {
        grid.spacing = v.spacing;
        if let Some(origin) = v.origin {
            grid.origin = origin;
            origin_from = Some(v.what.clone());
        }
    }
    Ok(TiffStack {
        grid,
        scalar,
        pages,
        cache: Mutex::new(Cache::default()),
        spacing_from: voxel.map(|v| v.what),
        origin_from,
        mapped,
    })
}

impl TiffStack {
    /// Plane `z` decoded into its own type: the last one decoded is kept
    /// (both `read_plane` and the slab loop ask for it), and decoding runs
    /// without the cache's lock, so two workers decode side by side (the
    /// decoder is taken out of the cache meanwhile).
    fn shared(&self, z: usize) -> Result<SharedPlane> {
        let lock = || self.cache.lock().unwrap_or_else(|p| p.into_inner());
        let mut kept = {
            let mut cache = lock();
            if let Some((cz, plane)) = &cache.shared {
                if *cz == z {
                    return Ok(plane.clone());
                }
            }
            cache.decoder.take()
        };
        let bytes = self.decode_bytes(z, &mut kept)?;
        let len = bytes.len();
        let plane = SharedPlane::new(Arc::new(bytes), 0..len, self.scalar);
        let mut cache = lock();
        cache.shared = Some((z, plane.clone()));
        if kept.is_some() {
            cache.decoder = kept;
        }
        Ok(plane)
    }

    /// Decodes the page of plane `z` into a buffer of its own type (native
    /// byte order), with the decoder in `kept` if it is that of the page's
    /// file (else with a new one, left in `kept`).
    fn decode_bytes(
        &self,
        z: usize,
        kept: &mut Option<(PathBuf, Decoder<BufReader<File>>)>,
    ) -> Result<Vec<u8>> {
        let (file, index) = &self.pages[z];
        let err = |e: String| Error::Format(format!("{} page {index}: {e}", file.display()));
        let mut dec = match kept.take() {
            Some((path, dec)) if path == *file => dec,
            _ => decoder(file)?,
        };
        dec.seek_to_image(*index).map_err(|e| err(e.to_string()))?;
        let len = self.grid.plane_len() * self.scalar.size();
        let layout = dec.image_buffer_layout().map_err(|e| err(e.to_string()))?;
        if layout.len != len {
            return Err(err(format!("page holds {} bytes, need {len}", layout.len)));
        }
        let mut bytes = vec![0u8; len];
        dec.read_image_bytes(&mut bytes)
            .map_err(|e| err(e.to_string()))?;
        *kept = Some((file.clone(), dec));
        Ok(bytes)
    }
}

impl SampleSource for TiffStack {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        let nz = self.grid.dims[2];
        if z >= nz {
            return Err(Error::Invalid(format!(
                "plane {z} out of range: the volume has {nz} planes"
            )));
        }
        if out.len() != self.grid.plane_len() {
            return Err(Error::Invalid(format!(
                "plane buffer holds {} samples, a plane has {}",
                out.len(),
                self.grid.plane_len()
            )));
        }
        // The page decoded in its own type (native byte order), converted
        // as a chunk layer's plane is: every type, 64-bit and half included.
        let plane = self.shared(z)?;
        let bytes = &plane.data[plane.bytes.clone()];
        if bytes.len() != out.len() * self.scalar.size() {
            let (file, index) = &self.pages[z];
            return Err(Error::Format(format!(
                "{} page {index}: not {} {} samples",
                file.display(),
                out.len(),
                self.scalar.name()
            )));
        }
        super::decode_samples(self.scalar, super::Endian::native(), bytes, out);
        Ok(())
    }

    fn data_files(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = Vec::new();
        for (path, _) in &self.pages {
            // Pages of one file are consecutive.
            if files.last() != Some(&path.as_path()) {
                files.push(path);
            }
        }
        files
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        self.mapped.lend(z, self.scalar)
    }

    /// A page that is not lent (compressed, tiled, the other byte order),
    /// decoded into its own type; `None` if it cannot be (`read_plane`
    /// then says why).
    fn share_plane(&self, z: usize) -> Option<SharedPlane> {
        // A plane of 64-bit integers or half floats is read as f64s.
        if z >= self.grid.dims[2] || !self.scalar.is_lent() {
            return None;
        }
        self.shared(z).ok()
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        self.mapped.advise(planes, access);
    }

    fn check_unchanged(&self) -> Result<()> {
        self.mapped.check_unchanged()
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.scalar)
    }

    fn notes(&self) -> SourceNotes {
        SourceNotes {
            spacing_from: match &self.spacing_from {
                Some(what) => ValueFrom::File { what: what.clone() },
                None => ValueFrom::Default,
            },
            origin_from: match &self.origin_from {
                Some(what) => ValueFrom::File { what: what.clone() },
                None => ValueFrom::Default,
            },
            chunks: None,
            units: None,
            skipped: Vec::new(),
            segments: Vec::new(),
            overlapping_segments: Vec::new(),
            warnings: Vec::new(),
        }
    }
}
