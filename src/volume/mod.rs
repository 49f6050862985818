//! Sample sources: a regular grid of scalar samples read one z-plane at a time.
//!
//! Every reader (one file per format) implements [`SampleSource`]; the slab
//! loop only ever asks for whole planes, so a reader may memory-map its file
//! and convert a plane on demand without holding the volume in memory.
//! [`write_volume`] goes the other way: it writes any source, plane by
//! plane, as a `.nrrd`, `.npy` or raw file.

mod array;
pub mod dicom;
pub mod metaimage;
pub mod nifti;
pub mod npy;
pub mod nrrd;
mod padded;
pub mod raw;
mod scalar;
pub mod tiff_stack;
pub mod vti;
pub mod vtk_legacy;
pub mod write;

pub use array::ArrayVolume;
pub use padded::Padded;
pub use raw::RawVolume;
pub use scalar::{decode_samples, decode_strided, encode_samples, Endian, ScalarType};
pub use write::{write_volume, VolumeFormat};

use crate::Result;
use std::ops::Range;
use std::path::Path;

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

    /// A hint about planes `planes`: they will be read soon, or this reader
    /// of them is done. A memory-mapped source passes it to the kernel, so
    /// that the page cache, not the process, holds the data. Never changes
    /// what is read.
    fn advise(&self, planes: Range<usize>, access: Access) {
        let _ = (planes, access);
    }

    /// Bytes one sample takes where it is stored (the file's sample size for
    /// a file reader), for reporting the bytes read; 8 (an `f64`) unless a
    /// source says otherwise.
    fn sample_bytes(&self) -> usize {
        8
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

/// Opens a volume file, choosing the reader by extension (`.npy`, `.nrrd`,
/// `.nii`, `.nii.gz`, `.hdr`, `.mhd`, `.mha`, `.vtk`, `.vti`, `.tif`/`.tiff`,
/// `.dcm`; a directory holding DICOM files is a DICOM series, another
/// directory or a glob pattern is a TIFF stack; a file with the DICOM magic
/// is DICOM whatever its name) or, when `raw` is given, reading headerless
/// samples.
pub fn open(path: &Path, raw: Option<&RawOptions>) -> Result<Box<dyn SampleSource>> {
    if let Some(options) = raw {
        return Ok(Box::new(raw::RawVolume::open(path, options)?));
    }
    if path.is_dir() && dicom::dir_has_dicom(path) {
        return Ok(Box::new(dicom::open(path)?));
    }
    if path.is_dir() || tiff_stack::is_pattern(path) {
        return Ok(Box::new(tiff_stack::open(path)?));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "npy" => Ok(Box::new(npy::open(path)?)),
        "nrrd" => Ok(Box::new(nrrd::open(path)?)),
        "nii" | "hdr" => Ok(Box::new(nifti::open(path)?)),
        "gz" if path.to_string_lossy().to_ascii_lowercase().ends_with(".nii.gz") => {
            Ok(Box::new(nifti::open(path)?))
        }
        "mhd" | "mha" => Ok(Box::new(metaimage::open(path)?)),
        "vtk" => Ok(Box::new(vtk_legacy::open(path)?)),
        "vti" => Ok(Box::new(vti::open(path)?)),
        "tif" | "tiff" => Ok(Box::new(tiff_stack::open(path)?)),
        "dcm" => Ok(Box::new(dicom::open(path)?)),
        _ if dicom::has_magic(path) => Ok(Box::new(dicom::open(path)?)),
        _ => Err(crate::Error::Invalid(format!(
            "{}: unknown input format (expected .npy, .nrrd, .nii, .nii.gz, .hdr, .mhd, .mha, .vtk, .vti, .tif/.tiff, .dcm, a directory of TIFFs or DICOM files, or give --dims and --dtype for raw data)",
            path.display()
        ))),
    }
}
