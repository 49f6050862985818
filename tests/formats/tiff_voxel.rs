//! The voxel size of TIFF stacks (ImageJ and OME-TIFF metadata written by
//! tifffile, `scripts/fixtures/make_tiff_voxel.py`) and `--spacing` /
//! `--origin` for every input: the same samples give the same mesh in the
//! same millimetres whether the grid comes from the file or the options,
//! an option that overrides the file says so, and `tmc info` tells where
//! each value came from.

use crate::common;

use common::cli::{s, tmc};
use common::formats::{all_samples, data_dir};
use std::path::PathBuf;
use tmc::volume::{self, ValueFrom};

fn data(name: &str) -> PathBuf {
    data_dir().join(name)
}

const MM: [f64; 3] = [0.5, 1.0, 2.0];

#[test]
fn imagej_and_ome_metadata_give_the_spacing_in_millimetres() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    for name in [
        "tv_imagej_mm.tif",
        "tv_imagej_micron.tif",
        "tv_ome.ome.tif",
        "tv_ome_angstrom.ome.tif",
        "tv_imagej_angstrom.tif",
    ] {
        let src = volume::open(&data(name), None).unwrap();
        let g = src.grid();
        for (got, want) in g.spacing.iter().zip(MM) {
            assert!((got - want).abs() < 1e-12, "{name}: {g:?}");
        }
        assert_eq!(g.origin, [0.0; 3], "{name}");
        assert_eq!(all_samples(&*src), all_samples(&*twin), "{name}");
        let notes = src.notes();
        assert!(
            matches!(&notes.spacing_from, ValueFrom::File { what } if what.contains("in mm")),
            "{name}: {notes:?}"
        );
        assert_eq!(notes.origin_from, ValueFrom::Default, "{name}");
    }
    let plain = volume::open(&data("tv_imagej_plain.tif"), None).unwrap();
    assert_eq!(plain.grid().spacing, [1.0; 3]);
    assert_eq!(plain.notes().spacing_from, ValueFrom::Default);
}

/// ImageJ's `xorigin=`, `yorigin=`, `zorigin=` (the pixel where the
/// coordinates' zero lies, as ImageJ's Calibration writes it) place the
/// first voxel at `-origin * spacing`; the origin was 0 and `tmc info` said
/// the file states none.
#[test]
fn imagej_origin_places_the_first_voxel() {
    let src = volume::open(&data("tv_imagej_origin.tif"), None).unwrap();
    let plain = volume::open(&data("tv_imagej_mm.tif"), None).unwrap();
    let (g, p) = (src.grid(), plain.grid());
    assert_eq!(g.spacing, p.spacing);
    let pixels = [3.0, -4.0, 1.5];
    for ((origin, pixel), spacing) in g.origin.iter().zip(pixels).zip(g.spacing) {
        assert!((origin + pixel * spacing).abs() < 1e-12, "{:?}", g.origin);
    }
    assert_eq!(all_samples(&*src), all_samples(&*plain));
    assert!(
        matches!(&src.notes().origin_from, ValueFrom::File { what } if what.contains("ImageJ")),
        "{:?}",
        src.notes().origin_from
    );
    assert_eq!(plain.grid().origin, [0.0; 3]);
    assert_eq!(plain.notes().origin_from, ValueFrom::Default);
}

/// Runs `tmc extract` and returns the PLY bytes.
fn mesh(input: &str, extra: &[&str], dir: &std::path::Path, name: &str) -> (Vec<u8>, String) {
    let out = dir.join(name);
    let mut args = vec!["extract", input, "--iso", "41", "-o", s(&out)];
    args.extend_from_slice(extra);
    let run = tmc(&args);
    assert!(run.status.success(), "{run:?}");
    let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
    (std::fs::read(&out).unwrap(), stderr)
}

#[test]
fn spacing_and_origin_set_the_grid_of_any_input_and_override_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let npy = data("vt_twin.npy");
    let tif = data("tv_imagej_mm.tif");
    let plain = data("vt_multi_u16.tif");
    // The ImageJ file's millimetres, and the same by option on a .npy and
    // on a TIFF without metadata (once refused for wanting --dims).
    let (from_file, note) = mesh(s(&tif), &[], dir.path(), "a.ply");
    assert!(note.is_empty(), "{note}");
    let (from_npy, note) = mesh(s(&npy), &["--spacing", "0.5,1,2"], dir.path(), "b.ply");
    assert!(note.is_empty(), "nothing overridden: {note}");
    let (from_tif, _) = mesh(s(&plain), &["--spacing", "0.5,1,2"], dir.path(), "c.ply");
    assert_eq!(from_file, from_npy);
    assert_eq!(from_file, from_tif);
    // Overriding the file's spacing says so, once, and wins.
    let (unit, note) = mesh(s(&tif), &["--spacing", "1,1,1"], dir.path(), "d.ply");
    let (want, _) = mesh(s(&npy), &[], dir.path(), "e.ply");
    assert_eq!(unit, want);
    assert_eq!(note.lines().count(), 1, "{note}");
    assert!(
        note.starts_with("tmc: note: ")
            && note.contains("--spacing 1,1,1 overrides the spacing 0.5,1,2"),
        "{note}"
    );
    let (_, quiet) = mesh(s(&tif), &["--spacing", "1,1,1", "-q"], dir.path(), "f.ply");
    assert!(quiet.is_empty(), "{quiet}");
    // An origin moves every vertex by itself.
    let (moved, _) = mesh(s(&npy), &["--origin", "10,-20,30.5"], dir.path(), "g.obj");
    let (still, _) = mesh(s(&npy), &[], dir.path(), "h.obj");
    let (moved, still) = (obj_vertices(&moved), obj_vertices(&still));
    assert!(!still.is_empty());
    assert_eq!(moved.len(), still.len());
    for (m, v) in moved.iter().zip(&still) {
        for (a, shift) in [10.0, -20.0, 30.5].iter().enumerate() {
            assert!((m[a] - v[a] - shift).abs() < 1e-4, "{m:?} {v:?}");
        }
    }
}

/// The `v x y z` lines of an OBJ file.
fn obj_vertices(bytes: &[u8]) -> Vec<[f64; 3]> {
    String::from_utf8_lossy(bytes)
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// `tmc info --json` of `args`.
fn info(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["info", "--json"];
    all.extend_from_slice(args);
    let out = tmc(&all);
    assert!(out.status.success(), "{out:?}");
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn info_shows_the_grid_used_and_where_each_value_came_from() {
    let tif = data("tv_imagej_micron.tif");
    let j = info(&[s(&tif)]);
    assert_eq!(j["spacing_from"]["kind"], "file");
    assert!(j["spacing_from"]["what"]
        .as_str()
        .unwrap()
        .contains("micron in mm"));
    assert_eq!(j["origin_from"]["kind"], "default");
    assert!(j["chunks"].is_null());
    let j = info(&[
        s(&data("tv_imagej_mm.tif")),
        "--spacing",
        "1,2,3",
        "--origin",
        "4,5,6",
    ]);
    assert_eq!(j["spacing"], serde_json::json!([1.0, 2.0, 3.0]));
    assert_eq!(j["origin"], serde_json::json!([4.0, 5.0, 6.0]));
    assert_eq!(
        j["spacing_from"],
        serde_json::json!({"kind": "option", "file": [0.5, 1.0, 2.0]})
    );
    assert_eq!(
        j["origin_from"],
        serde_json::json!({"kind": "option", "file": null})
    );
    let j = info(&[s(&data("vt_twin.npy"))]);
    assert_eq!(j["spacing_from"]["kind"], "default");
    let text = tmc(&["info", s(&data("vt_twin.npy")), "--spacing", "2,2,2"]);
    let text = String::from_utf8_lossy(&text.stdout);
    let from: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("from "))
        .map(|l| l.trim_start()[4..].trim())
        .collect();
    assert_eq!(
        from,
        ["command line", "default (the file states none)"],
        "{text}"
    );
}

#[test]
fn spacing_must_be_positive_for_every_input() {
    let out = tmc(&["info", s(&data("vt_twin.npy")), "--spacing", "1,0,1"]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
}

/// A hyperstack of several channels or time points beside its z slices
/// (ImageJ's `channels=` / `frames=` with `slices=`, OME's `SizeC` /
/// `SizeT` with `SizeZ`) is refused with one line: its pages interleave
/// the volumes, and were stacked as 4 z planes of two volumes mixed
/// (channel 0 of z 0, channel 1 of z 0, ...). Pages along one axis only
/// (`tv_imagej_plain.tif`, `channels=6`) stay a z stack (the test above).
/// Fixtures written by tifffile (`scripts/fixtures/make_tiff_voxel.py`).
#[test]
fn hyperstacks_of_several_channels_or_time_points_are_refused() {
    for (name, what) in [
        (
            "tv_imagej_channels.tif",
            "an ImageJ hyperstack of 2 channels, 2 z slices",
        ),
        (
            "tv_imagej_frames.tif",
            "an ImageJ hyperstack of 2 z slices, 2 time points",
        ),
        (
            "tv_ome_channels.ome.tif",
            "an OME-TIFF of 2 channels, 2 z slices",
        ),
    ] {
        let err = volume::open(&data(name), None)
            .err()
            .expect(name)
            .to_string();
        assert!(err.contains(what), "{name}: {err}");
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("m.ply");
        let r = tmc(&["extract", s(&data(name)), "--iso", "50", "-o", s(&out)]);
        assert!(!r.status.success(), "{name}");
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        assert!(stderr.contains(what), "{name}: {stderr}");
        assert!(!out.exists(), "{name}");
    }
}
