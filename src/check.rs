//! PLACEHOLDER, wt-io worktree only: a throwaway stand-in for the mesh checker
//! that is being written elsewhere. It exists only so that the `tmc check`
//! subcommand compiles here; replace this file wholesale with the real
//! `check` module (same names: `read_mesh`, `check_mesh`, `MeshReport`).

use crate::{Error, Mesh, Result};
use serde::Serialize;
use std::path::Path;

/// Placeholder: always fails, the real reader is not merged yet.
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    Err(Error::Invalid(format!(
        "{}: mesh checking is not available in this build",
        path.display()
    )))
}

/// Placeholder: counts only.
pub fn check_mesh(mesh: &Mesh) -> MeshReport {
    MeshReport {
        vertices: mesh.vertices.len(),
        triangles: mesh.triangles.len(),
    }
}

/// Placeholder report.
#[derive(Debug, Serialize)]
pub struct MeshReport {
    /// Vertices in the mesh.
    pub vertices: usize,
    /// Triangles in the mesh.
    pub triangles: usize,
}

impl MeshReport {
    /// Placeholder: prints the counts.
    pub fn print_text(&self, w: &mut impl std::io::Write) {
        let _ = writeln!(
            w,
            "{} vertices, {} triangles",
            self.vertices, self.triangles
        );
    }
}
