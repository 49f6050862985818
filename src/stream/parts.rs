//! Which cell layers part `i` of `n` holds, for split runs (`--part I/N`).
//!
//! The pass extracts only these layers of a part, and `tmc merge` checks its
//! parts against the same ranges, so both import this one definition.

use crate::{Error, Result};
use std::ops::Range;

/// The cell layers of part `index` of `count` among `layers`, balanced by
/// layer count. Parts beyond the number of layers are empty (and valid).
pub fn layer_range(layers: usize, index: usize, count: usize) -> Result<Range<usize>> {
    if index == 0 || index > count {
        return Err(Error::Invalid(format!(
            "part {index}/{count} does not exist; parts are numbered 1 to {count}"
        )));
    }
    let at = |k: usize| (k as u128 * layers as u128 / count as u128) as usize;
    Ok(at(index - 1)..at(index))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_tile_the_layers() {
        for layers in [1, 2, 5, 63, 64] {
            for n in [1, 2, 3, 7, 100] {
                let mut end = 0;
                for i in 1..=n {
                    let r = layer_range(layers, i, n).unwrap();
                    assert_eq!(r.start, end);
                    end = r.end;
                }
                assert_eq!(end, layers);
            }
        }
        assert!(layer_range(5, 0, 3).is_err());
    }
}
