//! DICOM as clinical exports deliver it, against independent writers: the
//! test files that ship inside the pydicom package (real files of many
//! vendors, mixed in one folder) and RT Dose grids written by pydicom from
//! known values (`scripts/fixtures/dicom_clinical.py`, run at test time).
//!
//! They need a Python with pydicom and numpy: `TMC_PYTHON` (then they must
//! run), else `python3` if it has them; otherwise they say so and pass.

use crate::common::cli::{tmc, tmc_within};
use crate::common::parse_off;
use std::path::{Path, PathBuf};
use std::process::Command;
use tmc::volume::{self, dicom};
use tmc::SampleSource;

/// `scripts/fixtures/dicom_clinical.py`.
fn script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/fixtures/dicom_clinical.py")
}

/// A Python with pydicom and numpy, or `None` (said on stderr) when there
/// is none and `TMC_PYTHON` is not set.
pub(super) fn python() -> Option<String> {
    let given = std::env::var("TMC_PYTHON").ok();
    let python = given.clone().unwrap_or_else(|| "python3".to_string());
    let ready = Command::new(&python)
        .args(["-c", "import pydicom, numpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    match (ready, given) {
        (true, _) => Some(python),
        (false, Some(p)) => panic!("TMC_PYTHON={p} has no pydicom and numpy"),
        (false, None) => {
            eprintln!(
                "skipped: no Python with pydicom and numpy (pip install pydicom numpy, or set TMC_PYTHON)"
            );
            None
        }
    }
}

/// Runs the fixture script with `args`; its stdout.
pub(super) fn run_script(python: &str, args: &[&str]) -> String {
    let out = Command::new(python)
        .arg(script())
        .args(args)
        .output()
        .expect("run dicom_clinical.py");
    assert!(
        out.status.success(),
        "dicom_clinical.py {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap().trim().to_string()
}

/// The folder of pydicom's test files (`pydicom/data/test_files`).
pub(super) fn test_files(python: &str) -> PathBuf {
    let dir = PathBuf::from(run_script(python, &["testfiles"]));
    assert!(dir.join("CT_small.dcm").is_file(), "{}", dir.display());
    dir
}

/// `tmc info` on every file and folder of pydicom's test files: exit 0, or
/// 1 with one `tmc: error:` line about the path asked for; never a panic,
/// never an error of a file about another file.
#[test]
fn info_on_every_pydicom_test_file_is_clean() {
    let Some(python) = python() else { return };
    let dir = test_files(&python);
    let mut paths = vec![dir.clone()];
    let mut folders = vec![dir.clone()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path.clone());
            }
            paths.push(path);
        }
    }
    paths.sort();
    let mut read = 0;
    for path in &paths {
        let name = path.to_str().unwrap();
        let out = tmc_within(&["info", name], 60);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        match out.status.code() {
            Some(0) => read += 1,
            Some(1) => {
                assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
                let line = stderr.trim_end();
                // The error names the path asked for, never another file.
                let about = line
                    .strip_prefix("tmc: error: ")
                    .unwrap_or_else(|| panic!("{name}: {line}"));
                // About the file, or about its series (named by its folder:
                // an uneven gap), never naming another file.
                let folder = format!("{}: ", path.parent().unwrap().display());
                let cause = about
                    .strip_prefix(name)
                    .or_else(|| about.strip_prefix(folder.as_str()))
                    .unwrap_or_else(|| panic!("{name}: {line}"));
                // A folder's error may name its own files (its series').
                let others = paths.iter().filter(|p| *p != path && p.is_file());
                for other in others.filter(|_| path.is_file()) {
                    let other = other.to_str().unwrap();
                    assert!(!cause.contains(other), "{name}: {line}");
                }
            }
            code => panic!("{name}: exit {code:?}: {stderr}"),
        }
    }
    // The folder itself lists its series (exit 0); so do these files, in
    // a folder with 30-odd series of every kind.
    let out = tmc(&["info", dir.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("series 4  CT  \"Lv2\""), "{text}");
    for name in [
        "CT_small.dcm",
        "MR_small.dcm",
        "rtdose.dcm",
        "JPEG2000.dcm",
        "MR_small_jp2klossless.dcm",
        "J2K_pixelrep_mismatch.dcm",
        "693_J2KI.dcm",
    ] {
        let path = dir.join(name);
        let out = tmc(&["info", path.to_str().unwrap()]);
        let ok = out.status.success();
        // JPEG2000.dcm (NM) has no ImagePositionPatient: an error about itself.
        assert_eq!(ok, name != "JPEG2000.dcm", "{name}: {:?}", out);
    }
    assert!(read > 10, "only {read} of {} paths read", paths.len());
}

/// JPEG 2000 lossless decodes to the samples of its uncompressed twin, bit
/// for bit; lossy JPEG 2000 files (8-16 bits, signed and unsigned) decode
/// to their size.
#[test]
fn jpeg2000_matches_its_uncompressed_twin() {
    let Some(python) = python() else { return };
    let dir = test_files(&python);
    let samples = |name: &str| {
        let path = dir.join(name);
        let vol = volume::open(&path, None).unwrap();
        let series = dicom::open(&path).unwrap();
        assert_eq!(series.plane_file(0), Some(path.as_path()), "{name}");
        let mut plane = vec![0.0; vol.grid().plane_len()];
        vol.read_plane(0, &mut plane).unwrap();
        (*vol.grid(), plane)
    };
    let (g1, plain) = samples("MR_small.dcm");
    let (g2, j2k) = samples("MR_small_jp2klossless.dcm");
    assert_eq!(g1, g2);
    assert_eq!(plain.len(), 64 * 64);
    assert!(plain.iter().any(|&v| v != plain[0]));
    assert_eq!(plain, j2k, "lossless JPEG 2000 differs from its twin");
    for (name, dims) in [
        ("693_J2KI.dcm", [512, 512, 1]),
        ("J2K_pixelrep_mismatch.dcm", [512, 512, 1]),
    ] {
        let (g, plane) = samples(name);
        assert_eq!(g.dims, dims, "{name}");
        assert!(plane.iter().all(|v| v.is_finite()), "{name}");
        assert!(plane.iter().any(|&v| v != plane[0]), "{name}");
    }
}

/// One slice file reads its own series, whatever else the folder holds;
/// `--series` picks a series of a folder by number or UID.
#[test]
fn a_series_is_chosen_among_many() {
    let Some(python) = python() else { return };
    let dir = test_files(&python);
    let ct = dicom::open(&dir.join("CT_small.dcm")).unwrap();
    assert_eq!(ct.grid().dims, [128, 128, 1]);
    assert!(ct
        .skipped()
        .iter()
        .any(|n| n.contains("rtplan.dcm: not an image (RTPLAN")));
    let d = dir.to_str().unwrap();
    let e = dicom::open(&dir).unwrap_err().to_string();
    assert!(e.contains("DICOM series in one directory"), "{e}");
    assert!(e.contains("--series"), "{e}");
    let list = dicom::list_series(&dir).unwrap();
    let lv2 = list
        .iter()
        .find(|s| s.description.as_deref() == Some("Lv2"))
        .unwrap();
    assert_eq!(
        (lv2.number.as_deref(), lv2.dims),
        (Some("4"), Some([512, 512, 1]))
    );
    for pick in ["4", lv2.uid.as_str()] {
        let out = tmc(&["info", d, "--series", pick, "--json"]);
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("\"dims\":[512,512,1]"), "{text}");
    }
    let out = tmc(&["info", d, "--json"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("\"series\":["), "{text}");
    let out = tmc(&["info", d, "--series", "12345"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no DICOM series 12345"));
}

/// RT Dose grids written by pydicom from dose(p) = 60 - |p - C| Gy, frames
/// placed by relative and by absolute Grid Frame Offset Vectors: both read
/// in Gy, and the 50 Gy isodose surface is the sphere of radius 10 mm
/// about C, in patient coordinates.
#[test]
fn rt_dose_isodose_is_in_place_and_in_gray() {
    let Some(python) = python() else { return };
    let centre = [14.0, -7.0, 103.0];
    let tmp = tempfile::tempdir().unwrap();
    let mut meshes = Vec::new();
    for form in ["relative", "absolute"] {
        let path = tmp.path().join(format!("dose_{form}.dcm"));
        let p = path.to_str().unwrap();
        run_script(&python, &["rtdose", p, form]);
        let out = tmc(&["info", p, "--json"]);
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("\"units\":\"GY\""), "{text}");
        assert!(text.contains("\"spacing\":[2.0,1.5,2.5]"), "{text}");
        assert!(text.contains("\"origin\":[0.0,-20.0,90.0]"), "{text}");
        let info = String::from_utf8_lossy(&tmc(&["info", p]).stdout).into_owned();
        assert!(info.contains("units           GY"), "{info}");
        let mesh = tmp.path().join(format!("{form}.off"));
        let out = tmc(&["extract", p, "--iso", "50", "-o", mesh.to_str().unwrap()]);
        assert!(out.status.success(), "{out:?}");
        let text = std::fs::read_to_string(&mesh).unwrap();
        let m = parse_off(&text);
        assert!(m.triangles.len() > 100, "{form}");
        for v in &m.vertices {
            let r = (0..3)
                .map(|i| (f64::from(v[i]) - centre[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!((r - 10.0).abs() < 0.3, "{form}: vertex {v:?} at {r} mm");
        }
        meshes.push(text);
    }
    assert_eq!(meshes[0], meshes[1], "relative and absolute offsets differ");
}

/// A series whose every attribute pydicom stored with VR UN (the bytes of
/// their own VR, as some converters write them) reads as the same series
/// stored plainly: grid, rescaled samples and mesh.
#[test]
fn attributes_stored_as_vr_un_read_as_their_own() {
    let Some(python) = python() else { return };
    let tmp = tempfile::tempdir().unwrap();
    run_script(&python, &["unknown_vr", tmp.path().to_str().unwrap()]);
    let read = |kind: &str| {
        let vol = volume::open(&tmp.path().join(kind), None).unwrap();
        let g = *vol.grid();
        let mut all = vec![0.0; g.plane_len() * g.dims[2]];
        for (z, plane) in all.chunks_exact_mut(g.plane_len()).enumerate() {
            vol.read_plane(z, plane).unwrap();
        }
        (g, all)
    };
    let (plain, un) = (read("plain"), read("un"));
    assert_eq!(plain.0, un.0);
    assert_eq!(plain.0.dims, [20, 16, 12]);
    assert_eq!(plain.1, un.1);
    assert!(plain.1.iter().any(|&v| v != plain.1[0]));
    let mesh = |kind: &str| {
        let out = tmp.path().join(format!("{kind}.ply"));
        let input = tmp.path().join(kind);
        let run = tmc(&[
            "extract",
            input.to_str().unwrap(),
            "--iso",
            "-500",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(run.status.success(), "{run:?}");
        std::fs::read(out).unwrap()
    };
    assert_eq!(mesh("plain"), mesh("un"));
}
