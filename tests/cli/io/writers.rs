//! The mesh writers (PLY, OBJ, STL, OFF), round-tripped through small
//! parsers written here, and the output-path checks.

use crate::common;
use crate::common::cli::names;
use std::fs;
use std::path::Path;
use tmc::export::{check_output_path, write_atomically, write_mesh};
use tmc::Mesh;

/// A tetrahedron, counter-clockwise seen from outside, with coordinates that
/// do not print short.
fn tetrahedron() -> Mesh {
    Mesh {
        vertices: vec![
            [0.1, -2.5e-3, 12345.678],
            [1.0 / 3.0, 0.0, 12345.678],
            [0.0, 7.25, 12345.678],
            [0.05, 1.0, 12350.0],
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
        ..Mesh::default()
    }
}

/// Parses a binary little-endian PLY as written by tmc.
pub(crate) fn parse_ply(bytes: &[u8]) -> Mesh {
    let end = b"end_header\n";
    let at = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = std::str::from_utf8(&bytes[..at]).unwrap();
    let lines: Vec<&str> = header.lines().collect();
    assert_eq!(lines[0], "ply");
    assert_eq!(lines[1], "format binary_little_endian 1.0");
    let count = |element: &str| -> usize {
        let prefix = format!("element {element} ");
        let line = lines.iter().find(|l| l.starts_with(&prefix)).unwrap();
        line[prefix.len()..].parse().unwrap()
    };
    assert!(header.contains("property float x\nproperty float y\nproperty float z\nelement face"));
    assert!(header.contains("property list uchar uint vertex_indices\nend_header\n"));
    let (nv, nf) = (count("vertex"), count("face"));
    let mut body = &bytes[at..];
    let mut take = |n: usize| {
        let (head, rest) = body.split_at(n);
        body = rest;
        head.to_vec()
    };
    let mut mesh = Mesh::default();
    for _ in 0..nv {
        let mut v = [0f32; 3];
        for c in &mut v {
            *c = f32::from_le_bytes(take(4).try_into().unwrap());
        }
        mesh.vertices.push(v);
    }
    for _ in 0..nf {
        assert_eq!(take(1), [3]);
        let mut t = [0u32; 3];
        for i in &mut t {
            *i = u32::from_le_bytes(take(4).try_into().unwrap());
        }
        mesh.triangles.push(t);
    }
    assert!(body.is_empty(), "trailing bytes");
    mesh
}

/// Parses an OBJ of `v` and `f` lines.
pub(crate) fn parse_obj(text: &str) -> Mesh {
    let mut mesh = Mesh::default();
    for line in text.lines() {
        let mut parts = line.split_whitespace();
        match parts.next() {
            Some("v") => {
                let v: Vec<f32> = parts.map(|p| p.parse().unwrap()).collect();
                mesh.vertices.push([v[0], v[1], v[2]]);
            }
            Some("f") => {
                let f: Vec<u32> = parts.map(|p| p.parse::<u32>().unwrap() - 1).collect();
                mesh.triangles.push([f[0], f[1], f[2]]);
            }
            Some(c) if c.starts_with('#') => {}
            other => panic!("unexpected OBJ line {other:?}"),
        }
    }
    mesh
}

/// Parses a binary STL into facets (normal, three corners).
pub(crate) fn parse_stl(bytes: &[u8]) -> Vec<[[f32; 3]; 4]> {
    assert!(!bytes.starts_with(b"solid"));
    let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * n);
    (0..n)
        .map(|i| {
            let facet = &bytes[84 + 50 * i..84 + 50 * (i + 1)];
            let f = |k: usize| f32::from_le_bytes(facet[4 * k..4 * k + 4].try_into().unwrap());
            assert_eq!(&facet[48..], [0, 0]);
            [
                [f(0), f(1), f(2)],
                [f(3), f(4), f(5)],
                [f(6), f(7), f(8)],
                [f(9), f(10), f(11)],
            ]
        })
        .collect()
}

#[test]
fn writers_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = tetrahedron();
    for ext in ["ply", "obj", "off", "PLY"] {
        let path = dir.path().join(format!("t.{ext}"));
        write_mesh(&path, &mesh).unwrap();
        let bytes = fs::read(&path).unwrap();
        let back = match ext {
            "ply" | "PLY" => parse_ply(&bytes),
            "obj" => parse_obj(std::str::from_utf8(&bytes).unwrap()),
            _ => common::parse_off(std::str::from_utf8(&bytes).unwrap()),
        };
        assert_eq!(back, mesh, "{ext}");
    }

    let path = dir.path().join("t.stl");
    write_mesh(&path, &mesh).unwrap();
    let facets = parse_stl(&fs::read(&path).unwrap());
    assert_eq!(facets.len(), mesh.triangles.len());
    let center =
        [0usize, 1, 2].map(|k| mesh.vertices.iter().map(|v| f64::from(v[k])).sum::<f64>() / 4.0);
    for (facet, t) in facets.iter().zip(&mesh.triangles) {
        for k in 0..3 {
            assert_eq!(facet[k + 1], mesh.vertices[t[k] as usize]);
        }
        let n = facet[0].map(f64::from);
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-6, "normal length {len}");
        // Counter-clockwise from outside: the normal points away from the centre.
        let outward: f64 = (0..3)
            .map(|k| n[k] * (f64::from(facet[1][k]) - center[k]))
            .sum();
        assert!(outward > 0.0);
    }

    // An empty mesh is a valid file in every format.
    for ext in ["ply", "obj", "off", "stl"] {
        let path = dir.path().join(format!("empty.{ext}"));
        write_mesh(&path, &Mesh::default()).unwrap();
        assert!(path.is_file());
    }
    assert!(names(dir.path()).iter().all(|n| !n.contains(".tmc-")));
}

/// The readers give back the normals and labels the writers put in: PLY
/// both, OBJ the normals (`vn`, faces `v//vn`), OFF neither; PLY also an
/// empty mesh's (declared in its header), OBJ none for an empty mesh.
#[test]
fn normals_and_labels_round_trip_through_the_readers() {
    let dir = tempfile::tempdir().unwrap();
    let mut mesh = tetrahedron();
    mesh.normals = Some(vec![
        [0.6, 0.0, -0.8],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ]);
    mesh.labels = Some(vec![5, 0, u32::MAX, 5]);
    let read = |mesh: &Mesh, ext: &str| {
        let path = dir.path().join(format!("t.{ext}"));
        write_mesh(&path, mesh).unwrap();
        tmc::check::read_mesh(&path).unwrap()
    };
    assert_eq!(read(&mesh, "ply"), mesh);
    let obj = read(&mesh, "obj");
    assert_eq!((&obj.normals, &obj.labels), (&mesh.normals, &None));
    let off = read(&mesh, "off");
    assert_eq!((&off.normals, &off.labels), (&None, &None));
    assert_eq!(off.triangles, mesh.triangles);
    // An empty mesh with both: the PLY declares them, the OBJ cannot.
    let empty = Mesh {
        normals: Some(Vec::new()),
        labels: Some(Vec::new()),
        ..Mesh::default()
    };
    assert_eq!(read(&empty, "ply"), empty);
    assert_eq!(read(&empty, "obj"), Mesh::default());
    // Without labels, the PLY is the bytes it was (no label property).
    mesh.labels = None;
    let path = dir.path().join("n.ply");
    write_mesh(&path, &mesh).unwrap();
    let bytes = fs::read(&path).unwrap();
    assert!(!String::from_utf8_lossy(&bytes).contains("label"));
    assert_eq!(tmc::check::read_mesh(&path).unwrap(), mesh);
}

#[test]
fn degenerate_stl_facets_get_a_zero_normal() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = Mesh {
        vertices: vec![[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
        triangles: vec![[0, 1, 2]],
        ..Mesh::default()
    };
    let path = dir.path().join("d.stl");
    write_mesh(&path, &mesh).unwrap();
    assert_eq!(parse_stl(&fs::read(&path).unwrap())[0][0], [0.0; 3]);
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let bad = Mesh {
        vertices: vec![[0.0; 3]],
        triangles: vec![[0, 0, 1]],
        ..Mesh::default()
    };
    let path = dir.path().join("bad.ply");
    let err = write_mesh(&path, &bad).unwrap_err().to_string();
    assert!(err.contains("refers to a vertex"), "{err}");
    assert!(write_mesh(&dir.path().join("t.xyz"), &tetrahedron()).is_err());
    assert!(write_mesh(&dir.path().join("no/dir/t.ply"), &tetrahedron()).is_err());

    // A writer failing half-way: the old file survives, no temporary is left.
    let keep = dir.path().join("keep.obj");
    fs::write(&keep, b"old").unwrap();
    let result = write_atomically(&keep, |w| {
        use std::io::Write;
        w.write_all(b"partial")?;
        Err(std::io::Error::other("disk on fire"))
    });
    let err = result.unwrap_err().to_string();
    assert!(
        err.contains("keep.obj") && err.contains("disk on fire"),
        "{err}"
    );
    assert_eq!(fs::read(&keep).unwrap(), b"old");
    assert_eq!(names(dir.path()), ["keep.obj"]);

    // Overwriting works.
    write_mesh(&keep, &tetrahedron()).unwrap();
    assert_eq!(
        parse_obj(&fs::read_to_string(&keep).unwrap()),
        tetrahedron()
    );
}

#[test]
fn output_path_checks() {
    let dir = tempfile::tempdir().unwrap();
    assert!(check_output_path(&dir.path().join("a.ply")).is_ok());
    assert!(check_output_path(&dir.path().join("a.STL")).is_ok());
    assert!(check_output_path(&dir.path().join("a.vtk")).is_err());
    assert!(check_output_path(&dir.path().join("missing/a.ply")).is_err());
    assert!(check_output_path(Path::new("relative.off")).is_ok());
    assert!(names(dir.path()).is_empty(), "probe file left behind");
}
