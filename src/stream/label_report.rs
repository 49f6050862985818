//! What a label map's pass reports (`tmc extract --labels --json`, the
//! Python package's `extract_labels_to`): [`LabelRun`], with one
//! [`LabelReport`] per label ([`label_reports`]), and the figures it is
//! made of ([`voxel_volume`], [`SurfaceSums`]).
//!
//! The library owns the report so that every caller gives it under the
//! same names, in the same order. The figures counted from a label's mesh
//! as its chunks stream (components, genus, closed, area, enclosed volume:
//! `crate::check::Measured`, which fills them in) are optional: a caller
//! that does not count them leaves them out.

use crate::grid::Grid;
use crate::stats::Stats;
use crate::volume::LabelCounts;
use serde::Serialize;
use std::path::PathBuf;

/// One label's figures. Serialized (serde), the optional figures are left
/// out when absent.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabelReport {
    /// The label's value.
    pub label: i64,
    /// The file its mesh went to (the one file, for one file of every label).
    pub output: String,
    /// Triangles of its mesh.
    pub triangles: u64,
    /// Vertices of its mesh.
    pub vertices: u64,
    /// Samples of the label.
    pub samples: u64,
    /// `samples` times the volume of a voxel ([`voxel_volume`]).
    pub voxel_volume: f64,
    /// Connected components of its mesh.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub components: Option<usize>,
    /// Total genus of its mesh (when every component is a closed manifold).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub genus: Option<i64>,
    /// Whether its mesh is a closed manifold.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed: Option<bool>,
    /// Surface area of its mesh ([`SurfaceSums`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub area: Option<f64>,
    /// Volume its mesh encloses ([`SurfaceSums`]); `None` unless the mesh
    /// is a closed manifold (over an open surface the sum depends on the
    /// origin).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub enclosed_volume: Option<f64>,
}

impl LabelReport {
    /// The figures of `label` that need not its mesh: written to `output`
    /// with `stats`, `samples` samples of `voxel` volume each; the others
    /// absent.
    pub fn new(label: i64, output: String, stats: &Stats, samples: u64, voxel: f64) -> Self {
        LabelReport {
            label,
            output,
            triangles: stats.triangles,
            vertices: stats.vertices,
            samples,
            voxel_volume: samples as f64 * voxel,
            components: None,
            genus: None,
            closed: None,
            area: None,
            enclosed_volume: None,
        }
    }
}

/// The figures of each of `labels` that need not its mesh
/// ([`LabelReport::new`]): written to its output (`outputs`, one per label
/// or the one file of every label), with its `stats` (in the order of
/// `labels`), its samples in `counts`, on `grid`.
pub fn label_reports(
    labels: &[i64],
    outputs: &[PathBuf],
    stats: &[Stats],
    counts: &LabelCounts,
    grid: &Grid,
) -> Vec<LabelReport> {
    let voxel = voxel_volume(grid);
    labels
        .iter()
        .zip(stats)
        .enumerate()
        .map(|(i, (&label, stats))| {
            let output = outputs.get(i).or(outputs.last());
            let output = output.map(|p| p.display().to_string());
            let samples = counts.samples(label);
            LabelReport::new(label, output.unwrap_or_default(), stats, samples, voxel)
        })
        .collect()
}

/// The report of a label map's pass, keys in this order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabelRun<'a> {
    /// The label map's path (or what stands for it, `"array"`).
    pub input: String,
    /// Whether the surfaces were closed at the volume's boundary.
    pub close: bool,
    /// The method's name ([`Method::name`](crate::params::Method::name)).
    pub method: &'static str,
    /// The value that `all` leaves out.
    pub background: i64,
    /// Each label's figures, in the order of the labels.
    pub labels: &'a [LabelReport],
    /// Seconds spent counting the values before the pass.
    pub scan_seconds: f64,
    /// Seconds of the pass, files finished included.
    pub pass_seconds: f64,
    /// Seconds of the whole run.
    pub seconds: f64,
}

/// The volume of one voxel of `grid`: |det| of its index-to-world map's
/// matrix.
pub fn voxel_volume(grid: &Grid) -> f64 {
    let m: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| grid.direction[i][j] * grid.spacing[j]));
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    det.abs()
}

/// Surface area and enclosed volume of a mesh (divergence theorem,
/// outward triangles: positive for a closed surface), summed in `f64`
/// triangle by triangle as its chunks stream: in the order of the file,
/// the sums do not depend on the threads, the slab depth or the parts.
#[derive(Debug, Default, Clone, Copy)]
pub struct SurfaceSums {
    /// Surface area so far.
    pub area: f64,
    /// Enclosed volume so far.
    pub volume: f64,
}

impl SurfaceSums {
    /// Adds `triangles`, whose corners index `vertices` (a triangle with a
    /// corner outside `vertices` is skipped).
    pub fn add(&mut self, vertices: &[[f32; 3]], triangles: &[[u32; 3]]) {
        for t in triangles {
            let corner = |k: u32| vertices.get(k as usize).map(|p| p.map(f64::from));
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                continue;
            };
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            self.area += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / 2.0;
            // a . (b x c) / 6
            let bc = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            self.volume += (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]) / 6.0;
        }
    }
}
