//! Choosing the reader: a path (and raw options, if given) to the
//! [`SampleSource`] that reads it.

use super::zarr::{self, ZarrSelect};
use super::{dicom, hdf5, metaimage, nifti, npy, nrrd, raw, tiff_stack, vti, vtk_legacy};
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
    /// A dataset of an HDF5 file (`.h5`, `.hdf5`, `.nxs`, ...).
    Hdf5,
}

impl Format {
    /// The reader for `path`: raw when `raw` options are given; a directory
    /// named `*.zarr` or holding Zarr metadata is Zarr; one holding DICOM files is a DICOM series, another directory or a glob
    /// pattern a TIFF stack; otherwise by extension (`.npy`, `.nrrd`,
    /// `.nhdr`, `.nii`, `.nii.gz`, `.hdr`, `.mhd`, `.mha`, `.vtk`, `.vti`,
    /// `.tif`/`.tiff`, `.dcm`, `.h5`, `.hdf5`, `.hdf`, `.he5`, `.nxs`), a
    /// file with the DICOM magic is DICOM and one with the HDF5 signature
    /// HDF5 whatever its name. `None` if no reader fits.
    pub fn detect(path: &Path, raw: bool) -> Option<Format> {
        if raw {
            return Some(Format::Raw);
        }
        if zarr::is_zarr(path) {
            return Some(Format::Zarr);
        }
        if path.is_file() && hdf5::is_hdf5(path) {
            return Some(Format::Hdf5);
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
            Format::Hdf5 => "HDF5",
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
/// (`--array`, `--level`) or the dataset of an HDF5 file (`--dataset`, or
/// `path` given as `FILE:/path/to/dataset`) or the series of a DICOM
/// directory (`--series`); `select` must be empty for other formats.
pub fn open_selected(
    path: &Path,
    raw: Option<&RawOptions>,
    select: &ZarrSelect,
    cancel: &AtomicBool,
) -> Result<Box<dyn SampleSource>> {
    if raw.is_none() {
        if let Some((file, dataset)) = hdf5::split_path(path) {
            if select.dataset.is_some() {
                return Err(crate::Error::Invalid(format!(
                    "{}: give the dataset as FILE:PATH or with --dataset, not both",
                    path.display()
                )));
            }
            let volume = hdf5::open_at(&file, Some(&dataset), &select.at)?;
            return checked_size(path, Box::new(volume));
        }
    }
    check_input_kind(path)?;
    let format = Format::detect(path, raw.is_some());
    if (select.array.is_some() || select.level.is_some()) && format != Some(Format::Zarr) {
        return Err(crate::Error::Invalid(format!(
            "{}: --array and --level choose an array of a Zarr store, and this is not one",
            path.display()
        )));
    }
    if !select.at.is_empty() && !matches!(format, Some(Format::Zarr | Format::Hdf5)) {
        return Err(crate::Error::Invalid(format!(
            "{}: --at picks an entry of the axes before z, y, x of a Zarr array or HDF5 dataset, and this is neither",
            path.display()
        )));
    }
    if select.dataset.is_some() && format != Some(Format::Hdf5) {
        return Err(crate::Error::Invalid(format!(
            "{}: --dataset chooses a dataset of an HDF5 file, and this is not one",
            path.display()
        )));
    }
    if select.segment.is_some() && format != Some(Format::Dicom) {
        return Err(crate::Error::Invalid(format!(
            "{}: --segment picks a segment of a DICOM Segmentation object, and this is not one",
            path.display()
        )));
    }
    if select.series.is_some() && format != Some(Format::Dicom) {
        return Err(crate::Error::Invalid(format!(
            "{}: --series chooses a series of a DICOM directory, and this is not one",
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
    let format = Format::detect(path, false);
    if format.is_none() && path.is_file() {
        // `v.npy.gz`: a compressed file of a format read uncompressed. (A
        // regular file only: opening a FIFO would block.)
        let mut head = [0u8; 6];
        let n = std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
            .unwrap_or(0);
        if let Some(kind) = raw::compression_magic(&head[..n]) {
            return Err(raw::compressed_error(
                path,
                kind,
                "an uncompressed volume file",
            ));
        }
    }
    let format = format.ok_or_else(|| {
        crate::Error::Invalid(format!(
            "{}: unknown input format (expected .npy, .nrrd, .nhdr, .nii, .nii.gz, .hdr, .mhd, .mha, .vtk, .vti, .tif/.tiff, .dcm, .h5/.hdf5/.nxs, a Zarr store, a directory of TIFFs or DICOM files, or give --dims and --dtype for raw data)",
            path.display()
        ))
    })?;
    let source: Box<dyn SampleSource> = match format {
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
        Format::Dicom => dicom::open_source(path, select.series.as_deref(), select.segment)?,
        Format::Zarr => Box::new(zarr::open(path, select)?),
        Format::Hdf5 => Box::new(hdf5::open_at(path, select.dataset.as_deref(), &select.at)?),
    };
    checked_size(path, source)
}

/// Refuses a grid whose samples cannot be counted in a `usize`, or whose
/// plane of `f64` samples could not be addressed (the readers of chunked
/// stores, Zarr and HDF5, take any shape their metadata state; the
/// others check their sizes against their data).
fn checked_size(path: &Path, source: Box<dyn SampleSource>) -> Result<Box<dyn SampleSource>> {
    let [x, y, z] = source.grid().dims;
    let plane = x
        .checked_mul(y)
        .filter(|p| p.checked_mul(8).is_some_and(|b| b <= isize::MAX as usize));
    if plane.and_then(|p| p.checked_mul(z)).is_none() {
        return Err(crate::Error::Invalid(format!(
            "{}: dims {x}x{y}x{z} are too large (more samples than 64 bits count, or planes larger than memory can address)",
            path.display()
        )));
    }
    Ok(source)
}

/// The series of `path` when it is a DICOM directory of more than one
/// series, one of which must be chosen (`--series`); `None` for any other
/// input, which opens as one volume. What `tmc info DIR` lists.
pub fn dicom_series_to_choose(path: &Path) -> Result<Option<Vec<dicom::SeriesSummary>>> {
    if !path.is_dir() || Format::detect(path, false) != Some(Format::Dicom) {
        return Ok(None);
    }
    let series = dicom::list_series(path)?;
    Ok((series.len() > 1).then_some(series))
}

/// The name of the format [`open`] reads `path` as ("NRRD", "NIfTI-1",
/// "TIFF stack", "raw", ...), or `None` if `open` would refuse it. A NIfTI
/// file is named by its version, read from the first bytes of the header
/// (`None` if they cannot be read).
pub fn format_name(path: &Path, raw: Option<&RawOptions>) -> Option<&'static str> {
    if hdf5::split_path(path).is_some() {
        return Some(Format::Hdf5.name());
    }
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
