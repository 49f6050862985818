//! Label maps in one pass: the boundary surface of every label of a
//! segmentation, each exactly what an extraction of that label's 0/1
//! indicator volume at 0.5 writes.
//!
//! The pass is the ordinary one ([`super::pass`]): one seam and one sink per
//! label, slabs scheduled, triangulated and stitched as for isovalues. Only
//! what a worker does with a slab differs (`label_slab`):
//! 1. **code** the slab's planes once (`label_codes.rs`): each label
//!    gets the bounding rectangle of its samples in these planes and its
//!    runs along x; only where runs are many, or normals need the whole
//!    planes, each sample's label number (its code) is kept as well;
//! 2. for each label present, write its indicator (1 on the label, else 0;
//!    `--close`'s NaN border a tie; from its runs, or from the codes)
//!    over that rectangle grown by one
//!    sample on each side, and triangulate it with the ordinary slab loop
//!    as a [`Window`] of the grid: every crossed edge and every cell with a
//!    label corner lies in it, so the chunks are those of the whole
//!    indicator grid, placed from the whole grid's indices;
//! 3. a label absent from the slab's planes gets the slab's empty chunks.
//!
//! The work per slab is one reading of its planes plus, per label present,
//! the slab loop over that label's rectangle: labels that keep to their
//! own region of the volume cost about their region, not the volume.
//! Memory per worker: the runs (at most a byte per sample of the slab's
//! planes) or the codes (2 bytes a sample) and one label's indicator (1
//! byte per sample of its rectangle), whatever the number of labels; all
//! are kept for the worker's next slab.

use super::label_codes::{
    code_planes, group_by_label, window_ties, LabelRun, Lookup, Rect, RUNS_PER_SAMPLE, TIE,
};
use super::pass::{run_pass, SlabWork};
use crate::error::make_room;
use crate::grid::Grid;
use crate::mesh::{Chunk, MeshSink};
use crate::params::{ExtractParams, Inside, PipelineOptions};
use crate::slab::{process_window, PerVertex, Spares, Window};
use crate::volume::{Access, LentPlane, MapRuns, SampleSource};
use crate::{Error, Result, Stats};
use std::ops::Range;
use std::sync::{Mutex, PoisonError};

pub use crate::volume::MOST_LABELS;

/// Extracts the boundary surface of each of `labels` in one pass over
/// `source`, streaming label `labels[i]`'s mesh to `sinks[i]`; returns the
/// statistics of each.
///
/// Label `L`'s mesh is byte for byte what [`extract_to`](super::extract_to)
/// writes for the volume that is 1 where `source` is `L` and 0 elsewhere, at
/// isovalue 0.5 with `params`' method, `close` and threads (the sink is
/// told that isovalue): the surface of the trilinear interpolant of the
/// indicator, with the sign convention's ties. Samples that are not whole
/// numbers belong to no label; check the map with
/// [`scan_labels`](crate::volume::scan_labels) first to refuse them.
/// `params.iso` and `inside` are not used; with `params.normals` each
/// label's vertices get the normals of its indicator's gradient, as that
/// extraction with normals gives them.
/// The output does not depend on the threads, the slab depth or the part
/// (`part` as in [`extract_part_to`](super::extract_part_to)).
pub fn extract_labels_to(
    source: &dyn SampleSource,
    labels: &[i64],
    params: &ExtractParams,
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sinks: &mut [&mut dyn MeshSink],
) -> Result<Vec<Stats>> {
    let none = MapRuns::default();
    extract_labels_with_runs_to(source, &none, labels, params, options, part, sinks)
}

/// [`extract_labels_to`], with the runs of `source`'s planes that
/// [`scan_label_map`](crate::volume::scan_label_map) kept: the slabs are
/// coded from them rather than from the source's planes, which are read
/// only where no runs were kept. `runs` must be those of `source` (as the
/// map was when scanned): the meshes are those of the map the runs
/// describe. The runs are held through the pass, so they count against
/// `options.max_memory`: the slabs get what they leave.
pub fn extract_labels_with_runs_to(
    source: &dyn SampleSource,
    runs: &MapRuns,
    labels: &[i64],
    params: &ExtractParams,
    options: &PipelineOptions,
    part: Option<(usize, usize)>,
    sinks: &mut [&mut dyn MeshSink],
) -> Result<Vec<Stats>> {
    if labels.is_empty() {
        return Err(Error::Invalid("no label to extract".into()));
    }
    if labels.len() > MOST_LABELS {
        return Err(Error::Invalid(format!(
            "{} labels; one pass takes at most {MOST_LABELS}",
            labels.len()
        )));
    }
    let mut lookup: Vec<(i64, u16)> = labels
        .iter()
        .enumerate()
        .map(|(i, &l)| (l, i as u16 + 1))
        .collect();
    lookup.sort_unstable();
    if let Some(pair) = lookup.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(Error::Invalid(format!(
            "label {} is asked for twice",
            pair[0].0
        )));
    }
    let lookup = Lookup::new(lookup);
    let each = ExtractParams {
        iso: 0.5,
        inside: Inside::High,
        ..params.clone()
    };
    let all = vec![each; labels.len()];
    // The codes and indicator buffers of finished slabs, for the next
    // (as many as slabs run at once): a slab's codes are written afresh
    // over the last one's, not zeroed nor faulted in again.
    let scratch: Mutex<Vec<Scratch>> = Mutex::new(Vec::new());
    let run = |source: &dyn SampleSource, layers: Range<usize>, spares: &Spares| {
        let take = || scratch.lock().unwrap_or_else(PoisonError::into_inner).pop();
        let mut buffers = take().unwrap_or_default();
        let result = label_slab(
            (source, runs),
            &lookup,
            &all,
            layers,
            (spares, RUNS_PER_SAMPLE),
            &mut buffers,
        );
        scratch
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(buffers);
        result
    };
    let work = SlabWork {
        run: &run,
        budget_planes: work_planes(params.normals),
        held_bytes: runs.bytes() as u64,
    };
    run_pass(source, &all, options, part, sinks, Some(work))
}

/// The slab loop's planes a label pass's worker holds, for the budget:
/// the codes of the slab's planes (2 bytes a sample, a slab of up to 64
/// layers) and one indicator (1 byte), counted as 4 of the slab loop's
/// planes of 17 bytes; normals add the whole planes' indicator (1 byte)
/// and the gradients' window (up to four planes of 8 bytes).
fn work_planes(normals: bool) -> usize {
    if normals {
        8
    } else {
        4
    }
}

/// The bytes a label map's runs may take beside a label pass over `source`
/// within `options.max_memory`, for
/// [`scan_label_map`](crate::volume::scan_label_map): half of what the
/// workers' buffers leave (the other half is the mesh's in flight), and
/// at most a quarter of the budget; `None` without a budget. Fails, before
/// anything is read, as the pass would when the budget does not hold even
/// the workers' buffers. The runs only spare the pass a second reading of
/// the map: kept within this room, the size a refusal names is enough.
pub fn label_runs_room(
    source: &dyn SampleSource,
    params: &ExtractParams,
    options: &PipelineOptions,
) -> Result<Option<u64>> {
    let work = Some((work_planes(params.normals), 0));
    let (workers, plan) = super::pass::plan_source(source, params, work, options)?;
    Ok(options.max_memory.map(|max| {
        let buffers = u64::try_from(workers.buffers(plan.depth)).unwrap_or(u64::MAX);
        (max.saturating_sub(buffers) / 2).min(max / 4)
    }))
}

/// The last plane whose chunk may hold part of each of `labels`' meshes,
/// from the last plane holding each label (`counts`, the scan's); `None`
/// for a label the map does not hold. A chunk of plane `z` holds the
/// vertices on the edges of plane `z` and on the edges from `z` to `z + 1`,
/// and the triangles of the cells between the two planes: past the label's
/// last plane its indicator is 0 on both, so those chunks are empty. With
/// `close` the pass's grid has one plane more below the volume, so the
/// chunks' planes are one more. A label's file may therefore be finished
/// once the pass has handed it that plane's chunk
/// ([`crate::export::LabelFiles::finish_early`]).
pub fn last_label_chunks(
    counts: &crate::volume::LabelCounts,
    labels: &[i64],
    close: bool,
) -> Vec<Option<u64>> {
    labels
        .iter()
        .map(|&l| {
            let last = counts.last_plane(l)?;
            Some((last + usize::from(close)) as u64)
        })
        .collect()
}

/// A worker's buffers for a slab's codes and a label's indicator, kept
/// from one slab to the next.
#[derive(Default)]
struct Scratch {
    codes: Vec<u16>,
    indicator: Vec<u8>,
    /// The labels' runs in the slab's own planes, in the order coded.
    runs: Vec<LabelRun>,
    /// The same, ordered by label (stable: in coded order within one).
    by_label: Vec<LabelRun>,
}

/// The chunks and counts of every label for cell layers `layers` (see the
/// module documentation), the indicators written from the labels' runs
/// where there is at most one per `run_samples` samples (0: never; the
/// bytes are the same either way).
fn label_slab(
    (source, map_runs): (&dyn SampleSource, &MapRuns),
    lookup: &Lookup,
    params: &[ExtractParams],
    layers: Range<usize>,
    (spares, run_samples): (&Spares, usize),
    scratch: &mut Scratch,
) -> Result<Vec<(Vec<Chunk>, Stats)>> {
    // The source is padded with NaN for `--close` (see `run_pass`).
    let close = params.first().is_some_and(|p| p.close);
    let normals = params.first().is_some_and(|p| p.normals);
    let grid = *source.grid();
    let [nx, ny, nz] = grid.dims;
    let area = nx * ny;
    // The slab's planes, and with normals one more on each side (their
    // gradients need them).
    let codes_from = match normals {
        true => layers.start.saturating_sub(1),
        false => layers.start,
    };
    let codes_to = match normals {
        true => (layers.end + 1).min(nz - 1),
        false => layers.end,
    };
    let planes = codes_to + 1 - codes_from;
    let slab_planes = layers.len() + 1;
    let most_runs = match run_samples {
        0 => 0,
        n => (slab_planes * area / n).max(1024),
    };
    let mut rects: Vec<Option<Rect>> = vec![None; params.len()];
    scratch.runs.clear();
    // The runs alone where they are few (and no normals need the codes).
    let by_runs = !normals
        && code_planes(
            (source, map_runs),
            lookup,
            layers.start..=layers.end,
            &layers,
            close,
            &mut rects,
            (&mut scratch.runs, most_runs),
            None,
        )?;
    let (codes, from_runs): (&[u16], bool) = match by_runs {
        true => (&[], true),
        false => {
            rects.fill(None);
            scratch.runs.clear();
            // Every sample's code is written (the runs cover each row).
            if scratch.codes.len() < planes * area {
                let missing = planes * area - scratch.codes.len();
                make_room(&mut scratch.codes, missing, "the label codes of a slab")?;
                scratch.codes.resize(planes * area, 0);
            }
            let codes = &mut scratch.codes[..planes * area];
            let few = code_planes(
                (source, map_runs),
                lookup,
                codes_from..=codes_to,
                &layers,
                close,
                &mut rects,
                (&mut scratch.runs, most_runs),
                Some(codes),
            )?;
            (&scratch.codes[..planes * area], few)
        }
    };
    // The planes are coded: the source's pages may go (the slab above
    // releases the last plane, as in the slab loop).
    source.advise(layers.start..layers.end, Access::Done);
    let skip = (layers.start - codes_from) * area;
    // Each label's runs together, from `starts[code - 1]` on.
    let starts = match from_runs {
        true => Some(group_by_label(
            &scratch.runs,
            &mut scratch.by_label,
            params.len(),
        )),
        false => None,
    };
    let by_label = &scratch.by_label;
    let indicator = &mut scratch.indicator;
    // With normals, every label's indicator over the whole planes: ties
    // where the codes say so, each label's 1s written over its window and
    // taken out again after its normals.
    let mut whole = match normals {
        true => {
            let mut whole = crate::error::try_vec("the indicator of a slab's planes", codes.len())?;
            whole.extend(codes.iter().map(|&c| indicator_of(c, 0)));
            Some(whole)
        }
        false => None,
    };
    let mut results = Vec::with_capacity(params.len());
    for (i, (rect, p)) in rects.iter().zip(params).enumerate() {
        let Some(rect) = rect else {
            results.push((empty_chunks(&layers, nz), Stats::default()));
            continue;
        };
        let code = i as u16 + 1;
        let xs = rect.x[0].saturating_sub(1)..(rect.x[1] + 2).min(nx);
        let ys = rect.y[0].saturating_sub(1)..(rect.y[1] + 2).min(ny);
        let (wx, wy) = (xs.len(), ys.len());
        // Ties are the border's, where the window reaches it.
        let ties = close
            && (xs.start == 0
                || xs.end == nx
                || ys.start == 0
                || ys.end == ny
                || layers.start == 0
                || layers.end == nz - 1);
        indicator.clear();
        make_room(indicator, slab_planes * wx * wy, "a label's indicator")?;
        match &starts {
            // Zeros, the ties, then the label's runs: the codes are not
            // read (runs never cover a tie: the border is NaN, no label).
            Some(starts) => {
                indicator.resize(slab_planes * wx * wy, 0);
                if ties {
                    let caps = [layers.start == 0, layers.end == nz - 1];
                    window_ties(indicator, [&xs, &ys], [nx, ny], caps);
                }
                for run in &by_label[starts[i]..starts[i + 1]] {
                    let row = (run.k * wy + run.y - ys.start) * wx;
                    indicator[row + run.x[0] - xs.start..row + run.x[1] - xs.start].fill(1);
                }
            }
            _ => {
                for k in 0..slab_planes {
                    for y in ys.clone() {
                        let row = &codes[skip + k * area + y * nx..][xs.clone()];
                        // Without a branch, so that it runs in vector registers.
                        indicator.extend(row.iter().map(|&c| indicator_of(c, code)));
                    }
                }
            }
        }
        let window = Window {
            full: grid,
            offset: [xs.start, ys.start],
        };
        let view = Indicator {
            grid: Grid {
                dims: [wx, wy, nz],
                ..grid
            },
            planes: indicator,
            first: layers.start,
            ties,
            outer: source,
        };
        let result = match &mut whole {
            Some(whole) => {
                mark(whole, codes, code, [nx, area], [&xs, &ys]);
                let field = Indicator {
                    grid,
                    planes: whole,
                    first: codes_from,
                    ties: close,
                    outer: source,
                };
                let result = process_window(
                    &view,
                    p,
                    layers.clone(),
                    spares,
                    Some(&window),
                    PerVertex {
                        gradients: Some(&field),
                        values: None,
                    },
                );
                mark(whole, codes, 0, [nx, area], [&xs, &ys]);
                result?
            }
            None => process_window(
                &view,
                p,
                layers.clone(),
                spares,
                Some(&window),
                PerVertex::default(),
            )?,
        };
        results.push(result);
    }
    Ok(results)
}

/// A sample's byte in a label's indicator: 1 on label `code`, 2 on a tie
/// ([`TIE`]), 0 elsewhere (`code` 0: only the ties).
fn indicator_of(c: u16, code: u16) -> u8 {
    u8::from(c == code && code != 0) | (u8::from(c == TIE) << 1)
}

/// The chunks of cell layers `layers` of a grid of `nz` planes without a
/// surface: one per layer, and the top plane's when the layers end there
/// (what the slab loop hands back for them).
fn empty_chunks(layers: &Range<usize>, nz: usize) -> Vec<Chunk> {
    let top = (layers.end == nz - 1).then_some(nz - 1);
    layers
        .clone()
        .chain(top)
        .map(|z| Chunk {
            plane: z as u64,
            ..Chunk::default()
        })
        .collect()
}

/// One label's indicator over a window of a slab's planes, as a source
/// for the slab loop: 1 on the label, 0 elsewhere, NaN (a tie) where the
/// codes say [`TIE`]. Lends its planes as `u8` when there is no tie, as
/// an indicator volume stored as bytes is read.
struct Indicator<'a> {
    grid: Grid,
    /// Byte 0, 1 or 2 (a tie) per sample, planes from `first` on.
    planes: &'a [u8],
    first: usize,
    ties: bool,
    outer: &'a dyn SampleSource,
}

impl Indicator<'_> {
    fn plane(&self, z: usize) -> &[u8] {
        let len = self.grid.plane_len();
        let k = z - self.first;
        &self.planes[k * len..(k + 1) * len]
    }
}

impl SampleSource for Indicator<'_> {
    fn grid(&self) -> &Grid {
        &self.grid
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        read_indicator(self.plane(z), out);
        Ok(())
    }

    fn lend_plane(&self, z: usize) -> Option<LentPlane<'_>> {
        (!self.ties).then(|| LentPlane::U8(self.plane(z)))
    }

    fn interrupted(&self) -> bool {
        self.outer.interrupted()
    }

    fn sample_bytes(&self) -> usize {
        1
    }
}

/// Writes label `code`'s indicator (0: none, only the ties) into `whole`,
/// the indicator bytes of `codes` (planes of `area` samples, rows of
/// `nx`), over rows `ys`, columns `xs` of every plane: outside its window
/// a label has no sample, so this makes `whole` that label's indicator.
fn mark(
    whole: &mut [u8],
    codes: &[u16],
    code: u16,
    [nx, area]: [usize; 2],
    [xs, ys]: [&Range<usize>; 2],
) {
    for k in 0..whole.len() / area {
        for y in ys.clone() {
            let at = k * area + y * nx;
            let row = &codes[at..][xs.clone()];
            for (o, &c) in whole[at..][xs.clone()].iter_mut().zip(row) {
                *o = indicator_of(c, code);
            }
        }
    }
}

/// The samples of indicator bytes: 0, 1, and NaN for a tie (2).
fn read_indicator(bytes: &[u8], out: &mut [f64]) {
    for (o, &b) in out.iter_mut().zip(bytes) {
        *o = match b {
            0 => 0.0,
            1 => 1.0,
            _ => f64::NAN,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::ArrayVolume;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    /// A map of runs along x (labels 0 to 5), long or short.
    fn map(dims: [usize; 3], run: usize, seed: u64) -> Vec<i16> {
        let mut rng = Pcg64::seed_from_u64(seed);
        let mut out = Vec::new();
        while out.len() < dims.iter().product() {
            let label = rng.gen_range(0..=5);
            out.extend(std::iter::repeat_n(label, rng.gen_range(1..=run)));
        }
        out.truncate(dims.iter().product());
        out
    }

    /// Every slab's chunks and counts: indicators from the runs alone,
    /// from the codes, and from the runs beside the codes (normals) are
    /// the same, with and without `--close` (the padded volume's NaN
    /// border: ties, which the runs path writes itself); so are those of
    /// slabs coded from the scan's runs (all planes kept, some, none).
    #[test]
    fn runs_codes_and_the_scans_runs_give_the_same_chunks() {
        for (seed, run) in [(1, 1), (2, 4), (3, 40)] {
            let dims = [19, 13, 9];
            let volume = ArrayVolume::new(Grid::unit(dims), map(dims, run, seed)).unwrap();
            let lookup = Lookup::new((1..=5).map(|l| (l, l as u16)).collect());
            let scan = |cap| {
                crate::volume::scan_keeping_runs(&volume, None, 1, cap)
                    .unwrap()
                    .1
            };
            let all = scan(usize::MAX);
            assert_eq!(all.kept_planes(), dims[2]);
            // A cap that keeps some planes (each run of planes gets its share).
            let some = (1..10)
                .map(|tenths| scan(all.bytes() * tenths / 10))
                .find(|runs| (1..dims[2]).contains(&runs.kept_planes()))
                .unwrap();
            for (close, normals) in [(false, false), (true, false), (false, true), (true, true)] {
                let padded;
                let source: &dyn SampleSource = match close {
                    true => {
                        padded = crate::volume::Padded::new(&volume);
                        &padded
                    }
                    false => &volume,
                };
                let nz = source.grid().dims[2];
                let each = ExtractParams {
                    iso: 0.5,
                    close,
                    normals,
                    threads: 1,
                    ..Default::default()
                };
                let params = vec![each; 5];
                let spares = Spares::new(2, 8);
                let slab = |runs: &MapRuns, layers: Range<usize>, run_samples: usize| {
                    let mut scratch = Scratch::default();
                    let chunks = label_slab(
                        (source, runs),
                        &lookup,
                        &params,
                        layers,
                        (&spares, run_samples),
                        &mut scratch,
                    )
                    .unwrap();
                    // Bit for bit: a vertex without a gradient has a NaN
                    // normal until the stream fills it.
                    let bits = |c: &Chunk| {
                        let normals: Vec<[u32; 3]> =
                            c.normals.iter().map(|n| n.map(f32::to_bits)).collect();
                        let c = Chunk {
                            normals: Vec::new(),
                            ..c.clone()
                        };
                        (c, normals)
                    };
                    let bits: Vec<(Vec<_>, u64)> = chunks
                        .iter()
                        .map(|(c, stats)| (c.iter().map(bits).collect(), stats.triangles))
                        .collect();
                    bits
                };
                for layers in [0..nz - 1, 0..3, 3..4, 4..nz - 1] {
                    let read = slab(&MapRuns::default(), layers.clone(), 1);
                    assert!(read
                        .iter()
                        .any(|(c, _)| c.iter().any(|(c, _)| !c.triangles.is_empty())));
                    let codes = slab(&MapRuns::default(), layers.clone(), 0);
                    assert!(read == codes, "seed {seed} close {close} layers {layers:?}");
                    for runs in [&all, &some] {
                        for run_samples in [0, 1] {
                            let kept = slab(runs, layers.clone(), run_samples);
                            assert!(
                                read == kept,
                                "seed {seed} close {close} normals {normals} {layers:?}"
                            );
                        }
                    }
                }
            }
        }
    }
}
