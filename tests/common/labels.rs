//! Label maps for the `--labels` tests: generated maps written as NRRD,
//! each label extracted from its own indicator volume for comparison, and
//! the parts of tmc's binary PLY.

use super::cli::{s, tmc};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::Path;
use tmc::volume::{write_volume, ArrayVolume, ScalarType};
use tmc::Grid;

/// Runs `tmc` with `args`, asserting success; returns stdout.
pub fn ok(args: &[&str]) -> Vec<u8> {
    let out = tmc(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
    out.stdout
}

/// Writes `values` on a grid of `dims` (spacing 1, 1, 1.5, so that the
/// world map is not the identity) as an NRRD of `scalar`.
pub fn write(path: &Path, dims: [usize; 3], values: Vec<f64>, scalar: ScalarType) {
    let grid = Grid {
        spacing: [1.0, 1.0, 1.5],
        ..Grid::unit(dims)
    };
    let volume = ArrayVolume::new(grid, values).unwrap();
    write_volume(path, &volume, scalar, None).unwrap();
}

/// A label map: Voronoi regions of random seeds (labels 1..=regions,
/// touching each other and the border), background 0 where a random
/// field is low, a few one-voxel labels, and a torus (a label with a
/// tunnel).
pub fn label_map(dims: [usize; 3], regions: usize, seed: u64) -> Vec<f64> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let seeds: Vec<[f64; 3]> = (0..regions)
        .map(|_| std::array::from_fn(|i| rng.gen_range(0.0..dims[i] as f64)))
        .collect();
    let mut out = Vec::with_capacity(dims.iter().product());
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let p = [x as f64, y as f64, z as f64];
                let d2 = |c: &[f64; 3]| (0..3).map(|i| (p[i] - c[i]).powi(2)).sum::<f64>();
                let (k, _) = seeds
                    .iter()
                    .enumerate()
                    .map(|(k, c)| (k, d2(c)))
                    .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
                let background = rng.gen_bool(0.08);
                out.push(if background { 0.0 } else { (k + 1) as f64 });
            }
        }
    }
    let at = |x: usize, y: usize, z: usize| x + dims[0] * (y + dims[1] * z);
    // One-voxel labels, one on the border.
    for (i, p) in [[3, 4, 5], [0, 7, 2], [dims[0] - 2, 2, dims[2] / 2]]
        .iter()
        .enumerate()
    {
        out[at(p[0], p[1], p[2])] = (200 + i) as f64;
    }
    // A torus around the z axis through the grid's centre.
    let c = dims.map(|n| n as f64 / 2.0);
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let (dx, dy, dz) = (x as f64 - c[0], y as f64 - c[1], z as f64 - c[2]);
                let ring = ((dx * dx + dy * dy).sqrt() - 5.0).powi(2) + dz * dz;
                if ring < 2.3 {
                    out[at(x, y, z)] = 150.0;
                }
            }
        }
    }
    out
}

/// The values present, but 0.
pub fn labels_of(values: &[f64]) -> Vec<i64> {
    let mut l: Vec<i64> = values
        .iter()
        .map(|&v| v as i64)
        .filter(|&v| v != 0)
        .collect();
    l.sort_unstable();
    l.dedup();
    l
}

/// Extracts each of `labels` from `values` as its own u8 indicator volume
/// at 0.5 (with `extra`) and asserts that `dir/{label}.EXT` has its bytes.
pub fn assert_indicators(
    dir: &Path,
    dims: [usize; 3],
    values: &[f64],
    labels: &[i64],
    ext: &str,
    extra: &[&str],
) {
    let volume = dir.join("indicator.nrrd");
    let mesh = dir.join(format!("indicator.{ext}"));
    for &l in labels {
        let indicator = values.iter().map(|&v| f64::from(v == l as f64)).collect();
        write(&volume, dims, indicator, ScalarType::U8);
        let mut args = vec!["extract", s(&volume), "--iso", "0.5", "-o", s(&mesh), "-q"];
        args.extend_from_slice(extra);
        ok(&args);
        let label = dir.join(format!("{l}.{ext}"));
        assert!(
            std::fs::read(&mesh).unwrap() == std::fs::read(&label).unwrap(),
            "label {l} ({ext}, {extra:?}) differs from its indicator's extraction"
        );
    }
}

/// The body of a binary PLY after `end_header\n`, and the header.
pub fn split_ply(bytes: &[u8]) -> (String, &[u8]) {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    (
        String::from_utf8_lossy(&bytes[..end]).into_owned(),
        &bytes[end..],
    )
}

pub fn count(header: &str, element: &str) -> usize {
    let line = header
        .lines()
        .find(|l| l.starts_with(&format!("element {element} ")))
        .unwrap();
    line.rsplit(' ').next().unwrap().parse().unwrap()
}

pub fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// Vertices (12 bytes each) and faces of tmc's PLY.
pub fn parse_plain_ply(bytes: &[u8]) -> (Vec<[u8; 12]>, Vec<[u32; 3]>) {
    let (header, body) = split_ply(bytes);
    let (nv, nf) = (count(&header, "vertex"), count(&header, "face"));
    let v = (0..nv)
        .map(|i| body[i * 12..i * 12 + 12].try_into().unwrap())
        .collect();
    let f = (0..nf)
        .map(|i| {
            let at = nv * 12 + i * 13;
            assert_eq!(body[at], 3);
            std::array::from_fn(|k| u32_at(body, at + 1 + 4 * k))
        })
        .collect();
    (v, f)
}

/// A face of the one-file PLY and its label.
pub type LabelledFace = ([u32; 3], u32);

/// Vertices and (face, label) of the one-file PLY.
pub fn parse_labelled_ply(bytes: &[u8]) -> (Vec<[u8; 12]>, Vec<LabelledFace>) {
    let (header, body) = split_ply(bytes);
    assert!(header.contains("property list uchar uint vertex_indices\nproperty uint label\n"));
    let (nv, nf) = (count(&header, "vertex"), count(&header, "face"));
    assert_eq!(body.len(), nv * 12 + nf * 17);
    let v = (0..nv)
        .map(|i| body[i * 12..i * 12 + 12].try_into().unwrap())
        .collect();
    let f = (0..nf)
        .map(|i| {
            let at = nv * 12 + i * 17;
            assert_eq!(body[at], 3);
            let face = std::array::from_fn(|k| u32_at(body, at + 1 + 4 * k));
            (face, u32_at(body, at + 13))
        })
        .collect();
    (v, f)
}
