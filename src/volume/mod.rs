//! Sample sources: a regular grid of scalar samples read one z-plane at a time.
//!
//! Every reader (one file per format) implements [`SampleSource`]; the slab
//! loop only ever asks for whole planes, so a reader may memory-map its file
//! and convert a plane on demand without holding the volume in memory.
//! [`write_volume`] goes the other way: it writes any source, plane by
//! plane, as a `.nrrd`, `.npy` or raw file.

mod array;
mod ascii;
pub mod dicom;
mod dicom_lengths;
mod guarded;
mod lent;
pub mod metaimage;
pub mod nifti;
pub mod npy;
pub mod nrrd;
mod nrrd_data;
mod nrrd_header;
mod nrrd_pattern;
mod padded;
pub mod raw;
mod scalar;
mod slab_stack;
mod spill;
pub mod summary;
pub mod tiff_stack;
pub mod vti;
pub mod vtk_legacy;
pub mod write;

pub use array::{ArrayVolume, Sample, Threshold};
pub use guarded::in_guarded_call;
pub use lent::LentPlane;
pub use padded::Padded;
pub use raw::RawVolume;
pub use scalar::{decode_samples, decode_strided, encode_samples, Endian, ScalarType};
pub use summary::{summarize, Suggestions, Summary, SummaryOptions};
pub use write::{write_volume, write_volume_cancellable, VolumeFormat};

use crate::Result;
use std::ops::Range;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Geometry of a regular grid: sample counts and the index-to-world map
/// `world = origin + direction * (index * spacing)` (x varies fastest in
/// memory).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// Distance between samples along x, y, z.
    pub spacing: [f64; 3],
    /// Physical position of sample (0, 0, 0).
    pub origin: [f64; 3],
    /// Direction cosines: column `j` is the unit world direction of index
    /// axis `j` (`direction[i][j]`, row = world axis), as in NIfTI and ITK.
    /// A reflection (negative determinant) flips the triangles' winding so
    /// that normals still point outward.
    pub direction: [[f64; 3]; 3],
}

/// The identity direction matrix: index axes along world axes.
pub const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Grid {
    /// A grid with unit spacing, zero origin and identity direction.
    pub fn unit(dims: [usize; 3]) -> Self {
        Grid {
            dims,
            spacing: [1.0; 3],
            origin: [0.0; 3],
            direction: IDENTITY,
        }
    }

    /// World position of the (fractional) grid index `index`.
    pub fn world(&self, index: [f64; 3]) -> [f64; 3] {
        let scaled = [0, 1, 2].map(|j| index[j] * self.spacing[j]);
        [0, 1, 2].map(|i| {
            self.origin[i]
                + self.direction[i][0] * scaled[0]
                + self.direction[i][1] * scaled[1]
                + self.direction[i][2] * scaled[2]
        })
    }

    /// Does the index-to-world map mirror space (negative determinant)?
    pub fn is_mirrored(&self) -> bool {
        let d = &self.direction;
        let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
            - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
            + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        det < 0.0
    }

    /// Samples in one z-plane.
    pub fn plane_len(&self) -> usize {
        self.dims[0] * self.dims[1]
    }
}

/// A source of samples, read plane by plane (`z` = slowest axis).
///
/// Implementations must be deterministic: reading the same plane twice gives
/// the same values. Values are converted to `f64` (exact for every supported
/// integer type).
pub trait SampleSource: Sync {
    /// The grid the samples live on.
    fn grid(&self) -> &Grid;
    /// Writes the samples of plane `z` (x fastest) into `out`, whose length
    /// is `grid().plane_len()`.
    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()>;

    /// Plane `z` as stored, when the source holds it in memory in native
    /// byte order and without scaling, so that no `f64` copy is needed;
    /// `None` (the default) makes the caller use [`SampleSource::read_plane`].
    /// Both must give the same values.
    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        let _ = z;
        None
    }

    /// A hint about planes `planes`: they will be read soon, or this reader
    /// of them is done. A memory-mapped source passes it to the kernel, so
    /// that the page cache, not the process, holds the data. Never changes
    /// what is read.
    fn advise(&self, planes: Range<usize>, access: Access) {
        let _ = (planes, access);
    }

    /// Checks that the storage behind the samples is still whole: a
    /// memory-mapped file must not have shrunk below the mapped length (a
    /// read from the missing part would raise SIGBUS). The pipeline calls
    /// it before each slab; it must be cheap (one `fstat`). `Ok` by default.
    fn check_unchanged(&self) -> Result<()> {
        Ok(())
    }

    /// The files the samples are read from during the extraction (mapped
    /// data files, DICOM slices), which the output must not overwrite;
    /// empty (the default) for sources that read nothing after opening.
    fn data_files(&self) -> Vec<&Path> {
        Vec::new()
    }

    /// Bytes one sample takes where it is stored (the file's sample size for
    /// a file reader), for reporting the bytes read; 8 (an `f64`) unless a
    /// source says otherwise.
    fn sample_bytes(&self) -> usize {
        8
    }

    /// The sample type as stored in the file (before any scaling), if the
    /// source knows it; `None` (the default) for computed or in-memory
    /// sources. Only reported, never used to read.
    fn stored_type(&self) -> Option<ScalarType> {
        None
    }
}

/// What the pipeline is about to do with some planes (see [`SampleSource::advise`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// They will be read soon: read ahead.
    Soon,
    /// This slab has read them for the last time: release the pages.
    Done,
}

/// Options for raw input, which carries no header of its own.
#[derive(Debug, Clone)]
pub struct RawOptions {
    /// Samples along x, y, z.
    pub dims: [usize; 3],
    /// Sample type.
    pub scalar: ScalarType,
    /// Byte order of multi-byte samples.
    pub endian: Endian,
    /// Bytes to skip before the first sample.
    pub header_bytes: u64,
    /// Distance between samples.
    pub spacing: [f64; 3],
    /// Position of the first sample.
    pub origin: [f64; 3],
}

/// The formats [`open`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Headerless samples described by [`RawOptions`].
    Raw,
    /// NumPy `.npy`.
    Npy,
    /// NRRD, attached (`.nrrd`) or detached (`.nhdr`) header.
    Nrrd,
    /// NIfTI-1 or NIfTI-2 (`.nii`, `.nii.gz`, `.hdr` + `.img`).
    Nifti,
    /// MetaImage (`.mhd`, `.mha`).
    MetaImage,
    /// Legacy VTK `STRUCTURED_POINTS` (`.vtk`).
    VtkLegacy,
    /// VTK XML ImageData (`.vti`).
    Vti,
    /// A multi-page TIFF, or a directory or glob of single-page TIFFs.
    TiffStack,
    /// A DICOM series (a directory, one slice file or a multi-frame file).
    Dicom,
}

impl Format {
    /// The reader for `path`: raw when `raw` options are given; a directory
    /// holding DICOM files is a DICOM series, another directory or a glob
    /// pattern a TIFF stack; otherwise by extension (`.npy`, `.nrrd`,
    /// `.nhdr`, `.nii`, `.nii.gz`, `.hdr`, `.mhd`, `.mha`, `.vtk`, `.vti`,
    /// `.tif`/`.tiff`, `.dcm`), and a file with the DICOM magic is DICOM
    /// whatever its name. `None` if no reader fits.
    pub fn detect(path: &Path, raw: bool) -> Option<Format> {
        if raw {
            return Some(Format::Raw);
        }
        if path.is_dir() && dicom::dir_has_dicom(path) {
            return Some(Format::Dicom);
        }
        if path.is_dir() || tiff_stack::is_pattern(path) {
            return Some(Format::TiffStack);
        }
        let name = path.to_string_lossy().to_ascii_lowercase();
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "npy" => Some(Format::Npy),
            "nrrd" | "nhdr" => Some(Format::Nrrd),
            "nii" | "hdr" => Some(Format::Nifti),
            "gz" if name.ends_with(".nii.gz") => Some(Format::Nifti),
            "mhd" | "mha" => Some(Format::MetaImage),
            "vtk" => Some(Format::VtkLegacy),
            "vti" => Some(Format::Vti),
            "tif" | "tiff" => Some(Format::TiffStack),
            "dcm" => Some(Format::Dicom),
            _ if dicom::has_magic(path) => Some(Format::Dicom),
            _ => None,
        }
    }

    /// A short human name ("NRRD", "NIfTI", "TIFF stack", ...).
    pub fn name(self) -> &'static str {
        match self {
            Format::Raw => "raw",
            Format::Npy => "NumPy",
            Format::Nrrd => "NRRD",
            Format::Nifti => "NIfTI",
            Format::MetaImage => "MetaImage",
            Format::VtkLegacy => "VTK legacy",
            Format::Vti => "VTK ImageData",
            Format::TiffStack => "TIFF stack",
            Format::Dicom => "DICOM",
        }
    }
}

/// Refuses an input that is neither a regular file nor a directory (a FIFO,
/// a socket, a device) before anything opens it: opening a FIFO for reading
/// blocks until a writer comes. A path that cannot be looked up passes, for
/// the reader to report.
pub fn check_input_kind(path: &Path) -> Result<()> {
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(());
    };
    let kind = meta.file_type();
    if kind.is_file() || kind.is_dir() {
        return Ok(());
    }
    #[cfg(unix)]
    let what = {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            "a FIFO (named pipe)"
        } else if kind.is_socket() {
            "a socket"
        } else if kind.is_char_device() || kind.is_block_device() {
            "a device"
        } else {
            "a special file"
        }
    };
    #[cfg(not(unix))]
    let what = "a special file";
    Err(crate::Error::Format(format!(
        "{}: is {what}, not a regular file or directory; inputs are memory-mapped or read by seeking and must be files",
        path.display()
    )))
}

/// Opens a volume, choosing the reader with [`Format::detect`].
pub fn open(path: &Path, raw: Option<&RawOptions>) -> Result<Box<dyn SampleSource>> {
    open_cancellable(path, raw, &AtomicBool::new(false))
}

/// [`open`] that stops with [`crate::Error::Interrupted`] once `cancel` is
/// set (from a signal handler, say) while compressed samples (gzip, bzip2,
/// zlib) are decompressed into their temporary file; it is looked at every
/// MiB of decompressed data. Other readers do not look at it.
pub fn open_cancellable(
    path: &Path,
    raw: Option<&RawOptions>,
    cancel: &AtomicBool,
) -> Result<Box<dyn SampleSource>> {
    check_input_kind(path)?;
    if let Some(options) = raw {
        if let Some(format) = Format::detect(path, false).filter(|_| path.is_file()) {
            return Err(crate::Error::Invalid(format!(
                "{}: {} data describe their own grid and samples; --dims and --dtype are for headerless raw samples",
                path.display(),
                format.name()
            )));
        }
        return Ok(Box::new(raw::RawVolume::open(path, options)?));
    }
    if !path.exists() && !tiff_stack::is_pattern(path) {
        return Err(crate::Error::Invalid(format!(
            "{}: no such file or directory",
            path.display()
        )));
    }
    let format = Format::detect(path, false).ok_or_else(|| {
        crate::Error::Invalid(format!(
            "{}: unknown input format (expected .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha, .vtk, .vti, .tif/.tiff, .dcm, a directory of TIFFs or DICOM files, or give --dims and --dtype for raw data)",
            path.display()
        ))
    })?;
    Ok(match format {
        Format::Raw => {
            return Err(crate::Error::Invalid(format!(
                "{}: raw samples need --dims and --dtype",
                path.display()
            )))
        }
        Format::Npy => Box::new(npy::open(path)?),
        Format::Nrrd => Box::new(nrrd::open_cancellable(path, cancel)?),
        Format::Nifti => Box::new(nifti::open_cancellable(path, cancel)?),
        Format::MetaImage => Box::new(metaimage::open_cancellable(path, cancel)?),
        Format::VtkLegacy => Box::new(vtk_legacy::open(path)?),
        Format::Vti => Box::new(vti::open(path)?),
        Format::TiffStack => Box::new(tiff_stack::open(path)?),
        Format::Dicom => Box::new(dicom::open(path)?),
    })
}

/// The name of the format [`open`] reads `path` as ("NRRD", "NIfTI-1",
/// "TIFF stack", "raw", ...), or `None` if `open` would refuse it. A NIfTI
/// file is named by its version, read from the first bytes of the header
/// (`None` if they cannot be read).
pub fn format_name(path: &Path, raw: Option<&RawOptions>) -> Option<&'static str> {
    check_input_kind(path).ok()?;
    match Format::detect(path, raw.is_some())? {
        Format::Nifti => nifti_name(path),
        format => Some(format.name()),
    }
}

/// "NIfTI-1" or "NIfTI-2", from the header of `path`.
fn nifti_name(path: &Path) -> Option<&'static str> {
    match nifti::version(path)? {
        1 => Some("NIfTI-1"),
        2 => Some("NIfTI-2"),
        _ => None,
    }
}

/// Puts an index-to-world matrix into `grid`: column `j` of `matrix` is the
/// world step along index axis `j` before scaling by `grid.spacing[j]`. Its
/// length multiplies that spacing and its unit vector becomes the
/// direction, so [`Grid::direction`] always holds unit columns. A matrix
/// with a non-finite entry, a zero column or (nearly) parallel columns is
/// refused: it cannot map a grid to a volume of space.
pub(crate) fn set_direction(
    grid: &mut Grid,
    matrix: [[f64; 3]; 3],
) -> std::result::Result<(), String> {
    let mut unit = [[0.0; 3]; 3];
    for c in 0..3 {
        let norm = (0..3).map(|r| matrix[r][c].powi(2)).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(format!(
                "direction of axis {c} ({}, {}, {}) is not a usable vector",
                matrix[0][c], matrix[1][c], matrix[2][c]
            ));
        }
        for r in 0..3 {
            unit[r][c] = matrix[r][c] / norm;
        }
        grid.spacing[c] *= norm;
    }
    let d = &unit;
    let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
        - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
        + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
    if det.abs() < 1e-6 {
        return Err("the direction matrix is singular (axes are parallel)".into());
    }
    grid.direction = unit;
    Ok(())
}
