//! Inputs whose stated dims are absurd (a Zarr store's metadata can state
//! any shape; its chunks may all be missing): one error line, never an
//! abort on an allocation of the size stated.

use crate::common;

use common::cli::{assert_one_line, s, tmc};

/// A Zarr v2 store of `shape`, every chunk missing (read as the fill value).
fn zarr(dir: &std::path::Path, shape: &str) -> std::path::PathBuf {
    let store = dir.join("huge.zarr");
    std::fs::create_dir(&store).unwrap();
    let meta = format!(
        r#"{{"zarr_format":2,"shape":{shape},"chunks":[2,2,2],"dtype":"<f4","compressor":null,"fill_value":0,"order":"C","filters":null}}"#
    );
    std::fs::write(store.join(".zarray"), meta).unwrap();
    store
}

#[test]
fn dims_whose_sample_count_overflows_are_refused_in_one_line() {
    for shape in [
        "[4294967296,4294967296,4294967296]",
        "[18446744073709551615,2,2]",
        "[2,2305843009213693952,2305843009213693952]",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let store = zarr(dir.path(), shape);
        let out = dir.path().join("m.ply");
        for args in [
            vec!["info", s(&store)],
            vec!["extract", s(&store), "--iso", "0.5", "-o", s(&out)],
        ] {
            let err = assert_one_line(&common::cli::tmc_within(&args, 60), 1);
            assert!(err.contains("too large"), "{shape} {args:?}: {err}");
        }
        assert!(!out.exists());
    }
    // A store that is large but countable is described, not refused.
    let dir = tempfile::tempdir().unwrap();
    let store = zarr(dir.path(), "[3,4,5]");
    assert!(tmc(&["info", s(&store)]).status.success());
}
