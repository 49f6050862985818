//! Times `tmc::normals::vertex_normals` against the extraction it follows,
//! on the CT-like head phantom of `tmc synth` held in memory (16-bit
//! samples as `f64`, as `time_extract` holds a volume), at its skull
//! isovalue.
//!
//! `time_normals [N] [THREADS] [RUNS]` (defaults 256, 1, 5) prints one line
//! per run and the medians: extraction seconds, normals seconds, and their
//! ratio. Build with `cargo build --release --example time_normals`.

use std::time::Instant;
use tmc::normals::vertex_normals;
use tmc::synth::{Kind, Synthetic};
use tmc::volume::ScalarType;
use tmc::{extract, ArrayVolume, ExtractParams, Grid, SampleSource};

fn main() -> tmc::Result<()> {
    let arg = |i: usize, default: usize| {
        std::env::args()
            .nth(i)
            .map_or(default, |s| s.parse().expect("a number"))
    };
    let (n, threads, runs) = (arg(1, 256), arg(2, 1), arg(3, 5).max(1));
    let head = Synthetic::new(Kind::Head, Grid::unit([n; 3]), ScalarType::I16, 1)?;
    let plane = head.grid().plane_len();
    let mut data = vec![0.0; plane * n];
    for (z, out) in data.chunks_exact_mut(plane).enumerate() {
        head.read_plane(z, out)?;
    }
    let volume = ArrayVolume::new(*head.grid(), data)?;
    let params = ExtractParams {
        iso: head.suggested_iso(),
        threads,
        ..Default::default()
    };
    let (mut extraction, mut normals) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        let start = Instant::now();
        let (mesh, _) = extract(&volume, &params)?;
        extraction.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        let n = vertex_normals(&volume, &params, &mesh)?;
        normals.push(start.elapsed().as_secs_f64());
        println!(
            "{} vertices: extraction {:.4} s, normals {:.4} s",
            n.len(),
            extraction[extraction.len() - 1],
            normals[normals.len() - 1]
        );
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (e, m) = (median(&mut extraction), median(&mut normals));
    println!(
        "median of {runs}, {n}^3, {threads} thread(s): extraction {e:.4} s, normals {m:.4} s ({:.1}%)",
        100.0 * m / e
    );
    Ok(())
}
