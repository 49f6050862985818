//! Zarr v2 and v3 and OME-Zarr against fixtures written by zarr-python 3
//! (`scripts/fixtures/make_zarr.py`): the same samples and the same mesh,
//! in the same physical coordinates, as the `.npy` of the same samples;
//! missing chunks read as the fill value; each chunk is decompressed once
//! per pass; damaged stores give one clear line and no output.

use crate::common;

use common::cli::{refused, s, tmc};
use common::formats::{all_samples, data_dir};
use std::path::{Path, PathBuf};
use tmc::volume::zarr::{self, ZarrSelect};
use tmc::volume::{self, ValueFrom};
use tmc::{extract, ExtractParams, SampleSource};

fn data(name: &str) -> PathBuf {
    data_dir().join(name)
}

/// The mesh of `src` at a few isovalues equals the twin's, placed on
/// `spacing` and `origin`.
fn same_mesh(src: &dyn SampleSource, twin: &dyn SampleSource, spacing: [f64; 3], origin: [f64; 3]) {
    for iso in [20.5, 41.0, 60.5] {
        let params = ExtractParams {
            iso,
            ..ExtractParams::default()
        };
        let (mesh, _) = extract(src, &params).unwrap();
        let (want, _) = extract(twin, &params).unwrap();
        assert!(!want.triangles.is_empty());
        assert_eq!(mesh.triangles, want.triangles, "iso {iso}");
        for (v, w) in mesh.vertices.iter().zip(&want.vertices) {
            for a in 0..3 {
                let mapped = origin[a] + f64::from(w[a]) * spacing[a];
                assert!((f64::from(v[a]) - mapped).abs() < 1e-5, "{v:?} vs {w:?}");
            }
        }
    }
}

#[test]
fn v2_and_v3_arrays_with_every_codec_read_as_the_npy() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    for name in [
        "zr_v3_zstd.zarr",
        "zr_v3_blosc_lz4.zarr",
        "zr_v3_blosc_zlib_bitshuffle.zarr",
        "zr_v3_gzip_big.zarr",
        "zr_v3_transpose.zarr",
        "zr_v3_shard.zarr",
        "zr_v2_blosc.zarr",
        "zr_v2_zlib_be.zarr",
    ] {
        let src = volume::open(&data(name), None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(src.grid().dims, [9, 7, 6], "{name}");
        assert_eq!(all_samples(&*src), all_samples(&*twin), "{name}");
        same_mesh(&*src, &*twin, [1.0; 3], [0.0; 3]);
        let notes = src.notes();
        let chunks = notes.chunks.unwrap();
        assert_eq!(chunks.chunk_shape, [4, 3, 2], "{name}");
        assert!(chunks.stored_bytes.unwrap() > 0);
    }
}

#[test]
fn missing_chunks_read_as_the_fill_value() {
    let src = volume::open(&data("zr_v3_missing.zarr"), None).unwrap();
    let want = volume::open(&data("zr_v3_missing.expected.npy"), None).unwrap();
    let got = all_samples(&*src);
    assert_eq!(got, all_samples(&*want));
    assert!(got[9 * 7 * 2..].iter().all(|&v| v == 7.0));
    assert!(got[..9 * 7 * 2].iter().any(|&v| v != 7.0));
}

#[test]
fn groups_by_path_or_array_option_and_ome_levels() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let by_path = volume::open(&data("zr_group.zarr/scans/ct"), None).unwrap();
    assert_eq!(all_samples(&*by_path), all_samples(&*twin));
    let select = ZarrSelect {
        array: Some("scans/ct".into()),
        ..ZarrSelect::default()
    };
    let by_option = zarr::open(&data("zr_group.zarr"), &select).unwrap();
    assert_eq!(all_samples(&by_option), all_samples(&*twin));
    for name in ["zr_ome_04.zarr", "zr_ome_05.zarr"] {
        let src = volume::open(&data(name), None).unwrap();
        let g = *src.grid();
        assert_eq!(g.spacing, [0.5, 1.0, 2.0], "{name}");
        assert_eq!(g.origin, [1.5, -2.0, 3.25], "{name}");
        assert!(matches!(src.notes().spacing_from, ValueFrom::File { .. }));
        same_mesh(&*src, &*twin, [0.5, 1.0, 2.0], [1.5, -2.0, 3.25]);
        let coarse = ZarrSelect {
            level: Some(1),
            ..ZarrSelect::default()
        };
        let l1 = zarr::open(&data(name), &coarse).unwrap();
        assert_eq!(l1.grid().dims, [5, 4, 3]);
        assert_eq!(l1.grid().spacing, [1.0, 2.0, 4.0]);
    }
}

/// A level of an OME-Zarr image opened by its path (`image.zarr/1`) is
/// placed as `--level 1` places it (the image's scale and translation),
/// not on a unit grid: the same array read two documented ways.
#[test]
fn an_ome_level_opened_by_its_path_keeps_the_image_grid() {
    for name in ["zr_ome_04.zarr", "zr_ome_05.zarr"] {
        for level in [0, 1] {
            let select = ZarrSelect {
                level: Some(level),
                ..ZarrSelect::default()
            };
            let want = zarr::open(&data(name), &select).unwrap();
            for path in [format!("{name}/{level}"), format!("{name}/{level}/")] {
                let got = volume::open(&data(&path), None).unwrap();
                assert_eq!(got.grid(), want.grid(), "{path}");
                let from = got.notes().spacing_from;
                assert!(matches!(from, ValueFrom::File { .. }), "{path}: {from:?}");
            }
        }
    }
    // A plain group's array keeps the unit grid.
    let plain = volume::open(&data("zr_group.zarr/scans/ct"), None).unwrap();
    assert_eq!(plain.grid().spacing, [1.0; 3]);
}

/// A space axis's `unit` converts its scale and translation to
/// millimetres whether or not the axis states its `type` (NGFF 0.4 and
/// 0.5: an axis MUST have a name and SHOULD have a type): `micrometer` on
/// axes `{"name": "z", "unit": "micrometer"}` read as micrometres. They
/// were read as millimetres, the mesh 1000 times too large. An axis
/// without a type whose unit is no length (a time axis in seconds) is
/// not a space axis and changes nothing.
#[test]
fn ome_axes_without_a_type_keep_their_unit() {
    let dir = tempfile::tempdir().unwrap();
    let stated = volume::open(&data("zr_ome_04.zarr"), None).unwrap();
    for (axes, mm, said) in [
        (
            r#"[{"name": "c", "type": "channel"},
                {"name": "z", "type": "space", "unit": "micrometer"},
                {"name": "y", "type": "space", "unit": "micrometer"},
                {"name": "x", "type": "space", "unit": "micrometer"}]"#,
            1e-3,
            "micrometer in mm",
        ),
        (
            r#"[{"name": "c", "unit": "second"},
                {"name": "z", "unit": "micrometer"},
                {"name": "y", "unit": "micrometer"},
                {"name": "x", "unit": "micrometer"}]"#,
            1e-3,
            "micrometer in mm",
        ),
        (
            r#"[{"name": "c"}, {"name": "z", "unit": "nanometer"},
                {"name": "y", "unit": "nanometer"}, {"name": "x", "unit": "nanometer"}]"#,
            1e-6,
            "nanometer in mm",
        ),
        (
            r#"[{"name": "c"}, {"name": "z"}, {"name": "y"}, {"name": "x"}]"#,
            1.0,
            "no unit: values as stated",
        ),
    ] {
        let store = copy("zr_ome_04.zarr", dir.path());
        let attrs_path = store.join(".zattrs");
        let mut attrs: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&attrs_path).unwrap()).unwrap();
        attrs["multiscales"][0]["axes"] = serde_json::from_str(axes).unwrap();
        std::fs::write(&attrs_path, serde_json::to_vec(&attrs).unwrap()).unwrap();
        let src = volume::open(&store, None).unwrap_or_else(|e| panic!("{axes}: {e}"));
        let (g, s) = (src.grid(), stated.grid());
        for a in 0..3 {
            assert!(
                (g.spacing[a] - s.spacing[a] * mm).abs() < 1e-15,
                "{axes}: spacing {:?}, stated {:?}",
                g.spacing,
                s.spacing
            );
            assert!(
                (g.origin[a] - s.origin[a] * mm).abs() < 1e-12,
                "{axes}: origin {:?}, stated {:?}",
                g.origin,
                s.origin
            );
        }
        let from = format!("{}", src.notes().spacing_from);
        assert!(from.contains(said), "{axes}: {from}");
        assert_eq!(all_samples(&*src), all_samples(&*stated));
        std::fs::remove_dir_all(&store).unwrap();
    }
}

#[test]
fn each_chunk_is_decompressed_once_per_pass() {
    let twin = volume::open(&data("zr_count.npy"), None).unwrap();
    for threads in [1, 2] {
        let src = zarr::open(&data("zr_count.zarr"), &ZarrSelect::default()).unwrap();
        let params = ExtractParams {
            iso: 100.5,
            threads,
            ..ExtractParams::default()
        };
        let (mesh, _) = extract(&src, &params).unwrap();
        let (want, _) = extract(&*twin, &params).unwrap();
        assert!(!want.triangles.is_empty());
        assert_eq!(mesh.triangles, want.triangles);
        assert_eq!(mesh.vertices, want.vertices);
        // 5 x 3 x 3 chunks. Two workers that miss the same layer at the
        // same moment may both decode it, at most once more per slab.
        let decoded = src.chunks_decoded();
        if threads == 1 {
            assert_eq!(decoded, 45);
        } else {
            assert!((45..=90).contains(&decoded), "{decoded}");
        }
    }
}

/// A copy of the fixture `name` in a temporary directory.
fn copy(name: &str, dir: &Path) -> PathBuf {
    fn walk(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            let target = to.join(e.file_name());
            if e.path().is_dir() {
                walk(&e.path(), &target);
            } else {
                std::fs::copy(e.path(), target).unwrap();
            }
        }
    }
    let to = dir.join(name);
    walk(&data(name), &to);
    to
}

#[test]
fn damaged_stores_give_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    // A truncated chunk.
    let t = copy("zr_v3_zstd.zarr", dir.path());
    let chunk = t.join("c/1/1/1");
    let bytes = std::fs::read(&chunk).unwrap();
    std::fs::write(&chunk, &bytes[..bytes.len() / 2]).unwrap();
    refused(&t, &[], "chunk [1, 1, 1]");
    // An unknown codec.
    let w = copy("zr_v2_blosc.zarr", dir.path());
    let meta = std::fs::read_to_string(w.join(".zarray")).unwrap();
    std::fs::write(
        w.join(".zarray"),
        meta.replace("\"blosc\"", "\"nosuchcodec\""),
    )
    .unwrap();
    refused(&w, &[], "cannot open the Zarr array");
    // No metadata.
    let m = copy("zr_v3_gzip_big.zarr", dir.path());
    std::fs::remove_file(m.join("zarr.json")).unwrap();
    refused(&m, &[], "no zarr.json (v3) or .zarray/.zgroup (v2)");
    // A group without naming its array, an array that is not there, a
    // level that is not there, an axis of two entries.
    refused(&data("zr_group.zarr"), &[], "--array PATH");
    refused(
        &data("zr_group.zarr"),
        &["--array", "scans/mr"],
        "cannot open the Zarr array at '/scans/mr'",
    );
    refused(
        &data("zr_ome_04.zarr"),
        &["--level", "2"],
        "2 levels (0 to 1)",
    );
    refused(&data("zr_t2.zarr"), &[], "has 2 entries");
    refused(&data("vt_twin.npy"), &["--array", "a"], "not one");
}

#[test]
fn cli_extracts_a_zarr_like_the_npy_and_info_tells_the_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let run = |input: &Path, extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args = vec!["extract", s(input), "--iso", "41", "-o", s(&out), "-q"];
        args.extend_from_slice(extra);
        let r = tmc(&args);
        assert!(r.status.success(), "{r:?}");
        std::fs::read(out).unwrap()
    };
    let want = run(
        &data("vt_twin.npy"),
        &["--spacing", "0.5,1,2", "--origin", "1.5,-2,3.25"],
        "a.ply",
    );
    assert_eq!(run(&data("zr_ome_05.zarr"), &[], "b.ply"), want);
    assert_eq!(
        run(
            &data("zr_group.zarr"),
            &[
                "--array",
                "scans/ct",
                "--spacing",
                "0.5,1,2",
                "--origin",
                "1.5,-2,3.25"
            ],
            "c.ply"
        ),
        want
    );
    let info = tmc(&["info", "--json", s(&data("zr_v3_shard.zarr"))]);
    let j: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(j["format"], "Zarr");
    assert_eq!(j["chunks"]["chunk_shape"], serde_json::json!([4, 3, 2]));
    assert!(j["chunks"]["codec"].as_str().unwrap().contains("sharding"));
    assert_eq!(j["chunks"]["chunks"], 8);
}

/// `{stem}` of an array inside a store is the store's name, whether the
/// array is given as `STORE.zarr/scans/ct` (its last name, `ct`, once
/// named the output) or with `--array scans/ct`, as for HDF5 datasets.
#[test]
fn stem_is_the_stores_name_with_or_without_array() {
    let dir = tempfile::tempdir().unwrap();
    let template = dir.path().join("{stem}.ply");
    let store = data("zr_group.zarr");
    for args in [
        vec![s(&store), "--array", "scans/ct"],
        vec![s(&store.join("scans/ct"))],
    ] {
        let mut all = vec!["extract"];
        all.extend(args);
        all.extend(["--iso", "41", "-q", "-o", s(&template)]);
        let r = tmc(&all);
        assert!(r.status.success(), "{r:?}");
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["zr_group.ply"], "{all:?}");
        std::fs::remove_file(dir.path().join("zr_group.ply")).unwrap();
    }
}

/// An OME-Zarr label image (`image.zarr/labels/cells`, a multiscale group
/// of its own) opens by path and by `--array labels/cells` alike, levels
/// included; the `labels` group itself is refused with its label images
/// named. Built from the OME fixtures, NGFF 0.4 (v2) and 0.5 (v3).
#[test]
fn an_ome_label_image_opens_by_path_or_array_and_its_group_lists_them() {
    let dir = tempfile::tempdir().unwrap();
    for (name, v3) in [("zr_ome_04.zarr", false), ("zr_ome_05.zarr", true)] {
        let image = dir.path().join(format!("image-{name}"));
        let labels = image.join("labels");
        let cells = copy(name, &labels.join("tmp"));
        std::fs::rename(&cells, labels.join("cells")).unwrap();
        std::fs::remove_dir(labels.join("tmp")).unwrap();
        match v3 {
            false => {
                for dir in [&image, &labels] {
                    std::fs::write(dir.join(".zgroup"), r#"{"zarr_format": 2}"#).unwrap();
                }
                std::fs::write(labels.join(".zattrs"), r#"{"labels": ["cells"]}"#).unwrap();
            }
            true => {
                let group = |attributes: &str| {
                    format!(
                        r#"{{"zarr_format": 3, "node_type": "group", "attributes": {attributes}}}"#
                    )
                };
                std::fs::write(image.join("zarr.json"), group("{}")).unwrap();
                let listed = r#"{"ome": {"version": "0.5", "labels": ["cells"]}}"#;
                std::fs::write(labels.join("zarr.json"), group(listed)).unwrap();
            }
        }
        for level in [None, Some(1)] {
            let by_path = zarr::open(
                &labels.join("cells"),
                &ZarrSelect {
                    level,
                    ..ZarrSelect::default()
                },
            )
            .unwrap();
            let by_array = zarr::open(
                &image,
                &ZarrSelect {
                    array: Some("labels/cells".into()),
                    level,
                    ..ZarrSelect::default()
                },
            )
            .unwrap();
            assert_eq!(by_array.grid(), by_path.grid(), "{name} {level:?}");
            assert_eq!(all_samples(&by_array), all_samples(&by_path));
        }
        let wanted = labels.join("cells").display().to_string();
        refused(&labels, &[], &format!("its label images: {wanted}"));
    }
}

/// The root of a bioformats2raw store (a group of OME-Zarr images, `0`,
/// `1`, ..., listed in its `OME` group's `series`) is refused with its
/// images named, as a `labels` group is with its label images; without the
/// `OME` list, the numbered groups there are. NGFF 0.4 (v2) and 0.5 (v3).
#[test]
fn a_bioformats2raw_root_lists_its_images() {
    let dir = tempfile::tempdir().unwrap();
    let write = |path: &Path, text: &str| {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    };
    for (v3, listed) in [(false, true), (false, false), (true, true), (true, false)] {
        let root = dir.path().join(format!("b2r-{v3}-{listed}.zarr"));
        let groups: &[&str] = if listed {
            &["", "OME", "0", "1", "2"]
        } else {
            &["", "0", "1", "3"]
        };
        for g in groups {
            let at = root.join(g);
            let attributes = match *g {
                "" if v3 => r#"{"ome": {"version": "0.5", "bioformats2raw.layout": 3}}"#,
                "" => r#"{"bioformats2raw.layout": 3}"#,
                "OME" if v3 => r#"{"ome": {"version": "0.5", "series": ["0", "2"]}}"#,
                "OME" => r#"{"series": ["0", "2"]}"#,
                _ => "{}",
            };
            if v3 {
                let meta = format!(
                    r#"{{"zarr_format": 3, "node_type": "group", "attributes": {attributes}}}"#
                );
                write(&at.join("zarr.json"), &meta);
            } else {
                write(&at.join(".zgroup"), r#"{"zarr_format": 2}"#);
                write(&at.join(".zattrs"), attributes);
            }
        }
        let images = if listed { ["0", "2"] } else { ["0", "1"] };
        let [a, b] = images.map(|n| root.join(n).display().to_string());
        refused(&root, &[], &format!("its images: {a}, {b})"));
    }
}
