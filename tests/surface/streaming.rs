//! The streaming pipeline gives byte-identical `.tmesh` files for every
//! thread count and slab depth, equal to the in-memory mesh, on random
//! volumes and on the real volumes of `../shared/data` (skipped, with a
//! message, when absent).

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::{Path, PathBuf};
use tmc::check::check_mesh;
use tmc::meshfile::{TmeshReader, TmeshWriter};
use tmc::{
    extract, extract_to, ArrayVolume, ExtractParams, Grid, MeshBuilder, MeshSink, PipelineOptions,
    SampleSource, Totals,
};

/// Writes `.tmesh` for every (threads, depth) and checks the bytes agree;
/// returns them.
fn same_bytes_everywhere(source: &dyn SampleSource, iso: f64, dir: &Path) -> Vec<u8> {
    let mut first: Option<Vec<u8>> = None;
    for threads in [1, 2, 3] {
        for depth in [1, 2, 7, 64] {
            let path = dir.join(format!("t{threads}-d{depth}.tmesh"));
            let params = ExtractParams {
                iso,
                close: true,
                threads,
                ..Default::default()
            };
            let options = PipelineOptions {
                slab_depth: depth,
                ..Default::default()
            };
            let mut writer = TmeshWriter::create(&path).expect("create");
            extract_to(source, &params, &options, &mut writer).expect("extract");
            let bytes = std::fs::read(&path).expect("read");
            match &first {
                None => first = Some(bytes),
                Some(b) => assert!(*b == bytes, "{threads} threads, depth {depth} differ"),
            }
        }
    }
    first.expect("at least one run")
}

/// The mesh in a `.tmesh` file.
fn read_back(path: &Path) -> tmc::Mesh {
    let mut reader = TmeshReader::open(path).expect("open");
    let mut builder = MeshBuilder::default();
    for i in 0..reader.entries().len() {
        let base = reader.entries()[i].vertex_base;
        let chunk = reader.chunk(i).expect("chunk");
        builder.chunk(base, &chunk).expect("chunk");
    }
    builder.finish(&Totals::default()).expect("finish");
    builder.into_mesh()
}

fn check_source(source: &dyn SampleSource, iso: f64, name: &str) {
    let dir = tempfile::tempdir().expect("tempdir");
    let bytes = same_bytes_everywhere(source, iso, dir.path());
    let path = dir.path().join("check.tmesh");
    std::fs::write(&path, &bytes).expect("write");
    let streamed = read_back(&path);
    let params = ExtractParams {
        iso,
        close: true,
        ..Default::default()
    };
    let (in_memory, _) = extract(source, &params).expect("in memory");
    assert!(
        streamed == in_memory,
        "{name}: streamed mesh differs from the in-memory one"
    );
    let report = check_mesh(&streamed);
    assert!(report.is_closed_manifold(), "{name}: {report:?}");
}

#[test]
fn random_volumes_stream_identically() {
    let mut rng = Pcg64::seed_from_u64(31);
    for trial in 0..12 {
        let dims = [
            rng.gen_range(2..20),
            rng.gen_range(2..20),
            rng.gen_range(2..40),
        ];
        let len = dims.iter().product();
        let values: Vec<f64> = (0..len)
            .map(|_| {
                if trial % 2 == 0 {
                    rng.gen_range(0..4) as f64
                } else {
                    rng.gen_range(-1.0..1.0)
                }
            })
            .collect();
        let iso = if trial % 2 == 0 { 1.0 } else { 0.0 };
        let vol = ArrayVolume::new(Grid::unit(dims), values).expect("volume");
        check_source(&vol, iso, &format!("random {dims:?}"));
    }
}

#[test]
fn real_volumes_stream_identically() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if !dir.is_dir() {
        eprintln!("skipped: {} not found", dir.display());
        return;
    }
    for (file, iso) in [
        ("headsq_quarter.nrrd", 500.0),
        ("neghip.nrrd", 60.0),
        ("carotid.nrrd", 100.0),
        ("hydrogen.nrrd", 0.01),
        ("bolt.nrrd", 127.5),
        ("mayavi_heart.nrrd", 100.0),
    ] {
        let vol = tmc::volume::open(&dir.join(file), None).expect(file);
        check_source(vol.as_ref(), iso, file);
    }
}
