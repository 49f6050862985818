//! `tmc extract --labels` on the command line: how its arguments are read
//! (negative labels), each checked against a run whose meaning is not in
//! doubt.

use crate::common;

use common::cli::{names, s};
use common::labels::{ok, write};
use std::fs;
use std::path::Path;
use tmc::volume::ScalarType;

/// A 6x6x6 map of labels -5 (a 2x2x2 block), 7 (one sample) and 0.
fn negative_map(dir: &Path) -> std::path::PathBuf {
    let dims = [6, 6, 6];
    let mut values = vec![0.0; 216];
    for z in 2..4 {
        for y in 2..4 {
            for x in 2..4 {
                values[x + 6 * (y + 6 * z)] = -5.0;
            }
        }
    }
    values[1 + 6 * (1 + 6 * 4)] = 7.0;
    let input = dir.join("map.nrrd");
    write(&input, dims, values, ScalarType::I16);
    input
}

#[test]
fn a_list_may_start_with_a_negative_label() {
    let dir = tempfile::tempdir().unwrap();
    let input = negative_map(dir.path());
    let spaced = dir.path().join("spaced");
    let joined = dir.path().join("joined");
    fs::create_dir(&spaced).unwrap();
    fs::create_dir(&joined).unwrap();
    // `--labels -5,7` as `--iso -500,500` and `--background -5` are read;
    // `--labels=-5,7` is the form no parser can take for an option.
    ok(&[
        "extract",
        s(&input),
        "--labels",
        "-5,7",
        "-o",
        s(&spaced.join("{label}.ply")),
        "-q",
    ]);
    ok(&[
        "extract",
        s(&input),
        "--labels=-5,7",
        "-o",
        s(&joined.join("{label}.ply")),
        "-q",
    ]);
    assert_eq!(names(&spaced), ["-5.ply", "7.ply"]);
    for name in ["-5.ply", "7.ply"] {
        let a = fs::read(spaced.join(name)).unwrap();
        assert_eq!(a, fs::read(joined.join(name)).unwrap(), "{name}");
    }
}
