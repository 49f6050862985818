//! `.tmesh`: the chunk reader (every chunk), the checker's reader
//! (`tmc check`) and the replay into a PLY file (`tmc convert`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tmc::meshfile::TmeshReader;
use tmc_fuzz::{put, temp_dir};

fuzz_target!(|data: &[u8]| {
    let dir = temp_dir();
    let path = put(dir.path(), "m.tmesh", data);
    if let Ok(mut reader) = TmeshReader::open(&path) {
        let _ = (reader.info(), reader.vertices(), reader.triangles());
        for i in 0..reader.entries().len() {
            let _ = reader.chunk(i);
        }
    }
    if let Ok(mesh) = tmc::check::read_mesh(&path) {
        let _ = tmc::check::check_mesh(&mesh);
    }
    if let Ok(mut reader) = TmeshReader::open(&path) {
        if let Ok(mut sink) = tmc::export::create_sink(&dir.path().join("out.ply")) {
            let _ = tmc::export::replay(&mut reader, sink.as_mut());
        }
    }
});
