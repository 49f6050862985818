//! Which cells TMC triangulates differently from standard marching cubes,
//! by kind: a survey of every cell of the volume with the kernel itself.
//!
//! Both methods copy the same MC table triangles for every cell that is not
//! ambiguous (the paper's Definition 1), so only ambiguous cells can differ.
//! Standard MC triangulates one with the fixed face rule of its table
//! (inside corners of an ambiguous face separated, see
//! [`tables`](crate::kernel::tables)) and flat contours; TMC differs there
//! when
//! * the asymptotic decider **joins** the inside corners of an ambiguous
//!   face (`face_decisions`: the contours themselves change),
//! * the inside corners are joined through the cell's interior
//!   (`tunnels`),
//! * a contour has **12 vertices** (`contours_12`: triangulated through the
//!   inner hexagon), or
//! * a contour meets a face twice and is triangulated round an **interior
//!   vertex** (`interior_vertices`).
//!
//! A cell may be of several kinds; `cells` counts each differing cell once.
//! The kinds are read from the kernel's own counts for the cell (its
//! [`Stats`] before and after), on the values the slab loop gives it, so
//! the survey's Table 1 equals the TMC extraction's, which the tests
//! check.

use crate::error::{Error, Result};
use crate::kernel::cell::face_decisions;
use crate::kernel::tables::tables;
use crate::kernel::{triangulate_ambiguous, CellMesh};
use crate::params::ExtractParams;
use crate::slab::Level;
use crate::volume::{Padded, SampleSource};
use crate::Stats;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};

/// Cells that TMC triangulates differently from standard MC, by kind (a
/// cell may count in several). Only ambiguous cells can differ: both
/// methods copy the same MC table triangles for the others.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct DifferingCells {
    /// Cells that differ, of any kind (each counted once).
    pub cells: u64,
    /// Cells with an ambiguous face whose inside corners the asymptotic
    /// decider joins (MC separates them).
    pub face_decisions: u64,
    /// Cells with a tunnel.
    pub tunnels: u64,
    /// Cells with a contour of 12 vertices.
    pub contours_12: u64,
    /// Cells with a contour triangulated round an interior vertex.
    pub interior_vertices: u64,
}

impl DifferingCells {
    fn add(&mut self, other: &DifferingCells) {
        self.cells += other.cells;
        self.face_decisions += other.face_decisions;
        self.tunnels += other.tunnels;
        self.contours_12 += other.contours_12;
        self.interior_vertices += other.interior_vertices;
    }
}

/// Surveys every cell of `source` under `params` (its isovalue, `inside`
/// and `close`; the method is ignored) on up to `threads` threads (0: all
/// cores), each reading two planes at a time. Returns the differing cells
/// and the kernel's Table 1 counts over the volume (those of a TMC
/// extraction). Stops with [`Error::Interrupted`] once `cancel` is set.
pub fn survey(
    source: &dyn SampleSource,
    params: &ExtractParams,
    threads: usize,
    cancel: Option<&AtomicBool>,
) -> Result<(DifferingCells, Stats)> {
    survey_marking(source, params, threads, cancel, None)
}

/// A place for each cell that differs: called (from any of the survey's
/// threads, in no particular order) with the cell's centre in world
/// coordinates.
pub type OnDiffering<'a> = &'a (dyn Fn([f64; 3]) + Sync);

/// [`survey`], calling `on_differing` with the centre of every cell that
/// differs (`tmc compare --preview` marks them).
pub fn survey_marking(
    source: &dyn SampleSource,
    params: &ExtractParams,
    threads: usize,
    cancel: Option<&AtomicBool>,
    on_differing: Option<OnDiffering<'_>>,
) -> Result<(DifferingCells, Stats)> {
    let padded;
    let source: &dyn SampleSource = if params.close {
        padded = Padded::new(source);
        &padded
    } else {
        source
    };
    let layers = source.grid().dims[2].saturating_sub(1);
    let threads = match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
    .clamp(1, layers.max(1));
    let level = Level::new(params);
    let per = layers.div_ceil(threads);
    let results: Vec<Result<(DifferingCells, Stats)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let range = (t * per).min(layers)..((t + 1) * per).min(layers);
                scope.spawn(move || survey_layers(source, level, range, cancel, on_differing))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    let mut total = (DifferingCells::default(), Stats::default());
    for result in results {
        let (cells, stats) = result?;
        total.0.add(&cells);
        total.1.add_counts(&stats);
    }
    Ok(total)
}

/// [`survey`] of the cell layers `range` on this thread.
fn survey_layers(
    source: &dyn SampleSource,
    level: Level,
    range: std::ops::Range<usize>,
    cancel: Option<&AtomicBool>,
    on_differing: Option<OnDiffering<'_>>,
) -> Result<(DifferingCells, Stats)> {
    let grid = *source.grid();
    let [nx, ny, _] = grid.dims;
    let plane = nx * ny;
    let mut differing = DifferingCells::default();
    let mut stats = Stats::default();
    if range.is_empty() {
        return Ok((differing, stats));
    }
    let buffer = |what| crate::error::try_filled(what, plane, 0.0);
    let (mut bottom, mut top) = (buffer("a plane of samples")?, buffer("a plane of samples")?);
    source.read_plane(range.start, &mut bottom)?;
    let t = tables();
    let mut cell = CellMesh::new();
    for z in range {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) || source.interrupted() {
            return Err(Error::Interrupted);
        }
        source.read_plane(z + 1, &mut top)?;
        for y in 0..ny.saturating_sub(1) {
            for x in 0..nx - 1 {
                let i = y * nx + x;
                let at = [i, i + 1, i + nx, i + nx + 1];
                let values: [f64; 8] =
                    std::array::from_fn(|c| if c < 4 { bottom[at[c]] } else { top[at[c - 4]] });
                let g = level.rel_all(values);
                let config = g
                    .iter()
                    .enumerate()
                    .fold(0u8, |m, (c, &v)| m | u8::from(v > 0.0) << c);
                if !t.is_ambiguous[config as usize] {
                    continue;
                }
                stats.ambiguous_cells += 1;
                let rest = level.residuals(values);
                let residual = (rest != [0.0; 8]).then_some(&rest);
                let before = stats.clone();
                let joined = face_decisions(&g, residual, config);
                cell.clear();
                triangulate_ambiguous(&g, residual, config, &mut stats, &mut cell);
                let kinds = [
                    joined != 0,
                    stats.tunnels > before.tunnels,
                    stats.contours_12 > before.contours_12,
                    stats.ambiguous_contours != before.ambiguous_contours,
                ];
                differing.face_decisions += u64::from(kinds[0]);
                differing.tunnels += u64::from(kinds[1]);
                differing.contours_12 += u64::from(kinds[2]);
                differing.interior_vertices += u64::from(kinds[3]);
                let differs = kinds.iter().any(|&k| k);
                differing.cells += u64::from(differs);
                if let (true, Some(on)) = (differs, on_differing) {
                    on(grid.world([x, y, z].map(|i| i as f64 + 0.5)));
                }
            }
        }
        std::mem::swap(&mut bottom, &mut top);
    }
    Ok((differing, stats))
}
