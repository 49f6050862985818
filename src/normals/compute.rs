//! [`vertex_normals`]: the walk over the layers, on the workers.

use super::buckets::{Buckets, Locator};
use super::fallback::{fill_pending, PENDING};
use super::gradient::Layer;
use super::ranges::layer_ranges;
use super::samples::{with_planes, Samples, Visit};
use super::vector::unit;
use super::window::Window;
use crate::error::try_filled;
use crate::grid::WorldToIndex;
use crate::mesh::Mesh;
use crate::params::{ExtractParams, Inside};
use crate::volume::{Padded, SampleSource};
use crate::{Error, Result};
use rayon::prelude::*;
use std::ops::Range;

/// Vertices per range of layers at the least: a range re-reads up to three
/// planes at its start, which must stay small next to its work.
const MIN_RANGE_VERTICES: usize = 1 << 14;

/// Unit outward normals of `mesh`'s vertices, from the field's gradient.
///
/// `mesh` is what [`extract`](crate::extract) returned for this same
/// `source` and `params`. Each normal is the central-difference gradient at
/// the samples (one-sided at the volume's border) trilinearly interpolated
/// to the vertex, taken to world coordinates through the grid's inverse
/// map (`direction^-T * diag(1 / spacing)`, so spacing, non-orthogonal and
/// mirroring directions are honoured), normalized, and pointed outward:
/// toward lower values for [`Inside::High`], higher for [`Inside::Low`].
/// A vertex within [`SNAP`](super::buckets::SNAP) of a cell face (in
/// index units) is taken as on it, which puts the vertices that marching
/// cubes left on grid edges back there exactly despite the `f32` rounding
/// of their coordinates: their gradient is then interpolated between the
/// edge's two ends only.
///
/// With `params.close` the field is the one the extraction saw, the source
/// inside a border of NaN samples; NaN samples count as equal to the
/// isovalue in the differences (outside, a tie), so the closing caps get
/// finite, outward normals. Where the interpolated gradient is zero or not
/// finite, the vertex gets the angle-weighted average of its triangles'
/// normals, and `[0, 0, 0]` if that is zero too (every incident triangle
/// degenerate, or none). Every other normal has unit length.
///
/// Memory: four planes of `f64` per worker, two `u32` per vertex for the
/// bucketing, and the result; the volume is never read whole, and planes
/// of layers without vertices are not read. Workers (`params.threads`, 0 =
/// all cores) take ranges of layers; the result does not depend on their
/// number. Errors: a failed read, or a grid with fewer than two samples
/// along an axis while the mesh has vertices; an empty mesh gives an empty
/// vector.
pub fn vertex_normals(
    source: &dyn SampleSource,
    params: &ExtractParams,
    mesh: &Mesh,
) -> Result<Vec<[f32; 3]>> {
    if mesh.vertices.is_empty() {
        return Ok(Vec::new());
    }
    if u32::try_from(mesh.vertices.len()).is_err() {
        return Err(Error::Invalid(format!(
            "{} vertices are more than triangles can number",
            mesh.vertices.len()
        )));
    }
    // The field the extraction saw: with `close`, inside a NaN border.
    let padded = params.close.then(|| Padded::new(source));
    let source: &dyn SampleSource = match &padded {
        Some(padded) => padded,
        None => source,
    };
    let grid = *source.grid();
    if grid.dims.iter().any(|&d| d < 2) {
        return Err(Error::Invalid(format!(
            "normals need a grid of at least 2 samples along every axis, not {:?}",
            grid.dims
        )));
    }
    let locator = Locator::new(&grid);
    let buckets = Buckets::new(&locator, &mesh.vertices)?;
    let threads = match params.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    };
    // About eight ranges per thread, so that a slow range leaves no thread
    // idle for long.
    let ranges = layer_ranges(&buckets.starts, threads * 8, MIN_RANGE_VERTICES);
    let walk = Walk {
        source,
        params,
        mesh,
        locator: &locator,
        buckets: &buckets,
    };
    let pieces: Vec<Vec<[f32; 3]>> = if threads == 1 || ranges.len() == 1 {
        ranges
            .into_iter()
            .map(|r| walk.range(r))
            .collect::<Result<_>>()?
    } else {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))?;
        pool.install(|| {
            ranges
                .into_par_iter()
                .map(|r| walk.range(r))
                .collect::<Result<_>>()
        })?
    };
    let mut normals = try_filled("the vertex normals", mesh.vertices.len(), [0.0f32; 3])?;
    let sorted = pieces.iter().flatten();
    for (&v, &normal) in buckets.order.iter().zip(sorted) {
        normals[v as usize] = normal;
    }
    fill_pending(mesh, &mut normals)?;
    Ok(normals)
}

/// What every range of the walk shares.
struct Walk<'a> {
    /// The (padded, with `close`) source.
    source: &'a dyn SampleSource,
    /// The extraction's parameters.
    params: &'a ExtractParams,
    /// The mesh whose vertices get normals.
    mesh: &'a Mesh,
    /// Where the vertices fall in the source's grid.
    locator: &'a Locator,
    /// The vertices by layer.
    buckets: &'a Buckets,
}

impl Walk<'_> {
    /// The normals of the vertices of `layers`, in bucket order
    /// ([`PENDING`] where the gradient says nothing); reads only the planes
    /// around layers that have vertices.
    fn range(&self, layers: Range<usize>) -> Result<Vec<[f32; 3]>> {
        let starts = &self.buckets.starts;
        let grid = self.source.grid();
        let map = grid.world_to_index();
        // Outward is down the gradient when the inside is high.
        let sign = match self.params.inside {
            Inside::High => -1.0,
            Inside::Low => 1.0,
        };
        let mut window = Window::new(self.source);
        let mut out = Vec::with_capacity(starts[layers.end] - starts[layers.start]);
        for z in layers {
            let vertices = &self.buckets.order[starts[z]..starts[z + 1]];
            if vertices.is_empty() {
                continue;
            }
            let (planes, numbers) = window.around(z)?;
            let layer = LayerNormals {
                walk: self,
                vertices,
                numbers,
                map: &map,
                sign,
                out: &mut out,
            };
            with_planes(planes, layer);
        }
        Ok(out)
    }
}

/// The normals of one layer's vertices, appended to `out`: the work of
/// [`Walk::range`] compiled once per sample type.
struct LayerNormals<'w, 'a> {
    /// The walk.
    walk: &'w Walk<'a>,
    /// The layer's vertices.
    vertices: &'w [u32],
    /// The plane numbers of the layer's planes.
    numbers: [usize; 4],
    /// The grid's world-to-index map.
    map: &'w WorldToIndex,
    /// 1, or -1 where outward is down the gradient.
    sign: f64,
    /// Where the normals go, in bucket order.
    out: &'w mut Vec<[f32; 3]>,
}

impl Visit for LayerNormals<'_, '_> {
    type Output = ();

    fn visit<P: Samples>(self, planes: [P; 4]) {
        let walk = self.walk;
        let [nx, ny, _] = walk.source.grid().dims;
        let layer = Layer {
            planes,
            numbers: self.numbers,
            nx,
            ny,
            tie: walk.params.iso,
        };
        let (map, sign) = (self.map, self.sign);
        self.out.extend(self.vertices.iter().map(|&v| {
            let (cell, t) = walk.locator.locate(walk.mesh.vertices[v as usize]);
            let g = map.gradient_to_world(layer.gradient([cell[0], cell[1]], t));
            unit(g.map(|c| sign * c)).unwrap_or(PENDING)
        }));
    }
}
