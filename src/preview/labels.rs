//! One picture of every label's surface of a label map's pass (`tmc
//! extract SEG --labels ... --preview FILE.png`): each label's sink is
//! paired with a [`ToLabelPicture`], which hands the label's chunks to one
//! shared [`PreviewSink`] as a mesh of its own
//! ([`PreviewSink::chunk_of`]), so that the labels' chunks, interleaved in
//! the pass, are each counted in their own plane order. The surfaces are
//! drawn together, each in its label's colour (the nearest wins, as in any
//! picture), and the caption
//! gives the number of labels with a surface, their triangles and the
//! verdict of all the surfaces taken together: closed when every label's
//! surface is, with the sum of their genera and components. It is the
//! picture `tmc preview` draws of the one `.tmesh` of every label.

use super::{BesideMesh, PreviewSink};
use crate::{Chunk, MeshInfo, MeshSink, Result, Totals};
use std::cell::RefCell;
use std::path::Path;

/// The picture of a pass's labels: made before the pass, shared by the
/// labels' [`ToLabelPicture`]s, written by [`LabelPicture::finish`] after
/// every label's mesh.
pub struct LabelPicture {
    preview: RefCell<PreviewSink>,
    /// Whether the picture's [`MeshSink::begin`] was called (by the first
    /// label's).
    begun: RefCell<bool>,
    /// The labels' totals, summed as each label finishes.
    totals: RefCell<Totals>,
}

impl LabelPicture {
    /// A picture at `path` titled `title` (and the number of labels with a
    /// surface) of the surfaces of `labels` (the pass's, in its order),
    /// each in its label's colour, drawn by `threads` workers (0: one per
    /// core).
    pub fn new(path: &Path, title: String, threads: usize, labels: &[i64]) -> LabelPicture {
        let sink = PreviewSink::new(path.to_path_buf(), title, None, threads).of_labels(labels);
        LabelPicture {
            preview: RefCell::new(sink),
            begun: RefCell::new(false),
            totals: RefCell::new(Totals::default()),
        }
    }

    /// `sink`, label number `index`'s, paired with this picture.
    pub fn pair<'a>(&'a self, index: usize, sink: &'a mut dyn MeshSink) -> ToLabelPicture<'a> {
        ToLabelPicture {
            inner: sink,
            index,
            picture: self,
        }
    }

    /// The pass's sinks, `sinks[i]` label `i`'s: each paired with
    /// `picture` (the pairs kept in `paired`) when there is one, else as
    /// they are.
    pub fn sinks<'a, S: MeshSink>(
        picture: Option<&'a LabelPicture>,
        sinks: &'a mut [S],
        paired: &'a mut Vec<ToLabelPicture<'a>>,
    ) -> Vec<&'a mut dyn MeshSink> {
        match picture {
            Some(picture) => {
                let each = sinks.iter_mut().enumerate();
                paired.extend(each.map(|(i, s)| picture.pair(i, s as &mut dyn MeshSink)));
                paired.iter_mut().map(|s| s as &mut dyn MeshSink).collect()
            }
            None => sinks.iter_mut().map(|s| s as &mut dyn MeshSink).collect(),
        }
    }

    /// Writes the picture, once every label's mesh is finished.
    pub fn finish(&self) -> Result<()> {
        let totals = *self.totals.borrow();
        self.preview.borrow_mut().finish(&totals)
    }
}

/// A label's sink paired with the [`LabelPicture`]: the label's mesh goes
/// to both, its own sink first finished.
pub struct ToLabelPicture<'a> {
    inner: &'a mut dyn MeshSink,
    index: usize,
    picture: &'a LabelPicture,
}

impl BesideMesh for ToLabelPicture<'_> {
    fn mesh(&mut self) -> &mut dyn MeshSink {
        self.inner
    }

    fn mesh_ref(&self) -> &dyn MeshSink {
        self.inner
    }

    /// The first label's begins the picture.
    fn begin_picture(&mut self, info: &MeshInfo) -> Result<()> {
        if self.picture.begun.replace(true) {
            return Ok(());
        }
        self.picture.preview.borrow_mut().begin(info)
    }

    fn draw(&mut self, chunk: &Chunk) -> Result<()> {
        self.picture
            .preview
            .borrow_mut()
            .chunk_of(self.index, chunk)
    }

    /// The label's last chunk drawn and its totals counted.
    fn after_mesh(&mut self, totals: &Totals) -> Result<()> {
        self.picture.preview.borrow_mut().end_of(self.index)?;
        let mut all = self.picture.totals.borrow_mut();
        all.vertices += totals.vertices;
        all.triangles += totals.triangles;
        all.chunks += totals.chunks;
        Ok(())
    }
}
