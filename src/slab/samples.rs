//! The eight samples of an ambiguous cell, read from its two planes with
//! one look at their sample type.
//!
//! [`Plane::values`] matches on its plane's sample type, so a cell read
//! through it twice (bottom and top: two jump tables and eight bounds
//! checks). [`cell_samples`] matches on both planes' types at once and
//! reads each of the four pairs of neighbouring samples with one range
//! check, converted as [`LentPlane::get_many`] converts them.

use super::plane::Plane;
use crate::volume::{LentPlane, Sample};

/// The samples of the cell whose corner 0 is sample `i` of `bottom` (rows
/// of `nx` samples), in cube corner order (`c = x + 2y + 4z`), as `f64`s:
/// what [`Plane::values`] of corners `i`, `i + 1`, `i + nx`, `i + nx + 1`
/// of `bottom` and then of `top` gives, bit for bit.
#[inline(always)]
pub(super) fn cell_samples(bottom: &Plane, top: &Plane, i: usize, nx: usize) -> [f64; 8] {
    use LentPlane as L;
    match (bottom.lent, top.lent) {
        (Some(L::U8(b)), Some(L::U8(t))) => typed(b, t, i, nx),
        (Some(L::I8(b)), Some(L::I8(t))) => typed(b, t, i, nx),
        (Some(L::U16(b)), Some(L::U16(t))) => typed(b, t, i, nx),
        (Some(L::I16(b)), Some(L::I16(t))) => typed(b, t, i, nx),
        (Some(L::U32(b)), Some(L::U32(t))) => typed(b, t, i, nx),
        (Some(L::I32(b)), Some(L::I32(t))) => typed(b, t, i, nx),
        (Some(L::F32(b)), Some(L::F32(t))) => typed(b, t, i, nx),
        (Some(L::F64(b)), Some(L::F64(t))) => typed(b, t, i, nx),
        (None, None) => typed(&bottom.read, &top.read, i, nx),
        // Unaligned, swapped, views, or planes of two forms.
        _ => {
            let corners = [i, i + 1, i + nx, i + nx + 1];
            let (low, high) = (bottom.values(corners), top.values(corners));
            std::array::from_fn(|c| if c < 4 { low[c] } else { high[c - 4] })
        }
    }
}

/// [`cell_samples`] of two planes of samples of type `S`.
#[inline(always)]
fn typed<S: Sample>(low: &[S], high: &[S], i: usize, nx: usize) -> [f64; 8] {
    let (a, b) = (&low[i..i + 2], &low[i + nx..i + nx + 2]);
    let (c, d) = (&high[i..i + 2], &high[i + nx..i + nx + 2]);
    [a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]].map(Sample::to_f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Grid;
    use crate::slab::spares::PlaneBuffers;

    const NX: usize = 7;
    const NY: usize = 5;

    /// Two planes holding `low` and `high` as `lend` lends them (`None`:
    /// as read into `f64`s).
    fn planes<'s>(lent: [Option<LentPlane<'s>>; 2], read: [&[f64]; 2]) -> [Plane<'s>; 2] {
        let grid = Grid::unit([NX, NY, 2]);
        [0, 1].map(|k| {
            let mut plane = Plane::new(PlaneBuffers::new(&grid));
            plane.lent = lent[k];
            plane.read = read[k].to_vec();
            plane
        })
    }

    /// `cell_samples` against the planes' `values` (the generic reading)
    /// at every cell of two planes.
    fn check(lent: [Option<LentPlane>; 2], read: [&[f64]; 2], what: &str) -> usize {
        let [bottom, top] = planes(lent, read);
        let mut cells = 0;
        for y in 0..NY - 1 {
            for x in 0..NX - 1 {
                let i = y * NX + x;
                let corners = [i, i + 1, i + NX, i + NX + 1];
                let (low, high) = (bottom.values(corners), top.values(corners));
                let expected: [f64; 8] =
                    std::array::from_fn(|c| if c < 4 { low[c] } else { high[c - 4] });
                let got = cell_samples(&bottom, &top, i, NX);
                assert_eq!(
                    got.map(f64::to_bits),
                    expected.map(f64::to_bits),
                    "{what} cell {x} {y}"
                );
                cells += 1;
            }
        }
        cells
    }

    /// Random samples of each type, and samples of few values (ties, the
    /// type's ends, for floats also -0, NaN and infinities), read by the
    /// typed path of `cell_samples`, by its generic one (planes of two forms),
    /// and from planes read as `f64`: always `Plane::values`, bit for bit.
    #[test]
    fn every_sample_type_reads_as_the_planes_values() {
        let mut next = crate::kernel::xorshift(0x2545_f491_4f6c_dd1du64);
        let n = NX * NY;
        let mut cells = 0;
        for round in 0..40 {
            let tie_heavy = round % 2 == 1;
            let mut bits = |few: &[u64]| -> Vec<u64> {
                (0..2 * n)
                    .map(|_| {
                        let r = next();
                        if tie_heavy {
                            few[(r % few.len() as u64) as usize]
                        } else {
                            r
                        }
                    })
                    .collect()
            };
            /// The checks for one sample type: `$t` from `u64` bits by `$from`.
            macro_rules! types {
                ($($t:ty, $v:ident, $from:expr, [$($few:expr),*];)*) => {$(
                    let few: Vec<u64> = vec![$(($few).to_bits_u64()),*];
                    let values: Vec<$t> = bits(&few).into_iter().map($from).collect();
                    let (low, high) = values.split_at(n);
                    let as_f64: Vec<f64> = values.iter().map(|&v| v.to_f64()).collect();
                    let (low64, high64) = as_f64.split_at(n);
                    let lent = [Some(LentPlane::$v(low)), Some(LentPlane::$v(high))];
                    cells += check(lent, [low64, high64], stringify!($t));
                    // The same samples, one plane lent and one read.
                    cells += check([lent[0], None], [low64, high64], stringify!($t));
                )*};
            }
            types! {
                u8, U8, |b| b as u8, [0u8, 1u8, 114u8, 255u8];
                i8, I8, |b| b as i8, [i8::MIN, -1i8, 0i8, 36i8, i8::MAX];
                u16, U16, |b| b as u16, [0u16, 1u16, 1600u16, u16::MAX];
                i16, I16, |b| b as i16, [i16::MIN, -1i16, 0i16, 550i16, i16::MAX];
                u32, U32, |b| b as u32, [0u32, 7u32, u32::MAX];
                i32, I32, |b| b as i32, [i32::MIN, 0i32, -5i32, i32::MAX];
                f32, F32, |b| f32::from_bits(b as u32), [0.0f32, -0.0f32, 0.5f32, f32::NAN, f32::INFINITY, f32::MIN];
                f64, F64, f64::from_bits, [0.0f64, -0.0f64, 114.0f64, f64::NAN, f64::NEG_INFINITY, f64::MAX];
            }
            // Planes read as `f64` (no lent plane).
            let read: Vec<f64> = (0..2 * n)
                .map(|_| {
                    let r = next();
                    if tie_heavy {
                        [0.0, -0.0, 1.5, f64::NAN][(r % 4) as usize]
                    } else {
                        f64::from_bits(r)
                    }
                })
                .collect();
            let (low, high) = read.split_at(n);
            cells += check([None, None], [low, high], "read");
        }
        assert_eq!(cells, 40 * (8 * 2 + 1) * (NX - 1) * (NY - 1));
    }

    /// The bits of a sample, as `few` lists them, for `bits` to hand back.
    trait ToBits {
        fn to_bits_u64(self) -> u64;
    }

    /// `ToBits` of integers (their two's complement) and floats (their bits).
    macro_rules! to_bits {
        ($($t:ty => $f:expr;)*) => {$(
            impl ToBits for $t {
                fn to_bits_u64(self) -> u64 {
                    $f(self)
                }
            }
        )*};
    }

    to_bits! {
        u8 => |v: u8| u64::from(v);
        i8 => |v: i8| v as u8 as u64;
        u16 => |v: u16| u64::from(v);
        i16 => |v: i16| v as u16 as u64;
        u32 => |v: u32| u64::from(v);
        i32 => |v: i32| v as u32 as u64;
        f32 => |v: f32| u64::from(v.to_bits());
        f64 => |v: f64| v.to_bits();
    }
}
