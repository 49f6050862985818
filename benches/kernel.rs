//! Criterion benchmarks of the kernel and the slab loop, so regressions show
//! in review: `cargo bench --bench kernel`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tmc::kernel::{triangulate_ambiguous, CellMesh, Triangles};
use tmc::{extract, synth, ExtractParams, Method, Stats};

/// Triangulates `cells` one by one, as the slab loop does.
fn triangulate_all(cells: &[([f64; 8], u8)], out: &mut CellMesh, stats: &mut Stats) {
    for (g, config) in cells {
        out.clear();
        let count = match triangulate_ambiguous(g, None, *config, stats, out) {
            Triangles::Table(fans) | Triangles::Centred(fans, _) => fans.len(),
            Triangles::Mesh => out.triangles.len(),
        };
        black_box(count);
    }
}

/// Ambiguous cells of uniform noise, triangulated one by one.
fn ambiguous_cells(c: &mut Criterion) {
    let tables = tmc::kernel::tables::tables();
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let mut cells = Vec::new();
    while cells.len() < 10_000 {
        let g: [f64; 8] = std::array::from_fn(|_| next());
        let config = (0..8).fold(0u8, |m, i| m | (u8::from(g[i] > 0.0) << i));
        if tables.is_ambiguous[config as usize] {
            cells.push((g, config));
        }
    }
    let mut out = CellMesh::new();
    let mut stats = Stats::default();
    c.bench_function("10k ambiguous cells", |b| {
        b.iter(|| triangulate_all(&cells, &mut out, &mut stats))
    });
}

/// The ambiguous cells of a real CT (cthead at 1600, from `../shared/data`
/// when present): integer values, the kernel's common case.
fn ct_ambiguous_cells(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/cthead.nrrd");
    let volume = match tmc::volume::open(&path, None) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("skipping the CT kernel benchmark: {e}");
            return;
        }
    };
    let tables = tmc::kernel::tables::tables();
    let iso = 1600.0;
    let [nx, ny, nz] = volume.grid().dims;
    let (mut low, mut high) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
    let mut cells = Vec::new();
    volume.read_plane(0, &mut low).expect("plane");
    for z in 1..nz {
        volume.read_plane(z, &mut high).expect("plane");
        for i in (0..nx * (ny - 1)).filter(|i| i % nx != nx - 1) {
            let at = [i, i + 1, i + nx, i + nx + 1];
            let g: [f64; 8] = std::array::from_fn(|c| {
                let plane = if c < 4 { &low } else { &high };
                plane[at[c % 4]] - iso
            });
            let config = (0..8).fold(0u8, |m, c| m | (u8::from(g[c] > 0.0) << c));
            if tables.is_ambiguous[config as usize] {
                cells.push((g, config));
            }
        }
        std::mem::swap(&mut low, &mut high);
    }
    let mut out = CellMesh::new();
    let mut stats = Stats::default();
    let name = format!("{} ambiguous cells of cthead @ 1600", cells.len());
    c.bench_function(&name, |b| {
        b.iter(|| triangulate_all(&cells, &mut out, &mut stats))
    });
}

/// The whole slab loop on a smooth volume and on noise, TMC and MC.
fn slab_loop(c: &mut Criterion) {
    let gyroid = synth::gyroid(96, 3.0);
    let noise = synth::noise(64, 3, 1);
    for (name, vol) in [("gyroid 96", &gyroid), ("noise 64", &noise)] {
        for method in [Method::Tmc, Method::Mc] {
            let params = ExtractParams {
                method,
                threads: 1,
                ..Default::default()
            };
            c.bench_function(&format!("{name} {method:?}"), |b| {
                b.iter(|| black_box(extract(vol, &params).expect("extract").1.triangles))
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = ambiguous_cells, ct_ambiguous_cells, slab_loop
}
criterion_main!(benches);
