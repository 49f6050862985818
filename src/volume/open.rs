//! Choosing the reader: a path (and raw options, if given) to the
//! [`SampleSource`] that reads it.

use super::zarr::{self, ZarrSelect};
use super::{dicom, metaimage, nifti, npy, nrrd, raw, tiff_stack, vti, vtk_legacy};
use super::{RawOptions, SampleSource};
use crate::files::{check_input_kind, lowercase_extension};
use crate::Result;
use std::path::Path;
use std::sync::atomic::AtomicBool;

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
    /// A Zarr v2 or v3 array or group, OME-Zarr included (a directory).
    Zarr,
}

impl Format {
    /// The reader for `path`: raw when `raw` options are given; a directory
    /// named `*.zarr` or holding Zarr metadata is Zarr; one holding DICOM files is a DICOM series, another directory or a glob
    /// pattern a TIFF stack; otherwise by extension (`.npy`, `.nrrd`,
    /// `.nhdr`, `.nii`, `.nii.gz`, `.hdr`, `.mhd`, `.mha`, `.vtk`, `.vti`,
    /// `.tif`/`.tiff`, `.dcm`), and a file with the DICOM magic is DICOM
    /// whatever its name. `None` if no reader fits.
    pub fn detect(path: &Path, raw: bool) -> Option<Format> {
        if raw {
            return Some(Format::Raw);
        }
        if zarr::is_zarr(path) {
            return Some(Format::Zarr);
        }
        if path.is_dir() && dicom::dir_has_dicom(path) {
            return Some(Format::Dicom);
        }
        if path.is_dir() || tiff_stack::is_pattern(path) {
            return Some(Format::TiffStack);
        }
        let name = path.to_string_lossy().to_ascii_lowercase();
        let ext = lowercase_extension(path);
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
            Format::Zarr => "Zarr",
        }
    }
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
    open_selected(path, raw, &ZarrSelect::default(), cancel)
}

/// [`open_cancellable`] with the array of a Zarr group chosen by `select`
/// (`--array`, `--level`); `select` must be empty for other formats.
pub fn open_selected(
    path: &Path,
    raw: Option<&RawOptions>,
    select: &ZarrSelect,
    cancel: &AtomicBool,
) -> Result<Box<dyn SampleSource>> {
    check_input_kind(path)?;
    if *select != ZarrSelect::default() && Format::detect(path, raw.is_some()) != Some(Format::Zarr)
    {
        return Err(crate::Error::Invalid(format!(
            "{}: --array and --level choose an array of a Zarr store, and this is not one",
            path.display()
        )));
    }
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
        // An I/O error of kind NotFound (Python raises FileNotFoundError),
        // with the same words as ever.
        let missing =
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or directory");
        return Err(crate::Error::io(path, missing));
    }
    let format = Format::detect(path, false).ok_or_else(|| {
        crate::Error::Invalid(format!(
            "{}: unknown input format (expected .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha, .vtk, .vti, .tif/.tiff, .dcm, a Zarr store, a directory of TIFFs or DICOM files, or give --dims and --dtype for raw data)",
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
        Format::Zarr => Box::new(zarr::open(path, select)?),
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
