//! Preview pictures of meshes (`tmc extract --preview`, `tmc preview`,
//! `tmc compare --preview`): a PNG with four shaded views of the mesh
//! (three orthogonal, one oblique) and a caption (name, isovalue,
//! triangles, closed or open and the genus), drawn in software while the
//! chunks stream, so the mesh is never held whole.
//!
//! The files, in the order a chunk meets them: [`views`] (the projections,
//! fitted to bounds known before the first triangle), [`sink`] (the
//! [`MeshSink`](crate::MeshSink) that hands chunks to workers),
//! [`lines`] (the three axis views of an extracted mesh from its vertices
//! on grid lines, exact and without triangles), [`raster`] (depth buffers keeping the smallest `(depth, shade)` key per
//! pixel: the pixels do not depend on the order of the triangles, hence
//! not on threads, slabs or parts), [`crate::check::StreamCheck`] (the
//! closed/genus verdict, counted over a window of two chunks), [`picture`] (colours and the
//! caption, in the hand-drawn [`font`]) and [`png_out`] (the file, written
//! atomically); [`pair`] puts two pictures side by side with marks
//! (`tmc compare --preview`). [`frame`] tracks the box of the vertices
//! drawn: a `.tmesh` extracted on a rotated or mirrored grid (whose
//! direction the format does not keep) may leave the box its views were
//! fitted to, and is then drawn again, framed by its own box.
//! [`labels`] draws every label of a label map's pass into one picture
//! (`--labels ... --preview`).
//! [`with_mesh`] pairs the sink with a mesh's own sink (`--preview`) and
//! draws a mesh held whole (`tmc preview` of a PLY, Python's
//! `Mesh.preview`).

pub mod font;
pub mod frame;
pub mod labels;
pub mod lines;
pub mod pair;
pub mod picture;
pub mod png_out;
pub mod raster;
pub mod sink;
pub mod views;
pub mod with_mesh;

pub use crate::check::Verdict;
pub use labels::{LabelPicture, ToLabelPicture};
pub use pair::{side_by_side, Marks, MARK, PAIR_DIMENSIONS};
pub use png_out::{check_png_path, write_png};
pub use sink::PreviewSink;
pub use views::Bounds;
pub use with_mesh::{check_picture, draw_mesh, title_of, BesideMesh, WithPreview};
