//! `--preview`: a mesh sink paired with a [`PreviewSink`], so that one
//! stream of chunks writes both the mesh and its picture.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use tmc::preview::PreviewSink;
use tmc::{Chunk, ChunkEncoder, MeshInfo, MeshSink, Result, Totals};

/// The mesh sink and its preview. The mesh is finished first; if the
/// picture then fails, the mesh is taken back, so that a failed run leaves
/// neither.
pub(crate) struct WithPreview {
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
    pub(crate) fn wrap(
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

    /// Finishes the picture after the mesh; removes the mesh if it fails.
    fn after_mesh(&mut self, totals: &Totals) -> Result<()> {
        self.preview
            .finish(totals)
            .map_err(|e| super::output::withdraw([self.output.as_path()], e))
    }
}

impl MeshSink for WithPreview {
    fn begin(&mut self, info: &MeshInfo) -> Result<()> {
        self.inner.begin(info)?;
        self.preview.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &Chunk) -> Result<()> {
        self.preview.chunk(base, chunk)?;
        self.inner.chunk(base, chunk)
    }

    fn chunk_cancellable(&mut self, base: u64, chunk: &Chunk, cancel: &AtomicBool) -> Result<()> {
        self.preview.chunk(base, chunk)?;
        self.inner.chunk_cancellable(base, chunk, cancel)
    }

    fn finish(&mut self, totals: &Totals) -> Result<()> {
        self.inner.finish(totals)?;
        self.after_mesh(totals)
    }

    fn finish_cancellable(&mut self, totals: &Totals, cancel: &AtomicBool) -> Result<()> {
        self.inner.finish_cancellable(totals, cancel)?;
        self.after_mesh(totals)
    }

    fn encoder(&self) -> Option<ChunkEncoder> {
        self.inner.encoder()
    }
}

/// The title of a picture of `path`: its file name.
pub(crate) fn title_of(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Checks a picture path before any work: it ends in `.png`, can be
/// written, and is neither the input nor one of the meshes.
pub(crate) fn check_picture(picture: &Path, input: &Path, meshes: &[&Path]) -> Result<()> {
    tmc::preview::check_png_path(picture)?;
    tmc::files::check_distinct(input, picture)?;
    for mesh in meshes {
        if tmc::files::check_distinct(mesh, picture).is_err() || *mesh == picture {
            return Err(tmc::Error::Invalid(format!(
                "{}: the preview and the mesh are the same file",
                picture.display()
            )));
        }
    }
    Ok(())
}
