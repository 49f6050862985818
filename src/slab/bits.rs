//! Inside bits of a plane, 64 samples to a word.
//!
//! Most cells and edges of a volume see no sign change. With one bit per
//! sample, a word operation tells for 64 edges or cells at once whether any
//! of them is crossed, so uniform runs cost next to nothing and only crossed
//! edges and cells are visited (Flying Edges trims each row to its crossed
//! span; bits skip every uniform run, not only the ends).

/// One bit per sample (`1` = inside), row by row; each row is padded with
/// one all-zero word, so the "next sample" of a row's last word is defined.
#[derive(Debug)]
pub(super) struct SignBits {
    /// Words per row, padding included.
    words: usize,
    bits: Vec<u64>,
}

impl SignBits {
    /// All-zero bits for `ny` rows of `nx` samples.
    pub(super) fn new(nx: usize, ny: usize) -> Self {
        let words = nx.div_ceil(64) + 1;
        SignBits {
            words,
            bits: vec![0; words * ny],
        }
    }

    /// Words per row, padding included (the last word of a row is zero).
    pub(super) fn words(&self) -> usize {
        self.words
    }

    /// Row `y`, padding word included.
    pub(super) fn row(&self, y: usize) -> &[u64] {
        &self.bits[y * self.words..(y + 1) * self.words]
    }

    /// Row `y` to fill; bits beyond the row's samples must stay zero.
    pub(super) fn row_mut(&mut self, y: usize) -> &mut [u64] {
        &mut self.bits[y * self.words..(y + 1) * self.words]
    }
}

/// Word `k` of `row` shifted by one sample: its bit `j` is the bit of sample
/// `64 k + j + 1`.
#[inline]
pub(super) fn next(row: &[u64], k: usize) -> u64 {
    (row[k] >> 1) | (row[k + 1] << 63)
}

/// Bits of the positions `x < len` within word `k`.
#[inline]
pub(super) fn below(len: usize, k: usize) -> u64 {
    match len.saturating_sub(64 * k) {
        0 => 0,
        n if n >= 64 => u64::MAX,
        n => (1u64 << n) - 1,
    }
}

/// Calls `f(x)` for every set bit of word `k`, in increasing `x`.
#[inline]
pub(super) fn each_bit<E>(
    mut word: u64,
    k: usize,
    mut f: impl FnMut(usize) -> Result<(), E>,
) -> Result<(), E> {
    while word != 0 {
        f(64 * k + word.trailing_zeros() as usize)?;
        word &= word - 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_shifts_across_words_and_below_masks() {
        let mut s = SignBits::new(130, 1);
        assert_eq!(s.words(), 4);
        let row = s.row_mut(0);
        row[0] = 1 << 63;
        row[1] = 1 | 1 << 5;
        row[2] = 1 << 1; // sample 129, the last
        let row = s.row(0);
        assert_eq!(next(row, 0), 1 << 62 | 1 << 63);
        assert_eq!(next(row, 1), 1 << 4);
        assert_eq!(next(row, 2), 1);
        assert_eq!(below(130, 0), u64::MAX);
        assert_eq!(below(130, 2), 0b11);
        assert_eq!(below(130, 3), 0);
        let mut seen = Vec::new();
        each_bit::<()>(row[1], 1, |x| {
            seen.push(x);
            Ok(())
        })
        .unwrap();
        assert_eq!(seen, [64, 69]);
    }
}
