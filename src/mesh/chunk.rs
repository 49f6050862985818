//! [`Chunk`]: the unit the pipeline ([`crate::stream`]) streams, one grid plane's vertices and
//! the triangles of the cell layer above it.

/// The vertices owned by one grid plane and the triangles of the cell layer
/// above it.
///
/// Triangle indices are relative to the chunk's first vertex. They may point
/// past the chunk's own vertices, into the vertices of the *next* chunk
/// (the vertices on the next plane's edges, which come first there), but
/// never further.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Chunk {
    /// Grid plane (z index) that owns the vertices.
    pub plane: u64,
    /// Vertex positions, physical coordinates.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside, relative indices.
    pub triangles: Vec<[u32; 3]>,
    /// Unit outward vertex normals, one per vertex, when the sink's
    /// [`MeshInfo::normals`](crate::MeshInfo::normals) is set; empty
    /// otherwise.
    pub normals: Vec<[f32; 3]>,
    /// The label of each triangle, one per triangle, when the sink's
    /// [`MeshInfo::labels`](crate::MeshInfo::labels) is set (the surfaces
    /// of several labels in one mesh); empty otherwise.
    pub labels: Vec<u32>,
    /// One value per vertex when the extraction's
    /// [`PipelineOptions::vertex_values`](crate::PipelineOptions::vertex_values)
    /// computed them (on the worker that made the chunk); empty otherwise.
    /// No file format writes them.
    pub values: Vec<f32>,
    /// The chunk's bytes as its sink's [`MeshSink::encoder`](crate::MeshSink::encoder)
    /// made them, on the worker that made the chunk (a `.tmesh` writer's
    /// compressed payload), so that the one thread feeding the sinks need
    /// not; empty when the sink has no encoder, and cleared by whatever
    /// changes the chunk after (a sink encodes an empty one itself).
    pub encoded: Vec<u8>,
}
