//! Per-vertex normals from the gradient of the field, computed in the slab
//! loop ([`ExtractParams::normals`](crate::params::ExtractParams::normals)).
//!
//! Marching cubes places vertices on grid edges; the triangles around a
//! vertex give only a coarse normal, while the field's gradient gives a
//! smooth one, which is what renderers and the mesh formats that carry
//! normals want. The workers compute it as they triangulate, for the
//! library, the CLI and the bindings alike:
//!
//! * central-difference gradients at the samples (one-sided at the volume's
//!   border), interpolated linearly to the vertex along its edge (or
//!   trilinearly in its cell), as VTK and scikit-image do ([`gradient`]);
//!   a vertex on a grid edge needs the gradients at the edge's two ends
//!   only, and the gradient code is compiled once per sample type
//!   ([`samples`]);
//! * converted to world coordinates with the chain rule through the grid's
//!   inverse map, then normalized and pointed outward: toward lower values
//!   for [`Inside::High`](crate::params::Inside::High), higher for
//!   [`Inside::Low`](crate::params::Inside::Low) ([`in_slab`]), chunk by
//!   chunk, a vertex on an inner grid edge taken from its position straight
//!   to the edge's two ends ([`on_edge`]), any other located in its chunk's
//!   layer ([`locate`]), the planes around that layer held by a [`window`];
//!   the arithmetic after a vertex's samples are read runs on a `batch`
//!   of vertices at a time;
//! * where the gradient vanishes or is not finite (plateaus, ties), the
//!   angle-weighted average of the normals of the vertex's triangles,
//!   which needs the chunks on both sides: [`pending`] resolves them one
//!   chunk behind the stream.
//!
//! Each normal depends on the samples and the mesh only, so the output is
//! the same for any number of threads, slab depth or split into parts.

mod batch;
pub mod by_edge;
pub mod gradient;
pub mod in_slab;
mod index_map;
pub mod locate;
pub mod on_edge;
pub mod pending;
pub mod samples;
pub mod vector;
pub mod window;

pub use by_edge::BlockEdges;
pub use in_slab::SlabNormals;
pub use pending::{has_pending, FillPending, PENDING};
