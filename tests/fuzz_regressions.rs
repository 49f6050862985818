//! Inputs the fuzzers (`scripts/fuzz`, `fuzz/`) found to crash a reader,
//! kept in `tests/data/fuzz/`: each must now give one clear error line.

mod common;

use common::formats::{data_dir, open_err};

/// A TIFF tag claiming 2^31 values in a 3 KB file made the decoder reserve
/// 32 GiB (the reader had lifted the decoder's limits) and abort.
#[test]
fn tiff_tag_with_a_huge_count_is_an_error() {
    let e = open_err(&data_dir().join("fuzz/tiff_huge_tag_count.tif"));
    assert!(e.contains("tiff_huge_tag_count.tif"), "{e}");
}
