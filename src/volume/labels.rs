//! [`scan_labels`]: the values of a label map and how many samples each
//! has, read plane by plane, with the first sample that is not a whole
//! number refused ([`scan_label_map`] for a pass over a label map's
//! labels, [`LabelCounts::select`] for the labels it extracts).

use super::label_runs::{MapRuns, PlaneRuns, PlaneRunsBuilder};
use super::{LentPlane, Sample, SampleSource, ScalarType};
use crate::error::make_room;
use crate::fan_out::fan_out;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// The most labels one pass takes (the pass codes them as `u16`, 0 kept
/// for no label and one for `--close`'s border).
pub const MOST_LABELS: usize = u16::MAX as usize - 1;

/// The values of a label map, ascending, each with its number of samples
/// and the last plane that holds it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LabelCounts {
    /// `(value, samples)` for every value present, ascending.
    pub counts: Vec<(i64, u64)>,
    /// The last plane (largest z) holding each value of `counts`, in the
    /// same order: past it the value's indicator is 0, so its mesh is
    /// complete once the pass is there (see
    /// [`crate::stream::last_label_chunks`]).
    pub last_planes: Vec<usize>,
}

impl LabelCounts {
    /// The last plane holding `label` (`None` when absent).
    pub fn last_plane(&self, label: i64) -> Option<usize> {
        self.counts
            .binary_search_by_key(&label, |&(l, _)| l)
            .ok()
            .map(|k| self.last_planes[k])
    }

    /// The samples of `label` (0 when absent).
    pub fn samples(&self, label: i64) -> u64 {
        self.counts
            .binary_search_by_key(&label, |&(l, _)| l)
            .map_or(0, |k| self.counts[k].1)
    }

    /// Every value present but `background`, ascending.
    pub fn labels_except(&self, background: i64) -> Vec<i64> {
        self.counts
            .iter()
            .map(|&(l, _)| l)
            .filter(|&l| l != background)
            .collect()
    }

    /// The labels a pass over the label map `input` extracts: `wanted`, or
    /// without it every value present but `background`; an error when that
    /// leaves none.
    pub fn select(
        &self,
        wanted: Option<&[i64]>,
        background: i64,
        input: &Path,
    ) -> Result<Vec<i64>> {
        let labels = match wanted {
            Some(wanted) => wanted.to_vec(),
            None => self.labels_except(background),
        };
        if labels.is_empty() {
            return Err(Error::Invalid(format!(
                "{}: no label but the background {background}",
                input.display()
            )));
        }
        // Before any file is made for them: the pass would refuse them.
        if labels.len() > MOST_LABELS {
            return Err(Error::Invalid(format!(
                "{}: {} labels; one pass takes at most {MOST_LABELS}",
                input.display(),
                labels.len()
            )));
        }
        Ok(labels)
    }
}

/// Counts the values of the label map `input` read from `source` (as
/// [`scan_labels_on`]), first refusing a DICOM Segmentation whose segments
/// overlap: its label map gives a shared sample to one segment only, so
/// the meshes would not be the segments'. Errors name `input`. Also gives
/// the planes' runs, as many as [`MapRuns::cap`] allows and at most
/// `runs_room` bytes (what a budget leaves them:
/// [`crate::stream::label_runs_room`]), for the pass
/// ([`crate::stream::extract_labels_with_runs_to`]) to code its slabs
/// from.
pub fn scan_label_map(
    input: &Path,
    source: &dyn SampleSource,
    cancel: Option<&AtomicBool>,
    threads: usize,
    runs_room: Option<u64>,
) -> Result<(LabelCounts, MapRuns)> {
    let pairs = &source.notes().overlapping_segments;
    if !pairs.is_empty() {
        let pairs: Vec<String> = pairs.iter().map(|[a, b]| format!("{a} and {b}")).collect();
        return Err(Error::Invalid(format!(
            "{}: segments {} overlap, and a label map holds one segment per sample; extract each with --segment N --iso 0.5",
            input.display(),
            pairs.join(", ")
        )));
    }
    let [nx, ny, nz] = source.grid().dims;
    let samples = (nx as u64) * (ny as u64) * (nz as u64);
    let room = runs_room.map_or(usize::MAX, |room| {
        usize::try_from(room).unwrap_or(usize::MAX)
    });
    let cap = MapRuns::cap(samples, source.sample_bytes()).min(room);
    scan(source, cancel, threads, cap).map_err(|e| match e {
        Error::Invalid(m) => Error::Invalid(format!("{}: {m}", input.display())),
        other => other,
    })
}

/// Reads every plane of `source` once (in z order, one plane of `f64` in
/// memory) and counts the samples of each value. Label maps hold integers,
/// though many are stored as floats: a sample that is not a whole number
/// within ±2^53 (a fraction, NaN, an infinity) is an error naming its
/// position, the first in the file's order (x fastest, then y, then z);
/// so is a 64-bit integer sample read as ±2^53 (2^53 + 1 reads as 2^53).
/// Stops with [`Error::Interrupted`] once `cancel` is set (looked at every
/// plane).
pub fn scan_labels(source: &dyn SampleSource, cancel: Option<&AtomicBool>) -> Result<LabelCounts> {
    scan_labels_on(source, cancel, 1)
}

/// Runs of planes per thread in [`scan_labels_on`].
const JOBS_PER_THREAD: usize = 8;

/// [`scan_labels`] on `threads` threads (0: one per core), each reading
/// runs of planes in turn (one plane of `f64` each at most): the counts,
/// and the error, are those of one thread reading them all (the first
/// sample that is not a whole number in the file's order).
pub fn scan_labels_on(
    source: &dyn SampleSource,
    cancel: Option<&AtomicBool>,
    threads: usize,
) -> Result<LabelCounts> {
    Ok(scan(source, cancel, threads, 0)?.0)
}

/// [`scan_labels_on`], keeping the planes' runs while they take at most
/// `cap` bytes (each run of planes a thread reads its share of them).
pub(crate) fn scan(
    source: &dyn SampleSource,
    cancel: Option<&AtomicBool>,
    threads: usize,
    cap: usize,
) -> Result<(LabelCounts, MapRuns)> {
    let nz = source.grid().dims[2];
    let threads = match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
    .clamp(1, nz.max(1));
    // Several runs of planes per thread, taken from one queue: a thread
    // whose planes hold more runs (label maps are busier in some places)
    // does fewer of them, so the threads finish together.
    let jobs = (threads * JOBS_PER_THREAD).min(nz.max(1));
    let per = nz.div_ceil(jobs);
    let ranges: Vec<std::ops::Range<usize>> = (0..jobs)
        .map(|i| (i * per).min(nz)..((i + 1) * per).min(nz))
        .filter(|r| !r.is_empty())
        .collect();
    // A thread stops once a thread with earlier planes has failed (its
    // error comes first); the ranges' results are merged in z order.
    let failed_before = std::sync::atomic::AtomicUsize::new(usize::MAX);
    let share = cap / ranges.len().max(1);
    let scan = |k: usize, range: std::ops::Range<usize>| {
        let result = count_planes(source, cancel, range, share, || {
            failed_before.load(Ordering::Relaxed) < k
        });
        if result.is_err() {
            failed_before.fetch_min(k, Ordering::Relaxed);
        }
        result
    };
    let results = fan_out(ranges, threads, scan);
    // Ranges in z order: a later range's last plane of a value is later.
    let mut counts: BTreeMap<i64, (u64, usize)> = BTreeMap::new();
    let mut runs = Vec::with_capacity(nz);
    for result in results {
        let (tally, kept) = result?;
        for (value, (n, last)) in tally {
            let entry = counts.entry(value).or_default();
            *entry = (entry.0 + n, entry.1.max(last));
        }
        runs.extend(kept);
    }
    let counts = LabelCounts {
        counts: counts.iter().map(|(&v, &(n, _))| (v, n)).collect(),
        last_planes: counts.values().map(|&(_, last)| last).collect(),
    };
    Ok((counts, MapRuns::new(runs)))
}

/// The counts of planes `planes` (see [`scan_labels`]), each value's with
/// the last of these planes holding it, and the planes' runs (`None` for
/// each plane from the first that would take the runs past `cap` bytes);
/// gives up, with [`Error::Interrupted`], once `cancel` is set or
/// `give_up` says so (looked at every plane).
fn count_planes(
    source: &dyn SampleSource,
    cancel: Option<&AtomicBool>,
    planes: std::ops::Range<usize>,
    mut cap: usize,
    give_up: impl Fn() -> bool,
) -> Result<(Counts, Vec<Option<PlaneRuns>>)> {
    const LIMIT: f64 = (1u64 << 53) as f64;
    // A 64-bit integer is read rounded to an `f64`: 2^53 + 1 reads as
    // 2^53, so a sample that reads as ±2^53 may be another label than
    // it says; such maps hold labels below 2^53 in magnitude.
    let rounded = matches!(
        source.stored_type(),
        Some(ScalarType::I64 | ScalarType::U64)
    );
    let ny = source.grid().dims[1];
    let mut plane = Vec::new();
    let mut counts = Tally::default();
    let mut kept = Vec::with_capacity(planes.len());
    let mut expected = 0;
    for z in planes {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) || give_up() {
            return Err(Error::Interrupted);
        }
        let mut runs = (cap > 0).then(|| PlaneRunsBuilder::new(ny, expected + expected / 4));
        plane_runs(source, z, &mut plane, |y, x, end, v| {
            let whole = v.fract() == 0.0;
            if !(whole && v.abs() <= LIMIT) || (rounded && v.abs() == LIMIT) {
                return Err(Error::Invalid(if rounded && whole {
                    // Its value as read is not the one stored: not printed.
                    format!(
                        "sample (x {x}, y {y}, z {z}) is a 64-bit integer at or beyond ±2^53, which is not read exactly: a label map's 64-bit labels are within ±(2^53 - 1)"
                    )
                } else {
                    // Whole, but beyond the integers an `f64` holds exactly;
                    // or a fraction, NaN or an infinity.
                    let why = if whole {
                        "beyond ±2^53"
                    } else {
                        "not a whole number"
                    };
                    format!(
                        "sample (x {x}, y {y}, z {z}) is {v}, {why}: a label map holds integer labels (whole numbers within ±2^53)"
                    )
                }));
            }
            counts.add(v as i64, (end - x) as u64, z);
            if let Some(runs) = &mut runs {
                runs.push(y, end, v as i64);
            }
            Ok(())
        })?;
        let runs = runs.map(PlaneRunsBuilder::finish);
        expected = runs.as_ref().map_or(0, PlaneRuns::len);
        // Past the cap, this plane and every later one are read again.
        match runs {
            Some(runs) if runs.bytes() <= cap => {
                cap -= runs.bytes();
                kept.push(Some(runs));
            }
            _ => {
                cap = 0;
                kept.push(None);
            }
        }
    }
    Ok((counts.into_map(), kept))
}

/// Samples and last plane of each value of some planes.
type Counts = BTreeMap<i64, (u64, usize)>;

/// Samples counted per value, with the last plane holding each (planes
/// are counted in z order): values from 0 to 65535 (most label maps'
/// labels) in an array up to the largest seen, a run's count one
/// addition; others in a map.
#[derive(Default)]
struct Tally {
    /// `small[v]`: the samples of value `v` and its last plane (empty
    /// until the first).
    small: Vec<(u64, usize)>,
    other: BTreeMap<i64, (u64, usize)>,
}

impl Tally {
    fn add(&mut self, value: i64, samples: u64, z: usize) {
        let entry = match usize::try_from(value) {
            Ok(v) if v < 1 << 16 => {
                // As long as the largest value seen (a map of a few hundred
                // labels: a few KiB, not 1 MiB of pages to fault in).
                if v >= self.small.len() {
                    self.small.resize((v + 1).next_power_of_two(), (0, 0));
                }
                &mut self.small[v]
            }
            _ => self.other.entry(value).or_default(),
        };
        *entry = (entry.0 + samples, z);
    }

    fn into_map(self) -> BTreeMap<i64, (u64, usize)> {
        let mut map = self.other;
        let present = self.small.iter().enumerate().filter(|&(_, &(n, _))| n > 0);
        map.extend(present.map(|(v, &entry)| (v as i64, entry)));
        map
    }
}

/// Calls `f(y, x, end, value)` for every run of equal samples
/// `x..end` of each row `y` of plane `z`, in raster order (a NaN is a run
/// of its own). Reads the plane as the source lends it when it does (runs
/// compared in the stored type), else into `buffer` as `f64`; stops at
/// the first error of `f`.
pub fn plane_runs(
    source: &dyn SampleSource,
    z: usize,
    buffer: &mut Vec<f64>,
    mut f: impl FnMut(usize, usize, usize, f64) -> Result<()>,
) -> Result<()> {
    let [nx, ny, _] = source.grid().dims;
    let len = nx * ny;
    match source.lend_plane(z).filter(|p| p.len() == len) {
        Some(LentPlane::U8(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::I8(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::U16(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::I16(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::U32(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::I32(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::F32(s)) => runs(s, nx, Sample::to_f64, f),
        Some(LentPlane::F64(s)) => runs(s, nx, Sample::to_f64, f),
        // Integers at an odd offset (a header of odd length): compared as
        // bytes, which is comparing the values.
        Some(LentPlane::U16Bytes(s)) => runs(s, nx, |b| f64::from(u16::from_ne_bytes(b)), f),
        Some(LentPlane::I16Bytes(s)) => runs(s, nx, |b| f64::from(i16::from_ne_bytes(b)), f),
        Some(LentPlane::U32Bytes(s)) => runs(s, nx, |b| f64::from(u32::from_ne_bytes(b)), f),
        Some(LentPlane::I32Bytes(s)) => runs(s, nx, |b| f64::from(i32::from_ne_bytes(b)), f),
        _ => {
            // Every sample is written by `read_plane`: no need to zero the
            // buffer again for each plane.
            if buffer.len() != len {
                buffer.clear();
                make_room(buffer, len, "a plane of samples")?;
                buffer.resize(len, 0.0);
            }
            source.read_plane(z, buffer)?;
            runs(&buffer[..], nx, Sample::to_f64, &mut f)
        }
    }
}

/// [`plane_runs`] of samples of type `T` (`value` gives each as an
/// `f64`), rows of `nx`. Samples are compared in `T`: NaN is unequal to
/// everything, so a NaN float is a run of its own.
#[inline]
fn runs<T: Copy + PartialEq>(
    samples: &[T],
    nx: usize,
    value: impl Fn(T) -> f64,
    mut f: impl FnMut(usize, usize, usize, f64) -> Result<()>,
) -> Result<()> {
    for (y, row) in samples.chunks_exact(nx).enumerate() {
        let mut x = 0;
        while x < nx {
            let v = row[x];
            let mut end = x + 1;
            // Sixteen samples at a time while all equal `v` (compared
            // without an early exit, so in vector registers: label maps
            // are mostly long runs), then one at a time.
            while let Some(block) = row.get(end..end + 16) {
                if !block.iter().fold(true, |same, &s| same & (s == v)) {
                    break;
                }
                end += 16;
            }
            while end < nx && row[end] == v {
                end += 1;
            }
            f(y, x, end, value(v))?;
            x = end;
        }
    }
    Ok(())
}
