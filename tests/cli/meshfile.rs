//! `.tmesh` round trips: what the pipeline streams into the file reads back
//! as the same mesh, the bytes do not depend on threads or slab depth, and
//! damage is detected and located.

use crate::common;

use tmc::meshfile::{TmeshReader, TmeshWriter};
use tmc::{
    extract, extract_to, synth, ExtractParams, MeshBuilder, MeshSink, PipelineOptions, Totals,
};

fn params(threads: usize) -> ExtractParams {
    ExtractParams {
        iso: 0.0,
        close: true,
        threads,
        ..Default::default()
    }
}

fn write(path: &std::path::Path, threads: usize, depth: usize) -> tmc::Stats {
    let vol = synth::noise(30, 12, 1);
    let mut writer = TmeshWriter::create(path).expect("create");
    let options = PipelineOptions {
        slab_depth: depth,
        ..Default::default()
    };
    extract_to(&vol, &params(threads), &options, &mut writer).expect("extract")
}

fn read_all(path: &std::path::Path) -> tmc::Mesh {
    let mut reader = TmeshReader::open(path).expect("open");
    let mut builder = MeshBuilder::default();
    let entries = reader.entries().to_vec();
    for (i, e) in entries.iter().enumerate() {
        let chunk = reader.chunk(i).expect("chunk");
        builder.chunk(e.vertex_base, &chunk).expect("build");
    }
    builder.finish(&Totals::default()).expect("finish");
    builder.into_mesh()
}

#[test]
fn round_trip_and_determinism() {
    let dir = tempfile::tempdir().expect("tempdir");
    let first = dir.path().join("a.tmesh");
    let stats = write(&first, 1, 0);
    let mesh = read_all(&first);
    let (expected, _) = extract(&synth::noise(30, 12, 1), &params(1)).expect("in memory");
    assert!(mesh == expected);
    assert_eq!(stats.triangles as usize, mesh.triangles.len());
    let reader = TmeshReader::open(&first).expect("open");
    assert_eq!(reader.vertices() as usize, mesh.vertices.len());
    assert_eq!(reader.info().iso, 0.0);
    assert!(reader.info().close);
    let bytes = std::fs::read(&first).expect("read");
    for (threads, depth) in [(2, 1), (3, 7), (2, 64)] {
        let other = dir.path().join(format!("b{threads}-{depth}.tmesh"));
        write(&other, threads, depth);
        assert!(
            std::fs::read(&other).expect("read") == bytes,
            "{threads} threads, depth {depth}"
        );
    }
}

/// Passes chunks on to a `.tmesh` writer but hides its encoder, so that the
/// writer compresses every chunk itself, on the thread that feeds it.
struct EncodeHere(TmeshWriter);

impl MeshSink for EncodeHere {
    fn begin(&mut self, info: &tmc::MeshInfo) -> tmc::Result<()> {
        self.0.begin(info)
    }

    fn chunk(&mut self, base: u64, chunk: &tmc::Chunk) -> tmc::Result<()> {
        assert!(
            chunk.encoded.is_empty(),
            "encoded for a sink without encoder"
        );
        self.0.chunk(base, chunk)
    }

    fn finish(&mut self, totals: &Totals) -> tmc::Result<()> {
        self.0.finish(totals)
    }
}

/// The pass compresses `.tmesh` chunks on its workers (`MeshSink::encoder`):
/// the file is byte for byte what the writer makes compressing each chunk
/// itself, for any threads and slab depth, with normals too, where the
/// vertices on plateaus and ties get theirs from the triangles after the
/// workers are done (`FillPending`), and for a part.
#[test]
fn chunks_compressed_on_the_workers_are_the_writers_bytes() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Noise in steps of 1/4: many samples at the isovalue 0, whose vertices
    // lie on plateaus, and a NaN border (--close) whose gradient vanishes.
    let noise = synth::noise(24, 5, 1);
    let steps: Vec<f64> = noise
        .data()
        .iter()
        .map(|v| (v * 4.0).round() / 4.0)
        .collect();
    let grid = *tmc::volume::SampleSource::grid(&noise);
    let vol = tmc::volume::ArrayVolume::new(grid, steps).expect("volume");
    for normals in [false, true] {
        let mut expected = None;
        for (threads, depth, part) in [
            (1, 0, None),
            (2, 1, None),
            (3, 5, None),
            (2, 3, Some((2, 3))),
        ] {
            let p = ExtractParams {
                normals,
                ..params(threads)
            };
            let options = PipelineOptions {
                slab_depth: depth,
                ..Default::default()
            };
            let run = |sink: &mut dyn MeshSink| {
                tmc::stream::extract_part_to(&vol, &p, &options, part, sink).expect("extract")
            };
            let here = dir.path().join("here.tmesh");
            run(&mut EncodeHere(TmeshWriter::create(&here).expect("create")));
            let workers = dir.path().join("workers.tmesh");
            run(&mut TmeshWriter::create(&workers).expect("create"));
            let bytes = std::fs::read(&workers).expect("read");
            let case =
                format!("normals {normals}, {threads} threads, depth {depth}, part {part:?}");
            assert!(std::fs::read(&here).expect("read") == bytes, "{case}");
            if part.is_none() {
                match &expected {
                    None => expected = Some(bytes),
                    Some(first) => assert!(*first == bytes, "{case}"),
                }
            }
        }
    }
}

/// The writer holds up to 1 MiB before it writes: a file of many MiB,
/// with chunks larger than that and thousands of small ones, reads back as
/// the mesh made in memory.
#[test]
fn large_and_many_chunks_round_trip() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cases = [
        (
            "noise",
            tmc::volume::ArrayVolume::from_fn([220, 220, 3], |x, y, z| {
                let h = ((x * 73_856_093) ^ (y * 19_349_663) ^ (z * 83_492_791)) % 1_000_003;
                h as f64 / 1_000_003.0 - 0.5
            }),
        ),
        (
            "tall",
            tmc::volume::ArrayVolume::from_fn([3, 2, 4000], |x, y, z| {
                ((x * 7 + y * 13 + z * 29) % 11) as f64 - 5.0
            }),
        ),
    ];
    for (name, vol) in cases {
        let path = dir.path().join(format!("{name}.tmesh"));
        let mut writer = TmeshWriter::create(&path).expect("create");
        let p = params(2);
        extract_to(&vol, &p, &PipelineOptions::default(), &mut writer).expect("extract");
        let (expected, _) = extract(&vol, &p).expect("in memory");
        assert!(read_all(&path) == expected, "{name}");
        let reader = TmeshReader::open(&path).expect("open");
        let offsets: Vec<u64> = reader.entries().iter().map(|e| e.offset).collect();
        let largest = offsets.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0);
        match name {
            "noise" => assert!(largest > 1 << 20, "{name}: largest chunk {largest} bytes"),
            _ => assert!(offsets.len() > 3000, "{name}: {} chunks", offsets.len()),
        }
    }
}

#[test]
fn damage_is_detected_and_located() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.tmesh");
    write(&path, 1, 0);
    let good = std::fs::read(&path).expect("read");
    let reader = TmeshReader::open(&path).expect("open");
    let target = reader.entries()[3];
    // Flip a byte inside the payload of chunk 3.
    let mut bad = good.clone();
    bad[target.offset as usize + 60] ^= 0x55;
    std::fs::write(&path, &bad).expect("write");
    let mut reader = TmeshReader::open(&path).expect("index intact");
    let err = reader.chunk(3).expect_err("damage").to_string();
    assert!(err.contains("chunk 3") && err.contains("checksum"), "{err}");
    // A truncated file has no end marker.
    std::fs::write(&path, &good[..good.len() - 10]).expect("write");
    let err = TmeshReader::open(&path)
        .err()
        .expect("truncated")
        .to_string();
    assert!(err.contains("truncated"), "{err}");
    // Not a mesh file at all.
    std::fs::write(&path, vec![7u8; 500]).expect("write");
    assert!(TmeshReader::open(&path).is_err());
}

/// A chunk header (checksum recomputed, so only the bounds can catch it)
/// claiming a payload far past the chunk's room: the last chunk (bounded
/// by the index offset) and a size whose sum with the offset overflows.
/// `tmc check` and `tmc convert` give one line naming the chunk, no panic,
/// no huge allocation, nothing at the output path; so does
/// `scripts/read_tmesh.py` (when python3 has numpy and zstandard), which
/// asked Python for that many bytes.
#[test]
fn a_chunk_size_past_its_room_is_a_clean_error() {
    use common::cli::{assert_one_line, python_ready, read_tmesh_py_error, s, tmc};
    let python = python_ready();
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.tmesh");
    write(&path, 1, 0);
    let good = std::fs::read(&path).expect("read");
    let reader = TmeshReader::open(&path).expect("open");
    let last = reader.entries().len() - 1;
    let at = reader.entries()[last].offset as usize;
    for size in [1u64 << 40, u64::MAX - 8] {
        let mut bad = good.clone();
        bad[at + 32..at + 40].copy_from_slice(&size.to_le_bytes());
        let crc = crc32fast::hash(&bad[at..at + 40]);
        bad[at + 40..at + 44].copy_from_slice(&crc.to_le_bytes());
        std::fs::write(&path, &bad).expect("write");
        let err = TmeshReader::open(&path)
            .expect("index intact")
            .chunk(last)
            .expect_err("damage")
            .to_string();
        let name = format!("chunk {last} ");
        assert!(err.contains(&name) && err.contains("runs past"), "{err}");
        let out = tmc(&["check", s(&path)]);
        let line = assert_one_line(&out, 1);
        assert!(line.contains(&name) && line.contains("runs past"), "{line}");
        let ply = dir.path().join("m.ply");
        let line = assert_one_line(&tmc(&["convert", s(&path), "-o", s(&ply)]), 1);
        assert!(line.contains(&name) && line.contains("runs past"), "{line}");
        assert!(!ply.exists());
        if python {
            let line = read_tmesh_py_error(&path);
            let room = format!("payload of {size} bytes runs past the chunk's room");
            assert!(line.contains(&name) && line.contains(&room), "{line}");
        }
    }
}

/// Fields that checksums do not vouch for (or that a writer could get
/// wrong) are refused with one line by the reader, `tmc check` and `tmc
/// convert`, and by `scripts/read_tmesh.py` (when python3 has numpy and
/// zstandard) with the same words: a header size other than 128, a zero
/// dimension, a spacing that is not finite and positive, an origin that is
/// not finite, a NaN or infinite isovalue, unknown method, inside and close bytes, nonzero reserved
/// header and chunk header bytes, a repeated plane, a plane far beyond the
/// grid, and non-finite vertex coordinates.
#[test]
fn unchecked_fields_are_refused() {
    use common::cli::{assert_one_line, python_ready, read_tmesh_py_error, s, tmc};
    let python = python_ready();
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.tmesh");
    write(&path, 1, 0);
    let good = std::fs::read(&path).expect("read");
    let reader = TmeshReader::open(&path).expect("open");
    let entries = reader.entries().to_vec();
    let n = good.len();
    let index = u64::from_le_bytes(good[n - 32..n - 24].try_into().unwrap()) as usize;
    let header = |f: &dyn Fn(&mut Vec<u8>)| {
        let mut b = good.clone();
        f(&mut b);
        let crc = crc32fast::hash(&b[..124]);
        b[124..128].copy_from_slice(&crc.to_le_bytes());
        b
    };
    let plane = |i: usize, p: u64| {
        let mut b = good.clone();
        let at = index + 16 + 32 * i + 24;
        b[at..at + 8].copy_from_slice(&p.to_le_bytes());
        let crc = crc32fast::hash(&b[index + 16..n - 32]);
        b[index + 4..index + 8].copy_from_slice(&crc.to_le_bytes());
        b
    };
    let mut reserved = good.clone();
    reserved[entries[2].offset as usize + 44] = 1;
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (header(&|b| b[16..24].fill(0)), "dimension is 0"),
        (
            header(&|b| b[88..96].copy_from_slice(&f64::NAN.to_le_bytes())),
            "not a finite",
        ),
        (
            header(&|b| b[88..96].copy_from_slice(&f64::NEG_INFINITY.to_le_bytes())),
            "not a finite",
        ),
        (header(&|b| b[96] = 7), "unknown method byte 7"),
        (header(&|b| b[97] = 2), "unknown inside byte 2"),
        (header(&|b| b[98] = 255), "unknown close byte 255"),
        (
            header(&|b| {
                b[8..12].copy_from_slice(&1u32.to_le_bytes());
                b[123] = 1;
            }),
            "reserved header bytes 99..124",
        ),
        (
            header(&|b| {
                b[8..12].copy_from_slice(&1u32.to_le_bytes());
                b[99] = 1;
            }),
            "reserved header bytes 99..124",
        ),
        (header(&|b| b[99] = 4), "unknown attribute bits 0x04"),
        (header(&|b| b[123] = 1), "reserved header bytes 100..124"),
        (
            header(&|b| b[8..12].copy_from_slice(&4u32.to_le_bytes())),
            ".tmesh version 4 is not supported",
        ),
        (
            header(&|b| {
                b[8..12].copy_from_slice(&2u32.to_le_bytes());
                b[99] = 5;
            }),
            "unknown attribute bits 0x05",
        ),
        (
            header(&|b| {
                b[8..12].copy_from_slice(&2u32.to_le_bytes());
                b[123] = 1;
            }),
            "reserved header bytes 100..124",
        ),
        (
            header(&|b| b[12..16].copy_from_slice(&129u32.to_le_bytes())),
            "header size 129 is not 128",
        ),
        (
            header(&|b| b[40..48].copy_from_slice(&f64::NAN.to_le_bytes())),
            "the spacing NaN 1 1 is not finite and positive",
        ),
        (
            header(&|b| b[48..56].copy_from_slice(&0f64.to_le_bytes())),
            "the spacing 1 0 1 is not finite and positive",
        ),
        (
            header(&|b| b[56..64].copy_from_slice(&(-2f64).to_le_bytes())),
            "the spacing 1 1 -2 is not finite and positive",
        ),
        (
            header(&|b| b[40..48].copy_from_slice(&f64::INFINITY.to_le_bytes())),
            "the spacing inf 1 1 is not finite and positive",
        ),
        (
            header(&|b| b[72..80].copy_from_slice(&f64::NEG_INFINITY.to_le_bytes())),
            "the origin 0 -inf 0 is not finite",
        ),
        (plane(4, entries[3].plane), "not after the previous"),
        (plane(entries.len() - 1, 1 << 63), "beyond the grid"),
        (reserved, "bytes 44..48 are not zero"),
    ];
    let ply = dir.path().join("m.ply");
    let png = dir.path().join("m.png");
    for (bytes, needle) in &cases {
        std::fs::write(&path, bytes).expect("write");
        for args in [
            vec!["check", s(&path)],
            vec!["convert", s(&path), "-o", s(&ply)],
            vec!["preview", s(&path), "-o", s(&png)],
        ] {
            let line = assert_one_line(&tmc(&args), 1);
            assert!(line.contains(needle), "{args:?}: {line:?} lacks {needle:?}");
            assert!(!ply.exists() && !png.exists());
        }
        if python {
            let line = read_tmesh_py_error(&path);
            assert!(
                line.contains(needle),
                "read_tmesh.py: {line:?} lacks {needle:?}"
            );
        }
    }
    // A NaN or infinite coordinate, written as it comes (the pipeline never
    // makes one).
    for bad in [f32::NAN, f32::INFINITY] {
        let mut writer = TmeshWriter::create(&path).expect("create");
        writer.begin(reader.info()).expect("begin");
        let chunk = tmc::Chunk {
            plane: 1,
            vertices: vec![[0.0, bad, 0.0]; 3],
            triangles: vec![[0, 1, 2]],
            normals: Vec::new(),
            labels: Vec::new(),
            values: Vec::new(),
            encoded: Vec::new(),
        };
        writer.chunk(0, &chunk).expect("chunk");
        let totals = Totals {
            vertices: 3,
            triangles: 1,
            ..Default::default()
        };
        writer.finish(&totals).expect("finish");
        let line = assert_one_line(&tmc(&["check", s(&path)]), 1);
        assert!(line.contains("not a finite number"), "{line}");
        if python {
            let line = read_tmesh_py_error(&path);
            let needle = "chunk 0 (plane 1, byte 128): vertex 0 has a coordinate that is not a finite number";
            assert!(line.contains(needle), "read_tmesh.py: {line}");
        }
    }
}

/// A file claiming more vertices in all than any address space holds (3000
/// chunks of 2^32 - 1 vertices each on a 65536 x 65536 grid: 144 TB of
/// coordinates, in a 96 kB index that passes every check made before the
/// chunks are read) makes `scripts/read_tmesh.py` run out of memory when
/// it allocates the mesh: one line on stderr and exit 1, not a traceback.
#[test]
fn read_tmesh_py_out_of_memory_is_one_line() {
    use common::cli::{python_ready, read_tmesh_py_error};
    if !python_ready() {
        return;
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.tmesh");
    write(&path, 1, 0);
    let mut bytes = std::fs::read(&path).expect("read")[..128].to_vec();
    let chunks = 3000u64;
    let count = u32::MAX;
    bytes[16..40].copy_from_slice(&[[0, 0, 1, 0, 0, 0, 0, 0]; 3].concat());
    bytes[32..40].copy_from_slice(&chunks.to_le_bytes());
    bytes[98] = 0; // no close: the grid as it is
    let crc = crc32fast::hash(&bytes[..124]);
    bytes[124..128].copy_from_slice(&crc.to_le_bytes());
    // Room for a chunk header at byte 128, which nothing reads.
    bytes.resize(128 + 48, 0);
    let mut entries = Vec::new();
    for i in 0..chunks {
        entries.extend_from_slice(&128u64.to_le_bytes()); // offset
        entries.extend_from_slice(&(i * u64::from(count)).to_le_bytes()); // base
        entries.extend_from_slice(&count.to_le_bytes());
        entries.extend_from_slice(&0u32.to_le_bytes()); // triangles
        entries.extend_from_slice(&i.to_le_bytes()); // plane
    }
    let index = bytes.len() as u64;
    bytes.extend_from_slice(b"INDX");
    bytes.extend_from_slice(&crc32fast::hash(&entries).to_le_bytes());
    bytes.extend_from_slice(&chunks.to_le_bytes());
    bytes.extend_from_slice(&entries);
    bytes.extend_from_slice(&index.to_le_bytes());
    bytes.extend_from_slice(&(chunks * u64::from(count)).to_le_bytes());
    bytes.extend_from_slice(&0u64.to_le_bytes());
    bytes.extend_from_slice(b"TMESHEND");
    std::fs::write(&path, &bytes).expect("write");
    let line = read_tmesh_py_error(&path);
    assert!(line.contains("m.tmesh: out of memory"), "{line}");
}

/// A chunk claiming more vertices than one plane of the grid can have (a
/// small file inflating to gigabytes) is refused from the index, before
/// any chunk is inflated, by the reader, `tmc check`, `tmc convert` and
/// `scripts/read_tmesh.py` (when python3 has numpy and zstandard).
#[test]
fn a_chunk_larger_than_a_plane_is_refused() {
    use common::cli::{assert_one_line, python_ready, read_tmesh_py, read_tmesh_py_error, s, tmc};
    let python = python_ready();
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("m.tmesh");
    write(&path, 1, 0);
    let info = TmeshReader::open(&path).expect("open").info().clone();
    let [nx, ny, _] = info.grid.dims;
    let pad = if info.close { 2 } else { 0 };
    let most = 11 * (nx + pad) * (ny + pad);
    for count in [most, most + 1] {
        let mut writer = TmeshWriter::create(&path).expect("create");
        writer.begin(&info).expect("begin");
        let chunk = tmc::Chunk {
            plane: 1,
            vertices: vec![[0.0, 0.0, 0.0]; count],
            triangles: vec![[0, 1, 2]],
            normals: Vec::new(),
            labels: Vec::new(),
            values: Vec::new(),
            encoded: Vec::new(),
        };
        writer.chunk(0, &chunk).expect("chunk");
        let totals = Totals {
            vertices: count as u64,
            triangles: 1,
            ..Default::default()
        };
        writer.finish(&totals).expect("finish");
        let opened = TmeshReader::open(&path);
        if count == most {
            opened.expect("as many as a plane can have");
            if python {
                let out = read_tmesh_py(&path);
                let stderr = String::from_utf8_lossy(&out.stderr);
                assert!(out.status.success(), "read_tmesh.py: {stderr}");
            }
            continue;
        }
        let err = opened.err().expect("refused").to_string();
        assert!(
            err.contains("more than one plane of the grid can have"),
            "{err}"
        );
        let ply = dir.path().join("m.ply");
        for args in [
            vec!["check", s(&path)],
            vec!["convert", s(&path), "-o", s(&ply)],
        ] {
            let line = assert_one_line(&tmc(&args), 1);
            assert!(line.contains("chunk 0 claims"), "{args:?}: {line}");
        }
        assert!(!ply.exists());
        if python {
            let stderr = read_tmesh_py_error(&path);
            let bound = format!(
                "chunk 0 claims {count} vertices and 1 triangles, more than one plane of the grid can have ({most} and {})",
                most / 11 * 32
            );
            assert!(stderr.contains(&bound), "{stderr}");
        }
    }
}

/// Files that earlier builds wrote are still read, to the meshes those
/// builds wrote: `tests/data/tmesh_v1.tmesh` (version 1, no attributes:
/// `tmc synth gyroid --dims 9,8,7 --dtype f32 -o tmesh_v1_input.nrrd`,
/// `tmc extract tmesh_v1_input.nrrd --iso 0.2 -o tmesh_v1.tmesh`) and
/// `tmesh_v2.tmesh` (version 2, normals and labels: `tmc extract
/// tmesh_v2_input.npy --labels all --close --normals -o tmesh_v2.tmesh`),
/// with the `.ply` files the same build (commit f06d952) wrote by the same
/// commands. This build's `tmc convert` of each old file writes that PLY
/// byte for byte, and so does its own extraction through a version 3
/// file (the packed payload unpacks to the same numbers); the Python
/// reader, which shares no code with tmc, reads the old and the new file
/// to the same arrays (when python3 has numpy and zstandard).
#[test]
fn earlier_versions_read_to_the_meshes_they_hold() {
    use common::cli::{python_ready, read_tmesh_script, s, tmc};
    let ok = |args: &[&str]| {
        let out = tmc(args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let dir = tempfile::tempdir().expect("tempdir");
    let python = python_ready();
    let cases: [(&str, &str, &[&str]); 2] = [
        ("tmesh_v1", "tmesh_v1_input.nrrd", &["--iso", "0.2"]),
        (
            "tmesh_v2",
            "tmesh_v2_input.npy",
            &["--labels", "all", "--close", "--normals"],
        ),
    ];
    for (name, input, options) in cases {
        let old = data.join(format!("{name}.tmesh"));
        let version = u32::from_le_bytes(
            std::fs::read(&old).expect("fixture")[8..12]
                .try_into()
                .unwrap(),
        );
        assert_eq!(version, if name == "tmesh_v1" { 1 } else { 2 });
        let expected = std::fs::read(data.join(format!("{name}.ply"))).expect("fixture");
        let converted = dir.path().join(format!("{name}-old.ply"));
        ok(&["convert", s(&old), "-o", s(&converted), "-q"]);
        assert!(
            std::fs::read(&converted).unwrap() == expected,
            "{name}: convert of the old file"
        );
        let new = dir.path().join(format!("{name}.tmesh"));
        let input = data.join(input);
        let mut args = vec!["extract", s(&input)];
        args.extend_from_slice(options);
        args.extend_from_slice(&["-o", s(&new), "-q"]);
        ok(&args);
        let version = u32::from_le_bytes(std::fs::read(&new).unwrap()[8..12].try_into().unwrap());
        assert_eq!(version, 3, "{name}: this build writes version 3");
        let reconverted = dir.path().join(format!("{name}-new.ply"));
        ok(&["convert", s(&new), "-o", s(&reconverted), "-q"]);
        assert!(
            std::fs::read(&reconverted).unwrap() == expected,
            "{name}: through version 3"
        );
        ok(&["check", s(&new), "-q"]);
        if python {
            let program = "import sys, numpy as np\n\
                sys.path.insert(0, sys.argv[1])\n\
                from read_tmesh import read_tmesh\n\
                va, ta, ia = read_tmesh(sys.argv[2])\n\
                vb, tb, ib = read_tmesh(sys.argv[3])\n\
                assert va.tobytes() == vb.tobytes() and np.array_equal(ta, tb)\n\
                for k in ('normals', 'labels'):\n\
                \x20   a, b = ia[k], ib[k]\n\
                \x20   assert (a is None) == (b is None) and (a is None or a.tobytes() == b.tobytes()), k\n\
                print(len(va), len(ta), int(ia['normals'] is not None), int(ia['labels'] is not None))\n";
            let out = std::process::Command::new("python3")
                .args(["-c", program])
                .arg(read_tmesh_script().parent().unwrap())
                .args([&old, &new])
                .output()
                .expect("python3");
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(
                out.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let with = u8::from(name == "tmesh_v2");
            assert!(
                stdout.trim_end().ends_with(&format!("{with} {with}")),
                "{name}: {stdout}"
            );
        }
    }
}

/// `tmc convert` reads PLY, OBJ, OFF and STL files whole (it refused
/// them: "tmc convert reads the .tmesh files ..."). A labelled `.tmesh`
/// with normals, streamed to PLY, converts from that PLY to each format
/// byte for byte as from the `.tmesh` itself (the PLY keeps the labels and
/// normals); its OBJ to OFF too; its STL (corners welded) gives the same
/// triangles as sets of corner positions. A `.tmesh` output, a truncated
/// PLY and a non-mesh are refused in one line with nothing written; a
/// `.tmesh` file named `.ply` is still streamed.
#[test]
fn convert_reads_ply_obj_off_and_stl_whole() {
    use common::cli::{assert_one_line, s, tmc};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let tmesh = data.join("tmesh_v2.tmesh");
    let dir = tempfile::tempdir().expect("tempdir");
    let at = |name: &str| dir.path().join(name);
    let convert = |input: &std::path::Path, output: &std::path::Path| {
        let run = tmc(&["convert", s(input), "-o", s(output), "-q"]);
        assert!(run.status.success(), "{input:?} -> {output:?}: {run:?}");
        std::fs::read(output).expect("read")
    };
    let mesh = tmc::check::read_mesh(&tmesh).expect("read");
    let filled = |n: Option<usize>| n.is_some_and(|n| n > 0);
    assert!(
        filled(mesh.labels.as_ref().map(Vec::len)) && filled(mesh.normals.as_ref().map(Vec::len))
    );
    convert(&tmesh, &at("a.ply"));
    for ext in ["ply", "obj", "off", "stl"] {
        let direct = convert(&tmesh, &at(&format!("direct.{ext}")));
        let via_ply = convert(&at("a.ply"), &at(&format!("via_ply.{ext}")));
        assert!(direct == via_ply, "{ext}: from the PLY");
    }
    let via_obj = convert(&at("direct.obj"), &at("via_obj.off"));
    assert!(
        via_obj == std::fs::read(at("direct.off")).unwrap(),
        "OBJ to OFF"
    );
    convert(&at("direct.stl"), &at("via_stl.ply"));
    let corners = |m: &tmc::Mesh| {
        let mut all: Vec<[[u32; 3]; 3]> = m
            .triangles
            .iter()
            .map(|t| t.map(|v| m.vertices[v as usize].map(f32::to_bits)))
            .collect();
        all.sort_unstable();
        all
    };
    let welded = tmc::check::read_mesh(&at("via_stl.ply")).expect("read");
    assert_eq!(corners(&welded), corners(&mesh), "STL");
    // The note names what the output leaves out, as for a .tmesh input.
    let run = tmc(&["convert", s(&at("a.ply")), "-o", s(&at("n.obj"))]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success() && err.contains("no place for the input's per-face labels:"),
        "{err}"
    );
    // Refusals: one line, nothing written.
    let refused = [
        (at("a.ply"), at("x.tmesh"), "records the extraction"),
        (at("short.ply"), at("x.obj"), "short.ply"),
        (data.join("../../Cargo.toml"), at("x.obj"), "Cargo.toml"),
    ];
    let whole = std::fs::read(at("a.ply")).unwrap();
    std::fs::write(at("short.ply"), &whole[..whole.len() - 5]).unwrap();
    for (input, output, words) in refused {
        let line = assert_one_line(&tmc(&["convert", s(&input), "-o", s(&output)]), 1);
        assert!(line.contains(words), "{input:?}: {line}");
        assert!(!output.exists(), "{output:?}");
    }
    // A .tmesh file named .ply is streamed all the same.
    let named = at("really_tmesh.ply");
    std::fs::copy(&tmesh, &named).expect("copy");
    assert!(convert(&named, &at("renamed.ply")) == std::fs::read(at("a.ply")).unwrap());
}

/// `tmc convert` says in one note what the output format leaves out of
/// the input: the labels of a labelled mesh with normals in `.obj` (which
/// keeps the normals), both in `.off` and `.stl`; nothing for `.ply` and
/// `.tmesh`, for a mesh without them, or with `-q`.
#[test]
fn convert_says_what_the_output_format_leaves_out() {
    use common::cli::{s, tmc};
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let dir = tempfile::tempdir().expect("tempdir");
    let (labelled, plain) = (data.join("tmesh_v2.tmesh"), data.join("tmesh_v1.tmesh"));
    let both = "no place for the input's per-face labels and vertex normals";
    let cases = [
        (
            &labelled,
            "obj",
            &[][..],
            Some("no place for the input's per-face labels:"),
        ),
        (&labelled, "off", &[][..], Some(both)),
        (&labelled, "stl", &[][..], Some(both)),
        (&labelled, "ply", &[][..], None),
        (&labelled, "tmesh", &[][..], None),
        (&plain, "off", &[][..], None),
        (&labelled, "obj", &["-q"][..], None),
    ];
    for (input, ext, extra, note) in cases {
        let out = dir.path().join(format!("x.{ext}"));
        let mut args = vec!["convert", s(input), "-o", s(&out)];
        args.extend_from_slice(extra);
        let run = tmc(&args);
        assert!(run.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&run.stderr);
        match note {
            Some(words) => assert!(
                err.lines().count() == 1 && err.starts_with("tmc: note: ") && err.contains(words),
                "{args:?}: {err}"
            ),
            None => assert!(err.is_empty(), "{args:?}: {err}"),
        }
    }
}

/// An empty mesh keeps its attributes through `tmc convert` of a PLY: a
/// run with `--normals` that finds no surface, and a label map's one-file
/// output of a label that is not there, write a PLY whose header declares
/// `nx ny nz` (the labels' face `label`); converting that PLY to PLY gives
/// its bytes back, as converting the `.tmesh` of the same run does. The
/// whole-mesh reader took "no vertices" for "no normals" (and "no
/// triangles" for "no labels") and dropped them from the header.
#[test]
fn convert_keeps_the_attributes_of_an_empty_mesh() {
    use common::cli::{npy_header, s, tmc};
    let dir = tempfile::tempdir().expect("tempdir");
    let at = |name: &str| dir.path().join(name);
    let mut npy = npy_header("{'descr': '|u1', 'fortran_order': False, 'shape': (3, 3, 3), }");
    npy.extend((0..27u8).map(|i| u8::from(i == 13) * 9));
    std::fs::write(at("v.npy"), npy).expect("write");
    let run = |args: &[&str]| {
        let out = tmc(args);
        assert!(out.status.success(), "{args:?}: {out:?}");
    };
    let v = at("v.npy");
    for (name, option) in [
        ("normals", &["--iso", "20", "--normals"][..]),
        ("labels", &["--labels", "7"][..]),
    ] {
        for ext in ["ply", "tmesh"] {
            let out = at(&format!("{name}.{ext}"));
            let mut args = vec!["extract", s(&v), "-o", s(&out), "-q"];
            args.extend_from_slice(option);
            run(&args);
        }
        let direct = std::fs::read(at(&format!("{name}.ply"))).expect("read");
        let header = String::from_utf8_lossy(&direct).into_owned();
        let property = if name == "normals" {
            "property float nx"
        } else {
            "property uint label"
        };
        assert!(header.contains(property), "{name}: {header}");
        for from in ["ply", "tmesh"] {
            let converted = at(&format!("{name}-from-{from}.ply"));
            let input = at(&format!("{name}.{from}"));
            run(&["convert", s(&input), "-o", s(&converted), "-q"]);
            let bytes = std::fs::read(&converted).expect("read");
            assert!(
                bytes == direct,
                "{name} from .{from}: {}",
                String::from_utf8_lossy(&bytes)
            );
        }
    }
}
