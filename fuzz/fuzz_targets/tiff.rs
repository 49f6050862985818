//! TIFF: the input as one (multi-page) `.tif`, and, split at `@@FILE@@`,
//! a directory of up to 3 single-page TIFFs.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, split, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    let parts = split(data, b"@@FILE@@", 3);
    if parts.len() == 1 {
        open_and_read(&put(dir.path(), "v.tif", data), None);
        return;
    }
    let stack = dir.path().join("stack");
    std::fs::create_dir(&stack).expect("stack directory");
    for (i, part) in parts.iter().enumerate() {
        put(&stack, &format!("s{i}.tif"), part);
    }
    open_and_read(&stack, None);
});
