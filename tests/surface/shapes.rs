//! Smooth shapes with known topology, geometry of the vertices, standard MC
//! beside TMC, and properties of the pipeline (threads, --close, --inside,
//! physical coordinates).

use tmc::check::check_mesh;
use tmc::{
    extract, extract_to, synth, ArrayVolume, ExtractParams, Grid, Inside, Mesh, MeshBuilder,
    Method, PipelineOptions, SampleSource,
};

fn params(close: bool) -> ExtractParams {
    ExtractParams {
        iso: 0.0,
        close,
        threads: 1,
        ..Default::default()
    }
}

fn closed_euler(vol: &ArrayVolume) -> (usize, i64) {
    let (mesh, _) = extract(vol, &params(true)).expect("extract");
    let r = check_mesh(&mesh);
    assert!(r.is_closed_manifold(), "{r:?}");
    (r.components, r.euler)
}

#[test]
fn sphere_torus_and_genus_three() {
    assert_eq!(closed_euler(&synth::sphere(24, 8.7)), (1, 2));
    assert_eq!(closed_euler(&synth::torus(40, 11.0, 4.2)), (1, 0));
    assert_eq!(closed_euler(&synth::three_holes()), (1, -4));
}

/// Trilinear interpolant of a volume with unit spacing at a point.
fn interpolate(vol: &ArrayVolume, p: [f64; 3]) -> f64 {
    let [nx, ny, nz] = vol.grid().dims;
    let d = vol.data();
    let i = [0, 1, 2].map(|k| (p[k].floor() as usize).min([nx, ny, nz][k] - 2));
    let t = [0, 1, 2].map(|k| p[k] - i[k] as f64);
    let mut v = 0.0;
    for c in 0..8 {
        let o = [c & 1, c >> 1 & 1, c >> 2 & 1];
        let w: f64 = (0..3)
            .map(|k| if o[k] == 1 { t[k] } else { 1.0 - t[k] })
            .product();
        v += w * d[(i[0] + o[0]) + nx * ((i[1] + o[1]) + ny * (i[2] + o[2]))];
    }
    v
}

#[test]
fn edge_vertices_lie_on_the_level_set() {
    for vol in [
        synth::gyroid(48, 3.0),
        synth::noise(32, 5, 1),
        synth::noise(24, 6, 0),
    ] {
        let range = vol.data().iter().fold(0.0f64, |m, v| m.max(v.abs())) * 2.0;
        let (mesh, _) = extract(&vol, &params(false)).expect("extract");
        let mut on_edges = 0;
        for v in &mesh.vertices {
            let p = v.map(f64::from);
            // Vertices on grid edges have two integer coordinates.
            if p.iter().filter(|c| c.fract() == 0.0).count() >= 2 {
                on_edges += 1;
                let err = interpolate(&vol, p).abs();
                // On an edge that ends at a tie (a sample at the isovalue)
                // the vertex keeps 2^-10 of the edge from it: on the level
                // of 2^-10 of the other end's value above the isovalue.
                let tie = p
                    .iter()
                    .any(|c| [1.0 / 1024.0, 1023.0 / 1024.0].contains(&c.fract()));
                let bound = if tie { range / 1024.0 } else { 1e-5 * range };
                assert!(err < bound, "vertex {p:?}: |T - iso| = {err}");
            }
        }
        assert!(on_edges > mesh.vertices.len() / 2);
    }
}

#[test]
fn standard_mc_differs_on_ambiguous_cells() {
    // MC case 4 with a strong tunnel: TMC joins the two corners, MC cannot.
    let cell = vec![10.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 10.0];
    let vol = ArrayVolume::new(Grid::unit([2, 2, 2]), cell).expect("volume");
    let tmc = check_mesh(&extract(&vol, &params(true)).expect("tmc").0);
    let mut p = params(true);
    p.method = Method::Mc;
    let mc = check_mesh(&extract(&vol, &p).expect("mc").0);
    assert!(tmc.is_closed_manifold() && mc.is_closed_manifold());
    assert_eq!((tmc.components, tmc.euler), (1, 2));
    assert_eq!((mc.components, mc.euler), (2, 4));
    // On noise the two disagree in topology, and MC stays a closed manifold.
    let noise = synth::noise(24, 11, 0);
    let tmc = check_mesh(&extract(&noise, &params(true)).expect("tmc").0);
    let mc = check_mesh(&extract(&noise, &p).expect("mc").0);
    assert!(mc.is_closed_manifold(), "{mc:?}");
    assert_ne!((tmc.components, tmc.euler), (mc.components, mc.euler));
}

#[test]
fn output_does_not_depend_on_threads_or_slab_depth() {
    for (vol, close) in [
        (synth::noise(40, 9, 1), false),
        (synth::noise(17, 3, 0), true),
    ] {
        let mut p = params(close);
        let one = extract(&vol, &p).expect("1 thread").0;
        assert!(check_mesh(&one).non_manifold_edges == 0);
        for threads in [1, 2, 3] {
            for depth in [1, 2, 7, 64] {
                p.threads = threads;
                let options = PipelineOptions {
                    slab_depth: depth,
                    ..Default::default()
                };
                let mut builder = MeshBuilder::default();
                let stats = extract_to(&vol, &p, &options, &mut builder).expect("extract");
                assert!(
                    builder.into_mesh() == one,
                    "{threads} threads, depth {depth}"
                );
                assert_eq!(stats.triangles as usize, one.triangles.len());
            }
        }
    }
}

/// A source that pads another with NaN by hand, to compare with `--close`.
fn padded_with_nan(vol: &ArrayVolume) -> ArrayVolume {
    let [nx, ny, nz] = vol.grid().dims;
    let d = vol.data();
    let mut out = ArrayVolume::from_fn([nx + 2, ny + 2, nz + 2], |x, y, z| {
        if x == 0 || y == 0 || z == 0 || x > nx || y > ny || z > nz {
            f64::NAN
        } else {
            d[(x - 1) + nx * ((y - 1) + ny * (z - 1))]
        }
    });
    let g = *out.grid();
    let shifted = Grid {
        origin: [-1.0; 3],
        ..g
    };
    out = ArrayVolume::new(shifted, out.data().to_vec()).expect("volume");
    out
}

#[test]
fn close_is_padding_with_outside_samples() {
    let vol = synth::noise(12, 4, 0);
    let closed = extract(&vol, &params(true)).expect("close").0;
    let padded = extract(&padded_with_nan(&vol), &params(false))
        .expect("padded")
        .0;
    assert!(closed == padded);
    assert!(check_mesh(&closed).is_closed_manifold());
}

fn signed_volume(m: &Mesh) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.vertices[i as usize].map(f64::from));
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum::<f64>()
        / 6.0
}

#[test]
fn normals_point_outside_and_inside_low_flips_the_roles() {
    // A ball of high values: outward normals give a positive enclosed volume.
    let ball = synth::sphere(20, 6.0);
    let m = extract(&ball, &params(true)).expect("ball").0;
    let v = signed_volume(&m);
    assert!(
        (v - 4.0 / 3.0 * std::f64::consts::PI * 216.0).abs() < 0.05 * v,
        "volume {v}"
    );
    // The same ball as a signed distance field (negative inside) with --inside low.
    let sdf =
        ArrayVolume::new(*ball.grid(), ball.data().iter().map(|v| -v).collect()).expect("sdf");
    let mut p = params(true);
    p.inside = Inside::Low;
    let low = extract(&sdf, &p).expect("low").0;
    assert!(low == m);
}

#[test]
fn coordinates_are_physical() {
    let ball = synth::sphere(12, 4.0);
    let grid = Grid {
        dims: [12, 12, 12],
        spacing: [0.5, 2.0, 3.0],
        origin: [10.0, -5.0, 1.0],
        direction: tmc::volume::IDENTITY,
    };
    let vol = ArrayVolume::new(grid, ball.data().to_vec()).expect("volume");
    let unit = extract(&ball, &params(false)).expect("unit").0;
    let phys = extract(&vol, &params(false)).expect("physical").0;
    assert_eq!(unit.triangles, phys.triangles);
    for (u, p) in unit.vertices.iter().zip(&phys.vertices) {
        for k in 0..3 {
            let expect = grid.origin[k] + f64::from(u[k]) * grid.spacing[k];
            assert!((f64::from(p[k]) - expect).abs() < 1e-4);
        }
    }
}

#[test]
fn nan_samples_are_outside_like_ties() {
    let noise = synth::noise(14, 21, 0);
    let with_nan: Vec<f64> = noise
        .data()
        .iter()
        .enumerate()
        .map(|(i, &v)| if i % 7 == 0 { f64::NAN } else { v })
        .collect();
    let at_iso: Vec<f64> = with_nan
        .iter()
        .map(|v| if v.is_nan() { 0.0 } else { *v })
        .collect();
    let a = ArrayVolume::new(*noise.grid(), with_nan).expect("nan");
    let b = ArrayVolume::new(*noise.grid(), at_iso).expect("iso");
    let ma = extract(&a, &params(true)).expect("nan").0;
    assert!(ma == extract(&b, &params(true)).expect("iso").0);
    assert!(ma.vertices.iter().flatten().all(|c| c.is_finite()));
    assert!(check_mesh(&ma).is_closed_manifold());
}

#[test]
fn rotations_and_reflections_map_vertices_and_keep_normals_outward() {
    let ball = synth::sphere(12, 4.0);
    let unit = extract(&ball, &params(true)).expect("unit").0;
    let (c, s) = (0.6f64, 0.8f64);
    let rotation = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    let reflection = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for direction in [rotation, reflection] {
        let grid = Grid {
            dims: [12; 3],
            spacing: [0.5, 2.0, 3.0],
            origin: [10.0, -5.0, 1.0],
            direction,
        };
        let vol = ArrayVolume::new(grid, ball.data().to_vec()).expect("volume");
        let mesh = extract(&vol, &params(true)).expect("mapped").0;
        assert_eq!(mesh.vertices.len(), unit.vertices.len());
        for (u, p) in unit.vertices.iter().zip(&mesh.vertices) {
            // The unit mesh's --close padding starts at -1: its coordinates
            // are grid indices.
            let w = grid.world(u.map(f64::from));
            for k in 0..3 {
                assert!(
                    (f64::from(p[k]) - w[k]).abs() < 1e-4,
                    "{u:?} -> {p:?} vs {w:?}"
                );
            }
        }
        assert!(
            signed_volume(&mesh) > 0.0,
            "normals point inward for {direction:?}"
        );
        assert!(check_mesh(&mesh).is_closed_manifold());
    }
}

#[test]
fn inside_low_on_a_mirrored_grid_keeps_normals_outward() {
    // An off-centre ball, so that a wrong reflection moves the vertices.
    let ball = ArrayVolume::from_fn([11, 9, 8], |x, y, z| {
        9.0 - ((x as f64 - 4.3).powi(2) + (y as f64 - 3.6).powi(2) + (z as f64 - 3.2).powi(2))
    });
    let sdf =
        ArrayVolume::new(*ball.grid(), ball.data().iter().map(|v| -v).collect()).expect("sdf");
    // A rotation about z composed with a reflection of y: determinant -1.
    let (c, s) = (0.6f64, 0.8f64);
    let grid = Grid {
        dims: [11, 9, 8],
        spacing: [0.5, 2.0, 3.0],
        origin: [10.0, -5.0, 1.0],
        direction: [[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, 1.0]],
    };
    assert!(grid.is_mirrored());
    let mut low = params(true);
    low.inside = Inside::Low;
    let unit = extract(&sdf, &low).expect("unit").0;
    let mirrored = ArrayVolume::new(grid, sdf.data().to_vec()).expect("volume");
    let mesh = extract(&mirrored, &low).expect("mirrored").0;
    // The two flips (low values inside, a mirroring map) do not cancel:
    // the mirror reverses every triangle, --inside low keeps normals outward.
    let reversed: Vec<[u32; 3]> = unit.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect();
    assert_eq!(mesh.triangles, reversed);
    for (u, p) in unit.vertices.iter().zip(&mesh.vertices) {
        let w = grid.world(u.map(f64::from));
        for k in 0..3 {
            assert!(
                (f64::from(p[k]) - w[k]).abs() < 1e-4,
                "{u:?} -> {p:?} vs {w:?}"
            );
        }
    }
    assert!(signed_volume(&unit) > 0.0 && signed_volume(&mesh) > 0.0);
    assert!(check_mesh(&mesh).is_closed_manifold());
    // The same surface as the high values of the ball on that grid.
    let high = ArrayVolume::new(grid, ball.data().to_vec()).expect("high");
    assert!(extract(&high, &params(true)).expect("high").0 == mesh);
}
