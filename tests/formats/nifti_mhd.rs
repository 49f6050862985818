//! NIfTI-1/2 and MetaImage readers against fixtures written by nibabel and
//! SimpleITK (`scripts/fixtures/make_nifti_mhd.py`): geometry, samples
//! (after scl_slope / scl_inter) and meshes equal to those of the `.npy`
//! twins, direction cosines, and one clear error per bad input.

use crate::common;

use common::formats::{all_samples, check_grid, close, data_dir, det, fixtures, open_err};
use std::fs;
use std::path::{Path, PathBuf};
use tmc::volume::{self, metaimage, nifti, ScalarType};
use tmc::{ExtractParams, SampleSource};

#[test]
fn manifest_lists_every_kind() {
    let names: Vec<String> = fixtures("nifti_mhd_manifest.json")
        .into_iter()
        .map(|f| f.name)
        .collect();
    assert!(names.len() >= 11, "{names:?}");
    for ext in [".nii", ".nii.gz", ".hdr", ".mhd", ".mha"] {
        assert!(
            fixtures("nifti_mhd_manifest.json")
                .iter()
                .any(|f| f.file.to_string_lossy().ends_with(ext)),
            "no {ext} fixture"
        );
    }
}

#[test]
fn fixtures_match_their_npy_twins() {
    for f in fixtures("nifti_mhd_manifest.json") {
        let vol = volume::open(&f.file, None).unwrap_or_else(|e| panic!("{}: {e}", f.name));
        let twin = data_dir().join(format!("{}.expected.npy", f.name));
        let npy = volume::open(&twin, None).unwrap();
        let grid = *vol.grid();
        check_grid(&grid, &f, 1e-5, 1e-6);
        assert_eq!(npy.grid().dims, f.dims, "{}", f.name);
        let got = all_samples(vol.as_ref());
        let want = all_samples(npy.as_ref());
        assert_eq!(got, want, "{}: samples differ", f.name);

        // Same mesh once physical coordinates are accounted for.
        let (lo, hi) = want
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        let params = ExtractParams {
            iso: lo + (hi - lo) * 0.4123,
            ..ExtractParams::default()
        };
        let (mesh, _) = tmc::extract(vol.as_ref(), &params).unwrap();
        let (mesh_npy, _) = tmc::extract(npy.as_ref(), &params).unwrap();
        assert!(!mesh.triangles.is_empty(), "{}: empty mesh", f.name);
        // A mirroring map reverses every triangle, so normals stay outward.
        let want: Vec<[u32; 3]> = if det(&f.direction) < 0.0 {
            mesh_npy
                .triangles
                .iter()
                .map(|&[a, b, c]| [a, c, b])
                .collect()
        } else {
            mesh_npy.triangles.clone()
        };
        assert_eq!(mesh.triangles, want, "{}", f.name);
        assert_eq!(mesh.vertices.len(), mesh_npy.vertices.len(), "{}", f.name);
        for (v, w) in mesh.vertices.iter().zip(&mesh_npy.vertices) {
            // The manifest's affine, not the reader's grid.
            let scaled = [0, 1, 2].map(|j| f64::from(w[j]) * f.spacing[j]);
            for i in 0..3 {
                let mapped =
                    f.origin[i] + (0..3).map(|j| f.direction[i][j] * scaled[j]).sum::<f64>();
                assert!(
                    close(f64::from(v[i]), mapped, 1e-5),
                    "{}: vertex {v:?} vs {w:?} mapped {mapped}",
                    f.name
                );
            }
        }
    }
}

#[test]
fn directions_and_header_details() {
    for f in fixtures("nifti_mhd_manifest.json") {
        let path = f.file.to_string_lossy().to_string();
        let direction = if path.ends_with(".mhd") || path.ends_with(".mha") {
            metaimage::open(&f.file).unwrap().direction()
        } else {
            nifti::open(&f.file).unwrap().direction()
        };
        for r in 0..3 {
            for c in 0..3 {
                assert!(
                    (direction[r][c] - f.direction[r][c]).abs() < 1e-6,
                    "{}: {direction:?} vs {:?}",
                    f.name,
                    f.direction
                );
            }
        }
    }
    let scaled = nifti::open(&data_dir().join("nifti1_scaled.nii")).unwrap();
    assert_eq!(scaled.scaling(), Some((2.0, -10.0)));
    assert_eq!(scaled.version(), 1);
    let unscaled = nifti::open(&data_dir().join("nifti1_u8.nii")).unwrap();
    assert_eq!(unscaled.scaling(), None);
    let v2 = nifti::open(&data_dir().join("nifti2_i16_qform.nii")).unwrap();
    assert_eq!(v2.version(), 2);
    assert_eq!(v2.sample_bytes(), 2);
    let list = metaimage::open(&data_dir().join("mhd_list_i16_be.mhd")).unwrap();
    assert!(list.is_slice_list());
    assert_eq!(list.sample_bytes(), 2);
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn bad_nifti_headers_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = fs::read(data_dir().join("nifti1_u8.nii")).unwrap();
    let good2 = fs::read(data_dir().join("nifti2_f32_sform.nii")).unwrap();

    let e = open_err(&write(d, "short.nii", &good[..200]));
    assert!(e.contains("truncated NIfTI header"), "{e}");
    let e = open_err(&write(d, "tiny.nii", &good[..3]));
    assert!(e.contains("too short"), "{e}");
    let e = open_err(&write(d, "nodata.nii", &good[..good.len() - 10]));
    assert!(e.contains("need"), "{e}");
    let e = open_err(&write(d, "empty.nii", &[]));
    assert!(e.contains("too short"), "{e}");

    let mut bad = good.clone();
    bad[..4].copy_from_slice(&349i32.to_le_bytes());
    let e = open_err(&write(d, "sizeof.nii", &bad));
    assert!(e.contains("sizeof_hdr is 349"), "{e}");

    let mut bad = good.clone();
    bad[70..72].copy_from_slice(&128i16.to_le_bytes()); // RGB24
    let e = open_err(&write(d, "rgb.nii", &bad));
    assert!(e.contains("datatype 128 is not supported"), "{e}");

    let mut bad = good2.clone();
    bad[12..14].copy_from_slice(&1792i16.to_le_bytes()); // complex128
    let e = open_err(&write(d, "complex2.nii", &bad));
    assert!(e.contains("datatype 1792"), "{e}");

    let mut bad = good.clone();
    bad[40..42].copy_from_slice(&4i16.to_le_bytes());
    bad[48..50].copy_from_slice(&3i16.to_le_bytes()); // dim[4] = 3 time points
    let e = open_err(&write(d, "time.nii", &bad));
    assert!(e.contains("not a 3-D volume"), "{e}");
    bad[48..50].copy_from_slice(&1i16.to_le_bytes()); // dim[4] = 1: fine
    let ok = write(d, "time1.nii", &bad);
    assert_eq!(volume::open(&ok, None).unwrap().grid().dims, [9, 7, 6]);

    let mut bad = good.clone();
    bad[42..44].copy_from_slice(&0i16.to_le_bytes());
    let e = open_err(&write(d, "zero.nii", &bad));
    assert!(e.contains("dim[1] = 0"), "{e}");

    let mut bad = good.clone();
    bad[344..348].copy_from_slice(b"xx1\0");
    let e = open_err(&write(d, "magic.nii", &bad));
    assert!(e.contains("magic"), "{e}");

    let mut bad = good.clone();
    bad[108..112].copy_from_slice(&1.0e9f32.to_le_bytes());
    let e = open_err(&write(d, "offset.nii", &bad));
    assert!(e.contains("need"), "{e}");

    bad[108..112].copy_from_slice(&0.0f32.to_le_bytes());
    let e = open_err(&write(d, "offset0.nii", &bad));
    assert!(e.contains("inside the 348-byte header"), "{e}");

    // The sform (code 2 here) rules: a zero column is refused, pixdim unused.
    let mut bad = good.clone();
    for row in [280, 296, 312] {
        bad[row..row + 4].copy_from_slice(&0.0f32.to_le_bytes()); // srow_*[0] = 0
    }
    let e = open_err(&write(d, "sform0.nii", &bad));
    assert!(e.contains("sform: direction of axis 0"), "{e}");
    let mut sform_only = good.clone();
    sform_only[80..84].copy_from_slice(&0.0f32.to_le_bytes()); // pixdim[1] = 0
    let v = volume::open(&write(d, "pixdim0.nii", &sform_only), None).unwrap();
    assert_eq!(v.grid().spacing, [0.5, 1.0, 2.0]);
    assert!(v.notes().warnings.is_empty(), "{:?}", v.notes().warnings);
    // With the qform only, pixdim is the spacing: zero reads as 1, as
    // nibabel reads it, with a note; NaN or infinite is refused.
    let qform = fs::read(data_dir().join("nifti1_i16_qform_flip.nii")).unwrap();
    let want = volume::open(&data_dir().join("nifti1_i16_qform_flip.nii"), None).unwrap();
    let mut zero = qform.clone();
    zero[80..84].copy_from_slice(&0.0f32.to_le_bytes());
    let v = volume::open(&write(d, "spacing.nii", &zero), None).unwrap();
    let spacing = want.grid().spacing;
    assert_eq!(v.grid().spacing, [1.0, spacing[1], spacing[2]]);
    let warnings = v.notes().warnings;
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("pixdim[1] = 0 (no voxel size along x)"),
        "{warnings:?}"
    );
    for (name, value) in [("nan", f32::NAN), ("inf", f32::INFINITY)] {
        let mut bad = qform.clone();
        bad[84..88].copy_from_slice(&value.to_le_bytes());
        let e = open_err(&write(d, &format!("{name}.nii"), &bad));
        assert!(
            e.contains("pixdim[2] = ") && e.contains("not a voxel size"),
            "{e}"
        );
    }
    // Neither sform nor qform: the same.
    let mut bare = zero.clone();
    bare[252..254].copy_from_slice(&0i16.to_le_bytes()); // qform_code = 0
    let v = volume::open(&write(d, "bare.nii", &bare), None).unwrap();
    assert_eq!(v.grid().spacing, [1.0, spacing[1], spacing[2]]);
    assert_eq!(v.notes().warnings.len(), 1);
    bare[88..92].copy_from_slice(&f32::NEG_INFINITY.to_le_bytes());
    let e = open_err(&write(d, "bare_inf.nii", &bare));
    assert!(e.contains("pixdim[3] = -inf"), "{e}");

    // A .hdr without its .img, and a single-file header named .hdr.
    let hdr = fs::read(data_dir().join("nifti1_pair.hdr")).unwrap();
    let e = open_err(&write(d, "alone.hdr", &hdr));
    assert!(e.contains("alone.img"), "{e}");
    let e = open_err(&write(d, "single.hdr", &good));
    assert!(e.contains("magic"), "{e}");

    // Truncated and corrupt gzip.
    let gz = fs::read(data_dir().join("nifti1_f32_gz.nii.gz")).unwrap();
    let e = open_err(&write(d, "cut.nii.gz", &gz[..gz.len() / 2]));
    assert!(e.contains("gzip"), "{e}");
    let e = open_err(&write(d, "notgz.nii.gz", &good));
    assert!(e.contains("gzip"), "{e}");
    let mut bad = gz.clone();
    let n = bad.len();
    bad[n - 6] ^= 0xff; // CRC
    let e = open_err(&write(d, "crc.nii.gz", &bad));
    assert!(e.contains("gzip"), "{e}");
}

#[test]
fn bad_metaimage_headers_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let raw = fs::read(data_dir().join("mhd_u8.raw")).unwrap();
    write(d, "data.raw", &raw);
    let header = |lines: &[&str]| lines.join("\n") + "\n";
    let base = [
        "ObjectType = Image",
        "NDims = 3",
        "DimSize = 9 7 6",
        "ElementType = MET_UCHAR",
        "ElementSpacing = 0.5 1 2",
        "ElementDataFile = data.raw",
    ];
    let ok = write(d, "ok.mhd", header(&base).as_bytes());
    assert_eq!(volume::open(&ok, None).unwrap().grid().dims, [9, 7, 6]);

    let with = |i: usize, line: &str| {
        let mut l = base.to_vec();
        l[i] = line;
        header(&l)
    };
    // An error in the data file names the header the user gave, then it.
    let dims_mhd = write(d, "dims.mhd", with(2, "DimSize = 9 7 7").as_bytes());
    let e = open_err(&dims_mhd);
    let data_raw = d.join("data.raw");
    let want = format!(
        "{}: data file {}: file has 378 bytes",
        dims_mhd.display(),
        data_raw.display()
    );
    assert!(e.starts_with(&want), "{e}");
    let e = open_err(&write(d, "dims2.mhd", with(2, "DimSize = 9 7").as_bytes()));
    assert!(e.contains("bad DimSize"), "{e}");
    let e = open_err(&write(
        d,
        "type.mhd",
        with(3, "ElementType = MET_STRING").as_bytes(),
    ));
    assert!(
        e.contains("ElementType 'MET_STRING' is not supported"),
        "{e}"
    );
    let e = open_err(&write(d, "ndims.mhd", with(1, "NDims = 2").as_bytes()));
    assert!(e.contains("NDims 2"), "{e}");
    let e = open_err(&write(
        d,
        "obj.mhd",
        with(0, "ObjectType = Tube").as_bytes(),
    ));
    assert!(e.contains("ObjectType"), "{e}");
    let e = open_err(&write(d, "nofile.mhd", header(&base[..5]).as_bytes()));
    assert!(e.contains("no ElementDataFile"), "{e}");
    let e = open_err(&write(
        d,
        "missing.mhd",
        with(5, "ElementDataFile = gone.raw").as_bytes(),
    ));
    assert!(e.contains("gone.raw"), "{e}");
    assert!(
        e.starts_with(&*d.join("missing.mhd").to_string_lossy()),
        "{e}"
    );
    let e = open_err(&write(
        d,
        "notype.mhd",
        header(&[base[2], base[5]]).as_bytes(),
    ));
    assert!(e.contains("missing ElementType"), "{e}");
    let e = open_err(&write(d, "garbage.mhd", b"\x00\x01 binary junk"));
    assert!(e.contains("bad header line"), "{e}");
    let e = open_err(&write(
        d,
        "spacing.mhd",
        with(4, "ElementSpacing = 1 x 2").as_bytes(),
    ));
    assert!(e.contains("bad ElementSpacing"), "{e}");
    let e = open_err(&write(
        d,
        "pattern.mhd",
        with(5, "ElementDataFile = slice%03d.raw 1 6 1").as_bytes(),
    ));
    assert!(e.contains("pattern"), "{e}");

    // HeaderSize: -1 reads the end of the file; too large is an error.
    let mut padded = vec![7u8; 11];
    padded.extend_from_slice(&raw);
    write(d, "padded.raw", &padded);
    let mut l = base.to_vec();
    l[5] = "HeaderSize = -1";
    l.push("ElementDataFile = padded.raw");
    let end = write(d, "end.mhd", header(&l).as_bytes());
    let want = all_samples(volume::open(&ok, None).unwrap().as_ref());
    assert_eq!(
        all_samples(volume::open(&end, None).unwrap().as_ref()),
        want
    );
    l[5] = "HeaderSize = 12";
    let e = open_err(&write(d, "skip.mhd", header(&l).as_bytes()));
    assert!(e.contains("need"), "{e}");
    l[5] = "HeaderSize = -1";
    l[2] = "DimSize = 9 7 7";
    let e = open_err(&write(d, "endshort.mhd", header(&l).as_bytes()));
    assert!(e.contains("the samples need"), "{e}");

    // LIST with too few slice files, and a missing slice file.
    let mut l = base.to_vec();
    l[5] = "ElementDataFile = LIST";
    l.push("data.raw");
    let e = open_err(&write(d, "list.mhd", header(&l).as_bytes()));
    assert!(e.contains("LIST names 1 files"), "{e}");
    l.resize(l.len() + 5, "nowhere.raw");
    let e = open_err(&write(d, "list2.mhd", header(&l).as_bytes()));
    assert!(e.contains("nowhere.raw"), "{e}");
    assert!(
        e.starts_with(&*d.join("list2.mhd").to_string_lossy()),
        "{e}"
    );

    // Truncated, corrupt and too-short zlib data in a .mha.
    let mha = fs::read(data_dir().join("mha_f32_zlib.mha")).unwrap();
    let e = open_err(&write(d, "cut.mha", &mha[..mha.len() - 100]));
    assert!(e.contains("zlib"), "{e}");
    let mut bad = mha.clone();
    let n = bad.len();
    bad[n - 2] ^= 0xff; // Adler-32
    let e = open_err(&write(d, "adler.mha", &bad));
    assert!(e.contains("zlib"), "{e}");
    let e = open_err(&write(d, "grown.mha", &mha_with_dims(&mha, "9 7 9")));
    assert!(e.contains("compressed data holds 1512 bytes"), "{e}");

    // Uncompressed .mha truncated.
    let mha = fs::read(data_dir().join("mha_i16.mha")).unwrap();
    let e = open_err(&write(d, "cut16.mha", &mha[..mha.len() - 1]));
    assert!(e.contains("need 756"), "{e}");
}

/// A 4-D MetaImage whose 4th axis has size 1 (a time series of one point,
/// as ITK writes it) is the 3-D volume; a longer 4th axis is refused,
/// naming it.
#[test]
fn metaimage_unit_fourth_axis_is_one_volume() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "data.raw",
        &fs::read(data_dir().join("mhd_u8.raw")).unwrap(),
    );
    let header = |dims: &str| {
        [
            "ObjectType = Image",
            "NDims = 4",
            "TransformMatrix = 0 1 0 0 -1 0 0 0 0 0 1 0 0 0 0 1",
            "Offset = 1 2 3 4",
            "ElementSpacing = 0.5 1 2 3",
            &format!("DimSize = {dims}"),
            "ElementType = MET_UCHAR",
            "ElementDataFile = data.raw",
        ]
        .join("\n")
            + "\n"
    };
    let three = header("9 7 6 1")
        .replace("NDims = 4", "NDims = 3")
        .replace("0 1 0 0 -1 0 0 0 0 0 1 0 0 0 0 1", "0 1 0 -1 0 0 0 0 1")
        .replace("1 2 3 4", "1 2 3")
        .replace("0.5 1 2 3", "0.5 1 2")
        .replace("9 7 6 1", "9 7 6");
    let want = volume::open(&write(d, "three.mhd", three.as_bytes()), None).unwrap();
    let got = volume::open(&write(d, "four.mhd", header("9 7 6 1").as_bytes()), None)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(got.grid(), want.grid());
    assert_eq!(got.grid().origin, [1.0, 2.0, 3.0]);
    assert_eq!(all_samples(got.as_ref()), all_samples(want.as_ref()));

    let e = open_err(&write(d, "time.mhd", header("9 7 3 2").as_bytes()));
    assert!(
        e.contains("DimSize '9 7 3 2' is not one volume: axis 4 has size 2, not 1"),
        "{e}"
    );
    let e = open_err(&write(
        d,
        "short.mhd",
        header("9 7 6 1").replace("0.5 1 2 3", "0.5 1 2").as_bytes(),
    ));
    assert!(
        e.contains("ElementSpacing (need 4 numbers for NDims 4, found 3)"),
        "{e}"
    );
}

/// `mha` with its DimSize value replaced (same length).
fn mha_with_dims(mha: &[u8], dims: &str) -> Vec<u8> {
    let key = b"DimSize = ";
    let at = mha.windows(key.len()).position(|w| w == key).unwrap() + key.len();
    let mut out = mha.to_vec();
    out[at..at + dims.len()].copy_from_slice(dims.as_bytes());
    out
}

/// A MetaImage header of 4x4x4 samples of `element_type` with
/// `BinaryData = False`, the lines `extra`, and `ElementDataFile = data`.
fn ascii_header(element_type: &str, extra: &str, data: &str) -> String {
    format!(
        "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = {element_type}\nBinaryData = False\n{extra}ElementDataFile = {data}\n"
    )
}

/// `values` as text, 16 to a line.
fn ascii_text(values: &[i64]) -> String {
    values
        .chunks(16)
        .map(|row| row.iter().map(|v| format!("{v} ")).collect::<String>() + "\n")
        .collect()
}

#[test]
fn ascii_metaimage_data_is_parsed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bytes: Vec<i64> = (0..64).map(|i| i * 4).collect();
    let shorts: Vec<i64> = (0..64).map(|i| i * 1000 - 32000).collect();
    let cases = [
        (
            write(
                d,
                "local.mha",
                (ascii_header("MET_UCHAR", "", "LOCAL") + &ascii_text(&bytes)).as_bytes(),
            ),
            &bytes,
            ScalarType::U8,
        ),
        (
            {
                write(d, "shorts.txt", ascii_text(&shorts).as_bytes());
                let header = ascii_header("MET_SHORT", "", "shorts.txt");
                write(d, "detached.mhd", header.as_bytes())
            },
            &shorts,
            ScalarType::I16,
        ),
        (
            {
                write(
                    d,
                    "skipped.txt",
                    (String::from("junk\n") + &ascii_text(&shorts)).as_bytes(),
                );
                let header = ascii_header("MET_SHORT", "HeaderSize = 5\n", "skipped.txt");
                write(d, "skip.mhd", header.as_bytes())
            },
            &shorts,
            ScalarType::I16,
        ),
    ];
    for (path, values, scalar) in cases {
        let vol = volume::open(&path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let want: Vec<f64> = values.iter().map(|&v| v as f64).collect();
        assert_eq!(all_samples(vol.as_ref()), want, "{}", path.display());
        assert_eq!(vol.stored_type(), Some(scalar), "{}", path.display());
    }
}

#[test]
fn bad_ascii_metaimage_data_is_one_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let values: Vec<i64> = (0..64).collect();
    let local = |name: &str, extra: &str, text: &str| {
        let bytes = ascii_header("MET_UCHAR", extra, "LOCAL") + text;
        write(d, name, bytes.as_bytes())
    };
    let cases = [
        (
            local("short.mha", "", &ascii_text(&values[..60])),
            "ascii data holds 60 values, 4x4x4 u8 needs 64",
        ),
        (
            local("long.mha", "", &(ascii_text(&values) + "7\n")),
            "ascii data holds more than the 64 values of 4x4x4 u8",
        ),
        (
            local(
                "token.mha",
                "",
                &ascii_text(&values).replace(" 9 ", " nine "),
            ),
            "ascii value 'nine' at sample 9 is not a number",
        ),
        (
            local(
                "range.mha",
                "",
                &ascii_text(&values).replace(" 9 ", " 256 "),
            ),
            "ascii value '256' at sample 9 does not fit u8",
        ),
        (
            local("zlib.mha", "CompressedData = True\n", &ascii_text(&values)),
            "BinaryData = False with CompressedData = True (compressed text) is not supported",
        ),
        (
            {
                write(d, "end.txt", ascii_text(&values).as_bytes());
                let header = ascii_header("MET_UCHAR", "HeaderSize = -1\n", "end.txt");
                write(d, "end.mhd", header.as_bytes())
            },
            "BinaryData = False with HeaderSize = -1 is not supported",
        ),
        (
            {
                write(d, "cut.txt", ascii_text(&values[..10]).as_bytes());
                write(
                    d,
                    "cut.mhd",
                    ascii_header("MET_UCHAR", "", "cut.txt").as_bytes(),
                )
            },
            "cut.txt: ascii data holds 10 values",
        ),
    ];
    for (path, phrase) in cases {
        let e = open_err(&path);
        assert!(e.contains(phrase), "{}: {e}", path.display());
    }
}

/// MetaIO's `MET_LONG` and `MET_ULONG` are 4-byte integers
/// (`MET_ValueTypeSize` in MetaIO's metaTypes.h; ITK writes them for
/// `long` pixels where `long` has 4 bytes): the same bytes read as
/// `MET_INT` and `MET_UINT` do (they were refused as unsupported).
#[test]
fn metaimage_long_is_four_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let values: Vec<i32> = (0..24).map(|i| (i - 12) * 100_000_000).collect();
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mha = |element_type: &str| {
        let mut out = format!(
            "ObjectType = Image\nNDims = 3\nDimSize = 2 3 4\nElementType = {element_type}\nElementDataFile = LOCAL\n"
        )
        .into_bytes();
        out.extend_from_slice(&bytes);
        out
    };
    for (long, int, scalar) in [
        ("MET_LONG", "MET_INT", ScalarType::I32),
        ("MET_ULONG", "MET_UINT", ScalarType::U32),
    ] {
        let want = volume::open(&write(d, &format!("{int}.mha"), &mha(int)), None).unwrap();
        let got = volume::open(&write(d, &format!("{long}.mha"), &mha(long)), None)
            .unwrap_or_else(|e| panic!("{long}: {e}"));
        assert_eq!(got.stored_type(), Some(scalar), "{long}");
        assert_eq!(got.grid(), want.grid(), "{long}");
        assert_eq!(
            all_samples(got.as_ref()),
            all_samples(want.as_ref()),
            "{long}"
        );
    }
}

/// NIfTI's `xyzt_units` (the space unit in its low three bits: 1 metre,
/// 2 millimetre, 3 micron) puts the grid in millimetres, as ITK's NIfTI
/// reader does and as the TIFF, OME-Zarr and HDF5 readers convert their
/// voxel sizes: a micron file's spacing and origin are a thousandth of
/// its header's numbers (they were taken as millimetres, so its mesh was
/// a thousand times too large beside the same samples as OME-TIFF).
/// Unknown units (0, what most writers leave) stay millimetres.
#[test]
fn nifti_xyzt_units_give_millimetres() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // (fixture, offset of xyzt_units, its width): an sform and a qform
    // NIfTI-1 file, a NIfTI-2 file.
    for (name, at, width) in [
        ("nifti1_u8.nii", 123, 1),
        ("nifti1_i16_qform_flip.nii", 123, 1),
        ("nifti2_i16_qform.nii", 500, 4),
    ] {
        let good = fs::read(data_dir().join(name)).unwrap();
        let stated = nifti::open(&data_dir().join(name)).unwrap();
        let stated_grid = *stated.grid();
        // Time units (bits 3 to 5) change nothing.
        for (units, mm) in [(2u8 | 8, 1.0), (1 | 16, 1000.0), (3 | 24, 1e-3), (0, 1.0)] {
            let mut bytes = good.clone();
            let little = matches!(
                i32::from_le_bytes([good[0], good[1], good[2], good[3]]),
                348 | 540
            );
            bytes[at..at + width].fill(0);
            bytes[if little { at } else { at + width - 1 }] = units;
            let path = write(d, &format!("u{units}_{name}"), &bytes);
            let vol = nifti::open(&path).unwrap_or_else(|e| panic!("{name} {units}: {e}"));
            let grid = *vol.grid();
            assert_eq!(grid.dims, stated_grid.dims, "{name} {units}");
            for i in 0..3 {
                for j in 0..3 {
                    let (a, b) = (grid.direction[i][j], stated_grid.direction[i][j]);
                    assert!(close(a, b, 1e-12), "{name} {units}: direction {a} vs {b}");
                }
                assert!(
                    close(grid.spacing[i], stated_grid.spacing[i] * mm, 1e-12),
                    "{name} units {units}: spacing {:?}, header {:?}",
                    grid.spacing,
                    stated_grid.spacing
                );
                assert!(
                    close(grid.origin[i], stated_grid.origin[i] * mm, 1e-12),
                    "{name} units {units}: origin {:?}, header {:?}",
                    grid.origin,
                    stated_grid.origin
                );
            }
            assert_eq!(all_samples(&vol), all_samples(&stated));
            let from = format!("{:?}", vol.notes().spacing_from);
            assert_eq!(from.contains("in mm"), mm != 1.0, "{name} {units}: {from}");
        }
    }
}
