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

/// Collects the chunks' per-vertex values and vertices, in stream order.
#[derive(Default)]
struct ValuesOf {
    vertices: Vec<[f32; 3]>,
    values: Vec<f32>,
}

impl MeshSink for ValuesOf {
    fn begin(&mut self, _info: &tmc::MeshInfo) -> tmc::Result<()> {
        Ok(())
    }

    fn chunk(&mut self, _base: u64, chunk: &tmc::Chunk) -> tmc::Result<()> {
        assert_eq!(
            chunk.values.len(),
            chunk.vertices.len(),
            "a value per vertex"
        );
        self.vertices.extend_from_slice(&chunk.vertices);
        self.values.extend_from_slice(&chunk.values);
        Ok(())
    }

    fn finish(&mut self, _totals: &Totals) -> tmc::Result<()> {
        Ok(())
    }
}

/// `PipelineOptions::vertex_values` gives every chunk one value per vertex,
/// computed from that vertex (here: x + 2y + 3z), for every thread count
/// and slab depth; the chunks' vertices are the mesh's, in order.
#[test]
fn vertex_values_come_with_every_chunk() {
    let mut rng = Pcg64::seed_from_u64(7);
    let dims = [13, 11, 29];
    let values: Vec<f64> = (0..dims.iter().product::<usize>())
        .map(|_| rng.gen_range(-1.0..1.0))
        .collect();
    let vol = ArrayVolume::new(Grid::unit(dims), values).expect("volume");
    let whole = extract(&vol, &ExtractParams::default()).expect("extract").0;
    let weigh = |vertices: &[[f32; 3]], out: &mut Vec<f32>| {
        out.extend(vertices.iter().map(|v| v[0] + 2.0 * v[1] + 3.0 * v[2]));
    };
    for threads in [1, 2, 3] {
        for depth in [1, 2, 7, 64] {
            let params = ExtractParams {
                threads,
                ..Default::default()
            };
            let options = PipelineOptions {
                slab_depth: depth,
                vertex_values: Some(&weigh),
                ..Default::default()
            };
            let mut sink = ValuesOf::default();
            extract_to(&vol, &params, &options, &mut sink).expect("extract");
            assert_eq!(
                sink.vertices, whole.vertices,
                "{threads} threads, depth {depth}"
            );
            let expected: Vec<f32> = whole
                .vertices
                .iter()
                .map(|v| v[0] + 2.0 * v[1] + 3.0 * v[2])
                .collect();
            assert_eq!(sink.values, expected, "{threads} threads, depth {depth}");
        }
    }
}
