//! What a worker holds does not grow with the plane: planes of 2048^2 and
//! 6144^2 samples (9x the samples) take about the same anonymous memory,
//! and a plane whose samples are not aligned for their type (a NRRD header
//! of odd length before 16-bit samples) gives the same mesh as an aligned
//! one.
//!
//! Before planes at any alignment were lent (`volume::Packed`), a
//! misaligned plane was read into `f64`s: 8 bytes per sample, two planes per
//! worker, so two workers on 6144^2 planes held some 1.2 GB more than on
//! 2048^2 planes, where this test allows 96 MiB.

mod common;

use common::cli::{json_number, s, synth, tmc};
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes an `n x n x nz` u16 NRRD of a small ball (2000 inside, 1000
/// outside, radius 20 samples) whose header is padded to `header_len`
/// bytes (odd: the samples are not 2-byte aligned in the file).
fn ball(dir: &Path, n: usize, nz: usize, header_len: usize) -> PathBuf {
    let path = dir.join(format!("ball{n}.nrrd"));
    let header = nrrd_header(&format!("{n} {n} {nz}"), header_len);
    let mut out = BufWriter::new(fs::File::create(&path).unwrap());
    out.write_all(&header).unwrap();
    let c = (n / 2) as f64;
    let mut plane = vec![0u8; 2 * n * n];
    for z in 0..nz {
        let dz = z as f64 - nz as f64 / 2.0;
        for y in 0..n {
            for x in 0..n {
                let (dx, dy) = (x as f64 - c, y as f64 - c);
                let v: u16 = if dx * dx + dy * dy + dz * dz < 400.0 {
                    2000
                } else {
                    1000
                };
                plane[2 * (y * n + x)..][..2].copy_from_slice(&v.to_le_bytes());
            }
        }
        out.write_all(&plane).unwrap();
    }
    out.flush().unwrap();
    path
}

/// A little-endian u16 raw NRRD header for `sizes`, padded with a comment
/// to exactly `len` bytes.
fn nrrd_header(sizes: &str, len: usize) -> Vec<u8> {
    let fields = format!(
        "NRRD0004\ntype: uint16\ndimension: 3\nsizes: {sizes}\nendian: little\nencoding: raw\n"
    );
    // "#" + padding + "\n" before the blank line that ends the header.
    let pad = len
        .checked_sub(fields.len() + 3)
        .expect("header length too short");
    format!("{fields}#{}\n\n", " ".repeat(pad)).into_bytes()
}

/// Peak anonymous memory of `tmc extract` on `input` at two threads, slabs
/// of one layer (so both workers hold planes at once).
fn peak_anon(input: &Path, output: &Path) -> f64 {
    let out = tmc(&[
        "extract",
        s(input),
        "--iso",
        "1500",
        "-o",
        s(output),
        "--threads",
        "2",
        "--slab-depth",
        "1",
        "--json",
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(json_number(&out.stdout, "triangles") > 0.0, "no surface");
    json_number(&out.stdout, "peak_rss_anon_bytes")
}

#[test]
fn anonymous_memory_does_not_grow_with_the_plane() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("mesh.tmesh");
    let (small, large) = (2048, 6144);
    let small_peak = peak_anon(&ball(dir.path(), small, 6, 301), &mesh);
    let large_peak = peak_anon(&ball(dir.path(), large, 6, 301), &mesh);
    let mib = |b: f64| b / f64::from(1 << 20);
    println!(
        "peak anonymous memory: {:.1} MiB at {small}^2, {:.1} MiB at {large}^2",
        mib(small_peak),
        mib(large_peak)
    );
    assert!(
        large_peak - small_peak < 96.0 * f64::from(1 << 20),
        "{large}^2 planes took {:.1} MiB more than {small}^2 planes",
        mib(large_peak - small_peak)
    );
}

#[test]
fn a_misaligned_plane_gives_the_mesh_of_an_aligned_one() {
    let dir = tempfile::tempdir().unwrap();
    // The head phantom's samples behind headers of odd and even length.
    let head = synth(dir.path(), "head", "96,80,40", "u16", "head.nrrd");
    let bytes = fs::read(&head).unwrap();
    let data = bytes.len() - 96 * 80 * 40 * 2;
    let mut meshes = Vec::new();
    for len in [301, 302, 304, 299] {
        let input = dir.path().join(format!("head{len}.nrrd"));
        let mut file = nrrd_header("96 80 40", len);
        file.extend_from_slice(&bytes[data..]);
        fs::write(&input, file).unwrap();
        let output = dir.path().join(format!("head{len}.tmesh"));
        for threads in ["1", "2"] {
            let out = tmc(&[
                "extract",
                s(&input),
                "--iso",
                "1500",
                "-o",
                s(&output),
                "--threads",
                threads,
                "-q",
            ]);
            assert!(out.status.success(), "{out:?}");
            meshes.push((len, fs::read(&output).unwrap()));
        }
    }
    let (_, first) = &meshes[0];
    assert!(first.len() > 10_000, "a surface");
    for (len, mesh) in &meshes {
        assert!(mesh == first, "header of {len} bytes: another mesh");
    }
}
