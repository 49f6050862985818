//! Which files make the series: a directory's files grouped by series from
//! their headers alone, one series chosen, and the slices of that series
//! that form one volume.
//!
//! Clinical exports mix things in one folder: several series, reports,
//! RT plans, presentation states, copies of one image in other transfer
//! syntaxes, a localizer in the series of its axial slices, files that are
//! not DICOM at all. Only the header of each file is read here (up to the
//! pixel data); pixel data is decoded later, and only for the chosen
//! series. What is not read is never an error: it is named in
//! [`DicomSeries::skipped`] (`tmc --verbose` prints it). Only the chosen
//! series can fail, and its error names its own files.
//!
//! Within the chosen series:
//! * copies of one image (the same `SOPInstanceUID`) count once: the file
//!   asked for, else a readable copy, else the first by name;
//! * files tmc cannot read (colour, an unsupported transfer syntax, a
//!   damaged header) are left out;
//! * the rest is split into groups whose slices can stack (same size,
//!   sample type, orientation and pixel spacing, [`Header::differs`]): the
//!   group of the file asked for, else the one with the most planes, is
//!   the volume; the others (localizers, projections) are left out.
//!
//! What was left out is added to an error the volume then meets (a gap
//! where a left-out slice was), and an error when nothing readable remains
//! says what was found.

use super::files::{dir_files, format_err, is_dicom_file};
use super::header::{probe, Header, Probe, SeriesMeta};
use super::seg_volume::{list, DicomSegmentation};
use super::series::{assemble, DicomSeries};
use crate::volume::SampleSource;
use crate::Result;
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// One series of a directory, as `tmc info DIR` lists it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeriesSummary {
    /// `SeriesInstanceUID`.
    pub uid: String,
    /// `SeriesNumber`, as written.
    pub number: Option<String>,
    /// `Modality` (CT, MR, RTDOSE ...).
    pub modality: Option<String>,
    /// `SeriesDescription`.
    pub description: Option<String>,
    /// Image files of the series (copies and left-out files included).
    pub files: usize,
    /// Planes of the volume tmc reads (0 if it reads none).
    pub slices: usize,
    /// Samples along x, y, z of that volume, if tmc reads it.
    pub dims: Option<[usize; 3]>,
    /// The transfer syntaxes of its files, by name.
    pub transfer_syntaxes: Vec<String>,
    /// Can tmc read it?
    pub readable: bool,
    /// Why not, or what it leaves out (one line), if anything.
    pub note: Option<String>,
}

/// An image file of a directory, with what its header says.
#[derive(Debug)]
struct ImageFile {
    path: PathBuf,
    meta: SeriesMeta,
    sop_uid: String,
    header: Result<Header>,
}

/// The files of a directory, classified from their headers.
#[derive(Debug)]
pub(super) struct Index {
    dir: PathBuf,
    images: Vec<ImageFile>,
    /// Files that are no image (or no DICOM), and why.
    skipped: Vec<String>,
}

impl Index {
    /// Reads the header of every DICOM file of `dir` (but `except`).
    pub(super) fn read(dir: &Path, except: Option<&Path>) -> Result<Index> {
        let mut images = Vec::new();
        let mut skipped = Vec::new();
        for file in dir_files(dir)? {
            let same = except.is_some_and(|e| file == e || file.file_name() == e.file_name());
            if same || !is_dicom_file(&file) {
                continue;
            }
            match probe(&file) {
                Probe::Skip(e) => skipped.push(e.to_string()),
                Probe::Image {
                    meta,
                    sop_uid,
                    header,
                } => images.push(ImageFile {
                    path: file,
                    meta,
                    sop_uid,
                    header,
                }),
            }
        }
        Ok(Index {
            dir: dir.to_path_buf(),
            images,
            skipped,
        })
    }

    /// The series UIDs, by series number (numerically where they are
    /// numbers), then UID.
    fn uids(&self) -> Vec<String> {
        let mut seen: Vec<(Option<i64>, Option<String>, String)> = Vec::new();
        for f in &self.images {
            if !seen.iter().any(|s| s.2 == f.meta.uid) {
                let n = f.meta.number.as_deref();
                seen.push((
                    n.and_then(|n| n.parse().ok()),
                    n.map(str::to_string),
                    f.meta.uid.clone(),
                ));
            }
        }
        seen.sort();
        seen.into_iter().map(|s| s.2).collect()
    }

    fn meta(&self, uid: &str) -> Option<&SeriesMeta> {
        self.images
            .iter()
            .find(|f| f.meta.uid == uid)
            .map(|f| &f.meta)
    }

    /// The UID of the series `wanted` names: a `SeriesInstanceUID`, or a
    /// `SeriesNumber` that one series of the directory has.
    fn choose(&self, wanted: &str) -> Result<String> {
        let uids = self.uids();
        if uids.iter().any(|u| u == wanted) {
            return Ok(wanted.to_string());
        }
        let same_number = |n: &str| match (n.parse::<i64>(), wanted.parse::<i64>()) {
            (Ok(a), Ok(b)) => a == b,
            _ => n == wanted,
        };
        let numbered: Vec<&String> = uids
            .iter()
            .filter(|u| {
                self.meta(u)
                    .and_then(|m| m.number.as_deref())
                    .is_some_and(same_number)
            })
            .collect();
        match numbered[..] {
            [uid] => Ok(uid.clone()),
            [] => Err(format_err(
                &self.dir,
                format!("no DICOM series {wanted} (found {})", self.list(&uids)),
            )),
            _ => Err(format_err(
                &self.dir,
                format!(
                    "{} series have the number {wanted}: {}; choose one by its UID",
                    numbered.len(),
                    numbered
                        .iter()
                        .map(|u| u.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// The series of `uids`, one phrase each, for an error.
    fn list(&self, uids: &[String]) -> String {
        uids.iter()
            .map(|uid| {
                let files = self.images.iter().filter(|f| &f.meta.uid == uid).count();
                let mut words = Vec::new();
                if let Some(m) = self.meta(uid) {
                    if let Some(n) = &m.number {
                        words.push(format!("series {n}"));
                    }
                    words.extend(m.modality.clone());
                }
                words.push(format!("{files} files"));
                format!("{uid} ({})", words.join(", "))
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The UID of the series `wanted` (a UID or a number), or of the only
    /// series when `None`; several series are then an error listing them.
    fn chosen(&self, wanted: Option<&str>) -> Result<String> {
        let uids = self.uids();
        match wanted {
            Some(w) => self.choose(w),
            None => match &uids[..] {
                [uid] => Ok(uid.clone()),
                [] => {
                    let why = match self.skipped.len() {
                        0 => String::new(),
                        n => format!(
                            " ({n} DICOM file(s) that hold no image or do not parse; tmc info on one says why)"
                        ),
                    };
                    Err(format_err(
                        &self.dir,
                        format!("no DICOM image files found{why}"),
                    ))
                }
                _ => Err(format_err(
                    &self.dir,
                    format!(
                        "{} DICOM series in one directory: {}; choose one with --series NUMBER or UID (tmc info lists them) or open one file of it",
                        uids.len(),
                        self.list(&uids)
                    ),
                )),
            },
        }
    }

    /// The Segmentation file of series `uid`, if it is a SEG series; an
    /// error if it holds several (each is a volume of its own).
    fn segmentation_file(&self, uid: &str) -> Result<Option<PathBuf>> {
        let segs: Vec<&ImageFile> = self
            .images
            .iter()
            .filter(|f| f.meta.uid == uid && f.meta.segmentation)
            .collect();
        match segs[..] {
            [] => Ok(None),
            [one] => Ok(Some(one.path.clone())),
            _ => Err(format_err(
                &self.dir,
                format!(
                    "series {uid} holds {} Segmentation files: open one of them",
                    segs.len()
                ),
            )),
        }
    }

    /// Opens series `uid`, to which file `asked` (already read) belongs if
    /// given: the file's own error if it cannot be read.
    pub(super) fn open_uid(mut self, uid: &str, asked: Option<ImageHeader>) -> Result<DicomSeries> {
        let mut others = std::mem::take(&mut self.skipped);
        let mut mine = Vec::new();
        for f in std::mem::take(&mut self.images) {
            if f.meta.uid == uid {
                mine.push(f);
            } else {
                others.push(format!(
                    "{}: of another series ({})",
                    f.path.display(),
                    f.meta.uid
                ));
            }
        }
        let mut series = select(&self.dir, uid, mine, asked)?;
        series.skipped.extend(others);
        Ok(series)
    }

    /// What `tmc info DIR` lists: every series, whether tmc can read it.
    pub(super) fn summaries(mut self) -> Vec<SeriesSummary> {
        let dir = self.dir.clone();
        let mut out = Vec::new();
        for uid in self.uids() {
            let (mine, rest): (Vec<ImageFile>, Vec<ImageFile>) = std::mem::take(&mut self.images)
                .into_iter()
                .partition(|f| f.meta.uid == uid);
            self.images = rest;
            let meta = mine[0].meta.clone();
            let files = mine.len();
            let syntaxes: BTreeSet<String> = mine
                .iter()
                .map(|f| f.meta.transfer_syntax.clone())
                .collect();
            let seg = mine
                .iter()
                .find(|f| f.meta.segmentation)
                .map(|f| f.path.clone());
            let opened = match seg {
                Some(path) => DicomSegmentation::open(&path, None).map(|s| {
                    let mut note = list(s.segments());
                    for [a, b] in s.overlapping_segments() {
                        note.push_str(&format!("; {a} and {b} overlap"));
                    }
                    (s.grid().dims, Some(note))
                }),
                None => select(&dir, &uid, mine, None).map(|s| {
                    let left = s.skipped.len();
                    let note = (left > 0).then(|| format!("{left} file(s) left out"));
                    (s.grid_dims(), note)
                }),
            };
            let (readable, dims, note) = match opened {
                Ok((dims, note)) => (true, Some(dims), note),
                Err(e) => (false, None, Some(short(&dir, &e.to_string()))),
            };
            out.push(SeriesSummary {
                uid,
                number: meta.number,
                modality: meta.modality,
                description: meta.description,
                files,
                slices: dims.map_or(0, |d| d[2]),
                dims,
                transfer_syntaxes: syntaxes.into_iter().collect(),
                readable,
                note,
            });
        }
        out
    }
}

/// Error `e` about series of `dir` in a line of a listing: file names
/// without the directory, the first reason only.
fn short(dir: &Path, e: &str) -> String {
    let prefix = format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR);
    let e = e.replace(&prefix, "");
    let e = e
        .strip_prefix(&format!("{}: ", dir.display()))
        .unwrap_or(&e);
    match e.split_once("; ") {
        Some((first, rest)) => format!("{first}; and {} more)", rest.matches("; ").count() + 1),
        None => e.to_string(),
    }
}

/// The file a user named, read before its directory.
#[derive(Debug)]
pub(super) struct ImageHeader {
    pub(super) sop_uid: String,
    pub(super) header: Header,
}

/// The volume of series `uid` from its image files `mine` (and the file
/// `asked` for, if any), as the module's doc says.
fn select(
    dir: &Path,
    uid: &str,
    mut mine: Vec<ImageFile>,
    asked: Option<ImageHeader>,
) -> Result<DicomSeries> {
    let mut left_out = Vec::new();
    let has_asked = asked.is_some();
    // Readable copies first, those with the most planes first, then by
    // name (the directory's order).
    mine.sort_by_key(|f| match &f.header {
        Ok(h) => (false, std::cmp::Reverse(h.planes.len())),
        Err(_) => (true, std::cmp::Reverse(0)),
    });
    let mut sops: Vec<(String, PathBuf)> = Vec::new();
    let mut headers = Vec::new();
    if let Some(a) = asked {
        sops.push((a.sop_uid, a.header.path.clone()));
        headers.push(a.header);
    }
    for f in mine {
        let copy = sops
            .iter()
            .find(|(sop, _)| !sop.is_empty() && *sop == f.sop_uid);
        if let Some((_, kept)) = copy {
            left_out.push(format!(
                "{}: a copy of {} (the same SOPInstanceUID)",
                f.path.display(),
                kept.display()
            ));
            continue;
        }
        sops.push((f.sop_uid, f.path.clone()));
        match f.header {
            Ok(h) => headers.push(h),
            Err(e) => left_out.push(e.to_string()),
        }
    }
    if headers.is_empty() {
        return Err(format_err(
            dir,
            format!(
                "DICOM series {uid} holds no image tmc can read ({})",
                first_reasons(&left_out)
            ),
        ));
    }
    // Groups of slices that stack; the first holds the file asked for.
    let mut groups: Vec<Vec<Header>> = Vec::new();
    for h in headers {
        match groups.iter_mut().find(|g| h.differs(&g[0]).is_none()) {
            Some(g) => g.push(h),
            None => groups.push(vec![h]),
        }
    }
    let planes = |g: &Vec<Header>| g.iter().map(|h| h.planes.len()).sum::<usize>();
    let chosen = if has_asked {
        0
    } else {
        (0..groups.len())
            .max_by_key(|&i| (planes(&groups[i]), std::cmp::Reverse(i)))
            .unwrap_or(0)
    };
    let volume = groups.swap_remove(chosen);
    for h in groups.into_iter().flatten() {
        let why = h.differs(&volume[0]).unwrap_or_default();
        left_out.push(format!("{}: left out: {why}", h.path.display()));
    }
    assemble(dir, uid.to_string(), volume, left_out)
}

/// Opens a DICOM directory, slice file or multi-frame file; a directory
/// must hold one series (else see [`open_series`]).
pub fn open(path: &Path) -> Result<DicomSeries> {
    open_series(path, None)
}

/// Opens what `path` holds, as [`crate::volume::open()`] does: a
/// Segmentation object (a SEG file, or the SEG series `series` of a
/// directory) as its label map, or its segment `segment` alone
/// ([`DicomSegmentation`]); any other series as [`open_series`] does,
/// and then `segment` must be `None`.
pub fn open_source(
    path: &Path,
    series: Option<&str>,
    segment: Option<u32>,
) -> Result<Box<dyn SampleSource>> {
    let seg_file = if path.is_dir() {
        let index = Index::read(path, None)?;
        let uid = index.chosen(series)?;
        match index.segmentation_file(&uid)? {
            Some(file) => Some(file),
            None if segment.is_none() => return Ok(Box::new(index.open_uid(&uid, None)?)),
            None => None,
        }
    } else {
        match probe(path) {
            Probe::Image { meta, .. } if meta.segmentation => {
                if let Some(wanted) = series {
                    if wanted != meta.uid && meta.number.as_deref() != Some(wanted) {
                        return Err(format_err(
                            path,
                            format!("belongs to series {}, not {wanted}", meta.uid),
                        ));
                    }
                }
                Some(path.to_path_buf())
            }
            _ => None,
        }
    };
    match seg_file {
        Some(file) => Ok(Box::new(DicomSegmentation::open(&file, segment)?)),
        None if segment.is_some() => Err(format_err(
            path,
            "--segment picks a segment of a DICOM Segmentation object (modality SEG), and this is not one",
        )),
        None => Ok(Box::new(open_series(path, series)?)),
    }
}

/// Opens the series `series` (a `SeriesInstanceUID` or a `SeriesNumber`)
/// of a directory, or the only series there when `series` is `None`. A
/// single-frame file stands for its own series in its directory, whatever
/// else the directory holds; a multi-frame file for itself.
pub fn open_series(path: &Path, series: Option<&str>) -> Result<DicomSeries> {
    if path.is_dir() {
        let index = Index::read(path, None)?;
        let uid = index.chosen(series)?;
        return index.open_uid(&uid, None);
    }
    let (meta, sop_uid, header) = match probe(path) {
        Probe::Skip(e) => return Err(e),
        Probe::Image {
            meta,
            sop_uid,
            header,
        } => (meta, sop_uid, header?),
    };
    let uid = header.series_uid.clone();
    if let Some(wanted) = series {
        if wanted != uid && meta.number.as_deref() != Some(wanted) {
            return Err(format_err(
                path,
                format!("belongs to series {uid}, not {wanted}"),
            ));
        }
    }
    if header.frames > 1 {
        return assemble(path, uid, vec![header], Vec::new());
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let asked = ImageHeader { sop_uid, header };
    Index::read(&dir, Some(path))?.open_uid(&uid, Some(asked))
}

/// Every series of directory `dir` (or of the directory of file `dir`),
/// readable or not, by series number: what `tmc info` lists.
pub fn list_series(dir: &Path) -> Result<Vec<SeriesSummary>> {
    let dir = if dir.is_dir() {
        dir.to_path_buf()
    } else {
        match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    Ok(Index::read(&dir, None)?.summaries())
}

/// The first reason of `left_out`, and how many more files there are, for
/// one error line: a series of thousands of files in a syntax tmc cannot
/// decode would otherwise be thousands of copies of the same reason.
fn first_reasons(left_out: &[String]) -> String {
    match left_out {
        [] => String::new(),
        [one] => one.clone(),
        [first, rest @ ..] => format!("{first}; and {} more files not read", rest.len()),
    }
}
