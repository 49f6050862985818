//! Streaming writers: every sink writes exactly the bytes `write_mesh`
//! writes for the same mesh, whatever the threads or slab depth; a `.tmesh`
//! file replays into any sink with the same result; a failure at any point
//! leaves nothing behind; the standalone Python reader agrees with tmc's.

use crate::common;

use common::cli::{names, python_ready, read_tmesh_py_error, read_tmesh_script};
use std::fs;
use std::path::Path;
use std::process::Command;
use tmc::export::{create_sink, replay, write_mesh};
use tmc::meshfile::TmeshReader;
use tmc::{
    extract, extract_to, synth, ArrayVolume, Chunk, Error, ExtractParams, Grid, Mesh, MeshBuilder,
    MeshInfo, PipelineOptions, Result, SampleSource, Totals,
};

const FORMATS: [&str; 4] = ["ply", "obj", "off", "stl"];

fn params(threads: usize, close: bool) -> ExtractParams {
    ExtractParams {
        iso: 0.0,
        close,
        threads,
        ..Default::default()
    }
}

/// Streams the extraction of `source` into the sink for `path`.
fn stream(
    source: &dyn SampleSource,
    path: &Path,
    params: &ExtractParams,
    depth: usize,
) -> Result<tmc::Stats> {
    let mut sink = create_sink(path)?;
    let options = PipelineOptions {
        slab_depth: depth,
        ..Default::default()
    };
    extract_to(source, params, &options, sink.as_mut())
}

/// Reads a whole `.tmesh` file with tmc's reader.
fn read_tmesh(path: &Path) -> Mesh {
    let mut reader = TmeshReader::open(path).unwrap();
    let mut builder = MeshBuilder::default();
    replay(&mut reader, &mut builder).unwrap();
    builder.into_mesh()
}

#[test]
fn sinks_write_the_bytes_of_write_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("noise", synth::noise(24, 3, 1), false),
        ("sphere", synth::sphere(20, 7.0), true),
    ];
    for (name, volume, close) in &cases {
        let (mesh, _) = extract(volume, &params(1, *close)).unwrap();
        assert!(mesh.triangles.len() > 100, "{name}: too small a test");
        for ext in FORMATS {
            let reference = dir.path().join(format!("{name}-reference.{ext}"));
            write_mesh(&reference, &mesh).unwrap();
            let expected = fs::read(&reference).unwrap();
            for (threads, depth) in [(1, 1), (1, 7), (2, 1), (2, 7), (2, 0)] {
                let path = dir.path().join(format!("{name}-{threads}-{depth}.{ext}"));
                let stats = stream(volume, &path, &params(threads, *close), depth).unwrap();
                assert_eq!(stats.triangles as usize, mesh.triangles.len());
                assert!(
                    fs::read(&path).unwrap() == expected,
                    "{name}.{ext}: {threads} threads, slab depth {depth}: bytes differ"
                );
            }
        }
    }
    assert!(names(dir.path()).iter().all(|n| !n.starts_with(".tmc-")));
}

#[test]
fn empty_meshes_stream_like_write_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let volume = synth::sphere(8, 2.0);
    let far = ExtractParams {
        iso: 100.0,
        ..params(2, true)
    };
    for ext in FORMATS {
        let reference = dir.path().join(format!("reference.{ext}"));
        write_mesh(&reference, &Mesh::default()).unwrap();
        let path = dir.path().join(format!("empty.{ext}"));
        stream(&volume, &path, &far, 1).unwrap();
        assert_eq!(fs::read(&path).unwrap(), fs::read(&reference).unwrap());
    }
    let path = dir.path().join("empty.tmesh");
    stream(&volume, &path, &far, 1).unwrap();
    assert_eq!(read_tmesh(&path), Mesh::default());
}

#[test]
fn tmesh_replays_into_every_sink_byte_identically() {
    let dir = tempfile::tempdir().unwrap();
    let volume = synth::noise(24, 3, 1);
    let tmesh = dir.path().join("noise.tmesh");
    let stats = stream(&volume, &tmesh, &params(2, true), 3).unwrap();
    let (mesh, _) = extract(&volume, &params(1, true)).unwrap();
    assert!(read_tmesh(&tmesh) == mesh);
    for ext in FORMATS {
        let reference = dir.path().join(format!("reference.{ext}"));
        write_mesh(&reference, &mesh).unwrap();
        let path = dir.path().join(format!("converted.{ext}"));
        let mut reader = TmeshReader::open(&tmesh).unwrap();
        let mut sink = create_sink(&path).unwrap();
        let totals = replay(&mut reader, sink.as_mut()).unwrap();
        assert_eq!(totals.vertices, stats.vertices);
        assert_eq!(totals.triangles, stats.triangles);
        assert!(
            fs::read(&path).unwrap() == fs::read(&reference).unwrap(),
            "{ext}"
        );
    }
    // .tmesh to .tmesh reproduces the file.
    let copy = dir.path().join("copy.tmesh");
    let mut sink = create_sink(&copy).unwrap();
    replay(&mut TmeshReader::open(&tmesh).unwrap(), sink.as_mut()).unwrap();
    assert!(fs::read(&copy).unwrap() == fs::read(&tmesh).unwrap());
}

/// A volume whose planes from `fail_at` on cannot be read.
struct Failing {
    inner: ArrayVolume,
    fail_at: usize,
}

impl SampleSource for Failing {
    fn grid(&self) -> &Grid {
        self.inner.grid()
    }

    fn read_plane(&self, z: usize, out: &mut [f64]) -> Result<()> {
        if z >= self.fail_at {
            return Err(Error::Format(format!("plane {z}: disk on fire")));
        }
        self.inner.read_plane(z, out)
    }
}

#[test]
fn a_failing_extraction_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let volume = Failing {
        inner: synth::noise(24, 3, 1),
        fail_at: 15,
    };
    for ext in ["ply", "obj", "off", "stl", "tmesh"] {
        for threads in [1, 2] {
            let path = dir.path().join(format!("out.{ext}"));
            let err = stream(&volume, &path, &params(threads, false), 1).unwrap_err();
            assert!(err.to_string().contains("disk on fire"), "{ext}: {err}");
            assert!(
                names(dir.path()).is_empty(),
                "{ext}: {:?}",
                names(dir.path())
            );
        }
        // An existing file is kept as it was.
        let keep = dir.path().join(format!("keep.{ext}"));
        fs::write(&keep, b"old").unwrap();
        assert!(stream(&volume, &keep, &params(2, false), 2).is_err());
        assert_eq!(fs::read(&keep).unwrap(), b"old");
        fs::remove_file(&keep).unwrap();
    }
    // A missing directory fails when the sink is created.
    let err = create_sink(&dir.path().join("no/such/out.ply"))
        .err()
        .expect("missing directory")
        .to_string();
    assert!(err.contains("out.ply"), "{err}");
    assert!(create_sink(&dir.path().join("out.vtk")).is_err());
}

fn info() -> MeshInfo {
    MeshInfo {
        grid: Grid::unit([2, 2, 2]),
        iso: 0.0,
        method: Default::default(),
        inside: Default::default(),
        close: false,
        normals: false,
        labels: false,
    }
}

fn chunk(plane: u64, vertices: usize, triangles: &[[u32; 3]]) -> Chunk {
    Chunk {
        plane,
        vertices: vec![[plane as f32, 0.5, 0.25]; vertices],
        triangles: triangles.to_vec(),
        normals: Vec::new(),
        labels: Vec::new(),
        values: Vec::new(),
        encoded: Vec::new(),
    }
}

#[test]
fn sinks_check_the_numbering_and_commit_nothing_when_it_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    for ext in FORMATS {
        let path = dir.path().join(format!("bad.{ext}"));
        let run = |chunks: &[(u64, Chunk)], totals: Totals| -> Result<()> {
            let mut sink = create_sink(&path)?;
            sink.begin(&info())?;
            for (base, c) in chunks {
                sink.chunk(*base, c)?;
            }
            sink.finish(&totals)
        };
        let totals = |vertices, triangles| Totals {
            vertices,
            triangles,
            chunks: 2,
        };
        // Reaching into the next chunk is fine.
        let good = [
            (0, chunk(0, 3, &[[0, 1, 3], [2, 4, 1]])),
            (3, chunk(1, 2, &[[0, 1, 0]])),
        ];
        run(&good, totals(5, 3)).unwrap();
        assert!(path.is_file());
        fs::remove_file(&path).unwrap();
        // A chunk that does not start where the previous one ended.
        let gap = [(0, chunk(0, 3, &[])), (4, chunk(1, 2, &[]))];
        let err = run(&gap, totals(6, 0)).unwrap_err().to_string();
        assert!(err.contains("starts at vertex 4"), "{ext}: {err}");
        // A triangle beyond the next chunk.
        let far = [
            (0, chunk(0, 3, &[[0, 1, 5]])),
            (3, chunk(1, 2, &[])),
            (5, chunk(2, 2, &[])),
        ];
        let err = run(&far, totals(7, 1)).unwrap_err().to_string();
        assert!(err.contains("beyond the next chunk"), "{ext}: {err}");
        // A triangle of the last chunk beyond the end.
        let last = [(0, chunk(0, 3, &[[0, 1, 3]]))];
        let err = run(&last, totals(3, 1)).unwrap_err().to_string();
        assert!(err.contains("vertex 3"), "{ext}: {err}");
        // Totals that disagree with the chunks.
        let err = run(&good, totals(5, 4)).unwrap_err().to_string();
        assert!(err.contains("totals"), "{ext}: {err}");
        assert!(
            names(dir.path()).is_empty(),
            "{ext}: {:?}",
            names(dir.path())
        );
    }
}

#[test]
fn the_python_reader_agrees_with_tmc() {
    if !python_ready() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tmesh = dir.path().join("noise.tmesh");
    stream(&synth::noise(24, 3, 1), &tmesh, &params(2, true), 4).unwrap();
    let expected = read_tmesh(&tmesh);
    let reader = TmeshReader::open(&tmesh).unwrap();
    assert!(reader.entries().len() > 10);

    let off = dir.path().join("noise.off");
    let out = Command::new("python3")
        .arg(read_tmesh_script())
        .arg(&tmesh)
        .arg("--off")
        .arg(&off)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = format!(
        "{} vertices, {} triangles, {} chunks; grid 24x24x24",
        reader.vertices(),
        reader.triangles(),
        reader.entries().len()
    );
    assert!(stdout.contains(&summary), "{stdout}");
    assert!(stdout.contains("iso 0.0, method tmc, inside high, close True"));
    let mesh = common::parse_off(&fs::read_to_string(&off).unwrap());
    assert_eq!(mesh.vertices.len(), expected.vertices.len());
    assert!(mesh == expected, "the meshes differ");

    // Damage in the payload of chunk 5 is found and located.
    let target = reader.entries()[5];
    let mut bytes = fs::read(&tmesh).unwrap();
    bytes[target.offset as usize + 48 + 10] ^= 0x55;
    fs::write(&tmesh, &bytes).unwrap();
    let stderr = read_tmesh_py_error(&tmesh);
    assert!(
        stderr.contains("chunk 5") && stderr.contains("checksum"),
        "{stderr}"
    );
}

/// A chunk whose zstd frame states a larger size than the chunk's counts
/// (a crafted file: checksums recomputed) is refused by both readers before
/// it is inflated; python-zstandard would allocate the stated size, which
/// its `max_output_size` does not bound.
#[test]
fn a_frame_larger_than_its_counts_is_refused() {
    use common::cli::{assert_one_line, s, tmc};
    let dir = tempfile::tempdir().unwrap();
    let tmesh = dir.path().join("noise.tmesh");
    stream(&synth::noise(24, 3, 1), &tmesh, &params(2, true), 4).unwrap();
    let reader = TmeshReader::open(&tmesh).unwrap();
    let last = reader.entries().len() - 1;
    let e = reader.entries()[last];
    let good = fs::read(&tmesh).unwrap();
    let n = good.len();
    let at = e.offset as usize;
    let index = u64::from_le_bytes(good[n - 32..n - 24].try_into().unwrap()) as usize;
    // The last chunk's payload, replaced by a frame of 1 MiB more zeros.
    let expect = 12 * (e.vertex_count + e.triangle_count) as usize;
    let frame = zstd::bulk::compress(&vec![0u8; expect + (1 << 20)], 1).unwrap();
    let mut bad = good[..at + 48].to_vec();
    bad[at + 4..at + 8].copy_from_slice(&crc32fast::hash(&frame).to_le_bytes());
    bad[at + 32..at + 40].copy_from_slice(&(frame.len() as u64).to_le_bytes());
    let crc = crc32fast::hash(&bad[at..at + 40]);
    bad[at + 40..at + 44].copy_from_slice(&crc.to_le_bytes());
    bad.extend_from_slice(&frame);
    let new_index = bad.len() as u64;
    bad.extend_from_slice(&good[index..]);
    let m = bad.len();
    bad[m - 32..m - 24].copy_from_slice(&new_index.to_le_bytes());
    fs::write(&tmesh, &bad).unwrap();
    let refusal = format!("chunk {last} (plane {}", e.plane);
    let line = assert_one_line(&tmc(&["check", s(&tmesh)]), 1);
    assert!(
        line.contains(&refusal) && line.contains("payload frame size disagrees with the counts"),
        "{line}"
    );
    if !python_ready() {
        return;
    }
    let stderr = read_tmesh_py_error(&tmesh);
    assert!(
        stderr.contains(&refusal)
            && stderr.contains("payload frame size disagrees with the counts"),
        "{stderr}"
    );
}
