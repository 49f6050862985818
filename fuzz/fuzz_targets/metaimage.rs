//! MetaImage: the input as `.mha` (data inline or `ElementDataFile` next to
//! it), or, split at a `@@FILE@@` line, an `.mhd` header and data files
//! `d0.raw`, `d1.raw`, ... (also as `d0.raw.gz`, `d0.zraw`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, split, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    let parts = split(data, b"\n@@FILE@@\n", 5);
    if parts.len() == 1 {
        open_and_read(&put(dir.path(), "v.mha", data), None);
        return;
    }
    for (i, part) in parts[1..].iter().enumerate() {
        put(dir.path(), &format!("d{i}.raw"), part);
        put(dir.path(), &format!("d{i}.zraw"), part);
    }
    open_and_read(&put(dir.path(), "v.mhd", parts[0]), None);
});
