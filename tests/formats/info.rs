//! `tmc info` run as a binary: the text report, the JSON object (grid,
//! range and suggested isovalues checked against values computed here),
//! every fixture format, raw input, and one-line errors.

use crate::common;

use common::cli::{npy_header, tmc};
use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// Runs `tmc info PATH --json [extra]` and parses its one line of stdout.
fn info_json(path: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["info", path.to_str().unwrap(), "--json"];
    args.extend_from_slice(extra);
    let out = tmc(&args);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.status.success(),
        "{path:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(stdout.lines().count(), 1, "not one line: {stdout}");
    serde_json::from_str(&stdout).unwrap()
}

/// Writes a C-order `.npy` of shape `(nz, ny, nx)` with dtype `descr`
/// (`<f4` or `<u2`) holding `values` (x fastest).
fn write_npy(path: &Path, descr: &str, dims: [usize; 3], values: &[f64]) {
    let [nx, ny, nz] = dims;
    let mut bytes = npy_header(&format!(
        "{{'descr': '{descr}', 'fortran_order': False, 'shape': ({nz}, {ny}, {nx}), }}"
    ));
    for &v in values {
        match descr {
            "<f4" => bytes.extend_from_slice(&(v as f32).to_le_bytes()),
            "<u2" => bytes.extend_from_slice(&(v as u16).to_le_bytes()),
            "<f8" => bytes.extend_from_slice(&v.to_le_bytes()),
            _ => panic!("unsupported descr {descr}"),
        }
    }
    fs::write(path, bytes).unwrap();
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn usizes(v: &Value) -> Vec<usize> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect()
}

/// Checks that the suggested isovalues lie strictly between min and max, in
/// ascending order; returns them (pair, single).
fn suggestions(json: &Value) -> ([f64; 2], f64) {
    let (min, max) = (json["min"].as_f64().unwrap(), json["max"].as_f64().unwrap());
    let pair = f64s(&json["suggested_iso"]);
    assert_eq!(pair.len(), 2, "{json}");
    let single = json["suggested_iso_single"].as_f64().unwrap();
    for v in [pair[0], pair[1], single] {
        assert!(min < v && v < max, "{v} not in ({min}, {max}): {json}");
    }
    assert!(pair[0] < pair[1], "{json}");
    ([pair[0], pair[1]], single)
}

/// A float volume with three plateaus of values, ripples and one NaN: the
/// JSON's range, counts and mean are those computed here.
#[test]
fn json_of_a_float_npy() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("three.npy");
    let dims = [12, 10, 8];
    let mut values: Vec<f64> = (0..dims.iter().product::<usize>())
        .map(|i| {
            let class = [-2.0, 1.0, 7.5][i % 7 % 3];
            // f32-exact ripples.
            class + (i % 5) as f64 * 0.0625
        })
        .collect();
    values[17] = f64::NAN;
    write_npy(&path, "<f4", dims, &values);

    let json = info_json(&path, &[]);
    assert_eq!(json["format"], "NumPy");
    assert_eq!(json["sample_type"], "f32");
    assert_eq!(usizes(&json["dims"]), dims);
    assert_eq!(json["samples"], 960);
    assert_eq!(json["data_bytes"], 960 * 4);
    assert_eq!(f64s(&json["spacing"]), [1.0; 3]);
    let finite: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
    let min = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let max = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    assert_eq!(json["min"].as_f64(), Some(min));
    assert_eq!(json["max"].as_f64(), Some(max));
    assert!((json["mean"].as_f64().unwrap() - mean).abs() < 1e-9);
    assert_eq!(json["nan_count"], 1);
    assert_eq!(json["infinite_count"], 0);
    assert_eq!(json["integer_valued"], false);
    assert_eq!(json["histogram_plane_step"], 1);
    let ([a, b], single) = suggestions(&json);
    // Classes [-2, -1.75], [1, 1.25], [7.5, 7.75]: one isovalue per gap.
    assert!(-1.75 < a && a < 1.0, "{a}");
    assert!(1.25 < b && b < 7.5, "{b}");
    assert!((-1.75 < single && single < 1.0) || (1.25 < single && single < 7.5));
    // The 4x4 affine of a unit grid is the identity.
    let affine: Vec<Vec<f64>> = json["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(f64s)
        .collect();
    for (r, row) in affine.iter().enumerate() {
        for (c, &v) in row.iter().enumerate() {
            assert_eq!(v, if r == c { 1.0 } else { 0.0 });
        }
    }
}

/// Integer data gets half-integer isovalues in the gaps between the
/// classes, which no sample can equal.
#[test]
fn integer_isovalues_are_half_integers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ct.npy");
    let dims = [16, 16, 6];
    let values: Vec<f64> = (0..dims.iter().product::<usize>())
        .map(|i| match i % 10 {
            0..=4 => (i % 3) as f64,           // air: 0..2
            5..=7 => 1000.0 + (i % 41) as f64, // soft tissue: 1000..1040
            _ => 2000.0 + (i % 97) as f64,     // bone: 2000..2096
        })
        .collect();
    write_npy(&path, "<u2", dims, &values);
    let json = info_json(&path, &[]);
    assert_eq!(json["sample_type"], "u16");
    assert_eq!(json["integer_valued"], true);
    let ([a, b], single) = suggestions(&json);
    for v in [a, b, single] {
        assert_eq!(v.fract(), 0.5, "{v}");
        assert!(!values.contains(&v));
    }
    assert!(2.0 < a && a < 1000.0, "{a}");
    assert!(1040.0 < b && b < 2000.0, "{b}");
}

/// The text report names the format and shows dims, spacing and the
/// suggestion.
#[test]
fn text_report_of_a_fixture() {
    let out = tmc(&["info", data_dir().join("mhd_u8.mhd").to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let line = |label: &str| {
        text.lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("no '{label}' line in:\n{text}"))
            .to_string()
    };
    assert!(line("format").ends_with("MetaImage"), "{text}");
    assert!(line("dims").contains("9 x 7 x 6"), "{text}");
    assert!(line("sample type").ends_with("u8"), "{text}");
    let manifest = manifest();
    let fixture = manifest.iter().find(|f| f["name"] == "mhd_u8").unwrap();
    let spacing: Vec<String> = f64s(&fixture["spacing"])
        .iter()
        .map(|v| v.to_string())
        .collect();
    assert!(line("spacing").ends_with(&spacing.join("  ")), "{text}");
    assert!(line("suggested iso").contains("two-level Otsu"), "{text}");
}

fn manifest() -> Vec<Value> {
    let text = fs::read_to_string(data_dir().join("nifti_mhd_manifest.json")).unwrap();
    serde_json::from_str::<Value>(&text)
        .unwrap()
        .as_array()
        .unwrap()
        .clone()
}

/// Every NIfTI and MetaImage fixture: the format name, the grid of the
/// manifest, and the range of the `.npy` twin's samples.
#[test]
fn json_of_every_nifti_and_metaimage_fixture() {
    for fixture in manifest() {
        let name = fixture["name"].as_str().unwrap();
        let file = data_dir().join(fixture["file"].as_str().unwrap());
        let json = info_json(&file, &[]);
        let format = json["format"].as_str().unwrap();
        let expected = match name {
            n if n.starts_with("nifti1") => "NIfTI-1",
            n if n.starts_with("nifti2") => "NIfTI-2",
            _ => "MetaImage",
        };
        assert_eq!(format, expected, "{name}");
        assert_eq!(usizes(&json["dims"]), usizes(&fixture["dims"]), "{name}");
        // NIfTI stores its affine in single precision.
        for key in ["spacing", "origin"] {
            for (got, want) in f64s(&json[key]).iter().zip(f64s(&fixture[key])) {
                assert!(
                    (got - want).abs() <= 1e-6 * want.abs().max(1.0),
                    "{name} {key}"
                );
            }
        }
        // The affine's column c is direction column c times spacing c, its
        // last column the origin (oblique and mirrored fixtures included).
        let (spacing, origin) = (f64s(&fixture["spacing"]), f64s(&fixture["origin"]));
        let affine: Vec<Vec<f64>> = json["affine"]
            .as_array()
            .unwrap()
            .iter()
            .map(f64s)
            .collect();
        for r in 0..3 {
            let direction = f64s(&fixture["direction"][r]);
            let want = [0, 1, 2, 3].map(|c| {
                if c < 3 {
                    direction[c] * spacing[c]
                } else {
                    origin[r]
                }
            });
            for (got, want) in affine[r].iter().zip(want) {
                assert!(
                    (got - want).abs() <= 1e-5 * want.abs().max(1.0),
                    "{name} affine row {r}: {:?} vs {want:?}",
                    affine[r]
                );
            }
        }
        assert_eq!(affine[3], [0.0, 0.0, 0.0, 1.0], "{name}");

        let twin = data_dir().join(format!("{name}.expected.npy"));
        let twin = tmc::volume::open(&twin, None).unwrap();
        let mut plane = vec![0.0; twin.grid().plane_len()];
        let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
        for z in 0..twin.grid().dims[2] {
            twin.read_plane(z, &mut plane).unwrap();
            for &v in &plane {
                min = min.min(v);
                max = max.max(v);
            }
        }
        assert_eq!(json["min"].as_f64(), Some(min), "{name}");
        assert_eq!(json["max"].as_f64(), Some(max), "{name}");
        suggestions(&json);
    }
}

/// The other formats are named too.
#[test]
fn format_names() {
    let cases = [
        ("headsq_quarter", "NRRD"),
        ("vt_ascii.vti", "VTK ImageData"),
        ("vt_tiff_dir", "TIFF stack"),
        ("vt_multi_u16.tif", "TIFF stack"),
        ("vt_legacy_bin.vtk", "VTK legacy"),
    ];
    for (file, format) in cases {
        let path = if file == "headsq_quarter" {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd")
        } else {
            data_dir().join(file)
        };
        assert_eq!(info_json(&path, &[])["format"], format, "{file}");
    }
}

/// Raw input takes the same options as 'tmc extract'.
#[test]
fn raw_input() {
    let path = data_dir().join("mhd_u8.raw");
    let json = info_json(
        &path,
        &[
            "--dims",
            "9,7,6",
            "--dtype",
            "u8",
            "--spacing",
            "0.5,1,2",
            "--origin",
            "-1,0,3",
        ],
    );
    assert_eq!(json["format"], "raw");
    assert_eq!(json["sample_type"], "u8");
    assert_eq!(json["file_bytes"], 378);
    assert_eq!(f64s(&json["spacing"]), [0.5, 1.0, 2.0]);
    let affine: Vec<Vec<f64>> = json["affine"]
        .as_array()
        .unwrap()
        .iter()
        .map(f64s)
        .collect();
    assert_eq!(affine[0], [0.5, 0.0, 0.0, -1.0]);
    assert_eq!(affine[2], [0.0, 0.0, 2.0, 3.0]);
    assert_eq!(affine[3], [0.0, 0.0, 0.0, 1.0]);
    // Same samples as the MetaImage header describes.
    let mhd = info_json(&data_dir().join("mhd_u8.mhd"), &[]);
    assert_eq!(json["min"], mhd["min"]);
    assert_eq!(json["suggested_iso"], mhd["suggested_iso"]);
}

/// The CT head of data/: a skin and a bone isovalue (VTK's examples use
/// 500 and 1150 on this data set).
#[test]
fn head_ct_suggestion_is_sensible() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd");
    let json = info_json(&path, &[]);
    let ([skin, bone], _) = suggestions(&json);
    assert!(400.0 < skin && skin < 800.0, "skin {skin}");
    assert!(1000.0 < bone && bone < 2000.0, "bone {bone}");
    // Thinning the histogram to every 2nd plane keeps the answer close.
    let thin = info_json(&path, &["--plane-step", "2"]);
    assert_eq!(thin["histogram_plane_step"], 2);
    assert_eq!(thin["min"], json["min"]);
    let ([skin2, bone2], _) = suggestions(&thin);
    assert!((skin2 - skin).abs() < 100.0 && (bone2 - bone).abs() < 200.0);
}

/// Bad input: one `tmc: error: PATH: ...` line, nothing on stdout, exit 1.
#[test]
fn bad_input_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.npy");
    fs::write(&bad, b"not numpy").unwrap();
    let missing = dir.path().join("missing.nrrd");
    let unknown = dir.path().join("volume.xyz");
    fs::write(&unknown, b"x").unwrap();
    for path in [&bad, &missing, &unknown] {
        for json in [false, true] {
            let mut args = vec!["info", path.to_str().unwrap()];
            if json {
                args.push("--json");
            }
            let out = tmc(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{stderr}");
            assert!(out.stdout.is_empty());
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(
                stderr.starts_with(&format!("tmc: error: {}", path.display())),
                "{stderr}"
            );
        }
    }
    // A usage error (--dtype without --dims) exits 2.
    let out = tmc(&["info", bad.to_str().unwrap(), "--dtype", "u8"]);
    assert_eq!(out.status.code(), Some(2));
}

/// Every reader reports its stored sample type, and a detached header's
/// size includes its data files.
#[test]
fn sample_type_and_file_bytes_of_every_reader() {
    let dir = tempfile::tempdir().unwrap();
    let vtk = dir.path().join("short.vtk");
    let values: String = (0..27).map(|i| format!("{} ", i * 100 - 1300)).collect();
    fs::write(
        &vtk,
        format!("# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 3 3\nPOINT_DATA 27\nSCALARS s short\nLOOKUP_TABLE default\n{values}\n"),
    )
    .unwrap();
    let len = |name: &str| fs::metadata(data_dir().join(name)).unwrap().len();
    let cases = [
        (
            data_dir().join("nrrd_gzip_be_i16.nrrd"),
            "i16",
            2,
            len("nrrd_gzip_be_i16.nrrd"),
        ),
        (
            data_dir().join("nrrd_ascii_i8.nrrd"),
            "i8",
            1,
            len("nrrd_ascii_i8.nrrd"),
        ),
        (
            data_dir().join("nrrd_detached_rot_f64.nhdr"),
            "f64",
            8,
            len("nrrd_detached_rot_f64.nhdr") + len("nrrd_detached_rot_f64.raw"),
        ),
        (
            data_dir().join("mhd_u8.mhd"),
            "u8",
            1,
            len("mhd_u8.mhd") + len("mhd_u8.raw"),
        ),
        (
            data_dir().join("nifti1_pair.hdr"),
            "u8",
            1,
            len("nifti1_pair.hdr") + len("nifti1_pair.img"),
        ),
        (data_dir().join("dicom_ct"), "i16", 2, 0),
        (vtk.clone(), "i16", 2, fs::metadata(&vtk).unwrap().len()),
    ];
    for (path, sample_type, size, file_bytes) in cases {
        let json = info_json(&path, &[]);
        let samples = json["samples"].as_u64().unwrap();
        assert_eq!(json["sample_type"], sample_type, "{path:?}");
        assert_eq!(
            json["data_bytes"].as_u64(),
            Some(samples * size),
            "{path:?}"
        );
        if file_bytes > 0 {
            assert_eq!(json["file_bytes"].as_u64(), Some(file_bytes), "{path:?}");
        }
    }
}

/// A file whose name holds `*` or `?` is read as itself when it exists; a
/// name that no file has is a TIFF glob.
#[test]
fn a_file_named_like_a_glob_is_read_as_itself() {
    let dir = tempfile::tempdir().unwrap();
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd");
    let starred = dir.path().join("b*.nrrd");
    fs::copy(&bundled, &starred).unwrap();
    let info = info_json(&starred, &[]);
    assert_eq!(info["format"], "NRRD", "{info}");
    let missing = dir.path().join("c*.tif");
    let out = tmc(&["info", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("c*.tif"), "{stderr}");
}

/// A mask (two values) has one threshold, not two: the two-level pair
/// would put both isovalues into the one gap, an empty middle class.
#[test]
fn a_mask_gets_one_isovalue_not_a_pair() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mask.npy");
    let dims = [8, 8, 8];
    let values: Vec<f64> = (0..dims.iter().product::<usize>())
        .map(|i| if i % 3 == 0 { 200.0 } else { 0.0 })
        .collect();
    write_npy(&path, "<u2", dims, &values);
    let json = info_json(&path, &[]);
    assert_eq!(f64s(&json["suggested_iso"]), Vec::<f64>::new(), "{json}");
    let single = json["suggested_iso_single"].as_f64().unwrap();
    assert!(0.0 < single && single < 200.0, "{json}");
    let out = tmc(&["info", path.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("suggested iso"))
        .unwrap();
    assert!(!line.contains("3 classes"), "{text}");
    let single_line = text.lines().find(|l| l.starts_with("single iso")).unwrap();
    assert!(single_line.contains(&single.to_string()), "{text}");
}

/// Numbers far from 1 are printed with an exponent where their decimal
/// would run to hundreds of digits (every finite double's decimal is
/// exact: 1e300 was a 1 and 300 zeros, 1e-300 a point, 299 zeros and a 1):
/// the text of `tmc info` (spacing, origin, the affine, min, max, mean,
/// suggestions), the note of `tmc extract` that finds no surface and its
/// `--stats` heading, as `{iso}` names a file (`1e-300`). Numbers of up to
/// 24 characters print as before.
#[test]
fn far_numbers_print_with_an_exponent() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v.npy");
    let values: Vec<f64> = (0..27)
        .map(|i| if i == 13 { 1e300 } else { -1e300 })
        .collect();
    write_npy(&path, "<f8", [3, 3, 3], &values);
    let ok = |args: &[&str]| {
        let out = tmc(args);
        assert!(out.status.success(), "{args:?}: {out:?}");
        out
    };
    let (v, grid) = (path.to_str().unwrap(), "1e-30,1e30,0.25");
    let out = ok(&[
        "info",
        v,
        "--spacing",
        grid,
        "--origin",
        "1e-300,5e30,-1600",
    ]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let longest = text.lines().map(str::len).max().unwrap_or(0);
    assert!(longest < 120, "a line of {longest} characters:\n{text}");
    let lines: Vec<String> = (text.lines())
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    for line in [
        "spacing 1e-30 1e30 0.25",
        "origin 1e-300 5e30 -1600",
        "max 1e300",
    ] {
        assert!(lines.iter().any(|l| l == line), "{line:?} in\n{text}");
    }
    let mesh = dir.path().join("m.ply");
    let (mesh, iso) = (mesh.to_str().unwrap(), "1e308");
    let out = ok(&["extract", v, "--iso", iso, "-o", mesh, "--stats"]);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(err.contains("no surface at isovalue 1e308:"), "{err}");
    assert!(err.contains("iso 1e308, method tmc"), "{err}");
    assert!(err.lines().all(|l| l.len() < 300), "{err}");
}

/// A volume of one sample (which `tmc extract --close` takes) is "1
/// sample", not "1 samples".
#[test]
fn one_sample_is_singular() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one.npy");
    write_npy(&path, "<f4", [1, 1, 1], &[3.0]);
    let out = tmc(&["info", path.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("1 x 1 x 1 (1 sample)\n"), "{text}");
}
