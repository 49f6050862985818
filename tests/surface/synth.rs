//! Synthetic volumes: every kind in every sample type and format reads back
//! exactly, headers are standard, output is deterministic, the head phantom
//! gives a closed manifold skull, and `tmc synth` fails cleanly.

use crate::common;

use common::cli::{names, tmc};
use std::fs;
use std::path::Path;
use tmc::synth::{hounsfield_to_stored, unit_to_stored, Kind, Synthetic, HEAD_SKULL_ISO_HU};
use tmc::volume::{
    decode_samples, encode_samples, write_volume, Endian, RawOptions, ScalarType, VolumeFormat,
};
use tmc::{ExtractParams, Grid, SampleSource};

/// `path` as a `&str`.
fn s(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// Every sample of `source`, plane after plane.
fn samples(source: &dyn SampleSource) -> Vec<f64> {
    let grid = source.grid();
    let mut plane = vec![0.0; grid.plane_len()];
    let mut all = Vec::new();
    for z in 0..grid.dims[2] {
        source.read_plane(z, &mut plane).expect("read plane");
        all.extend_from_slice(&plane);
    }
    all
}

/// A grid with uneven dims and spacing (catches swapped axes).
fn small_grid() -> Grid {
    Grid {
        dims: [12, 10, 8],
        spacing: [0.5, 0.7, 1.3],
        origin: [0.0; 3],
        direction: tmc::volume::IDENTITY,
    }
}

#[test]
fn every_kind_type_and_format_reads_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let grid = small_grid();
    for kind in Kind::ALL {
        for scalar in ScalarType::ALL {
            let source = Synthetic::new(kind, grid, scalar, 5).unwrap();
            assert_eq!(source.sample_bytes(), scalar.size());
            let expected = samples(&source);
            let (lo, hi) = expected
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            assert!(lo < hi, "{kind} {scalar}: constant volume");
            if !matches!(scalar, ScalarType::F16 | ScalarType::F32 | ScalarType::F64) {
                assert!(
                    expected.iter().all(|v| v.fract() == 0.0),
                    "{kind} {scalar}: not integral"
                );
            }
            for ext in ["nrrd", "npy", "raw"] {
                let path = dir.path().join(format!("{kind}-{scalar}.{ext}"));
                if (scalar, ext) == (ScalarType::F16, "nrrd") {
                    // NRRD has no 16-bit float type: refused, nothing written.
                    assert!(write_volume(&path, &source, scalar, None).is_err());
                    assert!(!path.exists());
                    continue;
                }
                let bytes = write_volume(&path, &source, scalar, None).unwrap();
                assert_eq!(bytes, fs::metadata(&path).unwrap().len());
                let raw = (ext == "raw").then_some(RawOptions {
                    dims: grid.dims,
                    scalar,
                    endian: Endian::Little,
                    header_bytes: 0,
                    spacing: grid.spacing,
                    origin: [0.0; 3],
                });
                let read = tmc::volume::open(&path, raw.as_ref()).unwrap();
                assert_eq!(read.grid().dims, grid.dims, "{}", path.display());
                if ext != "npy" {
                    assert_eq!(read.grid().spacing, grid.spacing, "{}", path.display());
                }
                assert_eq!(read.sample_bytes(), scalar.size());
                assert_eq!(samples(read.as_ref()), expected, "{}", path.display());
            }
        }
    }
}

#[test]
fn unit_fields_map_onto_the_type_range() {
    assert_eq!(unit_to_stored(0.0, ScalarType::U8), 127.5);
    assert_eq!(unit_to_stored(-1.0, ScalarType::U16), 0.0);
    assert_eq!(unit_to_stored(1.0, ScalarType::U16), 65535.0);
    assert_eq!(unit_to_stored(7.0, ScalarType::I16), 32767.0);
    assert_eq!(unit_to_stored(-0.5, ScalarType::F32), -0.5);
    assert_eq!(hounsfield_to_stored(-1000.0, ScalarType::U16), 0.0);
    assert_eq!(hounsfield_to_stored(500.0, ScalarType::U8), 150.0);
    assert_eq!(hounsfield_to_stored(500.0, ScalarType::I8), 40.0);
    assert_eq!(hounsfield_to_stored(500.0, ScalarType::I16), 500.0);
    let head = Synthetic::new(Kind::Head, small_grid(), ScalarType::U16, 0).unwrap();
    assert_eq!(head.suggested_iso(), 1500.0);
    let sphere = Synthetic::new(Kind::Sphere, small_grid(), ScalarType::U8, 0).unwrap();
    assert_eq!(sphere.suggested_iso(), 127.5);
}

#[test]
fn encoding_rounds_ties_to_even_and_saturates() {
    let values = [-1e10, -1.5, -0.5, 0.4, 0.5, 1.5, 2.5, 1e10, f64::NAN];
    let cases: [(ScalarType, [f64; 9]); 4] = [
        (ScalarType::U8, [0., 0., 0., 0., 0., 2., 2., 255., 0.]),
        (ScalarType::I8, [-128., -2., 0., 0., 0., 2., 2., 127., 0.]),
        (
            ScalarType::U32,
            [0., 0., 0., 0., 0., 2., 2., 4294967295., 0.],
        ),
        (
            ScalarType::I32,
            [-2147483648., -2., 0., 0., 0., 2., 2., 2147483647., 0.],
        ),
    ];
    for (scalar, expected) in cases {
        for endian in [Endian::Little, Endian::Big] {
            let mut bytes = vec![0u8; values.len() * scalar.size()];
            encode_samples(scalar, endian, &values, &mut bytes);
            let mut back = [0.0; 9];
            decode_samples(scalar, endian, &bytes, &mut back);
            assert_eq!(back, expected, "{scalar} {endian}");
        }
    }
    // Floats: f32 rounds, f64 is copied, NaN stays NaN.
    let mut bytes = vec![0u8; 8 * 3];
    encode_samples(
        ScalarType::F64,
        Endian::Big,
        &[0.1, -2.0, f64::NAN],
        &mut bytes,
    );
    let mut back = [0.0; 3];
    decode_samples(ScalarType::F64, Endian::Big, &bytes, &mut back);
    assert_eq!(back[..2], [0.1, -2.0]);
    assert!(back[2].is_nan());
}

#[test]
fn nrrd_header_is_standard() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ball.nrrd");
    let grid = Grid {
        dims: [5, 4, 3],
        spacing: [0.5, 1.0, 2.5],
        origin: [0.0; 3],
        direction: tmc::volume::IDENTITY,
    };
    let source = Synthetic::new(Kind::Sphere, grid, ScalarType::U16, 0).unwrap();
    write_volume(&path, &source, ScalarType::U16, None).unwrap();
    let bytes = fs::read(&path).unwrap();
    let end = bytes.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    let lines: Vec<&str> = header.lines().collect();
    assert_eq!(lines[0], "NRRD0004");
    for line in [
        "type: uint16",
        "dimension: 3",
        "sizes: 5 4 3",
        "endian: little",
        "encoding: raw",
        "space: left-posterior-superior",
        "space directions: (0.5,0,0) (0,1,0) (0,0,2.5)",
        "space origin: (0,0,0)",
        "kinds: domain domain domain",
    ] {
        assert!(lines.contains(&line), "header lacks '{line}':\n{header}");
    }
    for line in &lines[1..lines.len() - 1] {
        assert!(
            line.starts_with('#') || line.contains(": "),
            "bad line '{line}'"
        );
    }
    assert_eq!(bytes.len() - end, 5 * 4 * 3 * 2);
    assert_eq!(
        VolumeFormat::Nrrd.header(&grid, ScalarType::U16).unwrap(),
        bytes[..end]
    );
}

#[test]
fn npy_header_is_standard() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ball.npy");
    let grid = Grid::unit([5, 4, 3]);
    let source = Synthetic::new(Kind::Torus, grid, ScalarType::I16, 0).unwrap();
    write_volume(&path, &source, ScalarType::I16, None).unwrap();
    let bytes = fs::read(&path).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + len) % 64, 0);
    let dict = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(dict.starts_with("{'descr': '<i2', 'fortran_order': False, 'shape': (3, 4, 5), }"));
    assert!(dict.ends_with('\n'));
    assert_eq!(bytes.len(), 10 + len + 5 * 4 * 3 * 2);
}

#[test]
fn volumes_are_deterministic_for_a_seed() {
    let dir = tempfile::tempdir().unwrap();
    let grid = Grid::unit([20, 18, 12]);
    for kind in Kind::ALL {
        let a = samples(&Synthetic::new(kind, grid, ScalarType::F32, 1).unwrap());
        let b = samples(&Synthetic::new(kind, grid, ScalarType::F32, 1).unwrap());
        let c = samples(&Synthetic::new(kind, grid, ScalarType::F32, 2).unwrap());
        assert_eq!(a, b, "{kind}");
        assert_eq!(a != c, kind.uses_seed(), "{kind}");
        // The same file, byte for byte, twice.
        let source = Synthetic::new(kind, grid, ScalarType::U16, 7).unwrap();
        let (p, q) = (dir.path().join("p.nrrd"), dir.path().join("q.nrrd"));
        write_volume(&p, &source, ScalarType::U16, None).unwrap();
        write_volume(&q, &source, ScalarType::U16, None).unwrap();
        assert_eq!(fs::read(&p).unwrap(), fs::read(&q).unwrap(), "{kind}");
    }
}

#[test]
fn head_phantom_has_ct_values() {
    let grid = Grid::unit([81, 81, 81]);
    let head = Synthetic::new(Kind::Head, grid, ScalarType::I16, 3).unwrap();
    let mut plane = vec![0.0; grid.plane_len()];
    head.read_plane(40, &mut plane).unwrap();
    let at = |x: usize, y: usize| plane[x + 81 * y];
    // Air in the corner, brain in the middle (both with +-15 HU of noise).
    assert!((at(0, 0) + 1000.0).abs() <= 15.0, "{}", at(0, 0));
    assert!((at(40, 40) - 30.0).abs() <= 15.0, "{}", at(40, 40));
    // Bone along the x axis through the centre.
    let row_max = (0..81).map(|x| at(x, 40)).fold(f64::MIN, f64::max);
    assert!((1000.0..=1515.0).contains(&row_max), "{row_max}");
}

#[test]
fn head_skull_is_a_closed_manifold() {
    let grid = Grid {
        dims: [64, 60, 48],
        spacing: [1.0, 1.0, 1.3],
        origin: [0.0; 3],
        direction: tmc::volume::IDENTITY,
    };
    for scalar in [ScalarType::I16, ScalarType::U8] {
        let head = Synthetic::new(Kind::Head, grid, scalar, 11).unwrap();
        let iso = head.suggested_iso();
        assert_eq!(iso, hounsfield_to_stored(HEAD_SKULL_ISO_HU, scalar));
        let params = ExtractParams {
            iso,
            close: true,
            ..ExtractParams::default()
        };
        let (mesh, _) = tmc::extract(&head, &params).unwrap();
        let report = tmc::check::check_mesh(&mesh);
        assert!(!mesh.triangles.is_empty());
        assert!(report.is_closed_manifold(), "{scalar}: {report:?}");
        // The skull's outer and inner surfaces at least.
        assert!(report.components >= 2, "{scalar}: {report:?}");
    }
}

#[test]
fn cli_synth_writes_and_says_how_to_read_raw() {
    let dir = tempfile::tempdir().unwrap();
    let raw = dir.path().join("t.raw");
    let out = tmc(&[
        "synth",
        "torus",
        "--dims",
        "8,7,6",
        "--dtype",
        "i16",
        "-o",
        s(&raw),
        "--spacing",
        "1,1,2",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(out.stdout.is_empty());
    assert!(
        stderr.contains("--dims 8,7,6 --dtype i16 --spacing 1,1,2"),
        "{stderr}"
    );
    assert!(stderr.contains("--iso 0"), "{stderr}");
    assert_eq!(fs::metadata(&raw).unwrap().len(), 8 * 7 * 6 * 2);

    // The same volume through .nrrd, quietly.
    let nrrd = dir.path().join("t.nrrd");
    let out = tmc(&[
        "synth",
        "torus",
        "--dims",
        "8,7,6",
        "--dtype",
        "i16",
        "-o",
        s(&nrrd),
        "--spacing",
        "1,1,2",
        "--quiet",
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stderr.is_empty() && out.stdout.is_empty());
    let grid = Grid {
        dims: [8, 7, 6],
        spacing: [1.0, 1.0, 2.0],
        origin: [0.0; 3],
        direction: tmc::volume::IDENTITY,
    };
    let expected = samples(&Synthetic::new(Kind::Torus, grid, ScalarType::I16, 0).unwrap());
    let read = tmc::volume::open(&nrrd, None).unwrap();
    assert_eq!(read.grid(), &grid);
    assert_eq!(samples(read.as_ref()), expected);
    assert!(fs::read(&nrrd).unwrap().ends_with(&fs::read(&raw).unwrap()));
}

#[test]
fn cli_synth_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let out_nrrd = dir.path().join("v.nrrd");
    let missing = dir.path().join("missing/v.nrrd");
    let bad_ext = dir.path().join("v.vtk");
    let sub = dir.path().join("sub.nrrd");
    fs::create_dir(&sub).unwrap();
    let cases: [(Vec<&str>, i32, &str); 11] = [
        (
            vec![
                "cube",
                "--dims",
                "4,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&out_nrrd),
            ],
            2,
            "cube",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "0,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&out_nrrd),
            ],
            2,
            "0,4,4",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4",
                "--dtype",
                "u8",
                "-o",
                s(&out_nrrd),
            ],
            2,
            "4,4",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "u128",
                "-o",
                s(&out_nrrd),
            ],
            2,
            "u128",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "f16",
                "-o",
                s(&out_nrrd),
            ],
            1,
            "NRRD has no 16-bit float type",
        ),
        (
            vec!["sphere", "--dims", "4,4,4", "-o", s(&out_nrrd)],
            2,
            "--dtype",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "1,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&out_nrrd),
            ],
            1,
            "at least 2",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&bad_ext),
            ],
            1,
            "unknown volume format",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "u8",
                "-o",
                s(&missing),
            ],
            1,
            "missing does not exist",
        ),
        (
            vec!["sphere", "--dims", "4,4,4", "--dtype", "u8", "-o", s(&sub)],
            1,
            "directory",
        ),
        (
            vec![
                "sphere",
                "--dims",
                "4,4,4",
                "--dtype",
                "u8",
                "--spacing",
                "-1,1,1",
                "-o",
                s(&out_nrrd),
            ],
            2,
            "spacing must be positive",
        ),
    ];
    for (args, code, needle) in cases {
        let mut full = vec!["synth"];
        full.extend(&args);
        let out = tmc(&full);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("tmc: "), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(
            !stderr.contains(".tmc-"),
            "{args:?} names a temporary file: {stderr}"
        );
        assert_eq!(
            names(dir.path()),
            ["sub.nrrd"],
            "{args:?}: file left behind"
        );
    }
}

#[test]
fn cli_extract_reports_resources() {
    let dir = tempfile::tempdir().unwrap();
    let volume = dir.path().join("head.nrrd");
    let out = tmc(&[
        "synth",
        "head",
        "--dims",
        "40,36,30",
        "--dtype",
        "u8",
        "-o",
        s(&volume),
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let mesh = dir.path().join("skull.ply");
    let out = tmc(&[
        "extract",
        s(&volume),
        "--iso",
        "150",
        "--close",
        "-o",
        s(&mesh),
        "--json",
        "--quiet",
        "--slab-depth",
        "4",
        "--threads",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(stderr.is_empty(), "--quiet printed {stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "slabs",
        "threads",
        "slab_depth",
        "planes_read",
        "bytes_read",
        "bytes_written",
        "peak_rss_anon_bytes",
        "vm_hwm_bytes",
        "read_seconds",
        "cell_seconds",
        "write_seconds",
        "seconds",
        "wall_seconds",
        "vertices",
    ] {
        assert!(json.get(key).is_some(), "JSON lacks '{key}': {json}");
    }
    assert_eq!(json["slab_depth"], 4);
    // 31 cell layers with the padding, 4 per slab.
    assert_eq!(json["slabs"], 8);
    let planes = json["planes_read"].as_u64().unwrap();
    assert_eq!(json["bytes_read"], (planes - 2) * 40 * 36);
    assert_eq!(json["bytes_written"], fs::metadata(&mesh).unwrap().len());
    if cfg!(target_os = "linux") {
        assert!(json["peak_rss_anon_bytes"].as_u64().unwrap() > 0);
        assert!(json["vm_hwm_bytes"].as_u64().unwrap() > 0);
    }

    // The table has the same rows; --quiet and --stats do not go together.
    let out = tmc(&[
        "extract",
        s(&volume),
        "--iso",
        "150",
        "-o",
        s(&mesh),
        "--stats",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    for row in [
        "slabs",
        "bytes read",
        "bytes written",
        "peak anonymous memory",
        "wall time",
    ] {
        assert!(stderr.contains(row), "table lacks '{row}': {stderr}");
    }
    let out = tmc(&[
        "extract",
        s(&volume),
        "--iso",
        "150",
        "-o",
        s(&mesh),
        "--stats",
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
