//! `tmc check`'s geometric counts: zero-area triangles and vertices sharing
//! a position, and `--strict` failing on them.

use crate::common;

use common::cli::{s, tmc};
use std::fs;

/// `tmc check` counts zero-area triangles and vertices sharing a position,
/// names the first triangles of each, and fails on them only with
/// `--strict` (exit 1, one line, after the report).
#[test]
fn check_reports_zero_area_and_shared_positions_and_strict_fails_on_them() {
    let dir = tempfile::tempdir().unwrap();
    // A closed tetrahedron (faces 0..4), then the same with vertex 3 moved
    // to the middle of edge 0-1 (face 1 collinear) and onto vertex 0
    // (faces 1 and 3 collapse, every face has a shared corner).
    let faces = "f 1 2 3\nf 1 4 2\nf 2 4 3\nf 3 4 1\n";
    let tet = |apex: &str| format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nv {apex}\n{faces}");
    let cases = [
        ("sound.obj", tet("0 0 1"), (0, 0, 0), vec![], vec![]),
        ("collinear.obj", tet("0.5 0 0"), (1, 0, 0), vec![1], vec![]),
        (
            "shared.obj",
            tet("0 0 0"),
            (2, 2, 4),
            vec![1, 3],
            vec![0, 1, 2, 3],
        ),
    ];
    for (name, text, (zero, shared, shared_triangles), first_zero, first_shared) in cases {
        let path = dir.path().join(name);
        fs::write(&path, text).unwrap();
        let out = tmc(&["check", s(&path), "--json"]);
        assert_eq!(out.status.code(), Some(0), "{name}");
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let count = |key: &str| {
            json[key]
                .as_u64()
                .unwrap_or_else(|| panic!("{key}: {json}"))
        };
        let list = |key: &str| -> Vec<u64> {
            let v = json[key]
                .as_array()
                .unwrap_or_else(|| panic!("{key}: {json}"));
            v.iter().map(|n| n.as_u64().unwrap()).collect()
        };
        assert_eq!(count("zero_area_triangles"), zero, "{name}");
        assert_eq!(count("shared_position_vertices"), shared, "{name}");
        assert_eq!(
            count("shared_position_triangles"),
            shared_triangles,
            "{name}"
        );
        assert_eq!(list("first_zero_area_triangles"), first_zero, "{name}");
        assert_eq!(
            list("first_shared_position_triangles"),
            first_shared,
            "{name}"
        );
        let text = String::from_utf8(tmc(&["check", s(&path)]).stdout).unwrap();
        assert!(text.contains("zero-area triangles"), "{text}");
        let strict = tmc(&["check", s(&path), "--strict"]);
        if zero + shared == 0 {
            assert_eq!(strict.status.code(), Some(0), "{name}");
        } else {
            assert!(!strict.stdout.is_empty(), "{name}: the report comes first");
            assert_eq!(strict.status.code(), Some(1), "{name}");
            let line = String::from_utf8(strict.stderr).unwrap();
            assert_eq!(line.lines().count(), 1, "{line}");
            assert!(
                line.starts_with("tmc: error: ") && line.contains("--strict"),
                "{line}"
            );
            if zero > 0 {
                assert!(
                    line.contains(&format!("{zero} zero-area triangles (first: 1")),
                    "{line}"
                );
            }
        }
    }
}
