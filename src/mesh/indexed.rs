//! The indexed triangle mesh produced by an extraction.

use crate::{Error, Result};
use std::path::Path;

/// An indexed triangle mesh: vertex positions in physical coordinates and
/// triangles as counter-clockwise (seen from outside) vertex index triples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions `[x, y, z]`.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Unit outward vertex normals, one per vertex, or `None` when the
    /// mesh has none (an empty mesh extracted with normals, or read from a
    /// file that declares them, has `Some` of none: its file keeps them).
    pub normals: Option<Vec<[f32; 3]>>,
    /// The label of each triangle (a label map's surfaces written to one
    /// file, `--labels` without `{label}`), or `None` when the mesh has
    /// none (`Some` of none for such a file without triangles).
    pub labels: Option<Vec<u32>>,
}

impl Mesh {
    /// Checks what a writer or a picture of the mesh relies on: at most
    /// `u32::MAX` vertices and triangles, every index naming a vertex; the
    /// error names `path` (where the mesh was going) and the first
    /// triangle at fault.
    pub fn check_indices(&self, path: &Path) -> Result<()> {
        let n = self.vertices.len();
        if u32::try_from(n).is_err() || u32::try_from(self.triangles.len()).is_err() {
            return Err(Error::Invalid(format!(
                "{}: mesh too large ({} vertices, {} triangles; at most {} each)",
                path.display(),
                n,
                self.triangles.len(),
                u32::MAX
            )));
        }
        if let Some((i, t)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
        {
            return Err(Error::Invalid(format!(
                "{}: triangle {i} {t:?} refers to a vertex past the {n} vertices",
                path.display()
            )));
        }
        Ok(())
    }
}
