//! Legacy VTK, VTK XML image (`.vti`) and TIFF stack readers against
//! fixtures written by independent writers (`vtk`, `tifffile`; see
//! `scripts/fixtures/make_vtk_tiff.py`): same grid, same samples and same
//! mesh as the `.npy` twin; bad inputs give errors, not panics.

use crate::common;

use common::formats::{all_samples, data_dir};
use std::path::{Path, PathBuf};
use tmc::volume::{self, tiff_stack, vti};
use tmc::{extract, ExtractParams, SampleSource};

const DIMS: [usize; 3] = [9, 7, 6];
const SPACING: [f64; 3] = [0.5, 1.0, 2.0];
const ORIGIN: [f64; 3] = [1.5, -2.0, 3.25];

fn data(name: &str) -> PathBuf {
    data_dir().join(name)
}

/// All samples, checked to read the same again in reverse plane order.
fn planes(src: &dyn SampleSource) -> Vec<f64> {
    let g = *src.grid();
    let all = all_samples(src);
    let mut again = vec![0.0; g.plane_len()];
    for z in (0..g.dims[2]).rev() {
        src.read_plane(z, &mut again).unwrap();
        assert_eq!(again, all[z * g.plane_len()..(z + 1) * g.plane_len()]);
    }
    all
}

/// Checks `path` against the `.npy` twin; `world` says whether the file
/// carries the spacing and origin (TIFF does not).
fn check(path: &Path, world: bool) {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let src = volume::open(path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let g = *src.grid();
    assert_eq!(g.dims, DIMS, "{}", path.display());
    let (spacing, origin) = if world {
        (SPACING, ORIGIN)
    } else {
        ([1.0; 3], [0.0; 3])
    };
    assert_eq!(g.spacing, spacing, "{}", path.display());
    assert_eq!(g.origin, origin, "{}", path.display());
    assert_eq!(planes(&*src), planes(&*twin), "{}", path.display());

    for iso in [20.5, 41.0, 60.5] {
        let params = ExtractParams {
            iso,
            ..ExtractParams::default()
        };
        let (mesh, _) = extract(&*src, &params).unwrap();
        let (want, _) = extract(&*twin, &params).unwrap();
        assert!(!want.triangles.is_empty());
        assert_eq!(
            mesh.triangles,
            want.triangles,
            "{} iso {iso}",
            path.display()
        );
        assert_eq!(mesh.vertices.len(), want.vertices.len());
        for (v, w) in mesh.vertices.iter().zip(&want.vertices) {
            for a in 0..3 {
                let mapped = origin[a] + f64::from(w[a]) * spacing[a];
                assert!(
                    (f64::from(v[a]) - mapped).abs() < 1e-5,
                    "{} iso {iso}: {v:?} vs {w:?}",
                    path.display()
                );
            }
        }
    }
}

#[test]
fn legacy_vtk_binary_and_ascii() {
    for name in [
        "vt_legacy_bin.vtk",
        "vt_legacy_ascii.vtk",
        "vt_legacy_bin_f64.vtk",
    ] {
        check(&data(name), true);
    }
}

#[test]
fn vti_all_encodings() {
    for name in [
        "vt_ascii.vti",
        "vt_binary.vti",
        "vt_appended_raw.vti",
        "vt_appended_b64.vti",
        "vt_zlib.vti",
        "vt_zlib_appended_u64be.vti",
    ] {
        check(&data(name), true);
        let v = vti::open(&data(name)).unwrap();
        assert_eq!(
            v.direction(),
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        );
    }
}

/// An oblique, mirrored `Direction` and an extent not starting at 0: the
/// grid maps indices where VTK says they are, and the mesh is the twin's
/// mapped by that affine with every triangle reversed.
#[test]
fn vti_oblique_mirrored_direction() {
    let src = volume::open(&data("vt_oblique.vti"), None).unwrap();
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let g = *src.grid();
    assert!(g.is_mirrored());
    let text = std::fs::read_to_string(data("vt_oblique.json")).unwrap();
    let points: serde_json::Value = serde_json::from_str(&text).unwrap();
    for p in points.as_array().unwrap() {
        let index = [0, 1, 2].map(|a| p["index"][a].as_f64().unwrap());
        let want = [0, 1, 2].map(|a| p["world"][a].as_f64().unwrap());
        let got = g.world(index);
        for a in 0..3 {
            assert!(
                (got[a] - want[a]).abs() < 1e-9,
                "{index:?}: {got:?} vs {want:?}"
            );
        }
    }
    assert_eq!(planes(&*src), planes(&*twin));
    let params = ExtractParams {
        iso: 41.0,
        ..ExtractParams::default()
    };
    let (mesh, _) = extract(&*src, &params).unwrap();
    let (want, _) = extract(&*twin, &params).unwrap();
    let reversed: Vec<[u32; 3]> = want.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect();
    assert_eq!(mesh.triangles, reversed);
    for (v, w) in mesh.vertices.iter().zip(&want.vertices) {
        let mapped = g.world(w.map(f64::from));
        for a in 0..3 {
            assert!(
                (f64::from(v[a]) - mapped[a]).abs() < 1e-4,
                "{v:?} vs {mapped:?}"
            );
        }
    }
}

#[test]
fn tiff_multi_page_bigtiff_directory_and_glob() {
    check(&data("vt_multi_u16.tif"), false);
    check(&data("vt_big_f32.tif"), false);
    check(&data("vt_tiff_dir"), false);
    check(&data("vt_tiff_dir/slice_*.tif"), false);
}

/// A multi-page TIFF keeps one decoder, which finds each page from the
/// page list it has walked (a decoder per page walked the list from the
/// start each time: quadratic in the pages). The kept decoder reads the file
/// it opened, so the planes still read right after another file is renamed
/// over its name; a decoder per page would open the new file.
#[test]
fn multi_page_tiff_keeps_its_decoder() {
    for name in ["vt_multi_u16.tif", "vt_big_f32.tif"] {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join(name);
        std::fs::copy(data(name), &path).unwrap();
        let src = volume::open(&path, None).unwrap();
        let mut plane = vec![0.0; src.grid().plane_len()];
        src.read_plane(0, &mut plane).unwrap();
        let other = tmp.path().join("other.tif");
        std::fs::write(&other, b"not a TIFF").unwrap();
        std::fs::rename(&other, &path).unwrap();
        let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
        assert_eq!(planes(&*src), planes(&*twin), "{name}");
    }
}

fn expect_err(path: &Path, needle: &str) {
    match volume::open(path, None) {
        Ok(_) => panic!(
            "{} opened, expected an error with '{needle}'",
            path.display()
        ),
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.contains('\n'), "{msg}");
            assert!(msg.contains(needle), "'{msg}' lacks '{needle}'");
        }
    }
}

#[test]
fn bad_legacy_vtk() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(data("vt_legacy_bin.vtk")).unwrap();
    let p = dir.path().join("trunc.vtk");
    std::fs::write(&p, &good[..good.len() - 10]).unwrap();
    expect_err(&p, "bytes");

    let text = |body: &str| {
        format!(
            "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n{body}\nLOOKUP_TABLE default\n1 2 3 4 5 6 7 8\n"
        )
    };
    let cases = [
        (
            "DIMENSIONS 2 2 2\nPOINT_DATA 8\nSCALARS s long",
            "unsupported scalar type 'long'",
        ),
        (
            "DIMENSIONS 2 2 3\nPOINT_DATA 8\nSCALARS s float",
            "does not match DIMENSIONS",
        ),
        (
            "DIMENSIONS 2 2 2\nPOINT_DATA 8\nSCALARS s float 3",
            "components",
        ),
        (
            "DIMENSIONS 2 2\nPOINT_DATA 8\nSCALARS s float",
            "DIMENSIONS needs 3",
        ),
    ];
    for (i, (body, needle)) in cases.iter().enumerate() {
        let p = dir.path().join(format!("bad{i}.vtk"));
        std::fs::write(&p, text(body)).unwrap();
        expect_err(&p, needle);
    }
    let p = dir.path().join("short.vtk");
    std::fs::write(&p, text("DIMENSIONS 3 3 3\nPOINT_DATA 27\nSCALARS s float")).unwrap();
    expect_err(&p, "ascii data holds 8 values, 3x3x3 f32 needs 27");
    let p = dir.path().join("garbage.vtk");
    std::fs::write(&p, b"hello\n").unwrap();
    expect_err(&p, "not a legacy VTK");
}

#[test]
fn bad_vti() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["vt_zlib.vti", "vt_appended_raw.vti", "vt_binary.vti"] {
        let good = std::fs::read(data(name)).unwrap();
        let p = dir.path().join(format!("trunc_{name}"));
        std::fs::write(&p, &good[..good.len() * 2 / 3]).unwrap();
        assert!(volume::open(&p, None).is_err(), "{name}");
    }
    let good = std::fs::read_to_string(data("vt_ascii.vti")).unwrap();
    let p = dir.path().join("type.vti");
    std::fs::write(&p, good.replace("\"UInt8\"", "\"String\"")).unwrap();
    expect_err(&p, "unsupported DataArray type 'String'");
    let p = dir.path().join("extent.vti");
    std::fs::write(&p, good.replacen("0 8 0 6 0 5", "0 9 0 6 0 5", 1)).unwrap();
    expect_err(&p, "differs from WholeExtent");
    // ASCII values are checked against the declared type and counted.
    let p = dir.path().join("range.vti");
    std::fs::write(&p, good.replacen("125 97 77", "300 97 77", 1)).unwrap();
    expect_err(&p, "ascii value '300' at sample 0 does not fit u8");
    let p = dir.path().join("short.vti");
    std::fs::write(&p, good.replacen("125 97 77 65 61 65", "", 1)).unwrap();
    expect_err(&p, "ascii data holds 372 values, 9x7x6 u8 needs 378");
}

#[test]
fn bad_tiff_stacks() {
    let dir = tempfile::tempdir().unwrap();
    let src = data("vt_tiff_dir");
    let stack = dir.path().join("stack");
    std::fs::create_dir(&stack).unwrap();
    for z in [2, 6, 10] {
        let name = format!("slice_{z}.tif");
        std::fs::copy(src.join(&name), stack.join(&name)).unwrap();
    }
    // a page of another size and type
    std::fs::copy(data("vt_multi_u16.tif"), stack.join("slice_20.tif")).unwrap();
    tiff_stack::open(&stack).unwrap_err();
    expect_err(&stack, "slice_20.tif page 0");

    let good = std::fs::read(data("vt_multi_u16.tif")).unwrap();
    let p = dir.path().join("trunc.tif");
    std::fs::write(&p, &good[..good.len() / 2]).unwrap();
    let opened = volume::open(&p, None);
    if let Ok(src) = opened {
        // the directories may survive truncation; the pages must not decode
        let g = *src.grid();
        let mut plane = vec![0.0; g.plane_len()];
        assert!((0..g.dims[2]).any(|z| src.read_plane(z, &mut plane).is_err()));
    }
    expect_err(&dir.path().join("empty_*.tif"), "no TIFF files");
}

#[test]
fn multi_page_files_in_a_stack_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let multi = volume::open(&data("vt_multi_u16.tif"), None).unwrap();
    assert!(multi.grid().dims[2] > 1);
    // One file found: all its pages, as when it is opened on its own.
    let one = dir.path().join("one");
    std::fs::create_dir(&one).unwrap();
    std::fs::copy(data("vt_multi_u16.tif"), one.join("a.tif")).unwrap();
    let stack = volume::open(&one, None).unwrap();
    assert_eq!(planes(stack.as_ref()), planes(multi.as_ref()));
    // Several files: a multi-page one is refused, by directory and by glob.
    let two = dir.path().join("two");
    std::fs::create_dir(&two).unwrap();
    for name in ["a.tif", "b.tif"] {
        std::fs::copy(data("vt_multi_u16.tif"), two.join(name)).unwrap();
    }
    for path in [two.clone(), two.join("*.tif")] {
        expect_err(&path, "a.tif: has more than one page");
    }
}

/// `CELL_DATA` and its arrays before the point scalars are skipped, as
/// VTK's reader leaves them aside: binary arrays whose bytes hold line
/// breaks and a `POINT_DATA` line, a `FIELD`, vectors, and in an ascii
/// file scalars and colour scalars over several lines. The volume is the
/// file's without them (same grid, same samples).
#[test]
fn legacy_vtk_cell_data_before_point_data_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let cells = 8 * 6 * 5;
    // Bytes that look like header lines, where a line reader would stop.
    let noise = |n: usize| -> Vec<u8> {
        b"\nPOINT_DATA 9\nSCALARS x float\n"
            .iter()
            .copied()
            .cycle()
            .take(n)
            .collect()
    };
    let mut binary =
        format!("CELL_DATA {cells}\nSCALARS c float 1\nLOOKUP_TABLE default\n").into_bytes();
    binary.extend(noise(cells * 4));
    binary.extend(b"\nVECTORS v double\n");
    binary.extend(noise(cells * 3 * 8));
    binary.extend(format!("\nFIELD f 2\na 2 {cells} int\n").as_bytes());
    binary.extend(noise(cells * 2 * 4));
    binary.extend(format!("\nb 1 {cells} unsigned_char\n").as_bytes());
    binary.extend(noise(cells));
    binary.push(b'\n');

    let mut ascii = format!("CELL_DATA {cells}\nSCALARS c float\nLOOKUP_TABLE default\n");
    for i in 0..cells {
        ascii.push_str(&format!("{i}.5{}", if i % 9 == 8 { "\n" } else { " " }));
    }
    ascii.push_str("\nCOLOR_SCALARS rgb 3\n");
    for _ in 0..cells {
        ascii.push_str("0.25 0.5 1\n");
    }

    for (name, block) in [
        ("vt_legacy_bin.vtk", binary),
        ("vt_legacy_ascii.vtk", ascii.into_bytes()),
    ] {
        let original = std::fs::read(data(name)).unwrap();
        let at = original
            .windows(10)
            .position(|w| w == b"POINT_DATA")
            .unwrap();
        let mut edited = original[..at].to_vec();
        edited.extend(&block);
        edited.extend(&original[at..]);
        let path = dir.path().join(name);
        std::fs::write(&path, edited).unwrap();
        let want = volume::open(&data(name), None).unwrap();
        let got = volume::open(&path, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(want.grid(), got.grid(), "{name}");
        assert_eq!(planes(&*want), planes(&*got), "{name}");
    }
}
