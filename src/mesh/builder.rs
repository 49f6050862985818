//! [`MeshBuilder`]: the sink that collects the chunks into an in-memory
//! [`Mesh`]; [`Collector`] is the same with vertices in another type (the
//! Python package collects `f64` vertices as the chunks come, instead of
//! converting a finished mesh).

use super::room::{fit, reserve_for_planes};
use super::{Chunk, Mesh, MeshInfo, MeshSink, Totals};
use crate::error::make_room;
use crate::{Error, Result};

/// A vertex type a [`Collector`] can hold: made from the chunk's `f32`
/// position without loss.
pub trait Vertex: Copy {
    /// The vertex at `position`.
    fn from_f32(position: [f32; 3]) -> Self;
}

impl Vertex for [f32; 3] {
    #[inline(always)]
    fn from_f32(position: [f32; 3]) -> Self {
        position
    }
}

impl Vertex for [f64; 3] {
    #[inline(always)]
    fn from_f32(position: [f32; 3]) -> Self {
        position.map(f64::from)
    }
}

/// Collects the chunks into a vertex vector (of `V`), a triangle vector
/// (32-bit global indices) and, when the chunks carry them, a normal vector.
///
/// Each chunk is copied in as it comes, so that the chunk's vectors go
/// back to the slabs still to be computed: memory that is already paged in
/// is written again instead of new pages being faulted in (joining kept
/// chunks at the end wrote the whole mesh to fresh pages twice). When the
/// vectors are full they grow to what the planes so far predict for the
/// whole grid, and by remapping rather than copying (see
/// [`reserve_for_planes`]).
#[derive(Debug)]
pub struct Collector<V> {
    vertices: Vec<V>,
    triangles: Vec<[u32; 3]>,
    /// The chunks' normals (empty when they carry none).
    normals: Vec<[f32; 3]>,
    /// The chunks' triangle labels (empty when they carry none).
    labels: Vec<u32>,
    /// Grid planes, from [`MeshSink::begin`] (0: not known).
    planes: u64,
    /// Whether the mesh has normals and labels, from [`MeshSink::begin`]:
    /// an empty mesh has them too when its extraction or file does.
    attributes: [bool; 2],
}

/// Builds an in-memory [`Mesh`]: a [`Collector`] of `f32` vertices.
pub type MeshBuilder = Collector<[f32; 3]>;

impl<V> Default for Collector<V> {
    fn default() -> Self {
        Collector {
            vertices: Vec::new(),
            triangles: Vec::new(),
            normals: Vec::new(),
            labels: Vec::new(),
            planes: 0,
            attributes: [false; 2],
        }
    }
}

impl<V> Collector<V> {
    /// A collector with room for a mesh of known size (a replayed
    /// `.tmesh`), or [`Error::OutOfMemory`].
    pub fn with_room(vertices: usize, triangles: usize) -> Result<Self> {
        let mut collector = Collector::default();
        make_room(&mut collector.vertices, vertices, "the mesh's vertices")?;
        make_room(&mut collector.triangles, triangles, "the mesh's triangles")?;
        Ok(collector)
    }

    /// The vertices, triangles and normals (empty when the chunks had
    /// none) collected so far.
    /// Their vectors hold no more than an eighth of room beyond their
    /// length (see [`fit`]).
    pub fn into_parts(mut self) -> (Vec<V>, Vec<[u32; 3]>, Vec<[f32; 3]>) {
        fit(&mut self.vertices);
        fit(&mut self.triangles);
        fit(&mut self.normals);
        (self.vertices, self.triangles, self.normals)
    }
}

impl MeshBuilder {
    /// The mesh built so far, with the chunks' labels (`None` for every
    /// mesh but a label map's one-file output); normals and labels are
    /// `Some` when [`MeshSink::begin`] announced them or the chunks carried
    /// them, so an empty mesh keeps them.
    pub fn into_mesh(mut self) -> Mesh {
        let mut labels = std::mem::take(&mut self.labels);
        fit(&mut labels);
        let [with_normals, with_labels] = self.attributes;
        let (vertices, triangles, normals) = self.into_parts();
        Mesh {
            vertices,
            triangles,
            normals: (with_normals || !normals.is_empty()).then_some(normals),
            labels: (with_labels || !labels.is_empty()).then_some(labels),
        }
    }
}

impl<V: Vertex> MeshSink for Collector<V> {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        // Padded by one plane on each side with `--close`.
        self.planes = info.grid.dims[2] as u64 + if info.close { 2 } else { 0 };
        self.attributes = [info.normals, info.labels];
        Ok(())
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        let end = base + chunk.vertices.len() as u64;
        if end > u32::MAX as u64 {
            return Err(Error::Invalid(format!(
                "the mesh has more than {} vertices, more than an in-memory mesh with 32-bit indices holds; write a .tmesh file instead",
                u32::MAX
            )));
        }
        let (vertices, triangles) = (&mut self.vertices, &mut self.triangles);
        let (plane, planes) = (chunk.plane, self.planes);
        let what = "the mesh's vertices";
        reserve_for_planes(vertices, chunk.vertices.len(), plane, planes, what)?;
        let what = "the mesh's triangles";
        reserve_for_planes(triangles, chunk.triangles.len(), plane, planes, what)?;
        vertices.extend(chunk.vertices.iter().map(|&v| V::from_f32(v)));
        if !chunk.normals.is_empty() {
            let what = "the mesh's normals";
            reserve_for_planes(&mut self.normals, chunk.normals.len(), plane, planes, what)?;
            self.normals.extend_from_slice(&chunk.normals);
        }
        if !chunk.labels.is_empty() {
            let what = "the mesh's labels";
            reserve_for_planes(&mut self.labels, chunk.labels.len(), plane, planes, what)?;
            self.labels.extend_from_slice(&chunk.labels);
        }
        // May point into the next chunk, whose own check bounds it.
        let base = base as u32;
        triangles.extend(chunk.triangles.iter().map(|t| t.map(|i| base + i)));
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> Result<()> {
        Ok(())
    }
}
