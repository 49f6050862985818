//! `tmc check` of a `.tmesh` file streams its chunks: the report (text and
//! `--json`, exit status) is the one the in-memory checker gives the mesh
//! read whole (`check_mesh` of `read_mesh`, called here in the test), on
//! meshes tmc writes from synthetic and real volumes and on damaged meshes
//! written chunk by chunk; a damaged file is one error line.

use crate::common;

use common::cli::{assert_one_line, s, synth, tmc};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::path::{Path, PathBuf};
use tmc::check::{check_mesh, read_mesh};
use tmc::meshfile::{TmeshReader, TmeshWriter};
use tmc::{Chunk, Grid, MeshInfo, MeshSink, Totals};

/// Asserts that `tmc check mesh` (streamed) prints, as text and as JSON,
/// what the in-memory checker finds, with the same exit status; returns
/// the JSON report.
fn same_as_in_memory(mesh: &Path) -> serde_json::Value {
    let report = check_mesh(&read_mesh(mesh).expect("read whole"));
    let json = tmc(&["check", s(mesh), "--json"]);
    let text = tmc(&["check", s(mesh)]);
    let streamed: serde_json::Value = serde_json::from_slice(&json.stdout).expect("json");
    assert_eq!(
        streamed,
        serde_json::to_value(&report).unwrap(),
        "{}",
        mesh.display()
    );
    let mut expected = Vec::new();
    report.print_text(&mut expected).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&text.stdout),
        String::from_utf8_lossy(&expected),
        "{}",
        mesh.display()
    );
    let code = if report.is_oriented_manifold() { 0 } else { 1 };
    assert_eq!(json.status.code(), Some(code), "{json:?}");
    assert_eq!(text.status.code(), Some(code), "{text:?}");
    streamed
}

fn extract(input: &Path, out: PathBuf, args: &[&str]) -> PathBuf {
    let mut all = vec!["extract", s(input), "-o", s(&out), "-q"];
    all.extend(args);
    let run = tmc(&all);
    assert!(run.status.success(), "{all:?}: {run:?}");
    out
}

#[test]
fn streamed_reports_are_the_in_memory_ones_on_synthetic_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: &[(&str, &str, &[&str])] = &[
        ("sphere", "0.5", &["--close"]),
        ("torus", "0", &["--slab-depth", "3", "--threads", "2"]),
        ("gyroid", "0", &[]),
        ("gyroid", "0", &["--close", "--method", "mc"]),
        ("noise", "0.1", &[]),
        ("noise", "-0.2", &["--close", "--normals"]),
        ("head", "100", &[]),
        ("head", "400", &["--close"]),
    ];
    let mut several = 0;
    let mut open = 0;
    for (i, (kind, iso, args)) in cases.iter().enumerate() {
        let volume = synth(d, kind, "41,37,45", "f32", &format!("{kind}.nrrd"));
        let iso = format!("--iso={iso}");
        let mut all = vec![iso.as_str()];
        all.extend(*args);
        let mesh = extract(&volume, d.join(format!("{i}.tmesh")), &all);
        let report = same_as_in_memory(&mesh);
        assert!(report["triangles"].as_u64().unwrap() > 1000, "{kind}");
        several += usize::from(report["components"].as_u64().unwrap() > 1);
        open += usize::from(report["boundary_edges"].as_u64().unwrap() > 0);
    }
    assert!(
        several >= 3 && open >= 2,
        "{several} with several components, {open} open"
    );
    // Several labels' surfaces in one file, and an empty mesh.
    let labels = synth(d, "head", "30,28,26", "u8", "labels.nrrd");
    let all = extract(&labels, d.join("all.tmesh"), &["--labels", "all"]);
    same_as_in_memory(&all);
    let empty = extract(&labels, d.join("empty.tmesh"), &["--iso", "1000"]);
    let report = same_as_in_memory(&empty);
    assert_eq!(report["triangles"], 0);
}

#[test]
fn streamed_reports_are_the_in_memory_ones_on_real_meshes() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if !data.is_dir() {
        eprintln!("skipped: {} not found", data.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &[&str])] = &[
        ("headsq_quarter.nrrd", &["--iso", "500"]),
        ("cthead.nrrd", &["--iso", "1600"]),
        ("engine.nrrd", &["--iso", "80", "--close"]),
        ("stent_ct.nrrd", &["--iso", "600"]),
        ("hydrogen.nrrd", &["--iso", "0.01"]),
        ("carotid.nrrd", &["--iso", "100"]),
        ("sdf_bunny_128.nrrd", &["--iso", "0", "--inside", "low"]),
        ("frog_tissues.nrrd", &["--labels", "all"]),
    ];
    for (i, (file, args)) in cases.iter().enumerate() {
        let mesh = extract(
            &data.join(file),
            dir.path().join(format!("{i}.tmesh")),
            args,
        );
        same_as_in_memory(&mesh);
    }
}

/// A random number below `n`.
fn below(rng: &mut Pcg64, n: u64) -> u64 {
    rng.gen_range(0..n)
}

/// Writes a tube of `rows` rings of `ring` vertices, one chunk per ring,
/// with random damage: triangles dropped (boundary), flipped
/// (inconsistent, with `flips`), repeated corners (degenerate), a third
/// triangle on an edge (non-manifold), vertices no triangle uses, a
/// vertex at the position of another in the same or the previous ring,
/// and a triangle of collinear corners.
fn damaged_tube(path: &Path, rng: &mut Pcg64, flips: bool) {
    let (rows, ring) = (3 + below(rng, 6) as u32, 4 + below(rng, 5) as u32);
    let per = ring + 2;
    let at = |r: u32, i: u32| {
        let a = f64::from(i) * std::f64::consts::TAU / f64::from(ring);
        [a.cos() as f32, a.sin() as f32, r as f32]
    };
    let mut w = TmeshWriter::create(path).unwrap();
    w.begin(&MeshInfo {
        grid: Grid::unit([16, 16, rows as usize]),
        iso: 0.0,
        method: Default::default(),
        inside: Default::default(),
        close: false,
        normals: false,
        labels: false,
    })
    .unwrap();
    let mut base = 0u64;
    let mut triangles = 0u64;
    for r in 0..rows {
        // The ring, then a spare vertex (unused, or an extra apex) and
        // one at another vertex's position (here or the ring before).
        let mut vertices: Vec<[f32; 3]> = (0..ring).map(|i| at(r, i)).collect();
        vertices.push([5.0, 5.0, r as f32 + 0.5]);
        vertices.push(at(
            r.saturating_sub(below(rng, 2) as u32),
            below(rng, ring as u64) as u32,
        ));
        let mut tris = Vec::new();
        if r + 1 < rows {
            for i in 0..ring {
                let j = (i + 1) % ring;
                let (a, b, c, d) = (i, j, per + j, per + i);
                for mut t in [[a, b, c], [a, c, d]] {
                    match below(rng, 100) {
                        0..4 => continue,
                        4..7 if flips => t.swap(0, 1),
                        7..9 => tris.push([t[0], t[0], t[1]]),
                        9..11 => tris.push([t[0], t[1], ring]),
                        11..13 => tris.push([t[0], t[1], ring + 1]),
                        _ => {}
                    }
                    tris.push(t);
                }
            }
        }
        if below(rng, 3) == 0 {
            // Collinear corners: two ring vertices and their midpoint.
            vertices[ring as usize] = [
                (vertices[0][0] + vertices[2][0]) / 2.0,
                (vertices[0][1] + vertices[2][1]) / 2.0,
                r as f32,
            ];
            tris.push([0, 2, ring]);
        }
        let chunk = Chunk {
            plane: u64::from(r),
            vertices,
            triangles: tris,
            ..Chunk::default()
        };
        w.chunk(base, &chunk).unwrap();
        base += u64::from(per);
        triangles += chunk.triangles.len() as u64;
    }
    w.finish(&Totals {
        vertices: base,
        triangles,
        chunks: u64::from(rows),
    })
    .unwrap();
}

#[test]
fn streamed_reports_are_the_in_memory_ones_on_damaged_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Pcg64::seed_from_u64(11);
    let (mut defects, mut nonmanifold, mut fallbacks) = (0, 0, 0);
    for case in 0..60 {
        let path = dir.path().join(format!("{case}.tmesh"));
        damaged_tube(&path, &mut rng, case % 3 == 0);
        let report = same_as_in_memory(&path);
        let n = |k: &str| report[k].as_u64().unwrap();
        defects += usize::from(n("zero_area_triangles") > 0 && n("shared_position_vertices") > 0);
        nonmanifold += usize::from(n("non_manifold_vertices") > 0 && n("degenerate_triangles") > 0);
        if n("inconsistent_edges") > 0 {
            // The stream cannot tell whether they can be oriented: the
            // mesh is read whole, with a note.
            let err = tmc(&["check", s(&path)]).stderr;
            let err = String::from_utf8_lossy(&err);
            assert!(err.contains("reading the whole mesh"), "{err}");
            fallbacks += 1;
        }
    }
    assert!(
        defects > 10 && nonmanifold > 10 && fallbacks > 5,
        "{defects} with geometric defects, {nonmanifold} not manifold, {fallbacks} read whole"
    );
}

#[test]
fn a_damaged_tmesh_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    let volume = synth(dir.path(), "noise", "30,30,30", "f32", "n.nrrd");
    let mesh = extract(&volume, dir.path().join("m.tmesh"), &["--iso", "0.5"]);
    let good = std::fs::read(&mesh).unwrap();
    let last = *TmeshReader::open(&mesh).unwrap().entries().last().unwrap();
    // A payload byte of the last chunk: found only once the chunks
    // before have streamed through the check.
    let mut bad = good.clone();
    bad[last.offset as usize + 60] ^= 0x55;
    std::fs::write(&mesh, &bad).unwrap();
    for json in [false, true] {
        let mut args = vec!["check", s(&mesh)];
        args.extend(json.then_some("--json"));
        let line = assert_one_line(&tmc(&args), 1);
        assert!(line.contains("checksum"), "{line}");
    }
    // Truncated.
    std::fs::write(&mesh, &good[..good.len() / 2]).unwrap();
    assert_one_line(&tmc(&["check", s(&mesh)]), 1);
}
