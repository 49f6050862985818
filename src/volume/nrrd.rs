//! The NRRD reader: `.nrrd` (attached data) and `.nhdr` (detached data),
//! dimension 3.
//!
//! Understood fields: `type` (every NRRD name of 8-, 16- and 32-bit
//! integers, `float`, `double`; 64-bit integers are refused, since samples
//! become `f64`), `dimension` (must be 3), `sizes`, `endian`, `encoding`
//! (`raw`, memory-mapped; `gzip`/`gz` and `bzip2`/`bz2`, decompressed once
//! into a mapped temporary file, see `spill`; `ascii`/`text`/`txt`, parsed
//! into memory), `spacings` or `space directions`, `space
//! origin`, `space` (recorded, see [`NrrdVolume::space`]), `line skip` and
//! `byte skip` (`-1` for raw data at the end of the file), and `data file`
//! (or `datafile`): one file name (relative to the header's directory, or
//! absolute), `LIST [subdim]` with one name per line until the end of the
//! header file, or a printf pattern `<format> <min> <max> <step> [subdim]`.
//! Each file of a list or pattern holds a slab of `subdim` axes: 2 (the
//! default) means one z-slice per file, 3 an equal block of z-slices; the
//! skips apply to each file. The required fields (`type`, `dimension`,
//! `sizes`, `encoding`) each give their own error when missing.
//!
//! The spacing along each axis is the norm of its `space directions` vector
//! and its direction the unit vector, so the mesh lives in the NRRD's space,
//! rotation or axis flip included, shifted by `space origin`. Vectors that
//! are parallel (a singular matrix) are refused, as in the other readers.
//! Without `space directions`, `spacings` gives the spacing, and a negative
//! value mirrors its axis (positions decrease along it), as teem and ITK
//! read it; a zero or non-finite one is refused.

use super::nrrd_data::{open_data, DataFormat};
use super::nrrd_header::{parse_line, DataFile, Encoding, Header};
pub(crate) use super::nrrd_header::{read_line, MAX_HEADER};
use super::nrrd_pattern::format_number;
use super::raw::dims_text;
use super::slab_stack::SlabStack;
use super::{set_direction, Access, Endian, Grid, LentPlane, SampleSource, ScalarType};
use crate::{Error, Result};
use std::fs::File;
use std::io::BufReader;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A 3-D NRRD volume: its samples stay in their data file(s), memory-mapped
/// for raw encoding.
#[derive(Debug)]
pub struct NrrdVolume {
    scalar: ScalarType,
    endian: Endian,
    space: Option<String>,
    data: SlabStack,
}

impl NrrdVolume {
    /// The stored sample type.
    pub fn scalar(&self) -> ScalarType {
        self.scalar
    }

    /// The byte order of the stored samples.
    pub fn endian(&self) -> Endian {
        self.endian
    }

    /// The `space` field (`left-posterior-superior`, ...), if any. Recorded
    /// only: the grid maps indices into whatever space the header's
    /// directions and origin are in.
    pub fn space(&self) -> Option<&str> {
        self.space.as_deref()
    }

    /// How many files hold the samples (1 unless `data file` is a list or
    /// a pattern).
    pub fn data_files(&self) -> usize {
        self.data.files()
    }
}

impl SampleSource for NrrdVolume {
    fn grid(&self) -> &Grid {
        self.data.grid()
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        self.data.read_plane(z, out)
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        self.data.lend_plane(z)
    }

    fn advise(&self, planes: Range<usize>, access: Access) {
        self.data.advise(planes, access)
    }

    fn check_unchanged(&self) -> Result<()> {
        self.data.check_unchanged()
    }

    fn data_files(&self) -> Vec<&Path> {
        self.data.data_files()
    }

    fn sample_bytes(&self) -> usize {
        self.scalar.size()
    }

    fn stored_type(&self) -> Option<ScalarType> {
        Some(self.scalar)
    }
}

/// Opens a 3-D NRRD file (`.nrrd` or `.nhdr`).
pub fn open(path: &Path) -> Result<NrrdVolume> {
    open_cancellable(path, &AtomicBool::new(false))
}

/// [`open`] that stops with [`Error::Interrupted`] once `cancel` is set
/// while compressed samples are decompressed (it is looked at every MiB).
pub fn open_cancellable(path: &Path, cancel: &AtomicBool) -> Result<NrrdVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let (header, consumed) = read_header(path)?;

    let scalar = header
        .scalar
        .ok_or_else(|| fail("missing 'type' field".into()))?;
    match header.dimension {
        Some(3) => {}
        Some(d) => return Err(fail(format!("dimension {d} is not supported (need 3)"))),
        None => return Err(fail("missing 'dimension' field".into())),
    }
    let directions = header.directions.clone().transpose().map_err(fail)?;
    let dims = match header.sizes.as_deref() {
        Some(&[x, y, z]) => [x, y, z],
        Some(s) => return Err(fail(format!("'sizes' has {} values, need 3", s.len()))),
        None => return Err(fail("missing 'sizes' field".into())),
    };
    let encoding = header
        .encoding
        .ok_or_else(|| fail("missing 'encoding' field".into()))?;
    let endian = match (header.endian, scalar.size(), encoding) {
        (Some(e), _, _) => e,
        (None, 1, _) | (None, _, Encoding::Ascii) => Endian::Little,
        (None, _, _) => return Err(fail(format!("missing 'endian' field for type {scalar}"))),
    };
    let mut grid = Grid {
        dims,
        spacing: [1.0; 3],
        origin: header.origin.unwrap_or([0.0; 3]),
        direction: super::IDENTITY,
    };
    if let Some(matrix) = directions {
        // The vectors' lengths are the spacing.
        set_direction(&mut grid, matrix).map_err(|e| fail(format!("'space directions': {e}")))?;
    } else if let Some(spacings) = header.spacings {
        if spacings.iter().all(|s| s.is_finite() && *s != 0.0) {
            // Axis j points along +e_j or, for a negative spacing, along
            // -e_j (a mirrored grid): the diagonal of the signed spacings.
            let matrix =
                [0, 1, 2].map(|r| [0, 1, 2].map(|c| if r == c { spacings[c] } else { 0.0 }));
            set_direction(&mut grid, matrix).map_err(|e| fail(format!("'spacings': {e}")))?;
        } else {
            // Here, naming the header: the data file's reader would name
            // only itself, which the user of a detached header never gave.
            let [x, y, z] = spacings;
            return Err(fail(format!(
                "'spacings' {x} {y} {z} must be finite and nonzero (a NaN marks a non-spatial axis, which a 3-D volume cannot have)"
            )));
        }
    }
    if dims.contains(&0) {
        return Err(fail(format!("sizes {} contain a zero", dims_text(dims))));
    }

    let format = DataFormat {
        scalar,
        endian,
        encoding,
        line_skip: header.line_skip,
        byte_skip: header.byte_skip,
    };
    let (files, start) = data_files(path, &header, consumed, dims[2])?;
    let depth = dims[2] / files.len();
    let slab = Grid {
        dims: [dims[0], dims[1], depth],
        ..grid
    };
    let slabs = files
        .iter()
        .map(|file| open_data(path, file, start, slab, &format, cancel))
        .collect::<Result<Vec<_>>>()?;
    Ok(NrrdVolume {
        scalar,
        endian,
        space: header.space,
        data: SlabStack::new(grid, slabs),
    })
}

/// Reads the header of `path` (with the file names of `data file: LIST`);
/// also returns the bytes it takes, where attached data begins.
fn read_header(path: &Path) -> Result<(Header, u64)> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = BufReader::new(file);
    let mut consumed = 0u64;
    let next = |reader: &mut BufReader<File>, consumed: &mut u64| {
        read_line(reader, consumed).map_err(|e| Error::io(path, e))
    };

    let first =
        next(&mut reader, &mut consumed)?.ok_or_else(|| fail("empty file, not a NRRD".into()))?;
    if !first.starts_with("NRRD") {
        return Err(fail("not a NRRD file (no NRRD magic)".into()));
    }
    let mut header = Header::default();
    loop {
        if consumed > MAX_HEADER {
            return Err(fail("NRRD header too long".into()));
        }
        let Some(line) = next(&mut reader, &mut consumed)? else {
            if header.data_file.is_some() {
                break; // A detached header may end with the file.
            }
            return Err(fail(
                "the NRRD header does not end with a blank line (no attached data)".into(),
            ));
        };
        if line.is_empty() {
            break;
        }
        parse_line(&line, &mut header).map_err(fail)?;
        if let Some(DataFile::List { names, .. }) = &mut header.data_file {
            // The rest of the file names the data files, one per line.
            while let Some(line) = next(&mut reader, &mut consumed)? {
                if !line.trim().is_empty() {
                    names.push(line.trim().to_string());
                }
            }
            break;
        }
    }
    Ok((header, consumed))
}

/// The data files of `header` (read from `path`), each holding an equal
/// slab of the `nz` z-planes, and the byte where the data starts in each
/// (`consumed`, the end of the header, for attached data, else 0).
fn data_files(
    path: &Path,
    header: &Header,
    consumed: u64,
    nz: usize,
) -> Result<(Vec<PathBuf>, u64)> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let dir = path.parent().unwrap_or(Path::new("."));
    // `join` keeps an absolute name as it is.
    let resolve = |name: &str| dir.join(name);
    let (names, subdim) = match &header.data_file {
        None => return Ok((vec![path.to_path_buf()], consumed)),
        Some(DataFile::Single(name)) => return Ok((vec![resolve(name)], 0)),
        Some(DataFile::List { subdim, names }) => {
            let names: Vec<PathBuf> = names.iter().map(|n| resolve(n)).collect();
            (names, *subdim)
        }
        Some(DataFile::Pattern {
            format,
            min,
            max,
            step,
            subdim,
        }) => {
            let count = DataFile::pattern_count(*min, *max, *step);
            if count == 0 || count > nz as u64 {
                return Err(fail(format!(
                    "'data file' pattern '{format} {min} {max} {step}' names {count} files, sizes have {nz} z-slices"
                )));
            }
            // Each name is looked up as it is made, so that a pattern
            // naming a billion files that are not there fails at the first
            // one instead of building every name in memory.
            let mut names = Vec::new();
            for i in 0..count as i64 {
                let name = resolve(&format_number(format, min + i * step).map_err(fail)?);
                if let Err(e) = std::fs::metadata(&name) {
                    return Err(fail(format!(
                        "cannot open data file {} (file {} of the {count} the pattern names): {e}",
                        name.display(),
                        i + 1
                    )));
                }
                names.push(name);
            }
            (names, *subdim)
        }
    };
    let what = if matches!(header.data_file, Some(DataFile::List { .. })) {
        "'data file: LIST'"
    } else {
        "the 'data file' pattern"
    };
    match subdim.unwrap_or(2) {
        2 if names.len() != nz => Err(fail(format!(
            "{what} names {} files, sizes need {nz} (one per z-slice)",
            names.len()
        ))),
        3 if names.is_empty() || !nz.is_multiple_of(names.len()) => Err(fail(format!(
            "{what} names {} files, which do not split the {nz} z-slices evenly",
            names.len()
        ))),
        2 | 3 => Ok((names, 0)),
        s => Err(fail(format!(
            "'data file' subdimension {s} is not supported (2: one slice per file, or 3)"
        ))),
    }
}
