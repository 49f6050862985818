//! An independent mesh checker.
//!
//! [`check_mesh`] looks at the triangle indices of a [`Mesh`](crate::Mesh) and reports
//! whether the mesh is a closed, consistently oriented 2-manifold, together
//! with its Euler characteristic, connected components and their genus;
//! positions are used only for two geometric counts beside them
//! ([`check_geometry`]): zero-area triangles and vertices sharing a
//! position. [`read_mesh`] loads PLY, OBJ, OFF and `.tmesh`
//! files so that meshes written by any tool can be checked. Nothing here
//! shares code with the extraction kernel: the checker is the referee of the
//! kernel's tests and of `tmc check`.
//!
//! [`StreamCheck`] counts the same while a mesh streams, chunk by chunk,
//! over a window of two chunks, without holding the mesh: the preview's
//! closed/genus caption, and `tmc extract --labels --stats`
//! ([`StreamCheck::full`], whose [`Verdict::checked`] gives the figures of
//! `check_mesh`). [`Measured`] counts them, with the area and enclosed
//! volume, for each label of a label map's pass, for the CLI and the
//! Python package alike. [`check_tmesh`] checks a `.tmesh` file that way,
//! with every component's figures and the geometric counts, so that `tmc
//! check` gives `check_mesh`'s report of a mesh larger than memory.
//!
//! ## Definitions
//! * A triangle is **invalid** when an index is out of range and
//!   **degenerate** when it repeats an index. Both kinds are counted and then
//!   ignored: every other quantity is computed over the remaining **proper**
//!   triangles.
//! * A vertex is **referenced** when a proper triangle uses it; the others are
//!   counted as unreferenced and ignored.
//! * An (undirected) edge is a **boundary** edge when one proper triangle uses
//!   it, **manifold** when two do, and **non-manifold** when more than two do.
//!   A manifold edge is **inconsistent** when both triangles traverse it in the
//!   same direction (their orientations disagree).
//! * A referenced vertex is **non-manifold** when its incident triangles do not
//!   form a single fan: its link (the edges opposite to it) is not one path
//!   or one cycle. The ends of a non-manifold edge are non-manifold vertices.
//! * A proper triangle has **zero area** when the cross product of its edge
//!   vectors `b - a` and `c - a`, computed in `f64` from the `f32`
//!   coordinates, is zero: its corners are collinear or two coincide (the
//!   test is exact for coordinates within 2^29 of one another in
//!   magnitude). A vertex **shares a position** when another vertex has
//!   the same coordinates (`-0` as `0`).
//! * **Components** are the classes of triangles connected through shared
//!   vertices (so two spheres touching at one vertex are one component, with
//!   one non-manifold vertex).
//! * The **Euler characteristic** is `V - E + F` over referenced vertices,
//!   edges of proper triangles and proper triangles.
//! * A component's **boundary loops** are the connected components of the
//!   graph of its boundary edges, and its **genus** is `(2 - χ - b) / 2` for
//!   `b` boundary loops, reported only for orientable components without
//!   non-manifold edges or vertices.
//!
//! ## Scaling
//! The checker never hashes edges. Triangles are bucketed by vertex (a
//! counting sort into a compressed incidence list); each undirected edge
//! `{v, w}` with `v < w` is then found exactly once among the triangles of
//! `v`, by sorting that vertex's few `(w, direction, triangle)` entries. The
//! same pass checks the vertex links. Components use a union-find over
//! vertices, orientability a union-find with parity over triangles. Memory is
//! a few words per vertex and per triangle.

mod checker;
mod geometry;
mod link;
mod measure;
mod read;
mod report;
mod stream;
mod stream_components;
mod stream_edges;
mod stream_file;
mod stream_geometry;
mod stream_links;
mod union_find;

pub use checker::check_mesh;
pub use geometry::check_geometry;
pub use measure::{measure_reports, Measured, Measurement};
pub use read::{is_tmesh, read_mesh, read_mesh_to_draw};
pub use report::{ComponentReport, Geometry, MeshReport};
pub(crate) use stream::plural;
pub use stream::{Scratch, StreamCheck, Verdict};
pub use stream_file::check_tmesh;
pub use stream_links::{Checked, Links};
