//! HDF5 datasets against fixtures written by h5py
//! (`scripts/fixtures/make_hdf5.py`): contiguous and chunked (gzip with
//! shuffle) datasets of every sample type, big-endian, in groups, in files
//! of either format version, give the samples and the mesh of the `.npy`
//! of the same samples; `element_size_um` gives the spacing; each chunk
//! layer is read once per pass; a dataset that is missing or not a volume
//! gives one clear line and no output.

use crate::common;

use common::cli::{refused, s, tmc};
use common::formats::{all_samples, data_dir};
use std::path::{Path, PathBuf};
use tmc::volume::{self, hdf5, ValueFrom};
use tmc::{extract, ExtractParams, SampleSource};

fn data(name: &str) -> PathBuf {
    data_dir().join(name)
}

/// `FILE:/dataset` of the twin's HDF5 fixture.
fn at(file: &str, dataset: &str) -> PathBuf {
    PathBuf::from(format!("{}:{dataset}", data(file).display()))
}

/// The same triangles as the twin's, at a few isovalues.
fn same_mesh(src: &dyn SampleSource, twin: &dyn SampleSource) {
    for iso in [20.5, 41.0, 60.5] {
        let params = ExtractParams {
            iso,
            ..ExtractParams::default()
        };
        let (mesh, _) = extract(src, &params).unwrap();
        let (want, _) = extract(twin, &params).unwrap();
        assert!(!want.triangles.is_empty());
        assert_eq!(mesh.triangles, want.triangles, "iso {iso}");
        assert_eq!(mesh.vertices, want.vertices, "iso {iso}");
    }
}

#[test]
fn every_type_and_layout_reads_as_the_npy() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let mut names: Vec<(&str, String)> = [
        "uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64",
    ]
    .iter()
    .map(|t| ("h5_twin.h5", format!("/types/{t}")))
    .collect();
    for (file, d) in [
        ("h5_twin.h5", "/exchange/data"),
        ("h5_twin.h5", "exchange/data"),
        ("h5_twin.h5", "/big_endian"),
        ("h5_twin.h5", "/one_channel"),
        ("h5_latest.h5", "/fixed"),
        ("h5_latest.h5", "/extensible"),
        ("h5_latest.h5", "/btree2"),
    ] {
        names.push((file, d.to_string()));
    }
    for (file, d) in &names {
        let src = volume::open(&at(file, d), None).unwrap_or_else(|e| panic!("{d}: {e}"));
        assert_eq!(src.grid().dims, [9, 7, 6], "{d}");
        assert_eq!(src.grid().spacing, [1.0; 3], "{d}");
        assert_eq!(all_samples(&*src), all_samples(&*twin), "{d}");
        same_mesh(&*src, &*twin);
    }
    let src = volume::open(&at("h5_twin.h5", "/types/int16"), None).unwrap();
    let chunks = src.notes().chunks.unwrap();
    assert_eq!(chunks.chunk_shape, [4, 3, 2]);
    assert_eq!(chunks.codec, "HDF5 chunked: shuffle > deflate(level=4)");
    assert_eq!(chunks.chunks, 3 * 3 * 3);
    let contiguous = volume::open(&at("h5_twin.h5", "/exchange/data"), None).unwrap();
    assert!(contiguous.notes().chunks.is_none());
}

#[test]
fn element_size_um_gives_the_spacing_in_millimetres() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    for (d, want) in [
        ("/exchange/gz", [0.0005, 0.001, 0.002]),
        ("/int_spacing", [0.001, 0.002, 0.004]),
    ] {
        let src = volume::open(&at("h5_twin.h5", d), None).unwrap();
        let g = src.grid();
        for (got, want) in g.spacing.iter().zip(want) {
            assert!((got - want).abs() < 1e-15, "{d}: {:?}", g.spacing);
        }
        assert_eq!(g.origin, [0.0; 3]);
        assert!(
            matches!(&src.notes().spacing_from, ValueFrom::File { what } if what.contains("element_size_um")),
            "{:?}",
            src.notes()
        );
        assert_eq!(all_samples(&*src), all_samples(&*twin), "{d}");
    }
}

#[test]
fn each_chunk_layer_is_read_once_per_pass() {
    let src = hdf5::open(&data("h5_twin.h5"), Some("/types/uint16")).unwrap();
    assert_eq!(src.layer_depth(), 2);
    let params = ExtractParams {
        iso: 41.0,
        threads: 2,
        ..ExtractParams::default()
    };
    extract(&src, &params).unwrap();
    // 6 planes in layers of 2: 3 layers, each read once.
    assert_eq!(src.layers_read(), 3);
}

#[test]
fn missing_or_unreadable_datasets_give_one_line_and_no_output() {
    let file = data("h5_twin.h5");
    refused(
        &at("h5_twin.h5", "/exchange/nope"),
        &[],
        "no dataset '/exchange/nope'",
    );
    refused(&file, &["--dataset", "/nope"], "no dataset '/nope'");
    refused(&file, &[], "name the dataset to read");
    refused(&at("h5_twin.h5", "/flat"), &[], "has 2 axes");
    refused(&at("h5_twin.h5", "/text"), &[], "not one tmc reads");
    refused(
        &at("h5_twin.h5", "/exchange/data"),
        &["--dataset", "/exchange/data"],
        "not both",
    );
    refused(&data("vt_twin.npy"), &["--dataset", "/a"], "not one");
    // The file cut short (its metadata is read on opening).
    let dir = tempfile::tempdir().unwrap();
    let cut = dir.path().join("cut.h5");
    let bytes = std::fs::read(&file).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let cut_at = PathBuf::from(format!("{}:/types/float64", cut.display()));
    refused(&cut_at, &[], "cannot open as HDF5");
}

#[test]
fn cli_extracts_a_dataset_like_the_npy_and_info_tells_the_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let run = |input: &Path, extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args = vec!["extract", s(input), "--iso", "41", "-o", s(&out), "-q"];
        args.extend_from_slice(extra);
        let r = tmc(&args);
        assert!(r.status.success(), "{r:?}");
        std::fs::read(out).unwrap()
    };
    let spacing = ["--spacing", "0.0005,0.001,0.002"];
    let want = run(&data("vt_twin.npy"), &spacing, "a.ply");
    assert_eq!(run(&at("h5_twin.h5", "/exchange/gz"), &[], "b.ply"), want);
    // The same samples as int64 (read as f64, exact).
    assert_eq!(run(&at("h5_twin.h5", "/wide"), &spacing, "w.ply"), want);
    let file = data("h5_twin.h5");
    assert_eq!(run(&file, &["--dataset", "exchange/gz"], "c.ply"), want);
    let info = tmc(&["info", "--json", s(&at("h5_twin.h5", "/exchange/gz"))]);
    assert!(info.status.success(), "{info:?}");
    let j: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(j["format"], "HDF5");
    assert_eq!(j["chunks"]["chunk_shape"], serde_json::json!([4, 3, 2]));
    assert_eq!(j["sample_type"], "i16");
}

/// `{stem}` is the name of the HDF5 file whichever way the dataset is
/// chosen: `FILE.h5:/exchange/gz` and `FILE.h5 --dataset /exchange/gz`
/// both name `FILE.ply` (the dataset's last name, `gz`, once named the
/// first), and a batch of two files' datasets of one name writes two
/// outputs, not one name twice.
#[test]
fn stem_is_the_files_name_with_or_without_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let template = dir.path().join("{stem}.ply");
    let run = |args: &[&str]| {
        let mut all = vec!["extract"];
        all.extend_from_slice(args);
        all.extend(["--iso", "41", "-q", "-o", s(&template)]);
        let r = tmc(&all);
        assert!(r.status.success(), "{r:?}");
        let mut names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        for name in &names {
            std::fs::remove_file(dir.path().join(name)).unwrap();
        }
        names
    };
    let suffix = at("h5_twin.h5", "/exchange/gz");
    assert_eq!(run(&[s(&suffix)]), ["h5_twin.ply"]);
    let file = data("h5_twin.h5");
    assert_eq!(
        run(&[s(&file), "--dataset", "/exchange/gz"]),
        ["h5_twin.ply"]
    );
    // Two files, one dataset name: two names.
    let copies = tempfile::tempdir().unwrap();
    let other = copies.path().join("other.h5");
    std::fs::copy(&file, &other).unwrap();
    let other = PathBuf::from(format!("{}:/exchange/gz", other.display()));
    let names = run(&[s(&suffix), s(&other)]);
    assert_eq!(names, ["h5_twin.ply", "other.ply"]);
}

/// Writes `samples` into a new HDF5 file as dataset `/chunked` of
/// `(shape, chunk)`, deflated, and as `/contiguous` of `contiguous` shape.
fn write_chunked_and_contiguous(
    file: &Path,
    (shape, chunk): ([usize; 4], [usize; 4]),
    contiguous: &[usize],
    samples: &[f64],
) {
    let h5 = rust_hdf5::H5File::create(file).unwrap();
    let chunked = h5
        .new_dataset::<f64>()
        .shape(shape)
        .chunk(&chunk)
        .deflate(4);
    chunked
        .create("chunked")
        .unwrap()
        .write_raw(samples)
        .unwrap();
    let whole = h5.new_dataset::<f64>().shape(contiguous);
    whole
        .create("contiguous")
        .unwrap()
        .write_raw(samples)
        .unwrap();
}

/// A dataset with a channel axis of one entry last (`z, y, x, 1`: ilastik
/// exports `zyxc`), chunked with odd edge chunks and contiguous, reads as
/// its volume: it was refused as "13 entries along an axis before z, y,
/// x", reading the volume's z as a time axis and the channel as x.
#[test]
fn a_trailing_axis_of_one_entry_is_a_channel() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let [nx, ny, nz] = twin.grid().dims;
    let samples = all_samples(twin.as_ref());
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("zyxc.h5");
    let chunked = ([nz, ny, nx, 1], [3, 5, 4, 1]);
    write_chunked_and_contiguous(&file, chunked, &[1, nz, ny, nx, 1, 1], &samples);
    for name in ["/chunked", "/contiguous"] {
        let path = PathBuf::from(format!("{}:{name}", file.display()));
        let src = volume::open(&path, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(src.grid().dims, [nx, ny, nz], "{name}");
        same_mesh(src.as_ref(), twin.as_ref());
    }
}

/// A dataset with three channels last (`z, y, x, 3`, the channels
/// interleaved), chunked with all channels a chunk and contiguous: `--at
/// 3=C` reads channel C as its volume (it could not be read: the last
/// three axes were taken for z, y, x, with x three samples wide, and the
/// error named only an axis before them).
#[test]
fn a_channel_axis_last_is_picked_with_at() {
    let twin = volume::open(&data("vt_twin.npy"), None).unwrap();
    let [nx, ny, nz] = twin.grid().dims;
    let samples = all_samples(twin.as_ref());
    // Channel c holds the samples times c + 1.
    let interleaved: Vec<f64> = samples
        .iter()
        .flat_map(|&v| [v, 2.0 * v, 3.0 * v])
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("zyxc.h5");
    let chunked = ([nz, ny, nx, 3], [3, 5, 4, 3]);
    write_chunked_and_contiguous(&file, chunked, &[nz, ny, nx, 3], &interleaved);
    for name in ["/chunked", "/contiguous"] {
        for c in 0..3u64 {
            let picks = [("3".to_string(), c)];
            let src =
                hdf5::open_at(&file, Some(name), &picks).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(src.grid().dims, [nx, ny, nz], "{name}");
            let scale = (c + 1) as f64;
            let got = all_samples(&src);
            assert!(
                got.iter().zip(&samples).all(|(g, s)| *g == scale * s),
                "{name} channel {c}"
            );
        }
        let err = hdf5::open_at(&file, Some(name), &[])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("--at 3=I"), "{err}");
    }
    // The CLI: channel 1 gives the mesh of the samples times 2 at twice
    // the isovalue, which is the mesh of the samples.
    let out = dir.path().join("c1.off");
    let twin_out = dir.path().join("twin.off");
    let input = format!("{}:/chunked", file.display());
    let run = tmc(&[
        "extract",
        &input,
        "--at",
        "3=1",
        "--iso",
        "120",
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(run.status.success(), "{run:?}");
    let twin_path = data("vt_twin.npy");
    let run = tmc(&[
        "extract",
        s(&twin_path),
        "--iso",
        "60",
        "-q",
        "-o",
        s(&twin_out),
    ]);
    assert!(run.status.success(), "{run:?}");
    let (a, b) = (
        std::fs::read(&out).unwrap(),
        std::fs::read(&twin_out).unwrap(),
    );
    assert!(a.len() > 100);
    assert_eq!(a, b);
}
