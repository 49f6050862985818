//! Per-vertex normals of an extracted mesh, from the gradient of the field.
//!
//! Marching cubes places vertices on grid edges; the triangles around a
//! vertex give only a coarse normal, while the field's gradient gives a
//! smooth one, which is what renderers and the mesh formats that carry
//! normals want. [`vertex_normals`] computes it once, for the library, the
//! CLI and the bindings alike:
//!
//! * central-difference gradients at the samples (one-sided at the volume's
//!   border), trilinearly interpolated to the vertex, as VTK and
//!   scikit-image do ([`gradient`]); a vertex on a grid edge, as nearly
//!   all are, needs the gradients at the edge's two ends only, and the
//!   gradient code is compiled once per sample type ([`samples`]);
//! * converted to world coordinates with the chain rule through the grid's
//!   inverse map, then normalized and pointed outward: toward lower values
//!   for [`Inside::High`](crate::params::Inside::High), higher for
//!   [`Inside::Low`](crate::params::Inside::Low) ([`compute`]);
//! * where the gradient vanishes or is not finite (plateaus, ties), the
//!   angle-weighted average of the normals of the vertex's triangles
//!   ([`fallback`]).
//!
//! The volume is never held whole: the vertices are bucketed by cell layer
//! ([`buckets`]), and workers walk ranges of layers ([`ranges`]) holding
//! only the four planes around the current layer ([`window`]). Each
//! vertex's normal depends only on the samples, so the output is the same
//! for any number of threads.

pub mod buckets;
pub mod compute;
pub mod fallback;
pub mod gradient;
pub mod ranges;
pub mod samples;
pub mod vector;
pub mod window;

pub use compute::vertex_normals;
