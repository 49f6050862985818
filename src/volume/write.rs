//! Writing volumes: any [`SampleSource`] written plane by plane as a `.nrrd`
//! (attached header, raw encoding), `.npy` (version 1.0, C order) or
//! headerless raw file, little-endian, atomically.
//!
//! Only one plane of samples (plus a few encoded planes in flight) is held in
//! memory, so a volume of any size can be written; a writer thread writes
//! one plane while the next is computed and encoded.

use super::raw::{data_bytes, dims_text};
use super::{encode_samples, Grid, SampleSource, ScalarType};
use crate::error::try_filled;
use crate::files::{lowercase_extension, AtomicFile};
use crate::{Error, Result};
use rayon::prelude::*;
use std::io::{self, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

/// A volume file format that [`write_volume`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VolumeFormat {
    /// NRRD with an attached header, raw encoding, little-endian; the spacing
    /// is given as `space directions` (with `space: left-posterior-superior`
    /// and a zero `space origin`).
    Nrrd,
    /// numpy `.npy` version 1.0, shape `(nz, ny, nx)`, C order.
    Npy,
    /// Headerless little-endian samples, x fastest: reading them back needs
    /// the dims and the sample type.
    Raw,
}

impl VolumeFormat {
    /// The format named by `path`'s extension (`.nrrd`, `.npy`, `.raw`;
    /// case-insensitive).
    pub fn from_path(path: &Path) -> Result<VolumeFormat> {
        let ext = lowercase_extension(path);
        match ext.as_str() {
            "nrrd" => Ok(VolumeFormat::Nrrd),
            "npy" => Ok(VolumeFormat::Npy),
            "raw" => Ok(VolumeFormat::Raw),
            _ => Err(Error::Invalid(format!(
                "{}: unknown volume format (expected .nrrd, .npy or .raw)",
                path.display()
            ))),
        }
    }

    /// The bytes before the first sample of a volume on `grid` stored as
    /// `scalar`; an error for a type the format has no name for (NRRD has
    /// no 16-bit float).
    pub fn header(self, grid: &Grid, scalar: ScalarType) -> Result<Vec<u8>> {
        Ok(match self {
            VolumeFormat::Nrrd => nrrd_header(grid, scalar)?.into_bytes(),
            VolumeFormat::Npy => npy_header(grid, scalar),
            VolumeFormat::Raw => Vec::new(),
        })
    }
}

/// Writes the samples of `source` to `path` as `scalar` samples, in the
/// format named by the extension, and returns the file's size in bytes.
///
/// Samples are converted with [`encode_samples`] (integers rounded and
/// clamped to the type's range). `progress`, if given, is called with the
/// number of planes written and the number of planes in all after each plane.
/// The file is written atomically: on failure nothing is left at `path`.
pub fn write_volume(
    path: &Path,
    source: &dyn SampleSource,
    scalar: ScalarType,
    progress: Option<&dyn Fn(usize, usize)>,
) -> Result<u64> {
    write_volume_cancellable(path, source, scalar, progress, &AtomicBool::new(false))
}

/// [`write_volume`] that looks at `cancel` before each plane (one relaxed
/// load) and, once it is set (from a signal handler, say), stops with
/// [`Error::Interrupted`]; nothing is then left at `path`.
pub fn write_volume_cancellable(
    path: &Path,
    source: &dyn SampleSource,
    scalar: ScalarType,
    progress: Option<&dyn Fn(usize, usize)>,
    cancel: &AtomicBool,
) -> Result<u64> {
    let format = VolumeFormat::from_path(path)?;
    let grid = *source.grid();
    let data = data_bytes(grid.dims, scalar).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: dims {} {scalar} are too large",
            path.display(),
            dims_text(grid.dims)
        ))
    })?;
    if path.is_dir() {
        return Err(Error::Invalid(format!(
            "{}: is a directory, not an output file",
            path.display()
        )));
    }
    let header = format.header(&grid, scalar)?;
    let mut file = AtomicFile::create(path)?;
    let out = file.file();
    out.write_all(&header).map_err(|e| Error::io(path, e))?;
    write_planes(path, source, scalar, out, progress, cancel)?;
    file.commit()?;
    Ok(header.len() as u64 + data)
}

/// Computes and encodes the planes on this thread (and rayon's) while a
/// writer thread writes the previous plane to `out`.
fn write_planes(
    path: &Path,
    source: &dyn SampleSource,
    scalar: ScalarType,
    out: &mut std::fs::File,
    progress: Option<&dyn Fn(usize, usize)>,
    cancel: &AtomicBool,
) -> Result<()> {
    let [nx, _, nz] = source.grid().dims;
    let plane_len = source.grid().plane_len();
    let size = scalar.size();
    // Encoded planes go to the writer; emptied buffers come back for reuse.
    let (full_tx, full_rx) = mpsc::sync_channel::<Vec<u8>>(1);
    let (empty_tx, empty_rx) = mpsc::channel::<Vec<u8>>();
    std::thread::scope(|scope| -> Result<()> {
        let writer = scope.spawn(move || -> io::Result<()> {
            for bytes in full_rx {
                out.write_all(&bytes)?;
                // The producer may have stopped; a lost buffer is harmless.
                let _ = empty_tx.send(bytes);
            }
            Ok(())
        });
        let mut values = try_filled("a plane of samples", plane_len, 0.0)?;
        let mut produced = Ok(());
        for z in 0..nz {
            if cancel.load(Ordering::Relaxed) {
                produced = Err(Error::Interrupted);
                break;
            }
            if let Err(e) = source.read_plane(z, &mut values) {
                produced = Err(e);
                break;
            }
            let mut bytes = empty_rx
                .try_recv()
                .unwrap_or_else(|_| vec![0; plane_len * size]);
            let rows = (4096 / nx.max(1)).max(1);
            bytes
                .par_chunks_mut(nx * size * rows)
                .zip(values.par_chunks(nx * rows))
                .for_each(|(b, v)| encode_samples(scalar, super::Endian::Little, v, b));
            if full_tx.send(bytes).is_err() {
                // The writer failed; its error is reported below.
                break;
            }
            if let Some(report) = progress {
                report(z + 1, nz);
            }
        }
        drop(full_tx);
        let written = writer
            .join()
            .unwrap_or_else(|_| Err(io::Error::other("the writer thread panicked")));
        produced?;
        written.map_err(|e| Error::io(path, e))
    })
}

/// The NRRD type name of `scalar` (none for a 16-bit float).
fn nrrd_type(scalar: ScalarType) -> Result<&'static str> {
    Ok(match scalar {
        ScalarType::U8 => "uint8",
        ScalarType::I8 => "int8",
        ScalarType::U16 => "uint16",
        ScalarType::I16 => "int16",
        ScalarType::U32 => "uint32",
        ScalarType::I32 => "int32",
        ScalarType::F32 => "float",
        ScalarType::F64 => "double",
        ScalarType::I64 => "int64",
        ScalarType::U64 => "uint64",
        ScalarType::F16 => {
            return Err(Error::Invalid(
                "NRRD has no 16-bit float type: write f16 samples as .npy or .raw, or choose f32"
                    .into(),
            ))
        }
    })
}

/// A NRRD0004 header (ending with its blank line) for raw little-endian
/// samples on `grid`.
fn nrrd_header(grid: &Grid, scalar: ScalarType) -> Result<String> {
    let [nx, ny, nz] = grid.dims;
    let [sx, sy, sz] = grid.spacing;
    let [ox, oy, oz] = grid.origin;
    let name = nrrd_type(scalar)?;
    Ok(format!(
        "NRRD0004\n\
         # Complete NRRD file format specification at:\n\
         # http://teem.sourceforge.net/nrrd/format.html\n\
         type: {}\n\
         dimension: 3\n\
         space: left-posterior-superior\n\
         sizes: {nx} {ny} {nz}\n\
         space directions: ({sx},0,0) (0,{sy},0) (0,0,{sz})\n\
         kinds: domain domain domain\n\
         endian: little\n\
         encoding: raw\n\
         space origin: ({ox},{oy},{oz})\n\
         \n",
        name
    ))
}

/// The numpy dtype description of little-endian `scalar` samples.
fn npy_descr(scalar: ScalarType) -> &'static str {
    match scalar {
        ScalarType::U8 => "|u1",
        ScalarType::I8 => "|i1",
        ScalarType::U16 => "<u2",
        ScalarType::I16 => "<i2",
        ScalarType::U32 => "<u4",
        ScalarType::I32 => "<i4",
        ScalarType::F32 => "<f4",
        ScalarType::F64 => "<f8",
        ScalarType::I64 => "<i8",
        ScalarType::U64 => "<u8",
        ScalarType::F16 => "<f2",
    }
}

/// A `.npy` version 1.0 preamble and header for a C-order array of shape
/// `(nz, ny, nx)`, padded so the data starts at a multiple of 64 bytes.
fn npy_header(grid: &Grid, scalar: ScalarType) -> Vec<u8> {
    let [nx, ny, nz] = grid.dims;
    let mut dict = format!(
        "{{'descr': '{}', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}",
        npy_descr(scalar)
    );
    // Magic (6) + version (2) + length (2) + dict + newline.
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    // A 3-D shape of usize numbers is far shorter than 65535 bytes.
    bytes.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    bytes.extend_from_slice(dict.as_bytes());
    bytes
}
