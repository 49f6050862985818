//! Integration tests of `tmc::check`: reading PLY, OBJ and OFF files (good
//! and malformed) and checking the meshes read.

use std::path::{Path, PathBuf};

use tmc::check::{check_mesh, read_mesh, MeshReport};
use tmc::{Error, Mesh};

/// Corners of the unit cube, `x + 2y + 4z`.
fn cube_vertices() -> Vec<[f32; 3]> {
    (0..8)
        .map(|c| [(c & 1) as f32, ((c >> 1) & 1) as f32, ((c >> 2) & 1) as f32])
        .collect()
}

/// The six faces of the cube as outward quads.
const CUBE_QUADS: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn read_ok(path: &Path) -> (Mesh, MeshReport) {
    let mesh = read_mesh(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let report = check_mesh(&mesh);
    (mesh, report)
}

/// The one-line message of a format error.
fn read_err(path: &Path) -> String {
    match read_mesh(path) {
        Err(Error::Format(msg)) => {
            assert!(!msg.contains('\n'), "multi-line error: {msg}");
            assert!(
                msg.contains(&path.display().to_string()),
                "no path in: {msg}"
            );
            msg
        }
        other => panic!("{}: expected a format error, got {other:?}", path.display()),
    }
}

fn assert_sphere(report: &MeshReport) {
    assert!(report.is_closed_manifold(), "{report:?}");
    assert_eq!((report.components, report.euler), (1, 2), "{report:?}");
    assert_eq!(report.total_genus(), Some(0));
}

/// A binary PLY cube with extra vertex properties (normal, colour) and
/// quads, in the given byte order.
fn binary_ply_cube(big_endian: bool, index_type: &str) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment made by a test\nelement vertex 8\n\
         property float x\nproperty float y\nproperty float z\nproperty double nx\n\
         property uchar red\nelement face 6\nproperty uchar flags\n\
         property list uchar {index_type} vertex_indices\nelement edge 1\n\
         property int vertex1\nproperty int vertex2\nend_header\n"
    )
    .into_bytes();
    let f32b = |v: f32| {
        if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let u32b = |v: u32| {
        if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    for p in cube_vertices() {
        for c in p {
            out.extend(f32b(c));
        }
        out.extend(if big_endian {
            0.5f64.to_be_bytes()
        } else {
            0.5f64.to_le_bytes()
        });
        out.push(200);
    }
    for q in CUBE_QUADS {
        out.push(7);
        out.push(4);
        for i in q {
            out.extend(u32b(i));
        }
    }
    out.extend(u32b(0));
    out.extend(u32b(1));
    out
}

#[test]
fn binary_ply_little_and_big_endian() {
    let dir = tempfile::tempdir().unwrap();
    for (big, ty) in [(false, "int"), (true, "uint"), (false, "uint32")] {
        let path = write(dir.path(), "cube.ply", &binary_ply_cube(big, ty));
        let (mesh, report) = read_ok(&path);
        assert_eq!(mesh.vertices, cube_vertices());
        assert_eq!((mesh.triangles.len(), report.edges), (12, 18));
        assert_sphere(&report);
    }
}

#[test]
fn ascii_ply_with_lists_to_skip() {
    let dir = tempfile::tempdir().unwrap();
    let text = "ply\nformat ascii 1.0\nobj_info tetrahedron\nelement vertex 4\n\
                property float x\nproperty float y\nproperty float z\n\
                property list uchar float texcoord\nelement face 4\n\
                property list uchar int vertex_index\nend_header\n\
                0 0 0 2 0.5 0.5\n1 0 0 0\n0 1 0 1 7\n0 0 1 0\n\
                3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    let (mesh, report) = read_ok(&write(dir.path(), "tet.ply", text.as_bytes()));
    assert_eq!(mesh.vertices[2], [0.0, 1.0, 0.0]);
    assert_sphere(&report);
}

#[test]
fn obj_with_slashes_and_negative_indices() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("# cube\nmtllib x.mtl\no cube\n");
    for p in cube_vertices() {
        text += &format!("v {} {} {}\nvn 0 0 1\n", p[0], p[1], p[2]);
    }
    text += "vt 0 0\ns off\n";
    for (i, q) in CUBE_QUADS.iter().enumerate() {
        let word = |v: u32| match i % 3 {
            0 => format!("{}", v + 1),
            1 => format!("{}/1/{}", v + 1, v + 1),
            _ => format!("{}//{}", v as i64 - 8, v + 1),
        };
        text += &format!(
            "f {} {} {} {}\n",
            word(q[0]),
            word(q[1]),
            word(q[2]),
            word(q[3])
        );
    }
    let (mesh, report) = read_ok(&write(dir.path(), "cube.obj", text.as_bytes()));
    assert_eq!(mesh.triangles.len(), 12);
    assert_sphere(&report);
}

#[test]
fn off_with_comments_colours_and_polygons() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("COFF # coloured\n# counts next\n\n8 6 12\n");
    for p in cube_vertices() {
        text += &format!("{} {} {} 255 0 0 255\n", p[0], p[1], p[2]);
    }
    for q in CUBE_QUADS {
        text += &format!("4 {} {} {} {} 0.1 0.2 0.3\n", q[0], q[1], q[2], q[3]);
    }
    let (_, report) = read_ok(&write(dir.path(), "cube.off", text.as_bytes()));
    assert_sphere(&report);
    // Counts on the header line, no extension: found by sniffing.
    let text = "OFF 4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    let (_, report) = read_ok(&write(dir.path(), "tetrahedron", text.as_bytes()));
    assert_sphere(&report);
}

#[test]
fn open_and_inconsistent_meshes_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    // A square with a flipped triangle, and a lone vertex.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\nf 1 4 3\n";
    let (_, report) = read_ok(&write(dir.path(), "square.obj", text.as_bytes()));
    assert_eq!(report.boundary_edges, 4);
    assert_eq!(report.inconsistent_edges, 1);
    assert_eq!(report.unreferenced_vertices, 1);
    assert_eq!(report.per_component[0].boundary_loops, 1);
    assert!(!report.is_closed_manifold());
}

#[test]
fn malformed_files_give_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = binary_ply_cube(false, "int");
    let cases: Vec<(PathBuf, &str)> =
        vec![
        (write(d, "cut.ply", &cube[..cube.len() - 30]), "truncated"),
        (write(d, "cut_header.ply", &cube[..40]), "end_header"),
        (write(d, "notply.ply", b"plx\n"), "not a PLY"),
        (
            write(d, "noformat.ply", b"ply\nelement vertex 0\nend_header\n"),
            "format",
        ),
        (
            write(
                d,
                "range.ply",
                b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                  end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            ),
            "out of range",
        ),
        (
            write(
                d,
                "badnum.ply",
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n0 zero 0\n",
            ),
            "invalid number",
        ),
        (
            write(
                d,
                "noxyz.ply",
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
            ),
            "'y'",
        ),
        (
            write(
                d,
                "type.ply",
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n",
            ),
            "unknown PLY type",
        ),
        (
            write(d, "range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
            "out of range",
        ),
        (write(d, "neg.obj", b"v 0 0 0\nf -1 -2 -3\n"), "out of range"),
        (write(d, "zero.obj", b"v 0 0 0\nf 0 1 1\n"), "index 0"),
        (write(d, "line.obj", b"v 0 0 0\nv 1 0 0\nf 1 2\n"), "2 vertices"),
        (write(d, "shortv.obj", b"v 0 0\n"), "three coordinates"),
        (write(d, "range.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "out-of-range"),
        (write(d, "short.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n"), "truncated"),
        (write(d, "counts.off", b"OFF\nthree 1 0\n"), "counts"),
        (write(d, "empty.off", b""), "empty"),
        (write(d, "binary.off", b"OFF BINARY\n"), "binary"),
        (write(d, "mesh.stl", b"solid x\nendsolid x\n"), "STL"),
        (write(d, "stl_without_extension", b"solid x\nendsolid x\n"), "STL"),
        (write(d, "mesh.xyz", b"1 2 3\n"), "unrecognised"),
    ];
    for (path, expected) in &cases {
        let msg = read_err(path);
        assert!(
            msg.contains(expected),
            "{}: '{msg}' lacks '{expected}'",
            path.display()
        );
    }
}

#[test]
fn huge_binary_list_count_is_rejected_not_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                      property float y\nproperty float z\nelement face 1\n\
                      property list uint int vertex_indices\nend_header\n"
        .to_vec();
    bytes.extend([0u8; 36]);
    bytes.extend(u32::MAX.to_le_bytes());
    let msg = read_err(&write(dir.path(), "huge.ply", &bytes));
    assert!(msg.contains("list length"), "{msg}");
    // A header claiming billions of vertices in a tiny file.
    let bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n\
                  property float x\nproperty float y\nproperty float z\nend_header\n";
    let msg = read_err(&write(dir.path(), "liar.ply", bytes));
    assert!(msg.contains("truncated"), "{msg}");
}

#[test]
fn missing_file_is_an_io_error() {
    let err = read_mesh(Path::new("/nonexistent/dir/mesh.ply")).unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err:?}");
}

/// An `n` x `m` torus grid.
fn torus(n: u32, m: u32) -> Mesh {
    let id = |i: u32, j: u32| (i % n) + n * (j % m);
    let mut triangles = Vec::with_capacity(2 * (n * m) as usize);
    for j in 0..m {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh {
        vertices: vec![[0.0; 3]; (n * m) as usize],
        triangles,
        ..Mesh::default()
    }
}

#[test]
fn large_torus_and_reports() {
    let mesh = torus(700, 500);
    let report = check_mesh(&mesh);
    assert!(report.is_closed_manifold());
    assert_eq!(
        (report.triangles, report.euler, report.total_genus()),
        (700_000, 0, Some(1))
    );

    let json = serde_json::to_value(&report).unwrap();
    assert_eq!(json["euler"], 0);
    assert_eq!(json["per_component"][0]["genus"], 1);
    let mut text = Vec::new();
    report.print_text(&mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    assert!(
        text.contains("closed manifold") && text.contains("yes"),
        "{text}"
    );
}

/// Reads `bytes` as the file `name` and returns the error, which must
/// contain every string of `expected`.
fn assert_refused(dir: &Path, name: &str, bytes: &[u8], expected: &[&str]) {
    let msg = read_err(&write(dir, name, bytes));
    for e in expected {
        assert!(msg.contains(e), "{name}: '{msg}' lacks '{e}'");
    }
}

/// The tetrahedron as OBJ vertex and face lines.
const OBJ_TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
/// The tetrahedron as an OFF file.
const OFF_TET: &str =
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
/// The header of an ASCII PLY tetrahedron.
const PLY_TET_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
                              property float y\nproperty float z\nelement face 4\n\
                              property list uchar int vertex_indices\nend_header\n";
/// The body of the ASCII PLY tetrahedron.
const PLY_TET_BODY: &str = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

#[test]
fn obj_files_with_other_statements_are_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "# a tetrahedron\n\n   \nmtllib t.mtl\ng tet\nusemtl red\nvt 0 0\nvn 0 0 1\nvp 0.5\n\
         s 1\nmg 1 0.5\nl 1 2\np 1\ncstype bspline\ndeg 3 \\\n   3\nend\n{OBJ_TET}# end\n"
    );
    let (mesh, report) = read_ok(&write(dir.path(), "tet.obj", text.as_bytes()));
    assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (4, 4));
    assert_sphere(&report);
}

/// A face or vertex continued on the next line by a backslash is read
/// whole (its continuation was dropped, and `f 1 3 \\` was refused as
/// "invalid face vertex '\\'"), and a UTF-8 byte order mark before the
/// first statement is no part of it (it was "'\u{feff}v' is not an OBJ
/// statement"); a backslash in a comment continues nothing.
#[test]
fn obj_line_continuations_and_a_byte_order_mark_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 0 0 0\r\nv 1 \\\r\n  0 0\nv 0 1 0\nv 0 0 1\n\
                f 1 3 \\\n 2\nf 1 2 \\\n\\\n4\n# not continued \\\nf 2 3 4\nf 1 4 3\n";
    let (mesh, report) = read_ok(&write(dir.path(), "cont.obj", text.as_bytes()));
    assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (4, 4));
    assert_eq!(mesh.vertices[1], [1.0, 0.0, 0.0]);
    assert_eq!(mesh.triangles[0], [0, 2, 1]);
    assert_eq!(mesh.triangles[1], [0, 1, 3]);
    assert_sphere(&report);
    let bom = format!("\u{feff}{OBJ_TET}");
    let (mesh, report) = read_ok(&write(dir.path(), "bom.obj", bom.as_bytes()));
    assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (4, 4));
    assert_sphere(&report);
    // Found by its first bytes too.
    let (mesh, _) = read_ok(&write(dir.path(), "bom.mesh", bom.as_bytes()));
    assert_eq!(mesh.triangles.len(), 4);
}

#[test]
fn content_that_is_not_obj_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A binary NRRD volume, an executable and prose renamed `.obj`.
    let mut nrrd = b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n".to_vec();
    nrrd.extend((0..8).flat_map(|i| (i as f32).to_le_bytes()));
    assert_refused(
        d,
        "volume.obj",
        &nrrd,
        &["line 1:", "'NRRD0004' is not an OBJ statement"],
    );
    let elf = b"\x7fELF\x02\x01\x01\0\0\0\0\0\0\0\0\0\x03\0>\0\x01\0\0\0\n";
    assert_refused(d, "program.obj", elf, &["line 1:", "NUL or non-UTF-8"]);
    let prose = "Dear reader,\n\nthis is a letter, not a mesh.\n";
    assert_refused(d, "letter.obj", prose.as_bytes(), &["line 1:", "'Dear'"]);
    // Found further down, after valid statements.
    let text = format!("{OBJ_TET}\nhello world\n");
    assert_refused(d, "tail.obj", text.as_bytes(), &["line 10:", "'hello'"]);
    let text = format!("{OBJ_TET}# caf\u{e9}\n").replace('\u{e9}', "\u{1}");
    let mut bytes = text.into_bytes();
    let at = bytes.iter().position(|&b| b == 1).unwrap();
    bytes[at] = 0xe9; // Latin-1, not UTF-8
    assert_refused(d, "latin1.obj", &bytes, &["line 9:", "non-UTF-8"]);
    assert_refused(d, "nul.obj", b"v 0 0 0\nv 1 0\x000\n", &["line 2:", "NUL"]);
    // Keywords are case-sensitive.
    assert_refused(d, "upper.obj", b"V 0 0 0\n", &["line 1:", "'V'"]);
}

#[test]
fn non_finite_coordinates_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (i, word) in ["nan", "NaN", "inf", "-infinity", "1e39"]
        .iter()
        .enumerate()
    {
        let obj = OBJ_TET.replacen("v 1 0 0", &format!("v 1 {word} 0"), 1);
        let name = format!("{i}.obj");
        assert_refused(
            d,
            &name,
            obj.as_bytes(),
            &["line 2:", word, "not a finite number"],
        );
        let off = OFF_TET.replacen("0 1 0\n", &format!("0 1 {word}\n"), 1);
        let name = format!("{i}.off");
        assert_refused(
            d,
            &name,
            off.as_bytes(),
            &["line 5:", word, "not a finite number"],
        );
        let body = PLY_TET_BODY.replacen("0 0 1\n", &format!("0 {word} 1\n"), 1);
        let name = format!("{i}.ply");
        let ply = format!("{PLY_TET_HEADER}{body}");
        assert_refused(d, &name, ply.as_bytes(), &["vertex 3", "not a finite"]);
    }
    // Binary PLY: a NaN float, and a double beyond the range of f32.
    let mut cube = binary_ply_cube(true, "int");
    let header = cube.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let vertex = 12 + 8 + 1;
    cube[header + 5 * vertex + 4..][..4].copy_from_slice(&f32::NAN.to_be_bytes());
    assert_refused(d, "nan.ply", &cube, &["vertex 5", "NaN", "not a finite"]);
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n\
                  property double x\nproperty double y\nproperty double z\nend_header\n";
    let mut ply = header.as_bytes().to_vec();
    for c in [0.0, 1e300, 0.0f64] {
        ply.extend(c.to_le_bytes());
    }
    assert_refused(d, "big.ply", &ply, &["vertex 0", "1e300", "not a finite"]);
}

#[test]
fn data_after_the_declared_faces_or_elements_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // OFF: two more faces than the header's four.
    let extra = format!("{OFF_TET}3 0 1 2\n3 0 1 2\n").replacen("4 4 6", "4 4 0", 1);
    assert_refused(d, "extra.off", extra.as_bytes(), &["line 11:", "4 faces"]);
    let text = format!("{OFF_TET}\n# a comment\nend\n");
    assert_refused(
        d,
        "word.off",
        text.as_bytes(),
        &["line 13:", "content after"],
    );
    // Blank lines and comments after the faces are fine.
    let text = format!("{OFF_TET}\n  \n# the end\n");
    assert_sphere(&read_ok(&write(d, "comment.off", text.as_bytes())).1);

    // ASCII PLY: a fifth face, or a word, after the last element.
    let good = format!("{PLY_TET_HEADER}{PLY_TET_BODY}\n\n  \n");
    assert_sphere(&read_ok(&write(d, "tet.ply", good.as_bytes())).1);
    let extra = format!("{PLY_TET_HEADER}{PLY_TET_BODY}3 0 1 2\n");
    assert_refused(
        d,
        "extra.ply",
        extra.as_bytes(),
        &["after the last element"],
    );
    let extra = format!(
        "{PLY_TET_HEADER}{}",
        PLY_TET_BODY.replace("3 0 3 2", "3 0 3 2 7")
    );
    assert_refused(d, "word.ply", extra.as_bytes(), &["after the last element"]);
    // Binary PLY: any byte after the last element.
    for tail in [&b"\n"[..], b"\0\0\0\0", b"garbage"] {
        let mut cube = binary_ply_cube(false, "int");
        cube.extend(tail);
        assert_refused(d, "tail.ply", &cube, &["after the last element"]);
    }
}

/// The OFF tetrahedron under header `keyword`, with `vertex` after each
/// vertex line and `face` after each face line.
fn off_tet(keyword: &str, vertex: &str, face: &str) -> String {
    OFF_TET
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("{keyword}\n"),
            2..=5 => format!("{l}{vertex}\n"),
            6.. => format!("{l}{face}\n"),
            _ => format!("{l}\n"),
        })
        .collect()
}

/// OFF face lines may follow their vertex indices with a colour: nothing,
/// a colour index, RGB or RGBA, all numbers. Any other count of columns
/// (a face with more indices than its count, two lines run together) and a
/// column that is not a finite number are refused, naming the line (all
/// were read before, the extra columns dropped).
#[test]
fn off_face_colours_are_0_1_3_or_4_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (i, extra) in ["", " 5", " 255 0 0", " 1 0 0 0.5", " 0.5\t0.5 0.5 "]
        .iter()
        .enumerate()
    {
        let path = write(
            d,
            &format!("good{i}.off"),
            off_tet("OFF", "", extra).as_bytes(),
        );
        assert_sphere(&read_ok(&path).1);
    }
    let for_3 = "numbers after its 3 vertex indices; OFF allows 0, 1 (a colour index), 3 (r g b) or 4 (r g b a)";
    for (i, (extra, expected)) in [
        (" 1 2", format!("line 7: face has 2 {for_3}")),
        (" 1 0 0 1 1", format!("line 7: face has 5 {for_3}")),
        (" 3 0 2 1 3 0 1 3", format!("line 7: face has 8 {for_3}")),
        (
            " red",
            "line 7: face column 5 'red' is not a finite number (a face's colour follows its 3 vertex indices)".to_string(),
        ),
        (" 1 0 0 x", "line 7: face column 8 'x' is not a finite number".to_string()),
        (" nan", "line 7: face column 5 'nan' is not a finite number".to_string()),
        (" 1 inf 0", "line 7: face column 6 'inf' is not a finite number".to_string()),
    ]
    .iter()
    .enumerate()
    {
        let name = format!("bad{i}.off");
        let text = off_tet("OFF", "", extra);
        assert_refused(d, &name, text.as_bytes(), &[expected]);
    }
}

/// OFF vertex lines hold the columns the header keyword declares
/// (`[ST][C][N]OFF`: x y z, then a normal, an RGB or RGBA colour, texture
/// coordinates); any other column count, a column that is not a finite
/// number and an unknown keyword are refused, naming the line.
#[test]
fn off_vertex_columns_follow_the_header_keyword() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let tet = |keyword: &str, extra: &str| off_tet(keyword, extra, "");
    for (i, (keyword, extra)) in [
        ("OFF", ""),
        ("COFF", " 255 0 0"),
        ("COFF", " 1 0 0 0.5"),
        ("NOFF", " 0 0 1"),
        ("STOFF", " 0.5 0.5"),
        ("STCNOFF", " 0.5 0.5 1 0 0 1 0 0 1"),
        ("NCOFF", " 0 0 1 1 0 0"),
    ]
    .iter()
    .enumerate()
    {
        let path = write(d, &format!("good{i}.off"), tet(keyword, extra).as_bytes());
        assert_sphere(&read_ok(&path).1);
    }
    for (i, (keyword, extra, expected)) in [
        (
            "OFF",
            " 255 0 0",
            "line 3: vertex has 6 columns; the header 'OFF' declares 3 (x y z)",
        ),
        ("OFF", " 1", "line 3: vertex has 4 columns"),
        (
            "COFF",
            "",
            "line 3: vertex has 3 columns; the header 'COFF' declares 6 or 7 (x y z r g b [a])",
        ),
        ("COFF", " 1 0 0 1 1", "line 3: vertex has 8 columns"),
        (
            "NOFF",
            " 0 0",
            "the header 'NOFF' declares 6 (x y z nx ny nz)",
        ),
        (
            "COFF",
            " red 0 0",
            "line 3: vertex column 4 'red' is not a finite number",
        ),
        (
            "NOFF",
            " 0 NaN 1",
            "line 3: vertex column 5 'NaN' is not a finite number",
        ),
        (
            "STOFF",
            " 0.5 -inf",
            "line 3: vertex column 5 '-inf' is not a finite number",
        ),
        ("XOFF", "", "line 1: unknown OFF header keyword 'XOFF'"),
        (
            "CCOFF",
            " 1 0 0",
            "line 1: unknown OFF header keyword 'CCOFF'",
        ),
    ]
    .iter()
    .enumerate()
    {
        let name = format!("bad{i}.off");
        assert_refused(d, &name, tet(keyword, extra).as_bytes(), &[expected]);
    }
}
