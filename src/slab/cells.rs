//! The cells of one layer (pass 3 of the slab loop): standard MC's table
//! for every cell whose corners are not all on one side, the kernel for the
//! ambiguous ones, triangle corners from the edge numbers of [`super::edges`].

use super::bits::{below, each_bit, next, uniform_alike};
use super::block::{local_index, Block, TRIANGLES, VERTICES};
use super::edges::{CellEdges, EdgeRows, LayerNumbers};
use super::placement::Placement;
use super::plane::Plane;
use super::samples::cell_samples;
use crate::error::make_room;
use crate::kernel::tables::Tables;
use crate::kernel::{triangulate_ambiguous_deferred, CellMesh, Known, Triangles, INTERIOR};
use crate::params::{ExtractParams, Method};
use crate::{Error, Result, Stats};
use glam::DVec3;

/// What the cells of one layer are triangulated from.
pub(super) struct Layer<'a> {
    pub(super) place: &'a Placement,
    pub(super) params: &'a ExtractParams,
    pub(super) tables: &'a Tables,
    pub(super) bottom: &'a Plane<'a>,
    pub(super) top: &'a Plane<'a>,
    /// Where the numbers of the layer's edge vertices come from.
    pub(super) numbers: LayerNumbers<'a>,
    /// Whether the run was cancelled ([`crate::volume::SampleSource::interrupted`]),
    /// asked every [`ROWS_PER_CHECK`] rows.
    pub(super) interrupted: &'a dyn Fn() -> bool,
}

/// Rows of cells between two looks at [`Layer::interrupted`]: a layer of a
/// dense 8192 x 8192 plane takes seconds, 16 of its rows a few
/// milliseconds, and one look per 16 rows costs nothing measurable.
const ROWS_PER_CHECK: usize = 16;

/// The ambiguous cells of a row that wait for the kernel, and its scratch.
pub(super) struct Ambiguous<'a> {
    /// `(x, config)` of each, in row order (room for a row).
    pub(super) waiting: &'a mut Vec<(usize, u8)>,
    pub(super) cell: &'a mut CellMesh,
}

/// Triangulates the cells between planes `bottom` and `top`, visiting only
/// the cells whose corners are not all on one side. With `Method::Tmc`, a
/// row's ambiguous cells are set aside and triangulated after its other
/// cells (their triangles follow the row's): the loop over a row then holds
/// only the table look-ups of standard MC, and its code does not change
/// with the kernel's.
///
/// Stops with [`Error::Interrupted`] once [`Layer::interrupted`] says so,
/// which it asks before every [`ROWS_PER_CHECK`] rows.
pub(super) fn layer_cells(
    layer: &Layer,
    rows: &mut EdgeRows,
    block: &mut Block,
    ambiguous: &mut Ambiguous,
    stats: &mut Stats,
) -> Result<()> {
    let last = layer.place.grid.dims[1] - 1;
    for first in (0..last).step_by(ROWS_PER_CHECK) {
        if (layer.interrupted)() {
            return Err(Error::Interrupted);
        }
        let ys = first..(first + ROWS_PER_CHECK).min(last);
        cell_rows(layer, ys, rows, block, ambiguous, stats)?;
    }
    Ok(())
}

/// The cells of rows `ys` of the layer (see [`layer_cells`]).
fn cell_rows(
    layer: &Layer,
    ys: std::ops::Range<usize>,
    rows: &mut EdgeRows,
    block: &mut Block,
    ambiguous: &mut Ambiguous,
    stats: &mut Stats,
) -> Result<()> {
    let nx = layer.place.grid.dims[0];
    let kernel = layer.params.method == Method::Tmc;
    let (bottom, top) = (layer.bottom, layer.top);
    let words = bottom.inside.words() - 1;
    for y in ys {
        let kinds = [
            bottom.inside.kind(y),
            bottom.inside.kind(y + 1),
            top.inside.kind(y),
            top.inside.kind(y + 1),
        ];
        if uniform_alike(kinds) {
            continue;
        }
        // Room for the MC triangles of every cell of the row, so that they
        // are pushed without a check (an ambiguous cell keeps this room).
        make_room(
            &mut block.triangles,
            layer.tables.mc_most * (nx - 1),
            TRIANGLES,
        )?;
        let edges = rows.cell_row(y, &layer.numbers);
        let rows = [
            bottom.inside.row(y),
            bottom.inside.row(y + 1),
            top.inside.row(y),
            top.inside.row(y + 1),
        ];
        for k in 0..words {
            // Corner c (cube numbering, c = x + 2y + 4z) of cell x is bit x
            // of rows[c / 2], shifted by one sample when c is odd.
            let corners: [u64; 8] = std::array::from_fn(|c| {
                let row = rows[c / 2];
                if c % 2 == 0 {
                    row[k]
                } else {
                    next(row, k)
                }
            });
            let any = corners.iter().fold(0, |m, w| m | w);
            let all = corners.iter().fold(u64::MAX, |m, w| m & w);
            let mixed = any & !all & below(nx - 1, k);
            each_bit(mixed, k, |x| {
                let j = x % 64;
                let config = corners
                    .iter()
                    .enumerate()
                    .fold(0u8, |m, (c, w)| m | (((w >> j) & 1) as u8) << c);
                let t = layer.tables;
                if t.is_ambiguous[config as usize] {
                    stats.ambiguous_cells += 1;
                    if kernel {
                        ambiguous.waiting.push((x, config));
                        return Ok(());
                    }
                }
                // No reallocation: the row made room for `mc_most` per cell.
                let range =
                    t.mc_start[config as usize] as usize..t.mc_start[config as usize + 1] as usize;
                let edges = edges.cell(x);
                let refs = t.mc_tris[range].iter().map(|tri| tri.map(|e| edges.get(e)));
                block.triangles.extend(refs);
                Ok(())
            })?;
        }
        for &(x, config) in ambiguous.waiting.iter() {
            ambiguous_cell(
                layer,
                edges.cell(x),
                block,
                ambiguous.cell,
                stats,
                [x, y],
                config,
            )?;
        }
        ambiguous.waiting.clear();
    }
    Ok(())
}

/// Triangulates ambiguous cell `(x, y)` of the layer, of configuration
/// `config`, with the kernel.
#[inline(never)]
pub(super) fn ambiguous_cell(
    layer: &Layer,
    edges: CellEdges,
    block: &mut Block,
    cell: &mut CellMesh,
    stats: &mut Stats,
    [x, y]: [usize; 2],
    config: u8,
) -> Result<()> {
    let Layer {
        place,
        tables: t,
        bottom,
        top,
        ..
    } = *layer;
    let nx = place.grid.dims[0];
    t.touch_sets(config);
    let values = cell_samples(bottom, top, y * nx + x, nx);
    // Both planes were read with the same level.
    let level = bottom.level;
    // Integer samples whose differences from the isovalue are exact (and
    // so have no residual), small integers themselves if both planes say
    // so: what the kernel then need not test (see `Known`).
    let integers = bottom.plain && top.plain;
    let known = match (integers, bottom.small && top.small) {
        (false, _) => Known::Nothing,
        (true, false) => Known::Integers,
        (true, true) => Known::SmallIntegers,
    };
    let g = if integers {
        level.plain_all(values)
    } else {
        level.rel_all(values)
    };
    let rest;
    let residual = if bottom.exact && top.exact {
        None
    } else {
        rest = level.residuals(values);
        (rest != [0.0; 8]).then_some(&rest)
    };
    cell.clear();
    // The cell's corner in grid index coordinates, for interior vertices
    // only (most ambiguous cells take table fans over edge vertices).
    let origin = || DVec3::from_array(place.index(x, y, bottom.z));
    // The table cells' flat contours reach `stats` at the slab's end
    // (`CellMesh::flush_counts` in `process_window`).
    match triangulate_ambiguous_deferred(&g, residual, config, known, stats, cell) {
        Triangles::Table(fans) => {
            // Edge vertices only, as MC.
            make_room(&mut block.triangles, fans.len(), TRIANGLES)?;
            let refs = fans.iter().map(|tri| tri.map(|e| edges.get(e)));
            block.triangles.extend(refs);
            Ok(())
        }
        Triangles::Centred(fans, centre) => {
            push_cell(block, place, edges, fans, [origin() + centre])
        }
        Triangles::Mesh => {
            let origin = origin();
            let interior = cell.interior.iter().map(|p| origin + *p);
            push_cell(block, place, edges, &cell.triangles, interior)
        }
    }
}

/// Appends a cell's interior vertices (grid index coordinates) and its
/// triangles, whose refs from [`INTERIOR`] on point at those vertices, to
/// the block.
pub(super) fn push_cell(
    block: &mut Block,
    place: &Placement,
    edges: CellEdges,
    triangles: &[[u8; 3]],
    interior: impl IntoIterator<Item = DVec3, IntoIter: ExactSizeIterator>,
) -> Result<()> {
    let interior = interior.into_iter();
    let first_interior = local_index(block)?;
    make_room(&mut block.vertices, interior.len(), VERTICES)?;
    make_room(&mut block.triangles, triangles.len(), TRIANGLES)?;
    for p in interior {
        block.vertices.push(place.at(p.to_array()));
    }
    let refs = triangles.iter().map(|tri| {
        tri.map(|r| {
            if r < INTERIOR {
                edges.get(r)
            } else {
                first_interior + (r - INTERIOR) as u32
            }
        })
    });
    block.triangles.extend(refs);
    Ok(())
}
