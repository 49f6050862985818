//! The slab loop: cell layers along z, edge vertices numbered per row.
//!
//! Vertices are owned by grid planes. Block `z` holds, in this order: the
//! vertices on x-edges of plane `z` (raster order), those on its y-edges, the
//! vertices on z-edges between planes `z` and `z + 1`, and the interior
//! vertices of cell layer `z`, which also emits its triangles into block `z`
//! (row by row; in a row, the ambiguous cells' after the others').
//! A block's content depends on planes `z` and `z + 1` only, so any split of
//! the layers into slabs, on any number of threads, gives the same blocks.
//! Triangles point into their own block or into the first part of block
//! `z + 1` (its plane vertices, numbered the same way by both slabs that
//! see that plane), so each block leaves the slab as a [`Chunk`](crate::Chunk) with
//! indices relative to its first vertex, and the seam step only adds
//! offsets. Inside a slab no hashing is needed: an edge vertex's number
//! follows from the sign bits of its row (module `slab::edges`).
//!
//! [`process_slab`] runs four passes per cell layer `z`, each over whole
//! rows, as Flying Edges does:
//! 1. **load** plane `z + 1` (`Plane::load`): its samples relative to the
//!    isovalue, one inside bit per sample (compared in the samples' own type
//!    when the source lends its plane, module `bits`), and the vertices of its crossed x- and
//!    y-edges in raster order, keeping only each row's first number;
//! 2. **z-edges**: the vertices on the edges between planes `z` and
//!    `z + 1`, found where the two planes' bits differ;
//! 3. **cells** (`layer_cells`): each row's cells from the bits of its four
//!    corner rows: a row whose corner rows all lie on one side is skipped
//!    whole, and 64 cells of a row are sorted out with a few word
//!    operations on their corner bits; an unambiguous cell copies its
//!    triangles from the MC table, and the ambiguous cells of a row go to
//!    the [`kernel`](crate::kernel) after the others; every triangle corner
//!    is an edge number from module `edges` or an interior vertex of its
//!    cell;
//! 4. **emit**: block `z` becomes a [`Chunk`](crate::Chunk)
//!    (`Block::into_chunk`), and plane `z + 1` becomes the bottom plane of
//!    the next layer.

mod bits;
mod block;
mod cells;
mod edges;
mod level;
mod normals;
mod placement;
mod plane;
mod process;
mod samples;
mod spares;
mod window;

pub(crate) use level::Level;
pub use process::{process_slab, process_window, PerVertex};
pub use spares::{chunk_bytes, Spares};
pub use window::Window;
