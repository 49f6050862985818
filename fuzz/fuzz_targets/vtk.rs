//! Legacy VTK `STRUCTURED_POINTS` (ASCII and binary): the input as one file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc_fuzz::{open_and_read, put, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    open_and_read(&put(dir.path(), "v.vtk", data), None);
});
