//! Where a vertex goes on a crossed edge that ends at a tie: a sample
//! equal to the isovalue (value 0 for the kernel, NaN and `--close`'s
//! padding included).
//!
//! A tie is outside, so the mesh has the topology of `{g > ε}` for an
//! infinitesimal `ε > 0`; but the linear crossing of an edge from an inside
//! value `a > 0` to a tie is `t = a / (a - 0) = 1`: the vertex would sit on
//! the tie sample itself, where every other crossed edge of that sample
//! puts its vertex too, and the triangles between them would have no area.
//! Instead the vertex goes a fixed fraction [`TIE_OFFSET`] of the edge away
//! from the tie, towards the inside end: the crossing of the level
//! `a · TIE_OFFSET / (1 - TIE_OFFSET)` above the isovalue along that edge.
//! Every edge vertex then lies strictly inside its edge, as it does in a
//! volume without ties, and the vertices around one tie sample lie on
//! distinct edges, so they are distinct points. An edge without a tie keeps
//! the plain crossing `a / (a - b)`, bit for bit.
//!
//! The slab loop may move a tie's vertex further (up to the middle of the
//! edge) when the `f32` world position at `TIE_OFFSET` rounds to the tie
//! sample's own (far from the origin, or with a tiny spacing); see
//! `slab::placement`.

/// How far (a fraction of the edge, in grid index units) a vertex on an
/// edge that ends at a tie lies from that tie: `2^-10`, below a
/// thousandth of the spacing, yet resolved in `f32` for coordinates up to
/// `2^13` spacings from the origin.
pub const TIE_OFFSET: f64 = 1.0 / 1024.0;

/// The crossing of the edge from value `a` to value `b` (one of them `> 0`,
/// the other `<= 0`), as a fraction of the edge from `a`'s end: the linear
/// crossing `a / (a - b)`, or [`TIE_OFFSET`] away from a tie end.
#[inline]
pub fn edge_fraction(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        TIE_OFFSET
    } else if b == 0.0 {
        1.0 - TIE_OFFSET
    } else {
        a / (a - b)
    }
}
