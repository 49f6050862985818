//! What earlier notes left open (issue 30, section 4): negative NRRD
//! `spacings` and NIfTI `pixdim` read as the reference readers read them,
//! error lines free of raw control bytes from a damaged header, `tmc info`
//! on values near the limits of their types, and `tmc info` on a folder it
//! cannot read. The same headers are read by pynrrd and nibabel in
//! `python/tests/test_negative_spacing.py`.

use crate::common;

use common::cli::{assert_one_line, npy_header, s, tmc};
use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};

/// `tmc info --json` of `path`.
fn info(path: &Path) -> Value {
    let out = tmc(&["info", s(path), "--json"]);
    assert!(out.status.success(), "{out:?}");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The 4x4 index-to-world matrix of `tmc info --json`.
fn affine(json: &Value) -> Vec<Vec<f64>> {
    json["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            row.as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// A 3x3x3 NRRD of `u8` samples (a bright centre) with the header lines
/// `geometry` (spacings or space directions).
fn nrrd(dir: &Path, name: &str, geometry: &str) -> PathBuf {
    let path = dir.join(name);
    let mut bytes =
        format!("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 3 3\n{geometry}\nencoding: raw\n\n")
            .into_bytes();
    bytes.extend((0..27).map(|i| if i == 13 { 200u8 } else { 10 }));
    fs::write(&path, bytes).unwrap();
    path
}

/// The vertices and triangles of an ASCII OFF file.
fn read_off(path: &Path) -> tmc::Mesh {
    common::parse_off(&fs::read_to_string(path).unwrap())
}

/// A negative `spacings` value mirrors its axis, as teem (which hands the
/// signed value on) and ITK (which maps indices with it) read it: the same
/// grid as the `space directions` with that axis reversed, and the mesh of
/// the positive spacings mirrored, winding reversed.
#[test]
fn a_negative_nrrd_spacing_mirrors_its_axis() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let negative = nrrd(d, "negative.nrrd", "spacings: -1 2 3");
    let directions = nrrd(
        d,
        "directions.nrrd",
        "space: left-posterior-superior\nspace directions: (-1,0,0) (0,2,0) (0,0,3)",
    );
    let positive = nrrd(d, "positive.nrrd", "spacings: 1 2 3");
    let want = vec![
        vec![-1.0, 0.0, 0.0, 0.0],
        vec![0.0, 2.0, 0.0, 0.0],
        vec![0.0, 0.0, 3.0, 0.0],
        vec![0.0, 0.0, 0.0, 1.0],
    ];
    assert_eq!(affine(&info(&negative)), want);
    assert_eq!(affine(&info(&directions)), want);
    let mesh = |input: &Path, name: &str| {
        let output = d.join(name);
        let out = tmc(&["extract", s(input), "--iso", "100", "-o", s(&output), "-q"]);
        assert!(out.status.success(), "{out:?}");
        output
    };
    let (neg, dirs, pos) = (
        mesh(&negative, "negative.off"),
        mesh(&directions, "directions.off"),
        mesh(&positive, "positive.off"),
    );
    assert_eq!(fs::read(&neg).unwrap(), fs::read(&dirs).unwrap());
    let (neg, pos) = (read_off(&neg), read_off(&pos));
    assert!(!pos.triangles.is_empty());
    let mirrored: Vec<[f32; 3]> = pos.vertices.iter().map(|&[x, y, z]| [-x, y, z]).collect();
    assert_eq!(neg.vertices, mirrored);
    let reversed: Vec<[u32; 3]> = pos.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect();
    assert_eq!(neg.triangles, reversed);
}

/// A 2x2x2 `u8` NIfTI-1 file with `pixdim` `pixdim`, qform code `qform`
/// (identity rotation, offset (10, 20, 30)) and sform code 0.
fn nifti(path: &Path, pixdim: [f32; 4], qform: i16) {
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    for (i, d) in [3i16, 2, 2, 2, 1, 1, 1, 1].iter().enumerate() {
        h[40 + 2 * i..42 + 2 * i].copy_from_slice(&d.to_le_bytes());
    }
    h[70..72].copy_from_slice(&2i16.to_le_bytes()); // DT_UNSIGNED_CHAR
    h[72..74].copy_from_slice(&8i16.to_le_bytes());
    for (i, p) in pixdim.iter().enumerate() {
        h[76 + 4 * i..80 + 4 * i].copy_from_slice(&p.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h[252..254].copy_from_slice(&qform.to_le_bytes());
    for (i, o) in [10f32, 20.0, 30.0].iter().enumerate() {
        h[268 + 4 * i..272 + 4 * i].copy_from_slice(&o.to_le_bytes());
    }
    h[344..348].copy_from_slice(b"n+1\0");
    h.extend([0u8, 0, 0, 0, 9, 9, 9, 9]);
    fs::write(path, h).unwrap();
}

/// nibabel sets negative `pixdim[1..3]` to their absolute values when it
/// loads a header, so its qform uses them: spacing |pixdim|, the
/// mirror only from `qfac` (`pixdim[0]`).
#[test]
fn a_negative_nifti_pixdim_is_its_absolute_value_as_in_nibabel() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("negative.nii");
    nifti(&path, [1.0, -2.0, 3.0, -4.0], 1);
    let want = vec![
        vec![2.0, 0.0, 0.0, 10.0],
        vec![0.0, 3.0, 0.0, 20.0],
        vec![0.0, 0.0, 4.0, 30.0],
        vec![0.0, 0.0, 0.0, 1.0],
    ];
    assert_eq!(affine(&info(&path)), want);
    // qfac -1 mirrors the third axis, whatever the sign of pixdim[3].
    nifti(&path, [-1.0, -2.0, 3.0, -4.0], 1);
    let mut mirrored = want.clone();
    mirrored[2][2] = -4.0;
    assert_eq!(affine(&info(&path)), mirrored);
    // Method 1 (no qform, no sform): the |pixdim| scaling alone.
    nifti(&path, [1.0, -2.0, 3.0, -4.0], 0);
    let json = info(&path);
    assert_eq!(json["spacing"], serde_json::json!([2.0, 3.0, 4.0]));
}

#[test]
fn error_lines_escape_control_bytes_of_a_damaged_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("damaged.nrrd");
    fs::write(
        &path,
        b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspace origin: (0,0,\x1b[2J\x07\r)\nencoding: raw\n\n12345678",
    )
    .unwrap();
    let output = dir.path().join("mesh.ply");
    let runs = [
        vec!["info", s(&path)],
        vec!["extract", s(&path), "--iso", "1", "-o", s(&output)],
    ];
    for args in runs {
        let command = args[0];
        let out = tmc(&args);
        let line = assert_one_line(&out, 1);
        assert!(
            line.contains(r"'(0,0,\x1b[2J\x07\r)'"),
            "{command}: {line:?}"
        );
        let raw = &out.stderr[..out.stderr.len() - 1];
        assert!(
            raw.iter().all(|&b| b >= 0x20 && b != 0x7f),
            "{command}: a control byte in {raw:?}"
        );
    }
}

#[test]
fn info_on_a_folder_without_tiff_or_dicom_says_what_it_looked_for() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("scans");
    fs::create_dir(&folder).unwrap();
    fs::write(folder.join("README.txt"), "notes").unwrap();
    fs::write(folder.join("volume.raw"), [0u8; 8]).unwrap();
    let line = assert_one_line(&tmc(&["info", s(&folder)]), 1);
    for looked_for in [".tif", ".tiff", "DICOM", ".dcm", "DICM"] {
        assert!(line.contains(looked_for), "{looked_for}: {line}");
    }
}

/// Writes a 2x2x2 `.npy` of little-endian `descr` samples from `bytes`.
fn npy(dir: &Path, name: &str, descr: &str, bytes: Vec<u8>) -> PathBuf {
    let path = dir.join(name);
    let mut data = npy_header(&format!(
        "{{'descr': '{descr}', 'fortran_order': False, 'shape': (2, 2, 2), }}"
    ));
    data.extend(bytes);
    fs::write(&path, data).unwrap();
    path
}

/// Values near the limits of their types: the mean is a number within
/// the range (no overflow to inf), the histogram has bins, and the
/// suggested isovalue lies strictly between the minimum and the maximum;
/// the text report holds no inf or NaN.
#[test]
fn info_near_the_limits_of_the_types() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let f64s = |v: [f64; 8]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let f32s = |v: [f32; 8]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let max = f64::MAX;
    let cases = [
        (
            "f64 extremes",
            "<f8",
            f64s([-max, max, max, -max, 0.0, max, -max, 1.0]),
        ),
        (
            "f64 max only",
            "<f8",
            f64s([max, max, max, max, max / 2.0, max, max, 0.0]),
        ),
        (
            "f32 extremes",
            "<f4",
            f32s([
                f32::MAX,
                -f32::MAX,
                f32::MAX,
                0.0,
                1.0,
                -f32::MAX,
                f32::MAX,
                2.0,
            ]),
        ),
        (
            "i64 extremes",
            "<f8",
            f64s([
                i64::MIN as f64,
                i64::MAX as f64,
                0.0,
                -1.0,
                1.0,
                i64::MAX as f64,
                i64::MIN as f64,
                7.0,
            ]),
        ),
        (
            "u64 extremes",
            "<f8",
            f64s([
                0.0,
                u64::MAX as f64,
                u64::MAX as f64,
                1.0,
                2.0,
                u64::MAX as f64,
                0.0,
                3.0,
            ]),
        ),
        (
            "subnormal",
            "<f8",
            f64s([0.0, 1e-320, 2e-320, 0.0, 1e-320, 3e-320, 0.0, 3e-320]),
        ),
    ];
    for (name, descr, bytes) in cases {
        let path = npy(d, &format!("{}.npy", name.replace(' ', "_")), descr, bytes);
        let json = info(&path);
        let get = |key: &str| {
            json[key]
                .as_f64()
                .unwrap_or_else(|| panic!("{name}: {key} is {}", json[key]))
        };
        let (min, mean, max) = (get("min"), get("mean"), get("max"));
        assert!(
            mean.is_finite() && min <= mean && mean <= max,
            "{name}: {min} {mean} {max}"
        );
        assert!(
            json["histogram_bins"].as_u64().is_some_and(|b| b >= 2),
            "{name}: {json}"
        );
        let iso = get("suggested_iso_single");
        assert!(min < iso && iso < max, "{name}: {min} < {iso} < {max}");
        let out = tmc(&["info", s(&path)]);
        // The label "NaN samples" aside, no value reads inf or NaN.
        let text = String::from_utf8(out.stdout)
            .unwrap()
            .replace("NaN samples", "");
        assert!(out.status.success(), "{name}");
        assert!(
            !text.contains("inf") && !text.contains("NaN"),
            "{name}: {text}"
        );
        assert!(
            !text.contains("fewer than two distinct values"),
            "{name}: {text}"
        );
    }
}
