//! Raw samples: the first 22 bytes choose the options (dims as three
//! little-endian u32, sample type, byte order, header bytes as a u64), the
//! rest is the file. Huge dims against a small file must be an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc::volume::{Endian, RawOptions, ScalarType};
use tmc_fuzz::{open_and_read, put, temp_dir};

fuzz_target!(|data: &[u8]| {
    if data.len() < 22 {
        return;
    }
    let u32_at = |i: usize| u32::from_le_bytes(data[i..i + 4].try_into().unwrap()) as usize;
    let options = RawOptions {
        dims: [u32_at(0), u32_at(4), u32_at(8)],
        scalar: ScalarType::ALL[usize::from(data[12]) % ScalarType::ALL.len()],
        endian: if data[13] & 1 == 0 {
            Endian::Little
        } else {
            Endian::Big
        },
        header_bytes: u64::from_le_bytes(data[14..22].try_into().unwrap()),
        spacing: [1.0; 3],
        origin: [0.0; 3],
    };
    let dir = temp_dir();
    open_and_read(&put(dir.path(), "v.raw", &data[22..]), Some(&options));
});
