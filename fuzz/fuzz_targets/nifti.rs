//! NIfTI-1/2: the input as `.nii`, as `.nii.gz` (the gzip reader on raw
//! fuzz bytes, and on the input gzip-compressed) and as a `.hdr` with the
//! same bytes as its `.img`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    open_and_read(&put(dir.path(), "v.nii", data), None);
    open_and_read(&put(dir.path(), "g.nii.gz", data), None);
    put(dir.path(), "p.img", data);
    open_and_read(&put(dir.path(), "p.hdr", data), None);
});
