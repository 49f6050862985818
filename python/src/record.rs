//! What a `.tmesh` file needs beyond the mesh: the extraction's
//! [`MeshInfo`] and its chunks (one per grid plane). [`Recorder`] keeps them
//! while the pipeline collects the mesh in memory, so that `Mesh.write` can
//! later replay the same chunks into a `.tmesh` file: the bytes
//! `extract_to` would have written.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::Path;
use tmc::mesh::{Chunk, Collector, MeshInfo, MeshSink, Totals, Vertex};
use tmc::{Grid, Inside, Mesh, Method};

/// The record of one extraction, kept by the Python `Mesh` (opaque there).
#[pyclass(frozen, module = "tmc._tmc")]
pub(crate) struct Record {
    info: MeshInfo,
    /// Per chunk: grid plane, vertices, triangles.
    chunks: Vec<[u64; 3]>,
}

/// A [`Record`] as plain values, what it pickles as: the grid (dims,
/// spacing, origin, direction), the isovalue, whether the method is MC,
/// the inside low, the surface closed, with normals, with labels, and the
/// chunks' (plane, vertices, triangles).
type State = (
    [usize; 3],
    [f64; 3],
    [f64; 3],
    [[f64; 3]; 3],
    f64,
    [bool; 5],
    Vec<[u64; 3]>,
);

#[pymethods]
impl Record {
    /// Pickles (and copies) as `Record._restore(state)`, so that a `Mesh`
    /// sent to another process, or deep-copied, still writes its `.tmesh`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (State,))> {
        let record = slf.get();
        let (info, grid) = (&record.info, &record.info.grid);
        let flags = [
            info.method == Method::Mc,
            info.inside == Inside::Low,
            info.close,
            info.normals,
            info.labels,
        ];
        let state = (
            grid.dims,
            grid.spacing,
            grid.origin,
            grid.direction,
            info.iso,
            flags,
            record.chunks.clone(),
        );
        let restore = slf.py().import("tmc._tmc")?.getattr("_restore_record")?;
        Ok((restore, (state,)))
    }
}

/// The record [`Record::__reduce__`] describes (a function of the module,
/// where pickle finds it by name; private: the `tmc` package never calls it).
#[pyfunction]
pub(crate) fn _restore_record(state: State) -> Record {
    let (dims, spacing, origin, direction, iso, flags, chunks) = state;
    let [mc, low, close, normals, labels] = flags;
    Record {
        info: MeshInfo {
            grid: Grid {
                dims,
                spacing,
                origin,
                direction,
            },
            iso,
            method: if mc { Method::Mc } else { Method::Tmc },
            inside: if low { Inside::Low } else { Inside::High },
            close,
            normals,
            labels,
        },
        chunks,
    }
}

/// A [`Collector`] (vertices as `V`) that also records the [`Record`].
pub(crate) struct Recorder<V> {
    /// The mesh being collected.
    pub collector: Collector<V>,
    info: Option<MeshInfo>,
    chunks: Vec<[u64; 3]>,
}

impl<V> Default for Recorder<V> {
    fn default() -> Self {
        Recorder {
            collector: Collector::default(),
            info: None,
            chunks: Vec::new(),
        }
    }
}

impl<V> Recorder<V> {
    /// The record of the finished extraction.
    pub fn record(&self) -> Option<Record> {
        self.info.clone().map(|info| Record {
            info,
            chunks: self.chunks.clone(),
        })
    }
}

impl<V: Vertex> MeshSink for Recorder<V> {
    fn begin(&mut self, info: &MeshInfo) -> tmc::Result<()> {
        self.info = Some(info.clone());
        self.collector.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> tmc::Result<()> {
        let sizes = [chunk.vertices.len(), chunk.triangles.len()].map(|n| n as u64);
        self.chunks.push([chunk.plane, sizes[0], sizes[1]]);
        self.collector.chunk(base, chunk)
    }

    fn finish(&mut self, totals: &Totals) -> tmc::Result<()> {
        self.collector.finish(totals)
    }
}

/// Writes `mesh`, made by the extraction `record` describes, as the
/// `.tmesh` file at `path`: its chunks again, in plane order. Fails if the
/// mesh no longer has the sizes the chunks add up to.
pub(crate) fn write_tmesh(path: &Path, mesh: &Mesh, record: &Record) -> PyResult<()> {
    let [vertices, triangles] = record
        .chunks
        .iter()
        .fold([0u64; 2], |[v, t], c| [v + c[1], t + c[2]]);
    if (vertices, triangles) != (mesh.vertices.len() as u64, mesh.triangles.len() as u64) {
        return Err(PyValueError::new_err(format!(
            "{}: the mesh has {} vertices and {} triangles, but its extraction made {vertices} and {triangles}; a .tmesh file holds an extraction's chunks as made",
            path.display(),
            mesh.vertices.len(),
            mesh.triangles.len()
        )));
    }
    // The normals attribute as the mesh has normals (an extraction with
    // normals whose mesh lost them writes a file without; an empty mesh
    // with normals, the file with the attribute, as the extraction's).
    let normals = mesh.normals.as_deref();
    let info = tmc::MeshInfo {
        normals: normals.is_some(),
        ..record.info.clone()
    };
    let replay = || -> tmc::Result<()> {
        let mut sink = tmc::meshfile::TmeshWriter::create(path)?;
        sink.begin(&info)?;
        let (mut base, mut first_triangle) = (0usize, 0usize);
        for (i, &[plane, v, t]) in record.chunks.iter().enumerate() {
            let (v, t) = (v as usize, t as usize);
            let triangles = &mesh.triangles[first_triangle..first_triangle + t];
            // A chunk's triangles reach at most into the next chunk's vertices.
            let reach = base + v + record.chunks.get(i + 1).map_or(0, |c| c[1] as usize);
            if let Some(bad) = triangles.iter().flatten().find(|&&k| {
                let k = k as usize;
                k < base || k >= reach
            }) {
                return Err(tmc::Error::Invalid(format!(
                    "{}: vertex {bad} of a triangle of plane {plane} is not one the extraction made there; a .tmesh file holds an extraction's chunks as made",
                    path.display()
                )));
            }
            let chunk = Chunk {
                plane,
                vertices: mesh.vertices[base..base + v].to_vec(),
                triangles: triangles
                    .iter()
                    .map(|tri| tri.map(|i| i.wrapping_sub(base as u32)))
                    .collect(),
                normals: normals.map_or_else(Vec::new, |n| n[base..base + v].to_vec()),
                labels: Vec::new(),
                values: Vec::new(),
                encoded: Vec::new(),
            };
            sink.chunk(base as u64, &chunk)?;
            base += v;
            first_triangle += t;
        }
        sink.finish(&Totals {
            vertices,
            triangles,
            chunks: record.chunks.len() as u64,
        })
    };
    replay().map_err(crate::errors::to_py)
}
