//! The NRRD reader: `.nrrd` (attached data) and `.nhdr` (detached data),
//! dimension 3, or 4 with an axis of size 1.
//!
//! Understood fields: `type` (every NRRD name of 8-, 16-, 32- and 64-bit
//! integers, `float`, `double`; 64-bit integers are read as `f64`, exact
//! within ±2^53), `dimension` (3, or 4 when an axis has size 1: that axis
//! is left out, as the `.npy` and MetaImage readers leave out a unit
//! axis; see `volume_axes`), `sizes`, `kinds` (an axis of size above 1
//! whose kind is not spatial, `RGB-color`, `3-vector`, `list` ..., is
//! refused: it would be read as x), `endian`, `encoding`
//! (`raw`, memory-mapped; `gzip`/`gz` and `bzip2`/`bz2`, decompressed once
//! into a mapped temporary file, see `spill`; `hex`, decoded so too;
//! `ascii`/`text`/`txt`, parsed into memory), `spacings` or `space directions`, `space
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
//! read it; a zero or non-finite one is refused. There, `axis mins` (with
//! `spacings` or `axis maxs`, and `centers`) give the origin as teem's
//! `nrrdOriginCalculate` does and ITK reads it (see `axis_origin`).
//! Lengths in another unit than millimetres (`space units`, or `units`
//! without `space directions`) are converted to millimetres (see
//! `lengths`).

use super::nrrd_data::{open_data, DataFormat};
use super::nrrd_header::{parse_line, DataFile, Encoding, Header};
pub(crate) use super::nrrd_header::{read_line, MAX_HEADER};
use super::nrrd_pattern::format_number;
use super::raw::dims_text;
use super::slab_stack::SlabStack;
use super::units::millimetres_per;
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
    /// Where the grid's lengths came from when the header's units are not
    /// millimetres (`space units` or `units`, converted or not known).
    unit: Option<String>,
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

    fn plane_memory(&self) -> super::PlaneMemory {
        self.data.plane_memory()
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

    /// Spacing and origin from the header, converted to millimetres from
    /// the units it states (said), or left as stated in a unit tmc does
    /// not know (said too).
    fn notes(&self) -> super::SourceNotes {
        let from = match &self.unit {
            Some(what) => super::ValueFrom::File { what: what.clone() },
            None => super::ValueFrom::header(),
        };
        super::SourceNotes {
            spacing_from: from.clone(),
            origin_from: from,
            ..super::SourceNotes::default()
        }
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
    let axes = volume_axes(&header).map_err(&fail)?;
    let dims = axes.map(|a| header.sizes.as_deref().unwrap_or_default()[a]);
    let lengths = lengths(&header, axes).map_err(&fail)?;
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
    if let Some(Ok(directions)) = &header.directions {
        let mut matrix = [[0.0; 3]; 3];
        for (j, &axis) in axes.iter().enumerate() {
            let Some(v) = &directions[axis] else {
                return Err(fail(format!(
                    "'space directions' entry {} is 'none' (a non-spatial axis), which a 3-D volume cannot have",
                    axis + 1
                )));
            };
            for (i, row) in matrix.iter_mut().enumerate() {
                row[j] = v[i] * lengths.mm[i];
            }
        }
        // The vectors' lengths are the spacing.
        set_direction(&mut grid, matrix).map_err(|e| fail(format!("'space directions': {e}")))?;
    } else if let Some(all) = &header.spacings {
        let spacings = axes.map(|a| all[a]);
        if spacings.iter().all(|s| s.is_finite() && *s != 0.0) {
            // Axis j points along +e_j or, for a negative spacing, along
            // -e_j (a mirrored grid): the diagonal of the signed spacings.
            let matrix = [0, 1, 2].map(|r| {
                [0, 1, 2].map(|c| {
                    if r == c {
                        spacings[c] * lengths.mm[c]
                    } else {
                        0.0
                    }
                })
            });
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
    if header.directions.is_none() && header.origin.is_none() {
        if let Some(origin) = axis_origin(&header, axes, dims) {
            grid.origin = origin;
        }
    }
    for (o, mm) in grid.origin.iter_mut().zip(lengths.mm) {
        *o *= mm;
    }

    let format = DataFormat {
        scalar,
        endian,
        encoding,
        line_skip: header.line_skip,
        byte_skip: header.byte_skip,
    };
    let (files, start) = data_files(path, &header, consumed, dims[2], axes)?;
    let depth = dims[2] / files.len();
    let slab = Grid {
        dims: [dims[0], dims[1], depth],
        ..grid
    };
    let slabs = files
        .iter()
        .map(|file| {
            open_data(file, start, slab, &format, cancel).map_err(|e| {
                // A detached data file: its errors name the header first.
                if file == path {
                    e
                } else {
                    e.in_data_file(path, file)
                }
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(NrrdVolume {
        scalar,
        endian,
        space: header.space,
        unit: lengths.what,
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
/// (`consumed`, the end of the header, for attached data, else 0). `axes`
/// are the header's axes that make the volume ([`volume_axes`]): a file's
/// `subdim` counts the header's axes, the unit one left out included.
fn data_files(
    path: &Path,
    header: &Header,
    consumed: u64,
    nz: usize,
    axes: [usize; 3],
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
    let n = header.dimension.unwrap_or(3);
    let subdim = subdim.unwrap_or(n - 1);
    // The volume's axes among the first `subdim` of the header's.
    let volume_subdim = if subdim > n {
        subdim
    } else {
        axes.iter().filter(|&&a| a < subdim).count()
    };
    match volume_subdim {
        2 if names.len() != nz => Err(fail(format!(
            "{what} names {} files, sizes need {nz} (one per z-slice)",
            names.len()
        ))),
        3 if names.is_empty() || !nz.is_multiple_of(names.len()) => Err(fail(format!(
            "{what} names {} files, which do not split the {nz} z-slices evenly",
            names.len()
        ))),
        2 | 3 => Ok((names, 0)),
        _ => Err(fail(format!(
            "'data file' subdimension {subdim} is not supported (one slice per file, or a block of slices)"
        ))),
    }
}

/// The origin that `axis mins` give a grid without `space directions`, as
/// teem's `nrrdOriginCalculate` computes it with cell centring by default
/// (ITK's NRRD reader calls it so): the centre of the first sample, at
/// `min + spacing / 2` on a cell-centred axis and `min` on a node-centred
/// one, the spacing from `spacings`, else from `axis maxs` (`(max - min)`
/// over `size`, or `size - 1` for nodes). `None`, as teem gives no origin,
/// when an axis lacks its min, or both its spacing and max.
fn axis_origin(header: &Header, axes: [usize; 3], dims: [usize; 3]) -> Option<[f64; 3]> {
    let mins = header.axis_mins.as_ref()?;
    let known = |v: Option<&Vec<f64>>, a: usize| v.map(|v| v[a]).filter(|x| x.is_finite());
    let mut origin = [0.0; 3];
    for (j, &a) in axes.iter().enumerate() {
        let min = known(Some(mins), a)?;
        let cell = header.centers.as_ref().is_none_or(|c| c[a] != "node");
        let denom = if cell { dims[j] } else { dims[j] - 1 } as f64;
        let spacing = match known(header.spacings.as_ref(), a) {
            Some(s) => s,
            None => (known(header.axis_maxs.as_ref(), a)? - min) / denom,
        };
        origin[j] = min + if cell { spacing / 2.0 } else { 0.0 };
    }
    origin.iter().all(|o| o.is_finite()).then_some(origin)
}

/// Millimetres per unit of the grid's lengths along each space axis, and
/// where they came from when not millimetres.
struct Lengths {
    /// Millimetres per stated unit, per space axis (1 for millimetres, no
    /// unit or one tmc does not know).
    mm: [f64; 3],
    /// For `tmc info`: the fields and units converted, or the unknown
    /// units left as stated; `None` for millimetres or no unit.
    what: Option<String>,
}

/// The units of the header's lengths: `space units` (one per space axis,
/// the unit of `space directions` and `space origin`, as Fiji's NRRD writer
/// gives `"microns"`) or, without `space directions`, `units` (one per
/// axis, the unit of `spacings` and `axis mins`/`axis maxs`; taken before
/// `space units`). With `space directions`, `units` that name one unit for
/// every axis are that of the space (teem allows no per-axis units there;
/// different ones are refused). Metres, microns, nanometres and the other
/// lengths [`millimetres_per`] knows are converted to millimetres, as
/// NIfTI's `xyzt_units` and the TIFF, OME-Zarr and HDF5 voxel sizes are;
/// an empty unit or `???` states none.
fn lengths(header: &Header, axes: [usize; 3]) -> std::result::Result<Lengths, String> {
    let stated = |u: &&String| !u.is_empty() && u.as_str() != "???";
    if let Some(space) = &header.space_units {
        if space.len() != 3 {
            return Err(format!(
                "'space units' has {} values, need 3 (one per space axis)",
                space.len()
            ));
        }
    }
    let space = |i: usize| header.space_units.as_ref().map(|s| &s[i]).filter(stated);
    let axis = |i: usize| header.units.as_ref().map(|u| &u[axes[i]]).filter(stated);
    let mut names: [Option<(&str, &String)>; 3] = [None; 3];
    for (i, name) in names.iter_mut().enumerate() {
        *name = if header.directions.is_some() {
            space(i).map(|u| ("space units", u))
        } else {
            axis(i)
                .map(|u| ("units", u))
                .or_else(|| space(i).map(|u| ("space units", u)))
        };
    }
    if header.directions.is_some() && header.space_units.is_none() {
        let given: Vec<&String> = (0..3).filter_map(axis).collect();
        if let Some(first) = given.first() {
            if given.len() < 3 || given.iter().any(|u| u != first) {
                let all = header.units.as_deref().unwrap_or_default().join("\" \"");
                return Err(format!(
                    "'units' \"{all}\" with 'space directions' must name one unit for every axis (or give 'space units', one per space axis)"
                ));
            }
            names = [Some(("units", *first)); 3];
        }
    }
    let mut mm = [1.0; 3];
    let (mut fields, mut known, mut unknown) = (Vec::new(), Vec::new(), Vec::new());
    for (i, (field, unit)) in names
        .iter()
        .enumerate()
        .filter_map(|(i, n)| Some((i, (*n)?)))
    {
        if !fields.contains(&field) {
            fields.push(field);
        }
        match millimetres_per(unit) {
            Some(f) => {
                mm[i] = f;
                if !known.contains(&unit.as_str()) {
                    known.push(unit.as_str());
                }
            }
            None => {
                let quoted = format!("'{unit}'");
                if !unknown.contains(&quoted) {
                    unknown.push(quoted);
                }
            }
        }
    }
    let fields = fields.join(", ");
    let what = if !unknown.is_empty() {
        Some(format!(
            "header, {fields} {} not known: values as stated",
            unknown.join(", ")
        ))
    } else if mm.iter().any(|&f| f != 1.0) {
        Some(format!("header, {fields} {}, in mm", known.join(", ")))
    } else {
        None
    };
    Ok(Lengths { mm, what })
}

/// The kinds of an axis that holds positions in space (`???` and `none`
/// say nothing, and are taken as such too); every other NRRD kind
/// (`RGB-color`, `3-vector`, `list`, `time`, ...) indexes components or
/// samples of something else.
fn spatial_kind(kind: &str) -> bool {
    ["domain", "space", "???", "none"]
        .iter()
        .any(|k| kind.eq_ignore_ascii_case(k))
}

/// The three axes of the header's `sizes` that make the volume, in order
/// (x, y, z): all three of a 3-D NRRD, or the axes of a 4-D NRRD but one of
/// size 1 (as `.npy` and MetaImage read a unit 4th axis; a unit axis moves
/// no sample). The axis left out is the unit axis marked non-spatial (a
/// `kinds` entry that is not [`spatial_kind`], a `none` direction or a NaN
/// spacing), else the last unit axis. Refused, naming the axis: an axis
/// of size above 1 whose kind is not spatial (a colour, vector or list
/// axis would be read as x), a 4-D NRRD with no unit axis, per-axis fields
/// whose count is not `dimension`.
fn volume_axes(header: &Header) -> std::result::Result<[usize; 3], String> {
    let n = match header.dimension {
        Some(n @ (3 | 4)) => n,
        Some(d) => {
            return Err(format!(
                "dimension {d} is not supported (need 3, or 4 with an axis of size 1)"
            ))
        }
        None => return Err("missing 'dimension' field".into()),
    };
    let count = |field: &str, len: Option<usize>, what: &str| match len {
        Some(len) if len != n => Err(format!(
            "'{field}' has {len} {what}, need {n} (one per axis)"
        )),
        _ => Ok(()),
    };
    count("spacings", header.spacings.as_ref().map(Vec::len), "values")?;
    count("kinds", header.kinds.as_ref().map(Vec::len), "values")?;
    count(
        "axis mins",
        header.axis_mins.as_ref().map(Vec::len),
        "values",
    )?;
    count(
        "axis maxs",
        header.axis_maxs.as_ref().map(Vec::len),
        "values",
    )?;
    count("centers", header.centers.as_ref().map(Vec::len), "values")?;
    count("units", header.units.as_ref().map(Vec::len), "values")?;
    match &header.directions {
        Some(Ok(d)) => count("space directions", Some(d.len()), "vectors")?,
        Some(Err(e)) => return Err(e.clone()),
        None => {}
    }
    let sizes = match header.sizes.as_deref() {
        Some(s) if s.len() == n => s,
        Some(s) => return Err(format!("'sizes' has {} values, need {n}", s.len())),
        None => return Err("missing 'sizes' field".into()),
    };
    let kind = |a: usize| header.kinds.as_ref().map(|k| k[a].as_str());
    let non_spatial = |a: usize| {
        kind(a).is_some_and(|k| !spatial_kind(k))
            || matches!(&header.directions, Some(Ok(d)) if d[a].is_none())
            || header.spacings.as_ref().is_some_and(|s| s[a].is_nan())
    };
    let sizes_text = || {
        let v: Vec<String> = sizes.iter().map(usize::to_string).collect();
        v.join(" ")
    };
    let mut axes: Vec<usize> = (0..n).collect();
    if n == 4 {
        let unit = |a: &usize| sizes[*a] == 1;
        let dropped = axes
            .iter()
            .copied()
            .filter(unit)
            .find(|&a| non_spatial(a))
            .or_else(|| axes.iter().copied().rfind(unit));
        match dropped {
            Some(a) => {
                axes.remove(a);
            }
            None => {
                let which = match (0..n).find(|&a| non_spatial(a)) {
                    Some(a) => match kind(a) {
                        Some(k) => format!("axis {} (kind '{k}') has size {}", a + 1, sizes[a]),
                        None => format!("axis {} (non-spatial) has size {}", a + 1, sizes[a]),
                    },
                    None => "no axis has size 1".to_string(),
                };
                return Err(format!(
                    "dimension 4 with sizes {} is not one volume: {which} (a 4-D NRRD is read when one axis has size 1); write one 3-D scalar volume (e.g. with teem's unu slice)",
                    sizes_text()
                ));
            }
        }
    }
    if let Some(&a) = axes
        .iter()
        .find(|&&a| sizes[a] > 1 && kind(a).is_some_and(|k| !spatial_kind(k)))
    {
        return Err(format!(
            "axis {} has kind '{}' and size {} (sizes {}): a scalar volume is needed, with spatial ('domain' or 'space') axes; write one component (e.g. with teem's unu slice)",
            a + 1,
            kind(a).unwrap_or_default(),
            sizes[a],
            sizes_text()
        ));
    }
    Ok([axes[0], axes[1], axes[2]])
}
