//! Throughput against thread count: medians of interleaved runs of the
//! streaming pipeline into a sink that only counts (no output cost), in
//! voxels per second. `cargo bench --bench threads` (`TMC_BENCH_N`, default
//! 256; `TMC_BENCH_RUNS`, default 5; `TMC_BENCH_THREADS`, default "1,2").

use std::time::Instant;
use tmc::{
    extract_to, synth, Chunk, ExtractParams, MeshInfo, MeshSink, PipelineOptions, SampleSource,
    Totals,
};

/// Counts what it is given.
struct Count(u64);

impl MeshSink for Count {
    fn begin(&mut self, _: &MeshInfo) -> tmc::Result<()> {
        Ok(())
    }
    fn chunk(&mut self, _: u64, chunk: &Chunk) -> tmc::Result<()> {
        self.0 += chunk.triangles.len() as u64;
        Ok(())
    }
    fn finish(&mut self, _: &Totals) -> tmc::Result<()> {
        Ok(())
    }
}

fn env(name: &str, default: &str) -> String {
    std::env::var(name).unwrap_or_else(|_| default.to_string())
}

fn main() {
    let n: usize = env("TMC_BENCH_N", "256").parse().expect("TMC_BENCH_N");
    let runs: usize = env("TMC_BENCH_RUNS", "5").parse().expect("TMC_BENCH_RUNS");
    let threads: Vec<usize> = env("TMC_BENCH_THREADS", "1,2")
        .split(',')
        .map(|t| t.parse().expect("TMC_BENCH_THREADS"))
        .collect();
    let mut volumes: Vec<(String, Box<dyn SampleSource>, f64)> = vec![
        (
            format!("gyroid {n}^3"),
            Box::new(synth::gyroid(n, 8.0)),
            0.0,
        ),
        (
            format!("noise {n}^3, 1 pass"),
            Box::new(synth::noise(n, 5, 1)),
            0.0,
        ),
    ];
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    for (file, iso) in [("cthead.nrrd", 550.0), ("bonsai.nrrd", 40.0)] {
        if let Ok(v) = tmc::volume::open(&shared.join(file), None) {
            volumes.push((format!("{file} @ {iso}"), v, iso));
        }
    }
    println!("{runs} interleaved runs, median; streaming into a counting sink");
    print!("{:<24} {:>12}", "volume", "triangles");
    for t in &threads {
        print!(" {:>10} {:>9}", format!("{t} thr s"), "Mvox/s");
    }
    println!(" {:>8}", "speed-up");
    for (name, vol, iso) in &volumes {
        let voxels = vol.grid().dims.iter().product::<usize>() as f64;
        let mut times = vec![Vec::new(); threads.len()];
        let mut triangles = 0;
        for _ in 0..runs {
            for (k, &t) in threads.iter().enumerate() {
                let params = ExtractParams {
                    iso: *iso,
                    threads: t,
                    ..Default::default()
                };
                let mut sink = Count(0);
                let start = Instant::now();
                extract_to(
                    vol.as_ref(),
                    &params,
                    &PipelineOptions::default(),
                    &mut sink,
                )
                .expect("extract");
                times[k].push(start.elapsed().as_secs_f64());
                triangles = sink.0;
            }
        }
        print!("{name:<24} {triangles:>12}");
        let medians: Vec<f64> = times
            .into_iter()
            .map(|mut v| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            })
            .collect();
        for m in &medians {
            print!(" {m:>10.3} {:>9.1}", voxels / m / 1e6);
        }
        println!(" {:>8.2}", medians[0] / medians[medians.len() - 1]);
    }
}
