//! DICOM: one file (`.dcm`, a single slice or multi-frame), and a series
//! assembled from up to 3 slices split at `@@FILE@@` (a directory of them,
//! and one slice file of the directory, which opens its series).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, split, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    let parts = split(data, b"@@FILE@@", 3);
    if parts.len() == 1 {
        open_and_read(&put(dir.path(), "one.dcm", data), None);
        return;
    }
    let series = dir.path().join("series");
    std::fs::create_dir(&series).expect("series directory");
    let mut first = None;
    for (i, part) in parts.iter().enumerate() {
        let path = put(&series, &format!("s{i}.dcm"), part);
        first.get_or_insert(path);
    }
    open_and_read(&series, None);
    if let Some(first) = first {
        open_and_read(&first, None);
    }
});
