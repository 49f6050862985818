//! Vertex normals computed in the slab loop (`ExtractParams::normals`):
//! accuracy against analytic normals, orientation on every kind of grid,
//! `close`, ties, the triangles' normals where the gradient vanishes,
//! determinism across threads, slab depths and parts.

use tmc::{
    extract, extract_part_to, ArrayVolume, ExtractParams, Grid, Inside, Mesh, MeshBuilder,
    PipelineOptions,
};

/// The field `f` sampled at the world positions of `grid`'s samples.
fn sampled(grid: Grid, f: impl Fn([f64; 3]) -> f64) -> ArrayVolume {
    let [nx, ny, nz] = grid.dims;
    let mut data = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                data.push(f(grid.world([x as f64, y as f64, z as f64])));
            }
        }
    }
    ArrayVolume::new(grid, data).unwrap()
}

fn params(iso: f64, inside: Inside, close: bool, threads: usize) -> ExtractParams {
    ExtractParams {
        iso,
        inside,
        close,
        threads,
        normals: true,
        ..Default::default()
    }
}

/// The mesh of `source` and its normals, every normal unit or zero.
fn mesh_and_normals(source: &ArrayVolume, p: &ExtractParams) -> (Mesh, Vec<[f32; 3]>) {
    let (mesh, _) = extract(source, p).unwrap();
    assert!(!mesh.vertices.is_empty());
    let normals = mesh.normals.clone().expect("normals");
    assert_eq!(normals.len(), mesh.vertices.len());
    for n in &normals {
        let len = n.iter().map(|&c| f64::from(c).powi(2)).sum::<f64>().sqrt();
        assert!(
            *n == [0.0; 3] || (len - 1.0).abs() < 1e-5,
            "normal {n:?} is neither unit nor zero"
        );
    }
    (mesh, normals)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = dot(v, v).sqrt();
    v.map(|c| c / l)
}

fn wide(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

/// Angles in degrees between the normals and `expected(vertex)`, sorted.
fn angles(mesh: &Mesh, normals: &[[f32; 3]], expected: impl Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
    let mut a: Vec<f64> = mesh
        .vertices
        .iter()
        .zip(normals)
        .map(|(&v, &n)| {
            let e = unit(expected(wide(v)));
            dot(wide(n), e).clamp(-1.0, 1.0).acos().to_degrees()
        })
        .collect();
    a.sort_by(f64::total_cmp);
    a
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let i = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[i]
}

/// The angle-weighted normals of the triangles around each vertex (an
/// independent outward reference: triangles are CCW seen from outside).
fn triangle_normals(mesh: &Mesh) -> Vec<[f64; 3]> {
    let mut sums = vec![[0.0; 3]; mesh.vertices.len()];
    for t in &mesh.triangles {
        let p = t.map(|v| wide(mesh.vertices[v as usize]));
        let e1 = [0, 1, 2].map(|a| p[1][a] - p[0][a]);
        let e2 = [0, 1, 2].map(|a| p[2][a] - p[0][a]);
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        for &v in t {
            for a in 0..3 {
                sums[v as usize][a] += n[a];
            }
        }
    }
    sums
}

/// Six times the signed volume the mesh encloses: positive when its
/// triangles are counter-clockwise seen from outside.
fn signed_volume(mesh: &Mesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| wide(mesh.vertices[v as usize]));
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum()
}

/// A grid with anisotropic spacing, a non-zero origin and `direction`.
fn grid(dims: [usize; 3], direction: [[f64; 3]; 3]) -> Grid {
    Grid {
        dims,
        spacing: [0.7, 1.0, 1.3],
        origin: [-12.0, 5.0, 31.0],
        direction,
    }
}

/// The centre of `g`'s box in the world.
fn centre(g: &Grid) -> [f64; 3] {
    g.world(g.dims.map(|d| (d as f64 - 1.0) / 2.0))
}

const R: f64 = 18.0;

/// A ball of radius `R` (world units) around the centre of `g`, positive
/// inside; its outward normal at `v`.
fn ball(g: Grid) -> (ArrayVolume, impl Fn([f64; 3]) -> [f64; 3]) {
    let c = centre(&g);
    let vol = sampled(g, move |p| R - dot(sub(p, c), sub(p, c)).sqrt());
    (vol, move |v| sub(v, c))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[test]
fn sphere_normals_match_the_analytic_ones() {
    let (vol, outward) = ball(grid([64, 48, 36], tmc::volume::IDENTITY));
    let (mesh, normals) = mesh_and_normals(&vol, &params(0.0, Inside::High, false, 0));
    let a = angles(&mesh, &normals, &outward);
    let (p99, max) = (percentile(&a, 0.99), a[a.len() - 1]);
    println!(
        "sphere: {} vertices, p99 {p99:.4} deg, max {max:.4} deg",
        a.len()
    );
    // Measured p99 0.070 deg, max 0.076 deg.
    assert!(p99 < 0.2, "p99 {p99}");
    assert!(max < 0.3, "max {max}");
}

#[test]
fn gyroid_normals_match_the_analytic_gradient() {
    let g = grid([60, 60, 60], tmc::volume::IDENTITY);
    let k = 0.25;
    let vol = sampled(g, move |p| {
        let [x, y, z] = p.map(|c| c * k);
        x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
    });
    // Outward is down the gradient (inside is high).
    let outward = move |p: [f64; 3]| {
        let [x, y, z] = p.map(|c| c * k);
        [
            x.cos() * y.cos() - z.sin() * x.sin(),
            -x.sin() * y.sin() + y.cos() * z.cos(),
            -y.sin() * z.sin() + z.cos() * x.cos(),
        ]
        .map(|c| -c)
    };
    let (mesh, normals) = mesh_and_normals(&vol, &params(0.0, Inside::High, false, 0));
    let a = angles(&mesh, &normals, outward);
    let p99 = percentile(&a, 0.99);
    println!(
        "gyroid: {} vertices, p99 {p99:.4} deg, max {:.4} deg",
        a.len(),
        a[a.len() - 1]
    );
    // Measured 3.38 deg: about 19 samples per period along z, where
    // central differences are off by a few percent.
    assert!(p99 < 4.5, "p99 {p99}");
}

#[test]
fn inside_low_flips_the_normals() {
    let g = grid([40, 40, 40], tmc::volume::IDENTITY);
    let (vol, outward) = ball(g);
    // The same data, the other side inside: the outside of the ball is the
    // object, so its outward normals point to the centre.
    let (mesh, normals) = mesh_and_normals(&vol, &params(0.0, Inside::Low, false, 0));
    let inward = angles(&mesh, &normals, |v| outward(v).map(|c| -c));
    assert!(
        percentile(&inward, 0.99) < 1.0,
        "{}",
        percentile(&inward, 0.99)
    );
    // A distance field positive outside, inside low: the ball again.
    let c = centre(&g);
    let dist = sampled(g, move |p| dot(sub(p, c), sub(p, c)).sqrt() - R);
    let (mesh, normals) = mesh_and_normals(&dist, &params(0.0, Inside::Low, false, 0));
    let a = angles(&mesh, &normals, &outward);
    assert!(percentile(&a, 0.99) < 1.0, "{}", percentile(&a, 0.99));
}

/// Normals point outward on mirrored and oblique grids, and the mesh
/// itself is oriented outward there too (so the triangle fallback is).
#[test]
fn mirrored_and_oblique_grids_keep_normals_outward() {
    let s = (0.5f64).sqrt();
    let mirrored = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
    let swapped = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    // Columns of unit length, not orthogonal (x and y axes 45 degrees apart).
    let oblique = [[1.0, s, 0.0], [0.0, s, 0.0], [0.0, 0.0, 1.0]];
    let oblique_mirrored = [[1.0, s, 0.0], [0.0, -s, 0.0], [0.0, 0.0, 1.0]];
    for (name, d) in [
        ("mirrored", mirrored),
        ("swapped", swapped),
        ("oblique", oblique),
        ("oblique mirrored", oblique_mirrored),
    ] {
        let g = grid([64, 64, 40], d);
        let (vol, outward) = ball(g);
        for inside in [Inside::High, Inside::Low] {
            let p = params(0.0, inside, false, 0);
            let (mesh, normals) = mesh_and_normals(&vol, &p);
            let volume = signed_volume(&mesh);
            let flip = if inside == Inside::High { 1.0 } else { -1.0 };
            assert!(flip * volume > 0.0, "{name}: mesh oriented inward");
            let a = angles(&mesh, &normals, |v| outward(v).map(|c| flip * c));
            let p99 = percentile(&a, 0.99);
            println!(
                "{name} {inside:?}: mirrored {}, p99 {p99:.4} deg",
                g.is_mirrored()
            );
            assert!(a[a.len() - 1] < 90.0, "{name}: a normal points inward");
            // Measured 0.070 deg (mirrored, swapped), 0.348 deg (oblique).
            assert!(p99 < 0.6, "{name}: p99 {p99}");
        }
    }
}

#[test]
fn close_caps_get_finite_outward_normals() {
    // A ball cut by the box: every face of the box is a cap.
    let g = grid([30, 26, 20], tmc::volume::IDENTITY);
    let c = centre(&g);
    let vol = sampled(g, move |p| 16.0 - dot(sub(p, c), sub(p, c)).sqrt());
    let (mesh, normals) = mesh_and_normals(&vol, &params(0.0, Inside::High, true, 0));
    // The body is convex, so an outward normal at `v` makes an acute angle
    // with `v - c`.
    for (v, n) in mesh.vertices.iter().zip(&normals) {
        assert!(n.iter().all(|c| c.is_finite()));
        assert!(*n != [0.0; 3], "a zero normal at {v:?}");
        assert!(dot(wide(*n), sub(wide(*v), c)) > 0.0, "{n:?} at {v:?}");
    }
    // NaN samples in the data are ties too.
    let mut data = vol.data().to_vec();
    data[0] = f64::NAN;
    let holed = ArrayVolume::new(g, data).unwrap();
    let (_, normals) = mesh_and_normals(&holed, &params(0.0, Inside::High, true, 0));
    assert!(normals.iter().flatten().all(|c| c.is_finite()));
}

/// The normals of `source` for part `part` (`None`: all) with `threads`
/// and slabs of `depth` layers.
fn normals_of(
    source: &dyn tmc::SampleSource,
    p: &ExtractParams,
    depth: usize,
    part: Option<(usize, usize)>,
) -> Vec<[f32; 3]> {
    let mut builder = MeshBuilder::default();
    let options = PipelineOptions {
        slab_depth: depth,
        ..Default::default()
    };
    extract_part_to(source, p, &options, part, &mut builder).unwrap();
    let mesh = builder.into_mesh();
    let normals = mesh.normals.expect("normals");
    assert_eq!(normals.len(), mesh.vertices.len());
    normals
}

fn bits(n: &[[f32; 3]]) -> Vec<u32> {
    n.iter().flatten().map(|c| c.to_bits()).collect()
}

#[test]
fn threads_slabs_and_parts_do_not_change_the_normals() {
    let vol = tmc::synth::gyroid(64, 4.0);
    let whole = normals_of(&vol, &params(0.1, Inside::High, false, 1), 0, None);
    assert!(whole.len() > 20_000, "{} vertices", whole.len());
    for (threads, depth) in [(2, 1), (3, 5), (0, 64), (2, 7)] {
        let p = params(0.1, Inside::High, false, threads);
        assert_eq!(bits(&whole), bits(&normals_of(&vol, &p, depth, None)));
    }
    for n in [2, 3, 7] {
        let p = params(0.1, Inside::High, false, 2);
        let parts: Vec<[f32; 3]> = (1..=n)
            .flat_map(|i| normals_of(&vol, &p, 3, Some((i, n))))
            .collect();
        assert_eq!(bits(&whole), bits(&parts), "{n} parts");
    }
}

/// Planes of 0 and 1 alternating along x: at iso 0.5 every vertex sits
/// between two samples whose central differences along x are 0, so the
/// gradient vanishes everywhere and every normal comes from the
/// triangles, across chunk, slab and part boundaries alike.
#[test]
fn where_the_gradient_vanishes_the_triangles_give_the_normal() {
    let (nx, ny, nz) = (9, 7, 12);
    let data: Vec<u8> = (0..nx * ny * nz).map(|i| (i % nx % 2) as u8).collect();
    let vol = ArrayVolume::new(Grid::unit([nx, ny, nz]), data).unwrap();
    let p = params(0.5, Inside::High, false, 1);
    let (mesh, _) = extract(&vol, &p).unwrap();
    assert!(!mesh.vertices.is_empty());
    let normals = mesh.normals.as_deref().expect("normals");
    assert_eq!(normals.len(), mesh.vertices.len());
    for (v, n) in mesh.vertices.iter().zip(normals) {
        // Inside (1) at odd x: out is toward the even neighbour.
        let x = v[0].round() as usize;
        let expected = if v[0] > x as f32 { 1.0 } else { -1.0 };
        let expected = if x % 2 == 1 { expected } else { -expected };
        assert_eq!(n[0], expected, "{n:?} at {v:?}");
        assert_eq!([n[1], n[2]], [0.0, 0.0], "{n:?} at {v:?}");
    }
    let whole = bits(normals);
    for depth in [1, 2, 5] {
        let p = params(0.5, Inside::High, false, 2);
        assert_eq!(whole, bits(&normals_of(&vol, &p, depth, None)));
        let parts: Vec<[f32; 3]> = (1..=4)
            .flat_map(|i| normals_of(&vol, &p, depth, Some((i, 4))))
            .collect();
        assert_eq!(whole, bits(&parts), "depth {depth}");
    }
}

#[test]
fn ties_on_a_plateau_point_out_of_the_gap() {
    // Two blocks of ones, one sample apart, in zeros; iso 0, so the
    // vertices sit 2^-10 of an edge from the zero samples (ties), and
    // those of the gap between the blocks, beside samples whose
    // neighbours are 1 on both sides (no gradient there), have a gradient
    // of about 2^-10 of the blocks' that must still point the right way
    // (where it vanished, the triangles' normals would stand in).
    let n = 20;
    let block = |x: usize, y: usize, z: usize| {
        let inner = (4..16).contains(&y) && (4..16).contains(&z);
        inner && ((3..9).contains(&x) || (10..17).contains(&x))
    };
    let data: Vec<u8> = (0..n * n * n)
        .map(|i| u8::from(block(i % n, (i / n) % n, i / (n * n))))
        .collect();
    let vol = ArrayVolume::new(Grid::unit([n; 3]), data).unwrap();
    let p = ExtractParams {
        normals: true,
        ..Default::default()
    };
    let (mesh, _) = extract(&vol, &p).unwrap();
    let normals = mesh.normals.clone().expect("normals");
    let reference = triangle_normals(&mesh);
    let mut in_gap = 0;
    for ((v, n), r) in mesh.vertices.iter().zip(&normals).zip(&reference) {
        let len = n.iter().map(|&c| c * c).sum::<f32>().sqrt();
        assert!(*n == [0.0; 3] || (len - 1.0).abs() < 1e-5, "{n:?}");
        if dot(*r, *r) > 0.0 && *n != [0.0; 3] {
            assert!(dot(wide(*n), *r) > 0.0, "{n:?} at {v:?} against {r:?}");
        }
        let inner = (5.0..14.0).contains(&v[1]) && (5.0..14.0).contains(&v[2]);
        if (v[0] - 9.0).abs() <= 1.0 / 512.0 && inner {
            in_gap += 1;
            assert!(n[0].abs() > 0.99, "{n:?} at {v:?}");
        }
    }
    assert!(in_gap > 0, "no vertex in the gap");
}

#[test]
fn without_normals_the_mesh_has_none_and_is_unchanged() {
    let vol = tmc::synth::sphere(24, 8.0);
    let with = params(0.0, Inside::High, false, 0);
    let without = ExtractParams {
        normals: false,
        ..with.clone()
    };
    let (a, _) = extract(&vol, &with).unwrap();
    let (b, _) = extract(&vol, &without).unwrap();
    assert!(b.normals.is_none());
    assert_eq!((&a.vertices, &a.triangles), (&b.vertices, &b.triangles));
    // No surface: no vertices, and normals of none (the mesh has them,
    // as its file declares them).
    let (empty, _) = extract(&vol, &params(100.0, Inside::High, false, 0)).unwrap();
    assert!(empty.vertices.is_empty() && empty.normals == Some(Vec::new()));
}

/// Gradients too small or too large to square in `f64` (the distance
/// from a point scaled by `2^-530` or `2^530`, exact in binary) take the
/// normalization's slow path, among batches of vertices whose gradients
/// are ordinary: the mesh is the unscaled field's to the bit and every
/// normal is that field's, up to the rounding of the other path.
#[test]
fn tiny_and_huge_gradients_keep_their_normals() {
    let grid = Grid::unit([26, 22, 19]);
    let distance = |p: [f64; 3]| {
        let d = sub(p, [12.3, 10.6, 9.2]);
        dot(d, d).sqrt()
    };
    let plain = sampled(grid, distance);
    let (mesh, normals) = mesh_and_normals(&plain, &params(7.5, Inside::Low, false, 1));
    assert!(
        mesh.vertices.len() > 1_000,
        "{} vertices",
        mesh.vertices.len()
    );
    for scale in [2f64.powi(-530), 2f64.powi(530)] {
        let scaled = sampled(grid, |p| distance(p) * scale);
        let p = params(7.5 * scale, Inside::Low, false, 1);
        let (m, n) = mesh_and_normals(&scaled, &p);
        assert_eq!(m.vertices, mesh.vertices, "scale {scale:e}");
        assert_eq!(m.triangles, mesh.triangles, "scale {scale:e}");
        for (i, (a, b)) in normals.iter().zip(&n).enumerate() {
            let off = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f32::max);
            assert!(off < 1e-6, "vertex {i}: {a:?} and {b:?} at scale {scale:e}");
        }
    }
}
