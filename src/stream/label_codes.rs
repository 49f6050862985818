//! How a worker reads a slab of a label map: each sample's value turned
//! into its label's number (its *code*, 1 for the first wanted label, 0
//! for any other value), each label's rectangle in the slab, and each
//! label's runs along x, from which its 0/1 indicator is written without
//! reading the slab again (`super::labels`).
//!
//! Two ways, chosen per slab: the **runs** alone (no normals, and at most
//! one run per [`RUNS_PER_SAMPLE`] samples: a segmentation's labels are
//! long runs), or, where they are too many or normals need the whole
//! planes' indicators, the **codes** of every sample (2 bytes each) as
//! well. Either way a label's indicator holds the same bytes.

use crate::volume::{plane_runs, MapRuns, SampleSource};
use crate::{Error, Result};
use std::ops::{Range, RangeInclusive};

/// The code of `--close`'s border of NaN samples (a tie: outside every
/// label, as in each label's padded indicator).
pub(super) const TIE: u16 = u16::MAX;

/// The wanted labels and their numbers (from 1): `(label, number)`
/// sorted by label, and for labels from 0 to 65535 the number by value.
pub(super) struct Lookup {
    sorted: Vec<(i64, u16)>,
    /// `direct[l]`: the number of label `l`, 0 for none (up to the
    /// largest wanted label below 65536).
    direct: Vec<u16>,
}

impl Lookup {
    pub(super) fn new(sorted: Vec<(i64, u16)>) -> Self {
        let small = |&&(l, _): &&(i64, u16)| (0..1 << 16).contains(&l);
        let len = sorted
            .iter()
            .filter(small)
            .map(|&(l, _)| l as usize + 1)
            .max()
            .unwrap_or(0);
        let mut direct = vec![0; len];
        for &(l, code) in sorted.iter().filter(small) {
            direct[l as usize] = code;
        }
        Lookup { sorted, direct }
    }

    /// The code of value `v`: its label's number (from 1), 0 for any
    /// other value (NaN too: no label).
    fn code_of(&self, v: f64) -> u16 {
        // Whole numbers in i64's range convert exactly; anything else is
        // no label (`as` saturates, and the comparison catches it).
        let l = v as i64;
        if l as f64 != v {
            return 0;
        }
        if let Some(&code) = usize::try_from(l).ok().and_then(|i| self.direct.get(i)) {
            return code;
        }
        match self.sorted.binary_search_by_key(&l, |&(label, _)| label) {
            Ok(k) => self.sorted[k].1,
            Err(_) => 0,
        }
    }
}

/// A label's rectangle in a slab's planes: inclusive x and y bounds.
#[derive(Clone, Copy)]
pub(super) struct Rect {
    pub(super) x: [usize; 2],
    pub(super) y: [usize; 2],
}

impl Rect {
    fn grow(&mut self, x: [usize; 2], y: usize) {
        self.x = [self.x[0].min(x[0]), self.x[1].max(x[1])];
        self.y = [self.y[0].min(y), self.y[1].max(y)];
    }
}

/// A run of one label's samples along x in one of a slab's own planes:
/// label number `code`, plane `k` of the slab (from `layers.start`), row
/// `y`, columns `x[0]..x[1]`.
#[derive(Clone, Copy, Default)]
pub(super) struct LabelRun {
    code: u16,
    pub(super) k: usize,
    pub(super) y: usize,
    pub(super) x: [usize; 2],
}

/// Samples of a slab's own planes per run kept (a run takes 32 bytes, so
/// at most a byte a sample, and at least 1,024 runs): a slab with more
/// runs, a map of short runs, builds its indicators from the codes.
pub(super) const RUNS_PER_SAMPLE: usize = 32;

/// Orders `runs` by label number into `out` (a counting sort, stable) and
/// returns where each label's begin: label number `c`'s runs are
/// `out[starts[c - 1]..starts[c]]`.
pub(super) fn group_by_label(
    runs: &[LabelRun],
    out: &mut Vec<LabelRun>,
    labels: usize,
) -> Vec<usize> {
    let mut starts = vec![0; labels + 1];
    for run in runs {
        starts[usize::from(run.code)] += 1;
    }
    for c in 1..=labels {
        starts[c] += starts[c - 1];
    }
    let mut next = starts.clone();
    out.clear();
    out.resize(runs.len(), LabelRun::default());
    for &run in runs {
        let at = &mut next[usize::from(run.code) - 1];
        out[*at] = run;
        *at += 1;
    }
    starts
}

/// Codes `--close`'s border of NaN in `plane` (rows of `nx`): a tie for
/// every label; the whole plane when it is the first or last.
pub(super) fn tie_border(plane: &mut [u16], nx: usize, cap: bool) {
    if cap {
        plane.fill(TIE);
        return;
    }
    for row in plane.chunks_exact_mut(nx) {
        row[0] = TIE;
        row[nx - 1] = TIE;
    }
    plane[..nx].fill(TIE);
    let area = plane.len();
    plane[area - nx..].fill(TIE);
}

/// Codes planes `planes` of the slab of cell layers `layers`: each wanted
/// label's rectangle in the slab's own planes into `rects` (by number, 1
/// first), its runs there into `runs` while they are at most `most_runs`,
/// and, given `codes`, each sample's code into it (plane after plane from
/// `planes.start()`, `--close`'s border [`TIE`] when `close`). Returns
/// whether `runs` holds every run; without `codes` it stops at the end of
/// the plane where they became too many.
#[allow(clippy::too_many_arguments)]
pub(super) fn code_planes(
    (source, map_runs): (&dyn SampleSource, &MapRuns),
    lookup: &Lookup,
    planes: RangeInclusive<usize>,
    layers: &Range<usize>,
    close: bool,
    rects: &mut [Option<Rect>],
    (runs, most_runs): (&mut Vec<LabelRun>, usize),
    mut codes: Option<&mut [u16]>,
) -> Result<bool> {
    let [nx, ny, nz] = source.grid().dims;
    let area = nx * ny;
    let mut values = Vec::new();
    let mut few = true;
    for (k, z) in planes.enumerate() {
        let mut plane = codes
            .as_deref_mut()
            .map(|c| &mut c[k * area..(k + 1) * area]);
        // Only the slab's own planes bound a label's cells.
        let own = layers.start <= z && z <= layers.end;
        // The scan's runs of the map's plane (with `--close` the source is
        // the padded map, a plane further on).
        let kept = match close {
            true => z.checked_sub(1).filter(|&z| z + 2 < nz),
            false => Some(z),
        }
        .and_then(|z| map_runs.plane(z));
        let each_run = |y, x, end, v| {
            let code = lookup.code_of(v);
            if let Some(plane) = plane.as_deref_mut() {
                let run = &mut plane[y * nx + x..y * nx + end];
                // Short runs (most of them) without a call to `memset`.
                if run.len() < 32 {
                    run.iter_mut().for_each(|c| *c = code);
                } else {
                    run.fill(code);
                }
            }
            if code != 0 && own {
                let run = [x, end - 1];
                match &mut rects[usize::from(code) - 1] {
                    Some(rect) => rect.grow(run, y),
                    slot => *slot = Some(Rect { x: run, y: [y, y] }),
                }
                if few {
                    few = runs.len() < most_runs;
                    runs.push(LabelRun {
                        code,
                        k: z - layers.start,
                        y,
                        x: [x, end],
                    });
                }
            }
            Ok(())
        };
        match kept {
            Some(kept) => kept.each(close, each_run)?,
            None => plane_runs(source, z, &mut values, each_run)?,
        }
        if let (Some(plane), true) = (plane, close) {
            tie_border(plane, nx, z == 0 || z == nz - 1);
        }
        if source.interrupted() {
            return Err(Error::Interrupted);
        }
        if !few && codes.is_none() {
            return Ok(false);
        }
    }
    Ok(few)
}

/// Writes `--close`'s ties (2) into a label's indicator over columns
/// `xs`, rows `ys` of a slab's own planes (`[wx, wy]` their lengths) in a
/// grid of `[nx, ny]` samples a plane: the samples [`tie_border`] codes
/// [`TIE`], all of the slab's first plane if `caps[0]` (it is the grid's
/// first) and of its last if `caps[1]`.
pub(super) fn window_ties(
    indicator: &mut [u8],
    [xs, ys]: [&Range<usize>; 2],
    [nx, ny]: [usize; 2],
    caps: [bool; 2],
) {
    let (wx, wy) = (xs.len(), ys.len());
    let planes = indicator.len() / (wx * wy);
    for (k, plane) in indicator.chunks_exact_mut(wx * wy).enumerate() {
        if (k == 0 && caps[0]) || (k + 1 == planes && caps[1]) {
            plane.fill(2);
            continue;
        }
        if ys.start == 0 {
            plane[..wx].fill(2);
        }
        if ys.end == ny {
            plane[(wy - 1) * wx..].fill(2);
        }
        for row in plane.chunks_exact_mut(wx) {
            if xs.start == 0 {
                row[0] = 2;
            }
            if xs.end == nx {
                row[wx - 1] = 2;
            }
        }
    }
}
