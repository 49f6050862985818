//! A long random search for kernel failures, beyond the fixed seeds of the
//! other files: small volumes of every sample type, full of ties and
//! plateaus, with either side inside, open and closed, each mesh checked
//! against the independent oracle and mesh checker and against itself run
//! with other threads and slab depths.
//!
//! Ignored by default (it is a search, not a regression test); run it with
//! `TMC_SOAK_CASES=200000 cargo test --release --test surface soak --
//! --ignored` (the seed range starts at `TMC_SOAK_FROM`, default 0). A
//! failure names its seed; the fixed tests keep what a search found.

use crate::common;

use common::{compare_with_oracle, oracle};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use tmc::check::check_mesh;
use tmc::volume::Sample;
use tmc::{
    extract, extract_to, ArrayVolume, ExtractParams, Grid, Inside, Mesh, MeshBuilder, Method,
    PipelineOptions, SampleSource,
};

/// Runs `check` on the seeds from `TMC_SOAK_FROM` (default 0), as many as
/// `TMC_SOAK_CASES` (default 2000); fails naming the first five failing.
fn search(check: fn(u64) -> Result<(), String>) {
    let from = env("TMC_SOAK_FROM", 0);
    let cases = env("TMC_SOAK_CASES", 2000);
    let mut failures = Vec::new();
    for seed in from..from + cases {
        if let Err(e) = check(seed) {
            eprintln!("{e}");
            failures.push(seed);
            if failures.len() >= 5 {
                break;
            }
        }
    }
    assert!(failures.is_empty(), "failing seeds: {failures:?}");
}

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A random case: dims, integer values in a small range (plateaus, runs
/// and ties at the isovalue likely), and the isovalue (a value of the
/// field or halfway between two).
fn case(seed: u64) -> ([usize; 3], Vec<i64>, f64) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut dim = |most: usize| rng.gen_range(2..=most);
    let dims = [dim(7), dim(7), dim(14)];
    let top = rng.gen_range(1..=6i64);
    let low = -rng.gen_range(0..=top);
    let repeat = rng.gen_range(0.0..0.8);
    let n: usize = dims.iter().product();
    let mut values: Vec<i64> = Vec::with_capacity(n);
    for i in 0..n {
        let v = match i.checked_sub(if rng.gen_bool(0.5) { 1 } else { dims[0] }) {
            Some(j) if rng.gen_bool(repeat) => values[j],
            _ => rng.gen_range(low..=top),
        };
        values.push(v);
    }
    let pick = values[rng.gen_range(0..n)] as f64;
    let iso = if rng.gen_bool(0.6) { pick } else { pick + 0.5 };
    (dims, values, iso)
}

fn run<T: Sample>(
    dims: [usize; 3],
    values: &[i64],
    params: &ExtractParams,
    cast: impl Fn(i64) -> T,
) -> Mesh {
    let data = values.iter().map(|&v| cast(v)).collect();
    let vol = ArrayVolume::new(Grid::unit(dims), data).expect("volume");
    extract(&vol, params).expect("extract").0
}

/// `params` with `threads`, and pipeline options with slab depth `depth`.
fn how(
    params: &ExtractParams,
    threads: usize,
    depth: usize,
) -> (ExtractParams, PipelineOptions<'static>) {
    let p = ExtractParams {
        threads,
        ..params.clone()
    };
    let options = PipelineOptions {
        slab_depth: depth,
        ..Default::default()
    };
    (p, options)
}

/// 2^k exactly, subnormal too (`powi` may round a large negative power
/// to zero at run time).
fn pow2(k: i32) -> f64 {
    match k {
        -1074..=-1023 => f64::from_bits(1 << (k + 1074)),
        _ => f64::from_bits(((k + 1023) as u64) << 52),
    }
}

fn same(a: &Mesh, b: &Mesh) -> bool {
    let bits =
        |m: &Mesh| -> Vec<[u32; 3]> { m.vertices.iter().map(|v| v.map(f32::to_bits)).collect() };
    bits(a) == bits(b) && a.triangles == b.triangles
}

fn check_case(seed: u64) -> Result<(), String> {
    let (dims, values, iso) = case(seed);
    let mut rng = Pcg64::seed_from_u64(seed ^ 0x5eed);
    let inside = if rng.gen_bool(0.5) {
        Inside::High
    } else {
        Inside::Low
    };
    let close = rng.gen_bool(0.5);
    let params = ExtractParams {
        iso,
        inside,
        close,
        method: Method::Tmc,
        threads: 1,
        ..Default::default()
    };
    let fail = |what: String| {
        format!("seed {seed}: {what}\n  dims {dims:?} iso {iso} {inside:?} close {close} values {values:?}")
    };
    let mesh = run(dims, &values, &params, |v| v as f64);
    let report = check_mesh(&mesh);
    if !report.is_oriented_manifold() || (close && !report.is_closed_manifold()) {
        return Err(fail(format!("not a manifold: {report:?}")));
    }
    if !report.geometry.is_sound() {
        return Err(fail(report.geometry.defects()));
    }
    if close {
        // The oracle's {g > 0}: Low is the field negated about the
        // isovalue (ties stay ties); the padding is a tie.
        let as_f64: Vec<f64> = values.iter().map(|&v| v as f64).collect();
        let mut g = oracle::scaled(&as_f64, iso);
        if inside == Inside::Low {
            g.iter_mut().for_each(|v| *v = -*v);
        }
        let (pdims, g) = oracle::padded(dims, &g, 1, 0);
        compare_with_oracle(&report, &oracle::topology(pdims, &g)).map_err(&fail)?;
    }
    // Every sample type that holds the values gives the same bits.
    let fits = |lo: i64, hi: i64| values.iter().all(|&v| (lo..=hi).contains(&v));
    let mut typed: Vec<(&str, Mesh)> = vec![("f32", run(dims, &values, &params, |v| v as f32))];
    if fits(0, 255) {
        typed.push(("u8", run(dims, &values, &params, |v| v as u8)));
        typed.push(("u16", run(dims, &values, &params, |v| v as u16)));
        typed.push(("u32", run(dims, &values, &params, |v| v as u32)));
    }
    typed.push(("i8", run(dims, &values, &params, |v| v as i8)));
    typed.push(("i16", run(dims, &values, &params, |v| v as i16)));
    typed.push(("i32", run(dims, &values, &params, |v| v as i32)));
    for (name, m) in &typed {
        if !same(m, &mesh) {
            return Err(fail(format!("{name} differs from f64")));
        }
    }
    // Other threads and slab depths give the same bits.
    let vol = ArrayVolume::new(Grid::unit(dims), values.iter().map(|&v| v as f64).collect())
        .expect("volume");
    for (threads, depth) in [(3, 1), (2, 2), (2, 5)] {
        let mut builder = MeshBuilder::default();
        let (p, options) = how(&params, threads, depth);
        extract_to(&vol as &dyn SampleSource, &p, &options, &mut builder).expect("extract");
        if !same(&builder.into_mesh(), &mesh) {
            return Err(fail(format!("threads {threads} slab depth {depth} differ")));
        }
    }
    Ok(())
}

#[test]
#[ignore = "a long random search: TMC_SOAK_CASES=N cargo test --release --test surface soak -- --ignored"]
fn soak_random_tie_volumes() {
    search(check_case);
}

/// The field of [`case`] moved to the ends of each sample type's range
/// (scaled by a power of two, or offset by a whole number, the isovalue
/// with it): exact in the type, so the surface is the same one, with the
/// same topology and the same vertices (the vertex of an edge is
/// `(iso - a) / (b - a)` along it, unchanged by either move).
fn check_moved(seed: u64) -> Result<(), String> {
    let (dims, values, iso) = case(seed);
    let mut rng = Pcg64::seed_from_u64(seed ^ 0x3070);
    let close = rng.gen_bool(0.5);
    let params = ExtractParams {
        iso,
        close,
        method: Method::Tmc,
        threads: 1,
        ..Default::default()
    };
    let mesh = run(dims, &values, &params, |v| v as f64);
    let base = check_mesh(&mesh);
    let fail = |what: String| {
        format!("seed {seed}: {what}\n  dims {dims:?} iso {iso} close {close} values {values:?}")
    };
    let p = |iso: f64| ExtractParams {
        iso,
        ..params.clone()
    };
    let moved: Vec<(String, Mesh)> = vec![
        {
            let k = [-1066, -600, 300, 1015][rng.gen_range(0..4)];
            let s = pow2(k);
            (
                format!("f64 x 2^{k}"),
                run(dims, &values, &p(iso * s), |v| v as f64 * s),
            )
        },
        {
            let o = pow2(49);
            (
                "f64 + 2^49".into(),
                run(dims, &values, &p(iso + o), |v| v as f64 + o),
            )
        },
        {
            let k = [-139, -60, 60, 120][rng.gen_range(0..4)];
            let s = pow2(k);
            (
                format!("f32 x 2^{k}"),
                run(dims, &values, &p(iso * s), |v| (v as f64 * s) as f32),
            )
        },
        {
            let o = 4_294_967_289i64;
            (
                "u32 + 2^32 - 7".into(),
                run(dims, &values, &p(iso + o as f64), |v| (v + o) as u32),
            )
        },
        {
            let o = i64::from(i32::MIN) + 6;
            (
                "i32 from its least".into(),
                run(dims, &values, &p(iso + o as f64), |v| (v + o) as i32),
            )
        },
        (
            "i32 x 2^27".into(),
            run(dims, &values, &p(iso * pow2(27)), |v| (v << 27) as i32),
        ),
        (
            "u16 + 65529".into(),
            run(dims, &values, &p(iso + 65529.0), |v| (v + 65529) as u16),
        ),
    ];
    for (name, m) in &moved {
        let r = check_mesh(m);
        let topo = |r: &tmc::check::MeshReport| {
            (
                r.components,
                r.euler,
                r.boundary_edges,
                r.is_oriented_manifold(),
            )
        };
        if topo(&r) != topo(&base) || m.triangles != mesh.triangles {
            return Err(fail(format!(
                "{name}: {:?} triangles {} against {:?} triangles {}",
                topo(&r),
                m.triangles.len(),
                topo(&base),
                mesh.triangles.len()
            )));
        }
        if !name.starts_with("f") && !same(m, &mesh) {
            return Err(fail(format!("{name}: other vertices")));
        }
    }
    Ok(())
}

#[test]
#[ignore = "a long random search: TMC_SOAK_CASES=N cargo test --release --test surface soak -- --ignored"]
fn soak_moved_to_the_ends_of_each_type() {
    search(check_moved);
}

/// A random label map (values from -2 to 4, plateaus likely) through the
/// one label pass, against a separate extraction of each label's 0/1
/// indicator at 0.5, with or without `--close` and normals, and the pass
/// itself with other threads and slab depths.
fn check_labels(seed: u64) -> Result<(), String> {
    let (dims, mut values, _) = case(seed);
    let mut rng = Pcg64::seed_from_u64(seed ^ 0x1abe1);
    values.iter_mut().for_each(|v| *v = (*v).clamp(-2, 4));
    let close = rng.gen_bool(0.5);
    let normals = rng.gen_bool(0.3);
    let mut labels: Vec<i64> = values.iter().copied().filter(|&v| v != 0).collect();
    labels.sort_unstable();
    labels.dedup();
    if labels.is_empty() {
        return Ok(());
    }
    let fail = |what: String| {
        format!("seed {seed}: {what}\n  dims {dims:?} close {close} normals {normals} values {values:?}")
    };
    let grid = Grid::unit(dims);
    let map = ArrayVolume::new(grid, values.iter().map(|&v| v as i16).collect()).expect("map");
    let params = ExtractParams {
        close,
        normals,
        threads: 1,
        ..Default::default()
    };
    let pass = |threads: usize, depth: usize| -> Vec<Mesh> {
        let mut builders: Vec<MeshBuilder> =
            labels.iter().map(|_| MeshBuilder::default()).collect();
        let mut sinks: Vec<&mut dyn tmc::MeshSink> = builders
            .iter_mut()
            .map(|b| b as &mut dyn tmc::MeshSink)
            .collect();
        let (p, options) = how(&params, threads, depth);
        tmc::stream::extract_labels_to(&map, &labels, &p, &options, None, &mut sinks)
            .expect("labels");
        builders.into_iter().map(MeshBuilder::into_mesh).collect()
    };
    let one = pass(1, 0);
    for (label, mesh) in labels.iter().zip(&one) {
        let indicator: Vec<u8> = values.iter().map(|&v| u8::from(v == *label)).collect();
        let vol = ArrayVolume::new(grid, indicator).expect("indicator");
        let p = ExtractParams {
            iso: 0.5,
            ..params.clone()
        };
        let expect = extract(&vol, &p).expect("indicator").0;
        let normal_bits = |m: &Mesh| -> Option<Vec<[u32; 3]>> {
            let bits = |n: &Vec<[f32; 3]>| n.iter().map(|n| n.map(f32::to_bits)).collect();
            m.normals.as_ref().map(bits)
        };
        if !same(mesh, &expect) || normal_bits(mesh) != normal_bits(&expect) {
            return Err(fail(format!("label {label} differs from its indicator's")));
        }
    }
    for (threads, depth) in [(3, 1), (2, 3)] {
        let other = pass(threads, depth);
        if other.iter().zip(&one).any(|(a, b)| !same(a, b)) {
            return Err(fail(format!("threads {threads} slab depth {depth} differ")));
        }
    }
    Ok(())
}

#[test]
#[ignore = "a long random search: TMC_SOAK_CASES=N cargo test --release --test surface soak -- --ignored"]
fn soak_label_maps_against_their_indicators() {
    search(check_labels);
}
