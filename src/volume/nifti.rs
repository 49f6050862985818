//! The NIfTI-1 and NIfTI-2 reader (`.nii`, `.nii.gz`, `.hdr` + `.img`).
//!
//! The version is detected from `sizeof_hdr` (348 or 540) in either byte
//! order. Supported datatypes: uint8, int8, uint16, int16, uint32, int32,
//! int64, uint64 (read as `f64`: exact within ±2^53), float32 and float64. The volume must be 3-D (`dim[0]` = 3, or more with
//! every extra dimension equal to 1). When
//! `scl_slope` is nonzero and the pair is not (1, 0), samples are returned
//! as `value * scl_slope + scl_inter` so isovalues are in physical units.
//!
//! The index-to-world map is the sform (`sform_code > 0`), else the qform
//! (`qform_code > 0`), else the `pixdim` scaling, as the standard orders
//! them; it goes into the [`Grid`] whole (spacing, origin and direction
//! cosines), so vertices are in the NIfTI world frame (RAS+ millimetres),
//! and a mirrored map (e.g. `qfac = -1`) flips the winding so normals
//! still point outward. Lengths in metres or microns (`xyzt_units`) are
//! converted to millimetres, as ITK reads them.
//!
//! Uncompressed data is memory-mapped (and its planes lent to the slab
//! loop, scaled ones as views computing the scaled samples); a `.nii.gz` file is decompressed
//! once into a temporary file that is then mapped (see the `spill` module).

use super::raw::{data_bytes, dims_text, Layout, Order, RawVolume};
use super::spill::spill;
use super::{
    set_direction, Access, Endian, Grid, LentPlane, PlaneView, SampleSource, ScalarType,
    SourceNotes,
};
use crate::{Error, Result};
use std::fs::File;
use std::io::{BufReader, Read};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, OnceLock};

/// A NIfTI volume: the stored samples, their scaling and orientation.
#[derive(Debug)]
pub struct NiftiVolume {
    inner: Arc<RawVolume>,
    version: u8,
    scaling: Option<(f64, f64)>,
    /// With scaling: one slot per plane, filled when it is first lent
    /// (`None` when the stored plane is not lent).
    scaled: Vec<OnceLock<Option<ScaledPlane>>>,
    /// What was read otherwise than written (a zero `pixdim` as 1), one
    /// line each, for [`SourceNotes::warnings`].
    warnings: Vec<String>,
    /// The unit of the header's lengths when it is not millimetres
    /// (`xyzt_units` metre or micron), converted to millimetres.
    unit: Option<&'static str>,
}

/// A plane of scaled samples, lent as a [`LentPlane::View`] of the stored
/// plane: each sample computed as `stored * slope + inter` when the slab
/// loop reads it, so a scaled NIfTI holds no `f64` copy of its planes
/// (8 bytes a sample, two planes a worker) any more than an unscaled one.
#[derive(Debug)]
struct ScaledPlane {
    raw: Arc<RawVolume>,
    z: usize,
    slope: f64,
    inter: f64,
}

impl ScaledPlane {
    /// The stored plane (lent when the view was made, so always).
    fn stored(&self) -> Option<LentPlane<'_>> {
        self.raw.lend_plane(self.z)
    }
}

impl PlaneView for ScaledPlane {
    fn len(&self) -> usize {
        self.stored().map_or(0, |p| p.len())
    }

    fn get(&self, i: usize) -> f64 {
        match self.stored() {
            Some(p) => p.get(i) * self.slope + self.inter,
            None => f64::NAN,
        }
    }

    fn range(&self, start: usize, out: &mut [f64]) {
        let Some(p) = self.stored() else {
            out.fill(f64::NAN);
            return;
        };
        p.get_range(start, out);
        for v in out.iter_mut() {
            *v = *v * self.slope + self.inter;
        }
    }
}

impl NiftiVolume {
    /// The NIfTI version of the header (1 or 2).
    pub fn version(&self) -> u8 {
        self.version
    }

    /// `(scl_slope, scl_inter)` when samples are scaled on reading.
    pub fn scaling(&self) -> Option<(f64, f64)> {
        self.scaling
    }

    /// The stored sample type (before scaling).
    pub fn scalar(&self) -> ScalarType {
        self.inner.scalar()
    }

    /// The direction cosines: `direction()[r][c]` is component `r` (x, y, z)
    /// of the unit vector of index axis `c`, from the sform when
    /// `sform_code > 0`, else from the qform quaternion when
    /// `qform_code > 0`, else the identity (the same as the grid's).
    pub fn direction(&self) -> [[f64; 3]; 3] {
        self.inner.grid().direction
    }
}

impl SampleSource for NiftiVolume {
    fn grid(&self) -> &Grid {
        self.inner.grid()
    }

    /// Spacing and origin from the header (converted to millimetres from
    /// metres or microns, said); a zero `pixdim` read as 1 said.
    fn notes(&self) -> SourceNotes {
        let from = match self.unit {
            Some(unit) => super::ValueFrom::File {
                what: format!("header, xyzt_units {unit}, in mm"),
            },
            None => super::ValueFrom::header(),
        };
        SourceNotes {
            spacing_from: from.clone(),
            origin_from: from,
            warnings: self.warnings.clone(),
            ..SourceNotes::default()
        }
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        self.inner.read_plane(z, out)?;
        if let Some((slope, inter)) = self.scaling {
            for v in out.iter_mut() {
                *v = *v * slope + inter;
            }
        }
        Ok(())
    }

    /// Lends the stored plane as `RawVolume` does when the samples are not
    /// scaled, and a view of it computing the scaled samples when they are
    /// (`ScaledPlane`): the slab loop then holds no `f64` copy of the
    /// plane (8 bytes a sample, two planes a worker).
    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        let Some((slope, inter)) = self.scaling else {
            return self.inner.lend_plane(z);
        };
        let view = self.scaled.get(z)?.get_or_init(|| {
            self.inner.lend_plane(z)?;
            Some(ScaledPlane {
                raw: Arc::clone(&self.inner),
                z,
                slope,
                inter,
            })
        });
        view.as_ref().map(|v| LentPlane::View(v))
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        self.inner.advise(planes, access);
    }

    fn plane_memory(&self) -> super::PlaneMemory {
        self.inner.plane_memory()
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

/// The fields of a NIfTI header that the reader uses.
struct Header {
    version: u8,
    endian: Endian,
    /// Whether the magic says the data is in a separate `.img` file.
    pair: bool,
    scalar: ScalarType,
    dims: [usize; 3],
    pixdim: [f64; 4],
    vox_offset: f64,
    slope: f64,
    inter: f64,
    qform_code: i64,
    sform_code: i64,
    quatern: [f64; 3],
    qoffset: [f64; 3],
    srow: [[f64; 4]; 3],
    /// The space unit of `xyzt_units` (its low three bits): 1 metre,
    /// 2 millimetre, 3 micron, 0 unknown.
    space_unit: u8,
}

/// Little helper reading fixed-offset fields of a header.
struct Fields<'a> {
    bytes: &'a [u8],
    endian: Endian,
}

impl Fields<'_> {
    fn raw<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut b = [0u8; N];
        b.copy_from_slice(&self.bytes[at..at + N]);
        if self.endian == Endian::Big {
            b.reverse();
        }
        b
    }
    fn i16(&self, at: usize) -> i64 {
        i64::from(i16::from_le_bytes(self.raw(at)))
    }
    fn i32(&self, at: usize) -> i64 {
        i64::from(i32::from_le_bytes(self.raw(at)))
    }
    fn i64(&self, at: usize) -> i64 {
        i64::from_le_bytes(self.raw(at))
    }
    fn f32(&self, at: usize) -> f64 {
        f64::from(f32::from_le_bytes(self.raw(at)))
    }
    fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.raw(at))
    }
}

/// Opens a NIfTI-1 or NIfTI-2 volume: `.nii`, `.nii.gz`, or a `.hdr` header
/// whose samples are in the `.img` file of the same stem.
pub fn open(path: &Path) -> Result<NiftiVolume> {
    open_cancellable(path, &AtomicBool::new(false))
}

/// [`open`] that stops with [`Error::Interrupted`] once `cancel` is set
/// while compressed samples are decompressed (it is looked at every MiB).
pub fn open_cancellable(path: &Path, cancel: &AtomicBool) -> Result<NiftiVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default()
        .to_ascii_lowercase();
    if name.ends_with(".gz") {
        let file = File::open(path).map_err(|e| Error::io(path, e))?;
        let mut decoder = flate2::read::MultiGzDecoder::new(BufReader::new(file));
        let mut head = Vec::new();
        (&mut decoder)
            .take(540)
            .read_to_end(&mut head)
            .map_err(|e| fail(format!("bad gzip data: {e}")))?;
        let header = parse_header(&head).map_err(fail)?;
        if header.pair {
            return Err(fail(
                "the header says the data is in a separate .img file (magic ni1/ni2), \
                 which is not supported for .nii.gz"
                    .into(),
            ));
        }
        let layout = layout(&header, header.vox_offset).map_err(fail)?;
        let need = data_bytes(header.dims, header.scalar)
            .and_then(|n| n.checked_add(layout.offset))
            .ok_or_else(|| fail("dims are too large".into()))?;
        let (samples, _) = spill(path, "gzip", &head, decoder, need, cancel)?;
        let inner = RawVolume::map_file(path, &samples, layout)?;
        return Ok(volume(header, inner));
    }

    let mut file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut head = Vec::new();
    (&mut file)
        .take(540)
        .read_to_end(&mut head)
        .map_err(|e| Error::io(path, e))?;
    let header = parse_header(&head).map_err(fail)?;
    let is_hdr = name.ends_with(".hdr");
    if is_hdr != header.pair {
        return Err(fail(if is_hdr {
            "a .hdr file must have the magic 'ni1' or 'ni2' (single-file magic found)".into()
        } else {
            "the magic says the data is in a separate .img file: open the .hdr file".into()
        }));
    }
    let min_offset = if header.version == 1 { 348.0 } else { 540.0 };
    if !is_hdr && header.vox_offset < min_offset {
        return Err(fail(format!(
            "vox_offset {} is inside the {min_offset}-byte header",
            header.vox_offset
        )));
    }
    let layout = layout(&header, header.vox_offset).map_err(fail)?;
    let inner = if is_hdr {
        let img = img_path(path);
        super::check_input_kind(&img)?;
        let data = File::open(&img).map_err(|e| Error::io(&img, e))?;
        RawVolume::map_file(&img, &data, layout)?
    } else {
        RawVolume::map_file(path, &file, layout)?
    };
    Ok(volume(header, inner))
}

/// The NIfTI version (1 or 2) of the file at `path`, from its `sizeof_hdr`
/// alone (the first 4 bytes, decompressed for `.gz`); `None` if it cannot
/// be read or is neither. Cheaper than [`open`] when only the name of the
/// format is wanted.
pub fn version(path: &Path) -> Option<u8> {
    let file = File::open(path).ok()?;
    let gz = path.to_string_lossy().to_ascii_lowercase().ends_with(".gz");
    let mut reader: Box<dyn Read> = if gz {
        Box::new(flate2::read::MultiGzDecoder::new(BufReader::new(file)))
    } else {
        Box::new(file)
    };
    let mut word = [0u8; 4];
    reader.read_exact(&mut word).ok()?;
    match (i32::from_le_bytes(word), i32::from_be_bytes(word)) {
        (348, _) | (_, 348) => Some(1),
        (540, _) | (_, 540) => Some(2),
        _ => None,
    }
}

/// Millimetres per unit of the header's lengths, with the unit's name
/// when it is not millimetres: `xyzt_units` metre or micron are converted,
/// as ITK's NIfTI reader does and as the TIFF, OME-Zarr and HDF5 readers
/// convert their voxel sizes; unknown units (0, what most writers leave)
/// and the codes NIfTI gives no length are read as millimetres.
fn space_unit(h: &Header) -> (f64, Option<&'static str>) {
    match h.space_unit {
        1 => (1e3, Some("metre")),
        3 => (1e-3, Some("micron")),
        _ => (1.0, None),
    }
}

/// The `.img` file beside a `.hdr` file (same case as the extension).
fn img_path(hdr: &Path) -> PathBuf {
    let upper = hdr
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e == "HDR");
    hdr.with_extension(if upper { "IMG" } else { "img" })
}

/// Builds the volume from a parsed header and its samples.
fn volume(header: Header, inner: RawVolume) -> NiftiVolume {
    let scaling = (header.slope != 0.0
        && header.slope.is_finite()
        && header.inter.is_finite()
        && (header.slope, header.inter) != (1.0, 0.0))
        .then_some((header.slope, header.inter));
    let planes = match scaling {
        Some(_) => inner.grid().dims[2],
        None => 0,
    };
    NiftiVolume {
        inner: Arc::new(inner),
        version: header.version,
        scaling,
        scaled: (0..planes).map(|_| OnceLock::new()).collect(),
        warnings: pixdim_warnings(&header),
        unit: space_unit(&header).1,
    }
}

/// The sample layout of `header`, the data starting at `offset`.
fn layout(header: &Header, offset: f64) -> std::result::Result<Layout, String> {
    if !(offset.is_finite() && offset >= 0.0 && offset.fract() == 0.0 && offset < 9e15) {
        return Err(format!("bad vox_offset {offset}"));
    }
    data_bytes(header.dims, header.scalar)
        .ok_or_else(|| format!("dims {} are too large", dims_text(header.dims)))?;
    Ok(Layout {
        grid: grid(header)?,
        scalar: header.scalar,
        endian: header.endian,
        offset: offset as u64,
        order: Order::XFastest,
    })
}

/// The index-to-world map, as NIfTI's three methods define it: the sform
/// when `sform_code > 0` (its columns are the scaled axes), else the qform
/// (quaternion rotation, `qfac` flipping the third axis, `|pixdim|`
/// spacing, `qoffset` origin), else `pixdim` scaling alone. A negative
/// `pixdim[1..3]` counts as its absolute value and a zero one as 1, as
/// nibabel reads them (its header check sets them so on load, with a
/// warning: [`pixdim_warnings`] says it here); a NaN or infinite one is
/// refused where it would be used (nibabel would make a NaN affine).
fn grid(h: &Header) -> std::result::Result<Grid, String> {
    let mm = space_unit(h).0;
    let pixdim = |i: usize| {
        let p = h.pixdim[i];
        if h.sform_code <= 0 && !p.is_finite() {
            return Err(format!(
                "pixdim[{i}] = {p} is not a voxel size (need a finite number; --spacing cannot mend the header, rewrite it)"
            ));
        }
        // A zero pixdim states no size: the default 1 is not converted.
        Ok(if p == 0.0 { 1.0 } else { p.abs() * mm })
    };
    let mut grid = Grid {
        dims: h.dims,
        spacing: [pixdim(1)?, pixdim(2)?, pixdim(3)?],
        origin: [0.0; 3],
        direction: super::IDENTITY,
    };
    if h.sform_code > 0 {
        grid.spacing = [1.0; 3];
        grid.origin = [0, 1, 2].map(|r| h.srow[r][3] * mm);
        let matrix = [0, 1, 2].map(|r| [0, 1, 2].map(|c| h.srow[r][c] * mm));
        set_direction(&mut grid, matrix).map_err(|e| format!("sform: {e}"))?;
    } else if h.qform_code > 0 {
        grid.origin = h.qoffset.map(|o| o * mm);
        // A rotation: its columns differ from unit length only by rounding,
        // which must not leak into the spacing.
        let spacing = grid.spacing;
        set_direction(&mut grid, qform_rotation(h)).map_err(|e| format!("qform: {e}"))?;
        grid.spacing = spacing;
    }
    if grid.spacing.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(format!(
            "voxel spacing {:?} must be positive and finite",
            grid.spacing
        ));
    }
    Ok(grid)
}

/// The line saying which `pixdim[1..3]` are 0 and so read as 1 by [`grid`]
/// (none when none is, or when the sform, which does not use them, places
/// the grid).
fn pixdim_warnings(h: &Header) -> Vec<String> {
    let zero: Vec<usize> = (1..=3).filter(|&i| h.pixdim[i] == 0.0).collect();
    if h.sform_code > 0 || zero.is_empty() {
        return Vec::new();
    }
    let list = |f: &dyn Fn(usize) -> String| zero.iter().map(|&i| f(i)).collect::<Vec<_>>();
    let axes = list(&|i| ["x", "y", "z"][i - 1].to_string()).join(", ");
    let fields = list(&|i| format!("pixdim[{i}]")).join(", ");
    vec![format!(
        "{fields} = 0 (no voxel size along {axes}): spacing 1 used there, as nibabel reads it; --spacing sets it"
    )]
}

/// The qform's rotation matrix, its third column multiplied by `qfac`.
fn qform_rotation(h: &Header) -> [[f64; 3]; 3] {
    let [b, c, d] = h.quatern;
    let a = (1.0 - (b * b + c * c + d * d)).max(0.0).sqrt();
    let qfac = if h.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
    [
        [
            a * a + b * b - c * c - d * d,
            2.0 * (b * c - a * d),
            2.0 * (b * d + a * c) * qfac,
        ],
        [
            2.0 * (b * c + a * d),
            a * a + c * c - b * b - d * d,
            2.0 * (c * d - a * b) * qfac,
        ],
        [
            2.0 * (b * d - a * c),
            2.0 * (c * d + a * b),
            (a * a + d * d - c * c - b * b) * qfac,
        ],
    ]
}

/// Parses a NIfTI-1 or NIfTI-2 header from the first bytes of a file.
fn parse_header(bytes: &[u8]) -> std::result::Result<Header, String> {
    if bytes.len() < 4 {
        return Err(format!(
            "file has {} bytes, too short for a NIfTI header",
            bytes.len()
        ));
    }
    let word = [bytes[0], bytes[1], bytes[2], bytes[3]];
    let (size, endian) = match (i32::from_le_bytes(word), i32::from_be_bytes(word)) {
        (n @ (348 | 540), _) => (n as usize, Endian::Little),
        (_, n @ (348 | 540)) => (n as usize, Endian::Big),
        (n, _) => {
            return Err(format!(
                "not a NIfTI file: sizeof_hdr is {n}, expected 348 (NIfTI-1) or 540 (NIfTI-2)"
            ))
        }
    };
    if bytes.len() < size {
        return Err(format!(
            "truncated NIfTI header: {} bytes, sizeof_hdr says {size}",
            bytes.len()
        ));
    }
    let f = Fields { bytes, endian };
    let v1 = size == 348;
    let magic = if v1 { &bytes[344..348] } else { &bytes[4..12] };
    let pair = match (v1, magic) {
        (true, b"n+1\0") => false,
        (true, b"ni1\0") => true,
        (false, m) if m == b"n+2\0\r\n\x1a\n" => false,
        (false, m) if m == b"ni2\0\r\n\x1a\n" => true,
        (true, _) => {
            return Err(
                "bad NIfTI-1 magic (not 'n+1' or 'ni1'; Analyze 7.5 headers are not supported)"
                    .into(),
            )
        }
        (false, _) => return Err("bad NIfTI-2 magic (not 'n+2' or 'ni2')".into()),
    };
    let datatype = if v1 { f.i16(70) } else { f.i16(12) };
    let scalar = match datatype {
        2 => ScalarType::U8,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        4 => ScalarType::I16,
        768 => ScalarType::U32,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        1024 => ScalarType::I64,
        1280 => ScalarType::U64,
        other => {
            return Err(format!(
                "NIfTI datatype {other} is not supported (uint8, int8, uint16, int16, uint32, int32, int64, uint64, float32, float64)"
            ))
        }
    };
    let dim = |i: usize| {
        if v1 {
            f.i16(40 + 2 * i)
        } else {
            f.i64(16 + 8 * i)
        }
    };
    let pixdim = |i: usize| {
        if v1 {
            f.f32(76 + 4 * i)
        } else {
            f.f64(104 + 8 * i)
        }
    };
    let ndim = dim(0);
    if !(3..=7).contains(&ndim) || (4..=ndim as usize).any(|i| dim(i) != 1) {
        let shown: Vec<String> = (0..8).map(|i| dim(i).to_string()).collect();
        return Err(format!(
            "dim [{}] is not a 3-D volume (need dim[0] = 3, or extra dimensions of size 1)",
            shown.join(", ")
        ));
    }
    let mut dims = [0usize; 3];
    for (i, d) in dims.iter_mut().enumerate() {
        let n = dim(i + 1);
        *d = usize::try_from(n)
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("dim[{}] = {n} must be positive", i + 1))?;
    }
    let real = |v1_at: usize, v2_at: usize| if v1 { f.f32(v1_at) } else { f.f64(v2_at) };
    let code = |v1_at: usize, v2_at: usize| if v1 { f.i16(v1_at) } else { f.i32(v2_at) };
    let vox_offset = if v1 { f.f32(108) } else { f.i64(168) as f64 };
    let mut srow = [[0.0; 4]; 3];
    for (r, row) in srow.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = real(280 + 16 * r + 4 * c, 400 + 32 * r + 8 * c);
        }
    }
    Ok(Header {
        version: if v1 { 1 } else { 2 },
        endian,
        pair,
        scalar,
        dims,
        pixdim: [pixdim(0), pixdim(1), pixdim(2), pixdim(3)],
        vox_offset,
        slope: real(112, 176),
        inter: real(116, 184),
        qform_code: code(252, 344),
        sform_code: code(254, 348),
        quatern: [real(256, 352), real(260, 360), real(264, 368)],
        qoffset: [real(268, 376), real(272, 384), real(276, 392)],
        srow,
        space_unit: (if v1 {
            i64::from(bytes[123])
        } else {
            f.i32(500)
        } & 0x07) as u8,
    })
}
