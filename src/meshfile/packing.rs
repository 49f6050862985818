//! How a version 3 `.tmesh` payload lays out its numbers before zstd
//! sees them: a reversible rearrangement that makes meshes compress
//! smaller and, above all, faster.
//!
//! zstd looks for repeated byte strings; the raw little-endian numbers of
//! a mesh have few (a vertex's `f32` coordinates differ from the last
//! vertex's in their low bytes, a triangle's indices grow by small steps),
//! so zstd spent three quarters of a `.tmesh` extraction's instructions
//! finding little. Here each array of 4-byte numbers becomes
//!
//! * **deltas**: an `f32` array of triples (the positions) keeps the
//!   first triple and then each component's bits XOR the same component
//!   of the triple before (neighbouring vertices share sign, exponent and
//!   leading mantissa bits, which XOR to zero); a `u32` array (triangle
//!   indices, labels) keeps each number's difference from the one before,
//!   wrapping, zig-zag coded so that small steps back are small numbers;
//! * **byte planes**: the lowest byte of every number, then every second
//!   byte, then every third, then every highest byte, so that the zero
//!   high bytes of the deltas form long runs.
//!
//! Normals are stored as they are: on a label map they take a few
//! directions, whose repeated 12-byte triples zstd finds (the frog's
//! compressed to 1.65 MB as they are, 4.18 MB packed), and on a CT they
//! hardly compress either way (cthead: 2.88 MB as they are, 2.76 MB
//! packed, of 3.12 MB).
//!
//! Both steps are plain integer operations on the bits, so a packed array
//! unpacks to exactly the numbers it came from (NaN payloads and `-0.0`
//! included), and the packed bytes depend only on the numbers: the files
//! stay byte for byte the same for any threads, slabs and parts.
//! Hand-written: it is a few loops, and no crate on crates.io offers
//! this pairing of XOR/zig-zag deltas with byte planes as a small, kept
//! dependency.

/// Appends the packed form of `triples` (the positions, as their bits):
/// the first triple's bits, then each component XOR the same component of
/// the triple before, as four byte planes.
pub fn pack_triples(out: &mut Vec<u8>, triples: &[[f32; 3]]) {
    let bits: &[u32] = bytemuck::cast_slice(triples.as_flattened());
    let first = bits.len().min(3);
    let mut words = Vec::with_capacity(bits.len());
    words.extend_from_slice(&bits[..first]);
    words.extend(
        bits[first..]
            .iter()
            .zip(bits)
            .map(|(now, before)| now ^ before),
    );
    put_planes(out, &words);
}

/// Appends the packed form of `numbers` (triangle indices or labels): each
/// number's wrapping difference from the one before (the first from 0),
/// zig-zag coded, as four byte planes.
pub fn pack_numbers(out: &mut Vec<u8>, numbers: &[u32]) {
    let zig_zag = |step: u32| (step << 1) ^ ((step as i32) >> 31) as u32;
    let mut words = Vec::with_capacity(numbers.len());
    words.extend(numbers.first().map(|&n| zig_zag(n)));
    if let Some(rest) = numbers.get(1..) {
        words.extend(
            rest.iter()
                .zip(numbers)
                .map(|(&now, &before)| zig_zag(now.wrapping_sub(before))),
        );
    }
    put_planes(out, &words);
}

/// Appends `floats` as they are (little-endian), for the normals.
pub fn put_as_is(out: &mut Vec<u8>, floats: &[f32]) {
    if cfg!(target_endian = "little") {
        // In memory they are the bytes the file wants: one copy.
        out.extend_from_slice(bytemuck::cast_slice(floats));
    } else {
        out.extend(floats.iter().flat_map(|f| f.to_le_bytes()));
    }
}

/// The triples [`pack_triples`] packed into `packed` (`3 * 4 * n` bytes).
pub fn unpack_triples(packed: &[u8]) -> Vec<[f32; 3]> {
    let mut last = [0u32; 3];
    let words = planes_to_words(packed);
    words
        .chunks_exact(3)
        .map(|d| {
            last = [d[0] ^ last[0], d[1] ^ last[1], d[2] ^ last[2]];
            last.map(f32::from_bits)
        })
        .collect()
}

/// The numbers [`pack_numbers`] packed into `packed` (`4 * n` bytes).
pub fn unpack_numbers(packed: &[u8]) -> Vec<u32> {
    let mut last = 0u32;
    planes_to_words(packed)
        .into_iter()
        .map(|z| {
            let step = (z >> 1) ^ (z & 1).wrapping_neg();
            last = last.wrapping_add(step);
            last
        })
        .collect()
}

/// Appends `words` as four byte planes: every word's lowest byte first,
/// its highest byte last (a pass per plane, which the compiler
/// vectorises).
fn put_planes(out: &mut Vec<u8>, words: &[u32]) {
    out.reserve(4 * words.len());
    for shift in [0, 8, 16, 24] {
        out.extend(words.iter().map(|w| (w >> shift) as u8));
    }
}

/// The words whose four byte planes `packed` holds (its length a multiple
/// of 4: the reader checks the counts before).
fn planes_to_words(packed: &[u8]) -> Vec<u32> {
    let n = packed.len() / 4;
    let (b0, rest) = packed.split_at(n);
    let (b1, rest) = rest.split_at(n);
    let (b2, b3) = rest.split_at(n);
    b0.iter()
        .zip(b1)
        .zip(b2)
        .zip(&b3[..n])
        .map(|(((&x0, &x1), &x2), &x3)| u32::from_le_bytes([x0, x1, x2, x3]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn triples_unpack_to_their_bits() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        for n in [0, 1, 2, 7, 1000] {
            let triples: Vec<[f32; 3]> = (0..n)
                .map(|_| {
                    [0; 3].map(|_| match rng.gen_range(0..4) {
                        0 => f32::from_bits(rng.gen()),
                        1 => -0.0,
                        _ => rng.gen_range(-1e3..1e3),
                    })
                })
                .collect();
            let mut packed = Vec::new();
            pack_triples(&mut packed, &triples);
            assert_eq!(packed.len(), 12 * n);
            let back = unpack_triples(&packed);
            let bits = |v: &[[f32; 3]]| v.iter().flatten().map(|c| c.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&back), bits(&triples));
        }
    }

    #[test]
    fn numbers_unpack_to_themselves() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(4);
        for n in [0, 1, 2, 9, 5000] {
            let numbers: Vec<u32> = (0..n)
                .map(|i| match rng.gen_range(0..3) {
                    0 => rng.gen(),
                    1 => u32::MAX - i,
                    _ => rng.gen_range(0..64),
                })
                .collect();
            let mut packed = vec![7u8];
            pack_numbers(&mut packed, &numbers);
            assert_eq!(packed.len(), 1 + 4 * n as usize);
            assert_eq!(unpack_numbers(&packed[1..]), numbers);
        }
    }

    #[test]
    fn small_steps_leave_high_planes_zero() {
        // Indices that step by a few, forward and back, pack to zero in
        // their three upper planes: what makes them compress.
        let numbers: Vec<u32> = (0..300u32).map(|i| 1000 + i / 2 - (i % 3)).collect();
        let mut packed = Vec::new();
        pack_numbers(&mut packed, &numbers);
        // The first number steps from 0 by 1000: its second byte is set.
        assert!(packed[300 + 1..].iter().all(|&b| b == 0));
        assert_eq!(packed[300], (2000u32 >> 8) as u8);
    }
}
