//! A picture beside a mesh: [`WithPreview`], a mesh sink paired with a
//! [`PreviewSink`] so that one stream of chunks writes both the mesh and
//! its picture (`tmc extract --preview`, Python's `extract_to(...,
//! preview=)`), and [`draw_mesh`], the picture of a mesh held whole (`tmc
//! preview` of a PLY, OBJ, OFF or STL file, Python's `Mesh.preview`).

use super::{Bounds, PreviewSink};
use crate::{Chunk, ChunkEncoder, Mesh, MeshInfo, MeshSink, Result, Totals};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// The mesh sink and its preview. The mesh is finished first; if the
/// picture then fails, the mesh is taken back, so that a failed run leaves
/// neither.
pub struct WithPreview {
    /// The mesh's own sink.
    pub inner: Box<dyn MeshSink>,
    /// The picture.
    pub preview: PreviewSink,
    /// Where the mesh goes (removed if the picture fails).
    pub output: PathBuf,
}

impl WithPreview {
    /// `inner` with a preview at `picture`, captioned `title`, drawn by
    /// `threads` workers (0: one per core).
    pub fn wrap(
        inner: Box<dyn MeshSink>,
        output: &Path,
        picture: &Path,
        title: String,
        threads: usize,
    ) -> Box<dyn MeshSink> {
        Box::new(WithPreview {
            inner,
            preview: PreviewSink::new(picture.to_path_buf(), title, None, threads),
            output: output.to_path_buf(),
        })
    }
}

impl BesideMesh for WithPreview {
    fn mesh(&mut self) -> &mut dyn MeshSink {
        &mut *self.inner
    }

    fn mesh_ref(&self) -> &dyn MeshSink {
        &*self.inner
    }

    fn begin_picture(&mut self, info: &MeshInfo) -> Result<()> {
        self.preview.begin(info)
    }

    fn draw(&mut self, chunk: &Chunk) -> Result<()> {
        self.preview.chunk(0, chunk)
    }

    /// Finishes the picture after the mesh; removes the mesh if it fails.
    fn after_mesh(&mut self, totals: &Totals) -> Result<()> {
        self.preview
            .finish(totals)
            .map_err(|e| crate::files::withdraw([self.output.as_path()], e))
    }
}

/// A mesh's own sink with a picture drawn beside it from the same chunks
/// ([`WithPreview`], and each label's sink with its
/// [`LabelPicture`](super::LabelPicture)): every such pair is a
/// [`MeshSink`] that begins the mesh, then the picture; draws each chunk,
/// then hands it to the mesh; finishes the mesh, then
/// [`BesideMesh::after_mesh`].
pub trait BesideMesh {
    /// The mesh's own sink.
    fn mesh(&mut self) -> &mut dyn MeshSink;
    /// The mesh's own sink, to ask.
    fn mesh_ref(&self) -> &dyn MeshSink;
    /// Begins the picture, after the mesh.
    fn begin_picture(&mut self, info: &MeshInfo) -> Result<()>;
    /// Draws a chunk, before the mesh takes it.
    fn draw(&mut self, chunk: &Chunk) -> Result<()>;
    /// What follows the mesh's finish.
    fn after_mesh(&mut self, totals: &Totals) -> Result<()>;
}

impl<T: BesideMesh> MeshSink for T {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.mesh().begin(info)?;
        self.begin_picture(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.draw(chunk)?;
        self.mesh().chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.draw(chunk)?;
        self.mesh().chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.mesh().finish(totals)?;
        self.after_mesh(totals)
    }

    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.mesh().finish_cancellable(totals, cancel)?;
        self.after_mesh(totals)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.mesh_ref().encoder()
    }
}

/// The title of a picture of `path`: its file name.
pub fn title_of(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Checks a picture path before any work: it ends in `.png`, can be
/// written, and is neither the input (if a file) nor one of the meshes.
pub fn check_picture(picture: &Path, input: Option<&Path>, meshes: &[&Path]) -> Result<()> {
    super::check_png_path(picture)?;
    if let Some(input) = input {
        crate::files::check_distinct(input, picture)?;
    }
    for mesh in meshes {
        if crate::files::check_distinct(mesh, picture).is_err() || *mesh == picture {
            return Err(crate::Error::Invalid(format!(
                "{}: the preview and the mesh are the same file",
                picture.display()
            )));
        }
    }
    Ok(())
}

/// Draws `mesh`, held whole, into the PNG `picture`, captioned `title`,
/// framed by its vertices' box, by `threads` workers (0: one per core);
/// a triangle naming a vertex the mesh does not have, or a vertex that is
/// not finite, is an error before anything is drawn;
/// setting `cancel` stops it with [`Error::Interrupted`](crate::Error),
/// leaving no picture. A mesh without vertices is drawn as `tmc extract
/// --preview` draws an isovalue that meets nothing ("empty: no surface").
/// A mesh with a label per triangle is drawn with the labels in their
/// colours and named in the caption.
pub fn draw_mesh(
    mesh: Mesh,
    picture: &Path,
    title: String,
    threads: usize,
    cancel: &AtomicBool,
) -> Result<()> {
    mesh.check_indices(picture)?;
    if let Some((i, v)) = mesh
        .vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !v.iter().all(|c| c.is_finite()))
    {
        return Err(crate::Error::Invalid(format!(
            "{}: vertex {i} {v:?} is not finite",
            picture.display()
        )));
    }
    // With finite vertices there is no box only when there are none.
    let bounds =
        Bounds::of_points(mesh.vertices.iter().map(|v| v.map(f64::from))).unwrap_or(Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        });
    let mut sink =
        PreviewSink::new(picture.to_path_buf(), title, Some(bounds), threads).without_grid();
    // A label per triangle (a PLY of every label of a map): named in the
    // caption and coloured, as in the `.tmesh` of the same labels.
    let labels = mesh
        .labels
        .filter(|l| l.len() == mesh.triangles.len() && !l.is_empty());
    let info = MeshInfo {
        grid: crate::Grid::unit([1, 1, 1]),
        iso: f64::NAN,
        method: crate::Method::Tmc,
        inside: crate::Inside::High,
        close: false,
        normals: false,
        labels: labels.is_some(),
    };
    sink.begin(&info)?;
    let chunk = Chunk {
        plane: 0,
        vertices: mesh.vertices,
        triangles: mesh.triangles,
        normals: Vec::new(),
        labels: labels.unwrap_or_default(),
        values: Vec::new(),
        encoded: Vec::new(),
    };
    sink.chunk_cancellable(0, &chunk, cancel)?;
    let totals = Totals {
        vertices: chunk.vertices.len() as u64,
        triangles: chunk.triangles.len() as u64,
        chunks: 1,
    };
    sink.finish_cancellable(&totals, cancel)
}
