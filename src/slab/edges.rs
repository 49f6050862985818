//! The vertex numbers of crossed edges, one row at a time.
//!
//! A plane numbers its edge vertices in raster order as it is loaded (its
//! x-edges, then its y-edges), and the z-edges between two planes are
//! numbered row by row as well; all that is kept of that numbering is the
//! number of each row's first vertex. The sign bits of a row tell which of
//! its edges are crossed, so the numbers of a row can be spelled out again
//! whenever they are needed: the `n`th crossed edge of a row has number
//! `first + n`. That is done just before the cells of a row are
//! triangulated, for the rows they touch, into one record per position `x`
//! that holds all the numbers a cell at `x` reads (see [`Record`]).
//!
//! The records of a row are a few KiB and stay in the first-level cache.
//! Arrays for a whole plane (4 bytes per sample and per edge direction,
//! megabytes on a large grid) were written when a plane was loaded and had
//! left the cache by the time the cells read them: on a sparse 512^3 surface
//! that waiting took about a tenth of the extraction.

use super::bits::{each_bit, x_crossings, SignBits};
use std::convert::Infallible;

/// No row held.
const NO_ROW: usize = usize::MAX;

/// Writes `first`, `first + 1`, ... into field `field` of the records at
/// the positions of the set bits of the words `cross(0)`, `cross(1)`, ...
/// of a row, in increasing position (a tag bit in `first` is kept: the
/// numbers stay below it).
fn number_row(
    out: &mut [Record],
    field: usize,
    words: usize,
    first: u32,
    cross: impl Fn(usize) -> u64,
) {
    let mut number = first;
    for k in 0..words {
        let _ = each_bit::<Infallible>(cross(k), k, |x| {
            out[x][field] = number;
            number = number.wrapping_add(1);
            Ok(())
        });
    }
}

/// The edge numbers at one position `x` of a cell row: the x-edges of the
/// bottom plane on rows of even and odd `y` (fields 0 and 1), the same for
/// the top plane (2, 3) and for the z-edges (4, 5), then the y-edges of the
/// bottom and of the top plane between the cell row's two rows (6, 7).
/// Keeping them together lets a cell read its twelve numbers from two
/// neighbouring records.
type Record = [u32; 8];

/// Fields of [`Record`].
const BOTTOM_X: usize = 0;
const TOP_X: usize = 2;
const Z: usize = 4;
const BOTTOM_Y: usize = 6;
const TOP_Y: usize = 7;

/// Where the numbers of one layer's edges come from: the sign bits of its
/// two planes and the first vertex number of each row.
pub(super) struct LayerNumbers<'a> {
    pub(super) nx: usize,
    /// Or-ed into the numbers of the top plane's vertices, which belong to
    /// the next block.
    pub(super) top_tag: u32,
    pub(super) bottom: &'a SignBits,
    pub(super) top: &'a SignBits,
    /// First x-edge and y-edge vertex of each row of the bottom plane.
    pub(super) bottom_x: &'a [u32],
    pub(super) bottom_y: &'a [u32],
    /// The same for the top plane (numbers in the next block).
    pub(super) top_x: &'a [u32],
    pub(super) top_y: &'a [u32],
    /// First z-edge vertex of each row.
    pub(super) z: &'a [u32],
}

/// The edge numbers of the cell rows of a layer, spelled out row by row:
/// a row of x-edges or z-edges is numbered once and serves the two cell
/// rows it borders (rows of even `y` in one field, of odd `y` in the other).
#[derive(Debug)]
pub(super) struct EdgeRows {
    records: Vec<Record>,
    /// The rows held in the even and odd fields of the x-edges of each
    /// plane and of the z-edges (both kinds of x-edges and the z-edges are
    /// always numbered together).
    held: [usize; 2],
}

/// The edge numbers a row of cells refers to; see [`CellRowEdges::cell`].
pub(super) struct CellRowEdges<'a> {
    records: &'a [Record],
    /// Parity of the cell row's `y`: which fields hold its lower row.
    parity: usize,
}

impl EdgeRows {
    /// Records for rows of `nx` samples.
    pub(super) fn new(nx: usize) -> Self {
        EdgeRows {
            records: vec![[0; 8]; nx],
            held: [NO_ROW; 2],
        }
    }

    /// Forgets the rows held: a new layer begins.
    pub(super) fn new_layer(&mut self) {
        self.held = [NO_ROW; 2];
    }

    /// The edge numbers of cell row `y` of the layer `numbers` describes.
    #[inline]
    pub(super) fn cell_row(&mut self, y: usize, numbers: &LayerNumbers) -> CellRowEdges<'_> {
        let words = numbers.bottom.words() - 1;
        for r in [y, y + 1] {
            let parity = r % 2;
            if self.held[parity] != r {
                self.number_row_of_x_and_z(r, parity, numbers);
                self.held[parity] = r;
            }
        }
        let out = &mut self.records;
        for (bits, first, field) in [
            (numbers.bottom, numbers.bottom_y[y], BOTTOM_Y),
            (numbers.top, numbers.top_y[y] | numbers.top_tag, TOP_Y),
        ] {
            let (lower, upper) = (bits.row(y), bits.row(y + 1));
            number_row(out, field, words, first, |k| lower[k] ^ upper[k]);
        }
        CellRowEdges {
            records: &self.records,
            parity: y % 2,
        }
    }

    /// Numbers the x-edges of both planes and the z-edges on row `r`, into
    /// the fields of `parity`.
    fn number_row_of_x_and_z(&mut self, r: usize, parity: usize, numbers: &LayerNumbers) {
        let nx = numbers.nx;
        let words = numbers.bottom.words() - 1;
        let out = &mut self.records;
        for (bits, first, field) in [
            (numbers.bottom, numbers.bottom_x[r], BOTTOM_X),
            (numbers.top, numbers.top_x[r] | numbers.top_tag, TOP_X),
        ] {
            let row = bits.row(r);
            number_row(out, field + parity, words, first, |k| {
                x_crossings(row, k, nx)
            });
        }
        let (lower, upper) = (numbers.bottom.row(r), numbers.top.row(r));
        number_row(out, Z + parity, words, numbers.z[r], |k| {
            lower[k] ^ upper[k]
        });
    }
}

impl<'a> CellRowEdges<'a> {
    /// The edge numbers of cell `x`.
    #[inline(always)]
    pub(super) fn cell(&self, x: usize) -> CellEdges<'a> {
        let window = self.records[x..x + 2].as_flattened();
        CellEdges {
            window: window.try_into().expect("two records"),
            fields: &CELL_FIELDS[self.parity],
        }
    }
}

/// Where, in two neighbouring records (16 numbers), each of the twelve
/// edges of a cell of a row of even or odd `y` finds its number, in the
/// edge order of `kernel::cube`; padded to 16 entries so that an edge index
/// masked to four bits needs no bounds check.
const CELL_FIELDS: [[u8; 16]; 2] = {
    let mut fields = [[0; 16]; 2];
    let mut parity = 0;
    while parity < 2 {
        let (p, q) = (parity as u8, 1 - parity as u8);
        let (a, b) = (0, 8);
        let (bx, tx, z) = (BOTTOM_X as u8, TOP_X as u8, Z as u8);
        let (by, ty) = (BOTTOM_Y as u8, TOP_Y as u8);
        let edges = [
            a + bx + p,
            a + bx + q,
            a + tx + p,
            a + tx + q,
            a + by,
            b + by,
            a + ty,
            b + ty,
            a + z + p,
            b + z + p,
            a + z + q,
            b + z + q,
        ];
        let mut e = 0;
        while e < 12 {
            fields[parity][e] = edges[e];
            e += 1;
        }
        parity += 1;
    }
    fields
};

/// The edge numbers of one cell (entries of uncrossed edges are stale).
pub(super) struct CellEdges<'a> {
    window: &'a [u32; 16],
    fields: &'static [u8; 16],
}

impl CellEdges<'_> {
    /// The number of the vertex on edge `e` (`kernel::cube` order), tagged
    /// when it belongs to the next block.
    #[inline(always)]
    pub(super) fn get(&self, e: u8) -> u32 {
        debug_assert!(e < 12, "edge {e}");
        self.window[usize::from(self.fields[usize::from(e & 15)] & 15)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::cube::{edge_axis, EDGE_CORNERS};
    use std::collections::HashMap;

    #[test]
    fn a_row_is_numbered_in_increasing_position() {
        let mut out = vec![[u32::MAX; 8]; 130];
        number_row(&mut out, 3, 3, 7, |k| [1 << 5 | 1 << 63, 0, 1 << 1][k]);
        assert_eq!((out[5][3], out[63][3], out[129][3]), (7, 8, 9));
        assert_eq!(out[5][2], u32::MAX);
    }

    /// Every crossed edge of every cell gets the number a plain raster
    /// numbering gives it (x-edges, then y-edges of each plane; z-edges),
    /// whatever rows are visited.
    #[test]
    fn cells_see_the_raster_numbering() {
        const TAG: u32 = 1 << 31;
        for (nx, ny) in [(5, 4), (64, 3), (65, 5), (130, 6)] {
            let mut state = (nx * 31 + ny) as u64;
            let mut random = move || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 33) as i32 % 3 - 1
            };
            let values: [Vec<i32>; 2] = [0, 1].map(|_| (0..nx * ny).map(|_| random()).collect());
            let inside = |z: usize, x: usize, y: usize| values[z][y * nx + x] > 0;
            let planes = [0, 1].map(|z| {
                let mut bits = SignBits::new(nx, ny);
                bits.classify(&values[z], nx, 0.0, true);
                bits
            });
            // Reference numbers by (axis, plane, x, y), and the first of each row.
            let mut reference = HashMap::new();
            let mut firsts = [[vec![0; ny], vec![0; ny]], [vec![0; ny], vec![0; ny]]];
            for (z, [x_firsts, y_firsts]) in firsts.iter_mut().enumerate() {
                let tag = if z == 1 { TAG } else { 0 };
                let mut n = 0;
                for (y, first) in x_firsts.iter_mut().enumerate() {
                    *first = n;
                    for x in 0..nx - 1 {
                        if inside(z, x, y) != inside(z, x + 1, y) {
                            reference.insert((0, z, x, y), n | tag);
                            n += 1;
                        }
                    }
                }
                for (y, first) in y_firsts.iter_mut().enumerate().take(ny - 1) {
                    *first = n;
                    for x in 0..nx {
                        if inside(z, x, y) != inside(z, x, y + 1) {
                            reference.insert((1, z, x, y), n | tag);
                            n += 1;
                        }
                    }
                }
            }
            let mut z_first = vec![0; ny];
            let mut n = 500;
            for (y, first) in z_first.iter_mut().enumerate() {
                *first = n;
                for x in 0..nx {
                    if inside(0, x, y) != inside(1, x, y) {
                        reference.insert((2, 0, x, y), n);
                        n += 1;
                    }
                }
            }
            let numbers = LayerNumbers {
                nx,
                top_tag: TAG,
                bottom: &planes[0],
                top: &planes[1],
                bottom_x: &firsts[0][0],
                bottom_y: &firsts[0][1],
                top_x: &firsts[1][0],
                top_y: &firsts[1][1],
                z: &z_first,
            };
            let mut rows = EdgeRows::new(nx);
            // Every row, then every other row (rows skipped as uniform).
            for step in [1, 2] {
                rows.new_layer();
                for y in (0..ny - 1).step_by(step) {
                    let edges = rows.cell_row(y, &numbers);
                    for x in 0..nx - 1 {
                        let cell = edges.cell(x);
                        for (e, [a, b]) in EDGE_CORNERS.iter().enumerate() {
                            let at = |c: usize| (x + (c & 1), y + (c >> 1 & 1), c >> 2);
                            let ((xa, ya, za), (xb, yb, zb)) = (at(*a), at(*b));
                            if inside(za, xa, ya) == inside(zb, xb, yb) {
                                continue;
                            }
                            let key = (edge_axis(e), za, xa, ya);
                            assert_eq!(cell.get(e as u8), reference[&key], "{nx}x{ny} {key:?}");
                        }
                    }
                }
            }
        }
    }
}
