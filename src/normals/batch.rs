//! [`Batch`]: the normals of a few dozen edge vertices interpolated and
//! normalized together, in vector registers.
//!
//! Per vertex, reading the samples is scalar work, but what follows (the
//! interpolation between the edge's two ends, the chain rule, a square
//! root and a division, the conversion to `f32`) is the same arithmetic
//! for every vertex. [`EdgeNormals`](super::by_edge::EdgeNormals) gathers
//! the ends' differences of [`BATCH`] vertices into columns, and
//! [`Batch::normalize`] runs over the columns in a loop of fixed length,
//! which the compiler turns into instructions on two `f64` at a time.
//! Every operation is the one [`outward`](super::by_edge::outward) does,
//! in the same order (IEEE arithmetic, no fused multiply-add), so the
//! bits are the same; a vertex whose gradient is not of ordinary size is
//! left for the caller's exact path.

use super::index_map::IndexMap;

/// Vertices per batch.
pub(super) const BATCH: usize = 32;

/// The differences at the two ends of up to [`BATCH`] vertices' edges,
/// column by column, and what [`normalize`](Self::normalize) makes of
/// them.
///
/// Invariants: slot `j` of each column belongs to the same vertex; a slot
/// whose `offset` is NaN (no vertex's offset along an inner edge) holds a
/// vertex whose normal the caller takes elsewhere, its offset in
/// `border`.
pub(super) struct Batch {
    /// The central differences at the edge's lower end, per axis.
    pub(super) low: [[f64; BATCH]; 3],
    /// The central differences at the edge's upper end, per axis.
    pub(super) high: [[f64; BATCH]; 3],
    /// The vertex's offset along its edge from the lower end.
    pub(super) offset: [f64; BATCH],
    /// The lower end's sample index in its plane (`y * nx + x`).
    pub(super) at: [usize; BATCH],
    /// The offset read from the position, for a vertex whose normal the
    /// caller takes elsewhere (`offset` NaN).
    pub(super) border: [f64; BATCH],
    /// The squared length of the world gradient.
    pub(super) squared: [f64; BATCH],
    /// The normals, in vertex order: right where `squared` is of
    /// ordinary size.
    pub(super) normal: [[f32; 3]; BATCH],
}

/// What the interpolation multiplies the differences by: along x and y
/// (a half, times the grid's scale where the map has one per axis), and
/// across planes at the lower and the upper end.
#[derive(Debug, Clone, Copy)]
pub(super) struct Factors {
    /// Differences along x.
    pub(super) x: f64,
    /// Differences along y.
    pub(super) y: f64,
    /// Differences across planes at the edge's lower end.
    pub(super) z_low: f64,
    /// Differences across planes at the edge's upper end.
    pub(super) z_high: f64,
}

impl Batch {
    /// An empty batch (every column zero).
    pub(super) fn new() -> Self {
        Batch {
            low: [[0.0; BATCH]; 3],
            high: [[0.0; BATCH]; 3],
            offset: [0.0; BATCH],
            at: [0; BATCH],
            border: [0.0; BATCH],
            squared: [0.0; BATCH],
            normal: [[0.0; 3]; BATCH],
        }
    }

    /// The index-space gradient of slot `j`: the two ends' differences
    /// weighted by the offset, with the factors `f`, as
    /// [`normalize`](Self::normalize) takes it.
    #[inline(always)]
    pub(super) fn gradient(&self, j: usize, f: Factors) -> [f64; 3] {
        let (a, b) = (&self.low, &self.high);
        let w = self.offset[j];
        let (w_low, w_high) = (1.0 - w, w);
        [
            f.x * (w_low * a[0][j] + w_high * b[0][j]),
            f.y * (w_low * a[1][j] + w_high * b[1][j]),
            w_low * (a[2][j] * f.z_low) + w_high * (b[2][j] * f.z_high),
        ]
    }

    /// Sets `squared` and `normal` of every slot (those past the vertices
    /// gathered too, which nobody reads): the gradient, taken to world
    /// coordinates by `map`, times `sign`, over its length, as `f32`,
    /// which is what [`outward`](super::by_edge::outward) gives for a
    /// gradient whose squared length is of ordinary size.
    #[inline(always)]
    pub(super) fn normalize<M: IndexMap>(&mut self, f: Factors, map: M, sign: f64) {
        for j in 0..BATCH {
            let g = map.to_world(self.gradient(j, f));
            let squared = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
            let scale = sign / squared.sqrt();
            self.squared[j] = squared;
            self.normal[j] = g.map(|c| (c * scale) as f32);
        }
    }
}
