//! NRRD: attached header and data (`.nrrd`), or a detached header (`.nhdr`)
//! and its data files. The input is split at `@@FILE@@` lines: the first
//! part is the header, the others are written as `d0.raw`, `d1.raw`, ...
//! (and `d0.raw.gz` ... for gzip); with one part it is an attached `.nrrd`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, split, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    let parts = split(data, b"\n@@FILE@@\n", 5);
    if parts.len() == 1 {
        open_and_read(&put(dir.path(), "v.nrrd", data), None);
        return;
    }
    for (i, part) in parts[1..].iter().enumerate() {
        put(dir.path(), &format!("d{i}.raw"), part);
        put(dir.path(), &format!("d{i}.raw.gz"), part);
    }
    open_and_read(&put(dir.path(), "v.nhdr", parts[0]), None);
});
