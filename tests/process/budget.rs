//! `--max-memory` on inputs whose planes are decoded (Zarr, HDF5: their
//! chunk layers count) or lent in place (memory-mapped: only their inside
//! bits count), and its refusal before anything is read.

use crate::common;

use common::cli::{assert_one_line, json_number, names, s, tmc};
use std::fs;
use std::path::{Path, PathBuf};

/// Memory of the process that is not the pipeline's: the binary's code and
/// data, the allocator's arenas, the thread stacks (measured: `VmHWM` of
/// an extraction of a 2^3 volume is about 8 MiB).
const SLACK: f64 = 16.0 * (1 << 20) as f64;

const MIB: f64 = (1 << 20) as f64;

/// Samples of a flattened ball on `[nx, ny, nz]`: the squared distance
/// from the centre, z stretched 16 times (a sparse surface at 300^2).
fn ball(dims: [usize; 3]) -> Vec<f32> {
    let [nx, ny, nz] = dims;
    let mut v = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let d = [
                    x as f32 - nx as f32 / 2.0,
                    y as f32 - ny as f32 / 2.0,
                    16.0 * (z as f32 - nz as f32 / 2.0),
                ];
                v.push(d.iter().map(|c| c * c).sum());
            }
        }
    }
    v
}

/// `samples` as a Zarr v2 array of f32 on `dims`, uncompressed chunks of
/// `depth` whole planes (written by hand: a JSON file and the chunks'
/// bytes).
fn zarr(store: &Path, dims: [usize; 3], depth: usize, samples: &[f32]) -> PathBuf {
    let [nx, ny, nz] = dims;
    fs::create_dir(store).unwrap();
    let zarray = format!(
        r#"{{"shape": [{nz}, {ny}, {nx}], "chunks": [{depth}, {ny}, {nx}], "dtype": "<f4",
"fill_value": 0, "order": "C", "filters": null, "dimension_separator": ".",
"compressor": null, "zarr_format": 2}}"#
    );
    fs::write(store.join(".zarray"), zarray).unwrap();
    let plane = nx * ny;
    for k in 0..nz.div_ceil(depth) {
        // Edge chunks are stored whole.
        let mut bytes = vec![0u8; depth * plane * 4];
        let layer = &samples[k * depth * plane..((k + 1) * depth).min(nz) * plane];
        for (out, v) in bytes.chunks_exact_mut(4).zip(layer) {
            out.copy_from_slice(&v.to_le_bytes());
        }
        fs::write(store.join(format!("{k}.0.0")), bytes).unwrap();
    }
    store.to_path_buf()
}

/// `samples` as an HDF5 dataset `/v` of f32 on `dims` in chunks of
/// `depth` whole planes, deflated; the path to give tmc.
fn hdf5(file: &Path, dims: [usize; 3], depth: usize, samples: &[f32]) -> PathBuf {
    let [nx, ny, nz] = dims;
    let h5 = rust_hdf5::H5File::create(file).unwrap();
    h5.new_dataset::<f32>()
        .shape([nz, ny, nx])
        .chunk(&[depth, ny, nx])
        .deflate(1)
        .create("v")
        .unwrap()
        .write_raw(samples)
        .unwrap();
    drop(h5);
    PathBuf::from(format!("{}:/v", file.display()))
}

/// Extracts `input` at 300^2 with `threads` workers and `--max-memory
/// max` (MiB); the output, or the one-line error.
fn run(input: &Path, output: &Path, threads: &str, max: f64) -> std::process::Output {
    let max = format!("{}M", max.ceil());
    tmc(&[
        "extract",
        s(input),
        "--iso",
        "90000",
        "-o",
        s(output),
        "--threads",
        threads,
        "--max-memory",
        &max,
        "--json",
        "-q",
    ])
}

/// The MiB a refusal says the run needs ("need about N MiB").
fn needed_mib(line: &str) -> f64 {
    let at = line.find("need about ").expect("the size needed") + "need about ".len();
    let number: String = line[at..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    assert!(line[at + number.len()..].starts_with(" MiB"), "{line}");
    number.parse().unwrap()
}

/// At `max` MiB a run either stays within it (peak resident set, which
/// for these inputs holds no mapped file) or is refused up front, naming
/// what it needs; at that size it runs within it.
fn holds_or_is_refused(input: &Path, threads: &str, max: f64) {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("mesh.tmesh");
    let out = run(input, &output, threads, max);
    let (out, budget) = if out.status.success() {
        (out, max)
    } else {
        let line = assert_one_line(&out, 1);
        assert!(line.contains("is too small"), "{line}");
        assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
        let needed = needed_mib(&line);
        println!(
            "{} at {threads} threads: refused at {max} MiB, needs {needed} MiB",
            input.display()
        );
        let out = run(input, &output, threads, needed);
        assert!(
            out.status.success(),
            "at the size named, {needed} MiB: {out:?}"
        );
        (out, needed.ceil())
    };
    let peak = json_number(&out.stdout, "vm_hwm_bytes");
    assert!(json_number(&out.stdout, "triangles") > 0.0);
    println!(
        "{} at {threads} threads, --max-memory {budget}M: peak {:.1} MiB",
        input.display(),
        peak / MIB
    );
    assert!(
        peak <= budget * MIB + SLACK,
        "{}, {threads} threads: peak {:.1} MiB beyond --max-memory {budget}M and {} MiB of slack",
        input.display(),
        peak / MIB,
        SLACK / MIB
    );
}

/// Zarr and HDF5 chunks of 8 whole 1024^2 f32 planes: a decoded layer is
/// 32 MiB. The layers the cache keeps and those a worker's slab held were
/// not counted: at `--max-memory 100M` the runs went on and peaked at some
/// 200 MiB.
#[test]
fn chunked_inputs_keep_to_max_memory_or_are_refused_naming_the_size() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let dims = [1024, 1024, 40];
    let samples = ball(dims);
    let store = zarr(&dir.path().join("ball.zarr"), dims, 8, &samples);
    holds_or_is_refused(&store, "1", 100.0);
    holds_or_is_refused(&store, "2", 100.0);
    fs::remove_dir_all(&store).unwrap();
    let h5 = hdf5(&dir.path().join("ball.h5"), dims, 8, &samples);
    holds_or_is_refused(&h5, "2", 100.0);
}

/// A 4096x4096x6 u8 volume read in place holds two planes of inside bits
/// per worker, not two planes of `f64`s: 64 MiB is enough (it was refused,
/// "need about 944 MiB" at two threads), and the run's own memory (not the
/// mapped file's pages) stays within it on a sparse surface.
#[test]
fn lent_planes_run_in_a_budget_near_their_need() {
    let _cores = crate::CORES.read().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let [nx, ny, nz] = [4096usize, 4096, 6];
    let mut bytes = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                // A cylinder leaning in z: a sparse surface.
                let r = (x as f64 - 2048.0 - z as f64).hypot(y as f64 - 2048.0);
                bytes.push(if r < 1000.0 { 200u8 } else { 0 });
            }
        }
    }
    let input = dir.path().join("disc.raw");
    fs::write(&input, bytes).unwrap();
    let output = dir.path().join("disc.tmesh");
    let out = tmc(&[
        "extract",
        s(&input),
        "--dims",
        "4096,4096,6",
        "--dtype",
        "u8",
        "--iso",
        "100",
        "-o",
        s(&output),
        "--threads",
        "2",
        "--max-memory",
        "64M",
        "--json",
        "-q",
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(json_number(&out.stdout, "triangles") > 0.0);
    let peak = json_number(&out.stdout, "peak_rss_anon_bytes");
    println!(
        "lent u8 4096^2 x 6 at 64M: peak RssAnon {:.1} MiB",
        peak / MIB
    );
    assert!(peak <= 64.0 * MIB, "peak RssAnon {:.1} MiB", peak / MIB);
}

/// `--part` checksums the planes at its seams before the pass: a budget
/// too small is refused before that, so before reading any plane, here
/// of a Zarr whose chunks cannot be decoded (the refusal came after the
/// chunk's error).
#[test]
fn a_part_beyond_the_budget_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [64, 64, 16];
    let store = zarr(&dir.path().join("bad.zarr"), dims, 4, &ball(dims));
    for k in 0..4 {
        fs::write(store.join(format!("{k}.0.0")), b"not a chunk").unwrap();
    }
    let parts = dir.path().join("parts");
    fs::create_dir(&parts).unwrap();
    let output = parts.join("p2.tmesh");
    let part = |more: &[&str]| {
        let mut args = vec!["extract", s(&store), "--iso", "1000", "--part", "2/2"];
        args.extend(["-o", s(&output)]);
        args.extend(more);
        assert_one_line(&tmc(&args), 1)
    };
    let line = part(&["--max-memory", "1M"]);
    assert!(
        line.contains("--max-memory") && line.contains("too small"),
        "{line}"
    );
    assert!(names(&parts).is_empty(), "{:?}", names(&parts));
    // The same part with room reads the planes and meets the bad chunk.
    let line = part(&[]);
    assert!(line.contains("chunk"), "{line}");
}

/// A label map whose runs (about 2 MiB) are kept by the scan: labels
/// change every 100 samples along x. The pass holds the runs besides the
/// workers' buffers; the refusal named the workers' need alone, and the
/// pass had the budget less the runs, so that a run at the size the
/// refusal named was refused again ("--max-memory of 71.7 MiB is too
/// small ... need about 74.0 MiB" at `--max-memory 74M`).
#[test]
fn a_label_pass_at_the_size_its_refusal_names_runs() {
    let dir = tempfile::tempdir().unwrap();
    let [nx, ny, nz] = [512usize, 512, 48];
    let mut bytes = format!(
        "NRRD0004\ntype: uint16\ndimension: 3\nsizes: {nx} {ny} {nz}\nencoding: raw\nendian: little\n\n"
    )
    .into_bytes();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let label = (x / 100 + 3 * (y / 64) + z / 8) % 40 + 1;
                bytes.extend_from_slice(&(label as u16).to_le_bytes());
            }
        }
    }
    let map = dir.path().join("seg.nrrd");
    fs::write(&map, bytes).unwrap();
    let out = dir.path().join("out");
    fs::create_dir(&out).unwrap();
    let pattern = out.join("{label}.tmesh");
    let run = |max: &str| {
        tmc(&[
            "extract",
            s(&map),
            "--labels",
            "all",
            "-o",
            s(&pattern),
            "--threads",
            "2",
            "--max-memory",
            max,
            "-q",
        ])
    };
    let line = assert_one_line(&run("8M"), 1);
    assert!(line.contains("--max-memory of 8388608 bytes"), "{line}");
    assert!(names(&out).is_empty(), "{:?}", names(&out));
    let needed = needed_mib(&line);
    let done = run(&format!("{}M", needed.ceil()));
    assert!(
        done.status.success(),
        "at the size named, {needed} MiB: {done:?}"
    );
    assert_eq!(names(&out).len(), 32);
}
