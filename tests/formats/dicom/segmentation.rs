//! DICOM Segmentation objects against independent writers: SEGs written
//! by highdicom from a known label volume on a known CT geometry
//! (`scripts/fixtures/dicom_clinical.py seg`, run at test time: binary,
//! fractional, overlapping, frames of empty slices omitted) and pydicom's
//! own `liver_1frame.dcm`. A SEG's labels must give the meshes of the label
//! volume it was written from, byte for byte (the `.npy` twin on the same
//! grid, through `--spacing` and `--origin`).
//!
//! They need a Python with pydicom, numpy and highdicom; without
//! highdicom they say so and pass (CI installs it).

use super::clinical::{python, run_script, test_files};
use crate::common::cli::{assert_one_line, tmc};
use std::path::{Path, PathBuf};
use std::process::Command;
use tmc::volume::{self, zarr::ZarrSelect};

/// The fixtures, written into a temporary folder, with the `--spacing`
/// and `--origin` arguments of their grid; `None` (said on stderr) without
/// highdicom.
fn fixtures() -> Option<(String, tempfile::TempDir, Vec<String>)> {
    let python = python()?;
    let has_highdicom = Command::new(&python)
        .args(["-c", "import highdicom"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_highdicom {
        eprintln!("skipped: no highdicom for the Segmentation fixtures (pip install highdicom)");
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let grid = run_script(&python, &["seg", dir.path().to_str().unwrap()]);
    let v: Vec<&str> = grid.split_whitespace().collect();
    assert_eq!(v.len(), 6, "{grid}");
    let args = vec![
        "--origin".to_string(),
        v[..3].join(","),
        "--spacing".to_string(),
        v[3..].join(","),
    ];
    Some((python, dir, args))
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `tmc extract INPUT ARGS.. -o OUT` (quiet), which must succeed.
fn extract(input: &Path, args: &[&str], out: &Path) {
    let mut all = vec!["extract", p(input)];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", p(out), "-q"]);
    let run = tmc(&all);
    assert!(run.status.success(), "{all:?}: {run:?}");
}

/// Every sample of `path` opened with `segment`, in file order.
fn samples(path: &Path, segment: Option<u32>) -> Vec<f64> {
    let select = ZarrSelect {
        segment,
        ..ZarrSelect::default()
    };
    let never = std::sync::atomic::AtomicBool::new(false);
    let source = volume::open_selected(path, None, &select, &never).unwrap();
    let g = *source.grid();
    let mut all = vec![0.0; g.plane_len() * g.dims[2]];
    for (z, plane) in all.chunks_exact_mut(g.plane_len()).enumerate() {
        source.read_plane(z, plane).unwrap();
    }
    all
}

/// The labels of the binary and the fractional SEG (each segment of the
/// fractional one where its fraction is above one half) give the meshes
/// of the label volume they were written from, byte for byte, per label
/// and in one closed `.ply`; the frames highdicom omitted for empty slices
/// (no frame lies on two slices between the segments) read as empty.
#[test]
fn seg_labels_give_the_meshes_of_their_label_volume() {
    let Some((_python, dir, grid)) = fixtures() else {
        return;
    };
    let d = dir.path();
    let grid: Vec<&str> = grid.iter().map(String::as_str).collect();
    for (seg, twin) in [
        ("binary.dcm", "labels.npy"),
        ("fractional.dcm", "fractional_labels.npy"),
    ] {
        let (seg, twin) = (d.join(seg), d.join(twin));
        let mine = d.join("seg_{label}.ply");
        let theirs = d.join("npy_{label}.ply");
        extract(&seg, &["--labels", "all"], &mine);
        let mut args = grid.clone();
        args.extend(["--labels", "all"]);
        extract(&twin, &args, &theirs);
        for label in 1..=3 {
            let read =
                |t: &PathBuf| std::fs::read(p(t).replace("{label}", &label.to_string())).unwrap();
            let (a, b) = (read(&mine), read(&theirs));
            assert!(a.len() > 300, "{}: label {label} is empty", seg.display());
            assert!(
                a == b,
                "{}: label {label} differs from its twin",
                seg.display()
            );
        }
        let (a, b) = (d.join("seg_all.ply"), d.join("npy_all.ply"));
        extract(&seg, &["--labels", "all", "--close"], &a);
        args.push("--close");
        extract(&twin, &args, &b);
        assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap());
        // The samples themselves: the segment numbers of the label volume.
        assert_eq!(
            samples(&seg, None),
            samples(&twin, None),
            "{}",
            seg.display()
        );
    }
}

/// `--segment N` reads one segment alone: 0/1 for a binary SEG, the
/// fraction for a fractional one (its `--iso 0.5` surface is that of the
/// fractions written), whatever the other segments hold.
#[test]
fn one_segment_reads_as_zero_to_one() {
    let Some((_python, dir, grid)) = fixtures() else {
        return;
    };
    let d = dir.path();
    let labels = samples(&d.join("labels.npy"), None);
    for n in 1..=3u32 {
        let mine = samples(&d.join("binary.dcm"), Some(n));
        let want: Vec<f64> = labels
            .iter()
            .map(|&l| f64::from(u8::from(l == f64::from(n))))
            .collect();
        assert_eq!(mine, want, "segment {n}");
    }
    let fractions = samples(&d.join("fractional.dcm"), Some(1));
    assert_eq!(fractions, samples(&d.join("fraction1.npy"), None));
    assert!(fractions.iter().any(|&f| f > 0.0 && f < 1.0));
    let (a, b) = (d.join("seg1.ply"), d.join("npy1.ply"));
    extract(
        &d.join("fractional.dcm"),
        &["--segment", "1", "--iso", "0.5"],
        &a,
    );
    let mut args: Vec<&str> = grid.iter().map(String::as_str).collect();
    args.extend(["--iso", "0.5"]);
    extract(&d.join("fraction1.npy"), &args, &b);
    assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap());
}

/// Overlapping segments: `--labels` refuses with one line naming them and
/// writes nothing; `--segment N` reads each whole; `tmc info` names the
/// pair.
#[test]
fn overlapping_segments_are_refused_as_labels_and_read_one_by_one() {
    let Some((_python, dir, _grid)) = fixtures() else {
        return;
    };
    let d = dir.path();
    let seg = d.join("overlap.dcm");
    let out = d.join("o_{label}.ply");
    let run = tmc(&["extract", p(&seg), "--labels", "all", "-o", p(&out)]);
    let line = assert_one_line(&run, 1);
    assert!(line.contains("segments 1 and 2 overlap"), "{line}");
    assert!(!d.join("o_1.ply").exists() && !d.join("o_2.ply").exists());
    let labels = samples(&d.join("labels.npy"), None);
    let two = samples(&seg, Some(2));
    let want: Vec<f64> = labels
        .iter()
        .map(|&l| f64::from(u8::from(l == 1.0 || l == 2.0)))
        .collect();
    assert_eq!(two, want);
    let run = tmc(&["info", p(&seg), "--json"]);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(text.contains("\"overlapping_segments\":[[1,2]]"), "{text}");
}

/// `tmc info` describes a SEG's segments (text and JSON) and its grid; a
/// folder of SEGs lists each as a series with its segments; a segment the
/// file lacks, and `--segment` on another format, are one clear line.
#[test]
fn info_describes_the_segments() {
    let Some((_python, dir, _grid)) = fixtures() else {
        return;
    };
    let d = dir.path();
    let seg = d.join("binary.dcm");
    let text = String::from_utf8(tmc(&["info", p(&seg)]).stdout).unwrap();
    assert!(
        text.contains("segments        1  \"ball\"  Tissue  MANUAL  3 frame(s)"),
        "{text}"
    );
    assert!(
        text.contains("3  \"bar\"  Tissue  MANUAL  4 frame(s)"),
        "{text}"
    );
    assert!(text.contains("dims            20 x 16 x 8"), "{text}");
    assert!(!text.contains("overlapping"), "{text}");
    let json = String::from_utf8(tmc(&["info", p(&seg), "--json"]).stdout).unwrap();
    assert!(
        json.contains(
            "\"segments\":[{\"number\":1,\"label\":\"ball\",\"property\":\"Tissue\",\"algorithm\":\"MANUAL\",\"frames\":3}"
        ),
        "{json}"
    );
    assert!(json.contains("\"spacing\":[0.8,0.9,2.5]"), "{json}");
    assert!(json.contains("\"origin\":[-10.0,-5.0,35.0]"), "{json}");
    let listing = String::from_utf8(tmc(&["info", p(d)]).stdout).unwrap();
    assert!(
        listing.contains("series 10  SEG  \"binary\"  1 files, 8 slices  20 x 16 x 8"),
        "{listing}"
    );
    assert!(listing.contains("segments 1 (ball), 2 (box), 3 (bar); 1 and 2 overlap"));
    // The SEG series of the folder, chosen by number.
    let run = tmc(&["info", p(d), "--series", "11", "--json"]);
    assert!(String::from_utf8_lossy(&run.stdout).contains("\"frames\":3"));
    let run = tmc(&["info", p(&seg), "--segment", "7"]);
    let line = assert_one_line(&run, 1);
    assert!(line.contains("no segment 7 (it has segments 1 (ball), 2 (box), 3 (bar))"));
    let run = tmc(&["info", p(&d.join("labels.npy")), "--segment", "1"]);
    let line = assert_one_line(&run, 1);
    assert!(line.contains("--segment picks a segment of a DICOM Segmentation"));
}

/// pydicom's `liver_1frame.dcm` (a one-frame BINARY SEG from 3D Slicer,
/// cut down: no NumberOfFrames, three per-frame groups) and its explicit
/// big endian twin read as pydicom reads them.
#[test]
fn pydicoms_liver_segmentation_reads() {
    let Some(python) = python() else { return };
    let dir = test_files(&python);
    let tmp = tempfile::tempdir().unwrap();
    for name in ["liver_1frame.dcm", "liver_expb_1frame.dcm"] {
        let path = dir.join(name);
        let npy = tmp.path().join("liver.npy");
        run_script(&python, &["pixels", p(&path), p(&npy)]);
        let mine = samples(&path, None);
        assert_eq!(mine.len(), 512 * 512, "{name}");
        assert_eq!(mine, samples(&npy, None), "{name}");
        assert!(mine.iter().filter(|&&v| v == 1.0).count() > 30000, "{name}");
        let text = String::from_utf8(tmc(&["info", p(&path)]).stdout).unwrap();
        assert!(
            text.contains("1  \"Liver\"  Liver  SEMIAUTOMATIC"),
            "{text}"
        );
    }
}
