//! The indexed triangle mesh produced by an extraction.

/// An indexed triangle mesh: vertex positions in physical coordinates and
/// triangles as counter-clockwise (seen from outside) vertex index triples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions `[x, y, z]`.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Unit outward vertex normals, one per vertex, or empty when the mesh
    /// has none.
    pub normals: Vec<[f32; 3]>,
    /// The label of each triangle (a label map's surfaces written to one
    /// file, `--labels` without `{label}`), or empty when the mesh has none.
    pub labels: Vec<u32>,
}
