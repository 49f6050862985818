//! TMC against standard MC on the same code path: medians of interleaved
//! runs, and their ratio. Run with `cargo bench --bench tmc_vs_mc`
//! (or `scripts/bench-tmc-vs-mc`). Set `TMC_BENCH_RUNS` to change the number
//! of runs (default 7) and `TMC_BENCH_N` the grid size (default 192).

use std::time::Instant;
use tmc::{extract, synth, ExtractParams, Method, SampleSource};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time(vol: &dyn SampleSource, iso: f64, method: Method, threads: usize) -> (f64, u64) {
    let params = ExtractParams {
        iso,
        method,
        threads,
        ..Default::default()
    };
    let start = Instant::now();
    let (_, stats) = extract(vol, &params).expect("extraction");
    (start.elapsed().as_secs_f64(), stats.triangles)
}

fn main() {
    let runs: usize = std::env::var("TMC_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    let n: usize = std::env::var("TMC_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(192);
    let mut volumes: Vec<(String, Box<dyn SampleSource>, f64)> = vec![
        (
            "gyroid (smooth)".into(),
            Box::new(synth::gyroid(n, 6.0)),
            0.0,
        ),
        (
            "noise, 1 smoothing pass".into(),
            Box::new(synth::noise(n, 7, 1)),
            0.0,
        ),
        ("uniform noise".into(), Box::new(synth::noise(n, 7, 0)), 0.0),
    ];
    // The real CTs of ../shared/data, when present (the paper's comparison),
    // at the isovalues of its README: the four first, then the rest.
    let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    for (file, iso) in [
        ("cthead.nrrd", 550.0),
        ("cthead.nrrd", 1600.0),
        ("bonsai.nrrd", 40.0),
        ("engine.nrrd", 80.0),
        ("bonsai.nrrd", 100.0),
        ("engine.nrrd", 180.0),
        ("stent_ct.nrrd", 600.0),
        ("stent_ct.nrrd", 1500.0),
        ("lidc_chest_ct.nrrd", 36.0),
        ("lidc_chest_ct.nrrd", 114.0),
    ] {
        match tmc::volume::open(&shared.join(file), None) {
            Ok(v) => volumes.push((format!("{file} @ {iso}"), v, iso)),
            Err(e) => eprintln!("skipping {file}: {e}"),
        }
    }
    println!("grid {n}^3, {runs} interleaved runs each, 1 thread, median seconds");
    println!(
        "{:<28} {:>10} {:>10} {:>8} {:>12} {:>12}",
        "volume", "tmc s", "mc s", "tmc/mc", "tmc tris", "mc tris"
    );
    for (name, vol, iso) in &volumes {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let (mut ta, mut tb) = (0, 0);
        for _ in 0..runs {
            let (s, t) = time(vol.as_ref(), *iso, Method::Tmc, 1);
            a.push(s);
            ta = t;
            let (s, t) = time(vol.as_ref(), *iso, Method::Mc, 1);
            b.push(s);
            tb = t;
        }
        let (ma, mb) = (median(a), median(b));
        println!(
            "{name:<28} {ma:>10.4} {mb:>10.4} {:>8.3} {ta:>12} {tb:>12}",
            ma / mb
        );
    }
}
