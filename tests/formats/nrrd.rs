//! The NRRD reader against fixtures written by pynrrd and, for the
//! multi-file and skip variants pynrrd cannot write, by hand with numpy
//! data (`scripts/fixtures/make_nrrd.py`): attached and detached headers,
//! `data file` as one name, `LIST` (one slice or a block of slices per
//! file) and a printf pattern; raw, gzip, bzip2 and ascii encodings; line
//! and byte skips. Each gives the grid, samples and mesh of its `.npy` twin
//! (vertices mapped through the full affine), and every bad input one clear
//! line.

use crate::common;

use common::formats::{all_samples, check_grid, close, data_dir, fixtures, open_err};
use std::fs;
use std::path::Path;
use tmc::volume::{self, nrrd, ScalarType};
use tmc::{ExtractParams, SampleSource};

#[test]
fn manifest_lists_every_kind() {
    let all = fixtures("nrrd_manifest.json");
    assert!(all.len() >= 10, "{}", all.len());
    assert!(all.iter().any(|f| f.file.extension().unwrap() == "nhdr"));
    assert!(all.iter().any(|f| f.file.extension().unwrap() == "nrrd"));
    assert!(all.iter().any(|f| f.files > 1));
}

#[test]
fn fixtures_match_their_npy_twins() {
    for f in fixtures("nrrd_manifest.json") {
        let vol = volume::open(&f.file, None).unwrap_or_else(|e| panic!("{}: {e}", f.name));
        let twin = data_dir().join(format!("{}.expected.npy", f.name));
        let npy = volume::open(&twin, None).unwrap();
        let grid = *vol.grid();
        check_grid(&grid, &f, 1e-5, 1e-9);
        assert_eq!(npy.grid().dims, f.dims, "{}", f.name);
        let got = all_samples(vol.as_ref());
        let want = all_samples(npy.as_ref());
        assert_eq!(got, want, "{}: samples differ", f.name);

        // Same mesh once the affine is applied; a mirror reverses winding.
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
        let expected: Vec<[u32; 3]> = if grid.is_mirrored() {
            mesh_npy
                .triangles
                .iter()
                .map(|t| [t[0], t[2], t[1]])
                .collect()
        } else {
            mesh_npy.triangles.clone()
        };
        assert_eq!(mesh.triangles, expected, "{}", f.name);
        assert_eq!(mesh.vertices.len(), mesh_npy.vertices.len(), "{}", f.name);
        for (v, w) in mesh.vertices.iter().zip(&mesh_npy.vertices) {
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
fn header_details() {
    for f in fixtures("nrrd_manifest.json") {
        let vol = nrrd::open(&f.file).unwrap();
        assert_eq!(vol.data_files(), f.files, "{}", f.name);
    }
    let mirrored = nrrd::open(&data_dir().join("nrrd_gzip_be_i16.nrrd")).unwrap();
    assert!(mirrored.grid().is_mirrored());
    assert_eq!(mirrored.space(), Some("right-anterior-superior"));
    assert_eq!(mirrored.scalar(), ScalarType::I16);
    assert_eq!(mirrored.endian(), volume::Endian::Big);
    let list = nrrd::open(&data_dir().join("nrrd_list3_gz_u16.nhdr")).unwrap();
    assert_eq!(list.scalar(), ScalarType::U16);
    assert_eq!(list.sample_bytes(), 2);
    let skips = nrrd::open(&data_dir().join("nrrd_skips_u16.nrrd")).unwrap();
    assert_eq!(skips.space(), None);
}

#[test]
fn absolute_data_file_name() {
    let dir = tempfile::tempdir().unwrap();
    let header = fs::read_to_string(data_dir().join("nrrd_detached_rot_f64.nhdr")).unwrap();
    let raw = data_dir().join("nrrd_detached_rot_f64.raw");
    let header = header.replace(
        "data file: nrrd_detached_rot_f64.raw",
        &format!("data file: {}", raw.display()),
    );
    assert!(header.contains(&raw.display().to_string()));
    let path = dir.path().join("abs.nhdr");
    fs::write(&path, header).unwrap();
    let vol = volume::open(&path, None).unwrap();
    let twin = volume::open(&data_dir().join("nrrd_detached_rot_f64.expected.npy"), None).unwrap();
    assert_eq!(all_samples(vol.as_ref()), all_samples(twin.as_ref()));
}

/// Copies the fixture files whose names start with `prefix` into `dir`.
fn copy_set(dir: &Path, prefix: &str) {
    for entry in fs::read_dir(data_dir()).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().to_string_lossy().to_string();
        if name.starts_with(prefix) && !name.ends_with(".npy") {
            fs::copy(entry.path(), dir.join(&name)).unwrap();
        }
    }
}

/// Rewrites the header `path`, replacing `from` by `to` (which must occur).
fn edit(path: &Path, from: &str, to: &str) {
    let bytes = fs::read(path).unwrap();
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("'{from}' not in {}", path.display()));
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(to.as_bytes());
    out.extend_from_slice(&bytes[at + from.len()..]);
    fs::write(path, out).unwrap();
}

/// Each case: the fixture set to copy, the header to open, the edit to
/// make, and the phrases the error must contain.
type Case<'a> = (&'a str, &'a str, &'a str, &'a str, &'a [&'a str]);

#[test]
fn bad_headers_and_data_give_one_line_errors() {
    let cases: &[Case] = &[
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "sizes: 9 7 6\n",
            "",
            &["missing 'sizes' field"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "type: float",
            "type: quaternion",
            &["type 'quaternion' is not supported"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "type: float",
            "type: block",
            &["type 'block' is not supported"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "encoding: raw",
            "encoding: zrl",
            &["encoding 'zrl' is not supported (raw, gzip, bzip2, ascii or hex)"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "encoding: raw\n",
            "",
            &["missing 'encoding' field"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "type: float\n",
            "",
            &["missing 'type' field"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "dimension: 3\n",
            "",
            &["missing 'dimension' field"],
        ),
        (
            "nrrd_gzip_be_i16",
            "nrrd_gzip_be_i16.nrrd",
            "(0,-1,0)",
            "none",
            &["'space directions' entry 2 is 'none'"],
        ),
        (
            "nrrd_gzip_be_i16",
            "nrrd_gzip_be_i16.nrrd",
            "(0.5,0,0) (0,-1,0) (0,0,2)",
            "(1,0,0) (1,0,0) (0,0,1)",
            &["'space directions': the direction matrix is singular (axes are parallel)"],
        ),
        (
            "nrrd_gzip_be_i16",
            "nrrd_gzip_be_i16.nrrd",
            "(0.5,0,0) (0,-1,0) (0,0,2)",
            "(1,0,0) (0,1,0) (1,1,0)",
            &["the direction matrix is singular"],
        ),
        (
            "nrrd_gzip_be_i16",
            "nrrd_gzip_be_i16.nrrd",
            "(0,-1,0)",
            "(0,0,0)",
            &["'space directions': direction of axis 1 (0, 0, 0) is not a usable vector"],
        ),
        (
            "nrrd_detached_rot_f64",
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "sizes: 9 7 7",
            &["nrrd_detached_rot_f64.raw: file has 3024 bytes"],
        ),
        (
            "nrrd_detached_rot_f64",
            "nrrd_detached_rot_f64.nhdr",
            "data file: nrrd_detached_rot_f64.raw",
            "data file: elsewhere.raw",
            &[
                "nrrd_detached_rot_f64.nhdr: data file ",
                "elsewhere.raw: No such file",
            ],
        ),
        (
            "nrrd_list_i8",
            "nrrd_list_i8.nhdr",
            "nrrd_list_i8_3.raw",
            "nrrd_list_i8_missing.raw",
            &[
                "nrrd_list_i8.nhdr: data file ",
                "nrrd_list_i8_missing.raw: No such file",
            ],
        ),
        (
            "nrrd_list_i8",
            "nrrd_list_i8.nhdr",
            "nrrd_list_i8_5.raw\n",
            "",
            &["'data file: LIST' names 5 files, sizes need 6"],
        ),
        (
            "nrrd_list3_gz_u16",
            "nrrd_list3_gz_u16.nhdr",
            "LIST 3",
            "LIST 1",
            &["subdimension 1 is not supported"],
        ),
        (
            "nrrd_list3_gz_u16",
            "nrrd_list3_gz_u16.nhdr",
            "sizes: 9 7 6",
            "sizes: 9 7 5",
            &["do not split the 5 z-slices evenly"],
        ),
        (
            "nrrd_pattern_f64",
            "nrrd_pattern_f64.nhdr",
            "%03d.raw 7 2 -1 2",
            "%03d.raw 8 3 -1 2",
            &["cannot open data file", "nrrd_pattern_f64_008.raw"],
        ),
        (
            "nrrd_pattern_f64",
            "nrrd_pattern_f64.nhdr",
            "%03d.raw 7 2 -1 2",
            "%03d.raw 2 7 -1 2",
            &["names 0 files"],
        ),
        (
            "nrrd_pattern_f64",
            "nrrd_pattern_f64.nhdr",
            "%03d.raw 7 2 -1 2",
            "%s.raw 7 2 -1 2",
            &["bad 'data file' format"],
        ),
        (
            "nrrd_pattern_f64",
            "nrrd_pattern_f64.nhdr",
            "%03d.raw 7 2 -1 2",
            "%03d.raw 7 2 0 2",
            &["zero step"],
        ),
        (
            "nrrd_detached_rot_f64",
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "sizes: 9 7 6\nspace units: \"mm\" \"mm\"",
            &["'space units' has 2 values, need 3"],
        ),
        (
            "nrrd_detached_rot_f64",
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "sizes: 9 7 6\nspace units: \"mm\" \"mm\" \"mm",
            &["bad 'space units' value", "double quotes"],
        ),
        (
            "nrrd_detached_rot_f64",
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "sizes: 9 7 6\nunits: \"microns\" \"microns\" \"mm\"",
            &["'units' \"microns\" \"microns\" \"mm\" with 'space directions' must name one unit"],
        ),
        (
            "nrrd_raw_le_f32",
            "nrrd_raw_le_f32.nrrd",
            "spacings: 0.5 1 2",
            "spacings: 0.5 1 2\nunits: \"mm\" \"mm\"",
            &["'units' has 2 values, need 3"],
        ),
    ];
    for (set, header, from, to, phrases) in cases {
        let dir = tempfile::tempdir().unwrap();
        copy_set(dir.path(), set);
        let path = dir.path().join(header);
        edit(&path, from, to);
        let e = open_err(&path);
        for phrase in *phrases {
            assert!(e.contains(phrase), "{header} ({from} -> {to}): {e}");
        }
    }
}

#[test]
fn bad_data_files_give_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();

    // A truncated gzip data file.
    copy_set(d, "nrrd_detached_gz_u16");
    let gz = d.join("nrrd_detached_gz_u16.raw.gz");
    let bytes = fs::read(&gz).unwrap();
    fs::write(&gz, &bytes[..bytes.len() / 2]).unwrap();
    let nhdr = d.join("nrrd_detached_gz_u16.nhdr");
    let e = open_err(&nhdr);
    // The header the user gave first, then the data file.
    assert!(
        e.starts_with(&format!("{}: data file {}: ", nhdr.display(), gz.display())),
        "{e}"
    );
    assert!(e.contains("gzip data"), "{e}");

    // A LIST slice file too short for its slice.
    copy_set(d, "nrrd_list_i8");
    let slice = d.join("nrrd_list_i8_2.raw");
    let bytes = fs::read(&slice).unwrap();
    fs::write(&slice, &bytes[..bytes.len() - 1]).unwrap();
    let nhdr = d.join("nrrd_list_i8.nhdr");
    let e = open_err(&nhdr);
    assert!(
        e.starts_with(&format!(
            "{}: data file {}: file has 83 bytes",
            nhdr.display(),
            slice.display()
        )),
        "{e}"
    );

    // A pattern file with fewer samples than its skip-to-the-end needs.
    copy_set(d, "nrrd_pattern_f64");
    fs::write(d.join("nrrd_pattern_f64_004.raw"), b"short").unwrap();
    let e = open_err(&d.join("nrrd_pattern_f64.nhdr"));
    assert!(
        e.contains("nrrd_pattern_f64_004.raw: file has 5 bytes"),
        "{e}"
    );

    // A pattern naming a billion files that are not there: refused at the
    // first (its names are not all built first: that took gigabytes).
    let billion = d.join("billion.nhdr");
    fs::write(
        &billion,
        "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 1000000000\nencoding: raw\ndata file: s%03d.raw 0 999999999 1 2\n\n",
    )
    .unwrap();
    let e = open_err(&billion);
    assert!(
        e.contains("cannot open data file") && e.contains("s000.raw (file 1 of the 1000000000"),
        "{e}"
    );

    // A detached header's NaN spacing: the error names the header the
    // user gave (the data file's reader named only the data file).
    copy_set(d, "nrrd_detached_rot_f64");
    let nhdr = d.join("nrrd_detached_rot_f64.nhdr");
    let text = fs::read_to_string(&nhdr).unwrap();
    let directions = text
        .lines()
        .find(|l| l.starts_with("space directions"))
        .unwrap();
    edit(&nhdr, directions, "spacings: 1 2 nan");
    let e = open_err(&nhdr);
    assert!(
        e.starts_with(&format!(
            "{}: 'spacings' 1 2 NaN must be finite",
            nhdr.display()
        )),
        "{e}"
    );

    // Truncated ascii data.
    copy_set(d, "nrrd_ascii_i8");
    let ascii = d.join("nrrd_ascii_i8.nrrd");
    let bytes = fs::read(&ascii).unwrap();
    fs::write(&ascii, &bytes[..bytes.len() - 200]).unwrap();
    let e = open_err(&ascii);
    assert!(e.contains("ascii data holds"), "{e}");
}

/// An attached ascii NRRD of 4x4x4 samples of `type_name`: 63 zeros, then
/// `last`.
fn ascii_nrrd(dir: &Path, type_name: &str, last: &str) -> std::path::PathBuf {
    let mut text =
        format!("NRRD0004\ntype: {type_name}\ndimension: 3\nsizes: 4 4 4\nencoding: ascii\n\n");
    text.push_str(&"0 ".repeat(63));
    text.push_str(last);
    text.push('\n');
    let path = dir.join(format!("{type_name}.nrrd"));
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn ascii_values_must_fit_the_declared_type() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (type_name, last, phrase) in [
        (
            "uint8",
            "300",
            "ascii value '300' at sample 63 does not fit u8",
        ),
        (
            "uint8",
            "-1",
            "ascii value '-1' at sample 63 does not fit u8",
        ),
        (
            "uint8",
            "1.5",
            "ascii value '1.5' at sample 63 does not fit u8",
        ),
        ("int16", "40000", "'40000' at sample 63 does not fit i16"),
        (
            "uint8",
            "x7",
            "ascii value 'x7' at sample 63 is not a number",
        ),
        (
            "float",
            "1e300",
            "'1e300' at sample 63 is outside the range of f32",
        ),
    ] {
        let e = open_err(&ascii_nrrd(d, type_name, last));
        assert!(e.contains(phrase), "{type_name} {last}: {e}");
    }
    // The extremes of a type are values of it; float values are rounded
    // to float.
    for (type_name, last, scalar) in [
        ("uint8", "255", ScalarType::U8),
        ("int8", "-128", ScalarType::I8),
        ("uint32", "4294967295", ScalarType::U32),
        ("float", "0.1", ScalarType::F32),
    ] {
        let vol = volume::open(&ascii_nrrd(d, type_name, last), None).unwrap();
        let want: f64 = match scalar {
            ScalarType::F32 => f64::from(0.1f32),
            _ => last.parse().unwrap(),
        };
        assert_eq!(all_samples(vol.as_ref())[63], want, "{type_name}");
    }
}

/// A 4-D NRRD with an axis of size 1 (a channel or time axis left by a
/// pipeline, first or last) is its 3-D volume: the same grid and samples
/// as the 3-D file, whichever unit axis, attached or a `LIST` of slices
/// (whose default subdimension, 3, counts the unit axis).
#[test]
fn four_d_with_a_unit_axis_is_the_volume() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let same = |original: &Path, edited: &Path| {
        let (a, b) = (volume::open(original, None).unwrap(), {
            volume::open(edited, None).unwrap_or_else(|e| panic!("{e}"))
        });
        assert_eq!(a.grid(), b.grid(), "{}", edited.display());
        assert_eq!(all_samples(&*a), all_samples(&*b), "{}", edited.display());
    };
    for (sizes, spacings, kinds) in [
        (
            "1 9 7 6",
            "nan 0.5 1 2",
            "kinds: list domain domain domain\n",
        ),
        ("9 7 6 1", "0.5 1 2 nan", ""),
        (
            "9 7 6 1",
            "0.5 1 2 1",
            "kinds: domain domain domain domain\n",
        ),
        ("9 7 1 6", "0.5 1 nan 2", ""),
    ] {
        copy_set(d, "nrrd_raw_le_f32");
        let path = d.join("nrrd_raw_le_f32.nrrd");
        edit(&path, "dimension: 3", "dimension: 4");
        edit(&path, "sizes: 9 7 6\n", &format!("sizes: {sizes}\n{kinds}"));
        edit(&path, "spacings: 0.5 1 2", &format!("spacings: {spacings}"));
        same(&data_dir().join("nrrd_raw_le_f32.nrrd"), &path);
    }
    for (sizes, directions) in [
        ("1 9 7 6", "none (0.5,0,0) (0,1,0) (0,0,2)"),
        ("9 7 6 1", "(0.5,0,0) (0,1,0) (0,0,2) none"),
    ] {
        copy_set(d, "nrrd_list_i8");
        let path = d.join("nrrd_list_i8.nhdr");
        edit(&path, "dimension: 3", "dimension: 4");
        edit(&path, "sizes: 9 7 6", &format!("sizes: {sizes}"));
        edit(&path, "(0.5,0,0) (0,1,0) (0,0,2)", directions);
        same(&data_dir().join("nrrd_list_i8.nhdr"), &path);
    }
}

/// Other 4-D shapes, and a 3-D NRRD with a colour, vector or list axis
/// (which would be read as x), are refused in one line naming the axis.
#[test]
fn non_spatial_axes_are_refused_naming_them() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "3 9 7 6",
            "kinds: RGB-color domain domain domain\n",
            &[
                "sizes 3 9 7 6 is not one volume",
                "axis 1 (kind 'RGB-color') has size 3",
            ],
        ),
        (
            "9 7 6 2",
            "",
            &["sizes 9 7 6 2 is not one volume", "no axis has size 1"],
        ),
        (
            "3 7 6",
            "kinds: RGB-color domain domain\n",
            &[
                "axis 1 has kind 'RGB-color' and size 3",
                "a scalar volume is needed",
            ],
        ),
        (
            "9 7 4",
            "kinds: domain domain 3-vector\n",
            &["axis 3 has kind '3-vector' and size 4"],
        ),
        (
            "9 3 6",
            "kinds: space list space\n",
            &["axis 2 has kind 'list'"],
        ),
        (
            "9 7 6",
            "kinds: domain domain\n",
            &["'kinds' has 2 values, need 3 (one per axis)"],
        ),
        (
            "9 7 6 1",
            "",
            &["'spacings' has 3 values, need 4 (one per axis)"],
        ),
    ];
    for (sizes, kinds, phrases) in cases {
        let dir = tempfile::tempdir().unwrap();
        copy_set(dir.path(), "nrrd_raw_le_f32");
        let path = dir.path().join("nrrd_raw_le_f32.nrrd");
        let dimension = sizes.split(' ').count();
        edit(&path, "dimension: 3", &format!("dimension: {dimension}"));
        edit(&path, "sizes: 9 7 6\n", &format!("sizes: {sizes}\n{kinds}"));
        if dimension == 4 && !phrases[0].starts_with("'spacings'") {
            edit(&path, "spacings: 0.5 1 2", "spacings: 0.5 1 2 1");
        }
        let e = open_err(&path);
        for phrase in *phrases {
            assert!(e.contains(phrase), "{sizes} {kinds}: {e}");
        }
    }
    // A non-spatial kind on an axis of size 1 moves no sample: read.
    let dir = tempfile::tempdir().unwrap();
    let path = ascii_nrrd(dir.path(), "uint8", "1");
    edit(
        &path,
        "sizes: 4 4 4",
        "sizes: 4 16 1\nkinds: domain domain RGB-color",
    );
    let vol = volume::open(&path, None).unwrap();
    assert_eq!(vol.grid().dims, [4, 16, 1]);
}

/// Without `space directions`, `axis mins` give the origin as teem's
/// `nrrdOriginCalculate` computes it and ITK's NRRD reader takes it (with
/// cell centring where `centers` states none): the first sample's centre
/// is at `min + spacing / 2` on a cell-centred axis and at `min` on a
/// node-centred one, the spacing being `spacings` or, failing that,
/// `(max - min) / size` (cell) or `/ (size - 1)` (node) from `axis maxs`.
/// Every axis needs its min and a spacing or max, else the origin stays
/// 0, as in teem. Written so by Fiji's and CMTK's NRRD writers; the origin
/// was 0 whatever they said.
#[test]
fn axis_mins_give_the_origin_as_teem_computes_it() {
    let dir = tempfile::tempdir().unwrap();
    copy_set(dir.path(), "nrrd_raw_le_f32");
    let (d, plain) = (dir.path(), dir.path().join("nrrd_raw_le_f32.nrrd"));
    let base = volume::open(&plain, None).unwrap();
    let (spacing, dims) = (base.grid().spacing, base.grid().dims);
    assert_eq!(base.grid().origin, [0.0; 3]);
    let mins = [10.0, -5.0, 3.0];
    let maxs = [20.0, 9.0, 15.0];
    // (extra fields, whether `spacings` stay, the origin teem computes)
    let teem = |center: [&str; 3], spacings: bool| -> [f64; 3] {
        [0, 1, 2].map(|i| {
            let cell = center[i] != "node";
            let denom = if cell { dims[i] } else { dims[i] - 1 } as f64;
            let step = if spacings {
                spacing[i]
            } else {
                (maxs[i] - mins[i]) / denom
            };
            mins[i] + if cell { step / 2.0 } else { 0.0 }
        })
    };
    let cases: Vec<(String, bool, [f64; 3])> = vec![
        (
            "axis mins: 10 -5 3\n".into(),
            true,
            teem(["", "", ""], true),
        ),
        (
            "centers: node node node\naxis mins: 10 -5 3\n".into(),
            true,
            teem(["node"; 3], true),
        ),
        (
            "centerings: cell node ???\naxismins: 10, -5, 3\n".into(),
            true,
            teem(["cell", "node", ""], true),
        ),
        (
            "centers: node cell node\naxis mins: 10 -5 3\naxis maxs: 20 9 15\n".into(),
            false,
            teem(["node", "cell", "node"], false),
        ),
        // A min missing, or neither spacing nor max: no origin.
        ("axis mins: 10 nan 3\n".into(), true, [0.0; 3]),
        ("axis mins: 10 -5 3\n".into(), false, [0.0; 3]),
    ];
    for (i, (fields, keep_spacings, want)) in cases.into_iter().enumerate() {
        let path = d.join(format!("mins{i}.nrrd"));
        fs::copy(&plain, &path).unwrap();
        let spacings = "spacings: 0.5 1 2\n";
        edit(
            &path,
            spacings,
            &format!("{}{fields}", if keep_spacings { spacings } else { "" }),
        );
        let vol = volume::open(&path, None).unwrap_or_else(|e| panic!("{fields}: {e}"));
        let grid = vol.grid();
        for a in 0..3 {
            assert!(
                (grid.origin[a] - want[a]).abs() < 1e-12,
                "{fields}: origin {:?}, teem's {want:?}",
                grid.origin
            );
        }
        // The spacing is that of `spacings` (1 without: axis maxs never
        // set it, as in teem's nrrdSpacingCalculate).
        let want_spacing = if keep_spacings { spacing } else { [1.0; 3] };
        assert_eq!(grid.spacing, want_spacing, "{fields}");
        assert_eq!(all_samples(vol.as_ref()), all_samples(base.as_ref()));
    }

    // `space directions` place the grid; axis mins change nothing.
    copy_set(d, "nrrd_detached_rot_f64");
    let nhdr = d.join("nrrd_detached_rot_f64.nhdr");
    let before = *volume::open(&nhdr, None).unwrap().grid();
    let text = fs::read_to_string(&nhdr).unwrap();
    let sizes = text.lines().find(|l| l.starts_with("sizes")).unwrap();
    edit(&nhdr, sizes, &format!("{sizes}\naxis mins: 100 100 100"));
    assert_eq!(*volume::open(&nhdr, None).unwrap().grid(), before);
}

/// `space units` (per space axis, with `space directions` and `space
/// origin`, as Fiji's NRRD writer writes `"microns"`) and `units` (per
/// axis, with `spacings` and `axis mins`) in metres or microns convert
/// the grid to millimetres, as the NIfTI, TIFF, OME-Zarr and HDF5 readers
/// do; `tmc info` says so. A unit tmc does not know (`pixel`) leaves the
/// values as stated and is named; `mm`, `???` and `""` change nothing.
/// The grid was that of the numbers as written, a micron file's mesh
/// 1000 times too large beside the same samples as an OME-TIFF.
#[test]
fn space_units_give_millimetres() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    copy_set(d, "nrrd_detached_rot_f64");
    copy_set(d, "nrrd_raw_le_f32");
    // (fixture, line after which the field goes, the field, the factor
    // per world axis, what `spacing_from` must contain)
    let cases: [(&str, &str, &str, [f64; 3], &str); 10] = [
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"microns\" \"microns\" \"microns\"",
            [1e-3; 3],
            "space units microns, in mm",
        ),
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"m\" \"m\" \"m\"",
            [1e3; 3],
            "space units m, in mm",
        ),
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"µm\" \"µm\" \"mm\"",
            [1e-3, 1e-3, 1.0],
            "space units µm, mm, in mm",
        ),
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"mm\" \"mm\" \"mm\"",
            [1.0; 3],
            "header",
        ),
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"pixel\" \"pixel\" \"pixel\"",
            [1.0; 3],
            "'pixel' not known: values as stated",
        ),
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "space units: \"???\" \"\" \"???\"",
            [1.0; 3],
            "header",
        ),
        // Per-axis units of one unit with `space directions`: the space's.
        (
            "nrrd_detached_rot_f64.nhdr",
            "sizes: 9 7 6",
            "units: \"um\" \"um\" \"um\"",
            [1e-3; 3],
            "header, units um, in mm",
        ),
        (
            "nrrd_raw_le_f32.nrrd",
            "spacings: 0.5 1 2",
            "units: \"microns\" \"microns\" \"microns\"\naxis mins: 10 -5 3",
            [1e-3; 3],
            "units microns, in mm",
        ),
        (
            "nrrd_raw_le_f32.nrrd",
            "spacings: 0.5 1 2",
            "units: \"nm\" \"nm\" \"nm\"\nspace origin: (1,2,3)",
            [1e-6; 3],
            "units nm, in mm",
        ),
        (
            "nrrd_raw_le_f32.nrrd",
            "spacings: 0.5 1 2",
            "units: mm mm cm\naxis mins: 10 -5 3",
            [1.0, 1.0, 10.0],
            "units mm, cm, in mm",
        ),
    ];
    for (i, (name, after, field, mm, from)) in cases.into_iter().enumerate() {
        // The header of the numbers as written, and the same with its
        // unit field (each its own file: an attached header's data moves).
        let (unit_line, extra) = field.split_once('\n').unwrap_or((field, ""));
        let [stated_path, path] =
            ["stated", "units"].map(|what| d.join(format!("{what}{i}_{name}")));
        fs::copy(d.join(name), &stated_path).unwrap();
        if !extra.is_empty() {
            edit(&stated_path, after, &format!("{after}\n{extra}"));
        }
        fs::copy(&stated_path, &path).unwrap();
        edit(&path, after, &format!("{after}\n{unit_line}"));
        let stated = volume::open(&stated_path, None).unwrap();
        let vol = volume::open(&path, None).unwrap_or_else(|e| panic!("{field}: {e}"));
        let (g, s) = (vol.grid(), stated.grid());
        assert_eq!(g.dims, s.dims, "{field}");
        for p in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [8.0, 6.0, 5.0],
        ] {
            let (got, want) = (g.world(p), s.world(p));
            for a in 0..3 {
                assert!(
                    close(got[a], want[a] * mm[a], 1e-12),
                    "{field}: index {p:?} at {got:?}, stated {want:?} times {mm:?}"
                );
            }
        }
        assert_eq!(all_samples(vol.as_ref()), all_samples(stated.as_ref()));
        let notes = vol.notes();
        for what in [&notes.spacing_from, &notes.origin_from] {
            let text = format!("{what}");
            assert!(text.contains(from), "case {i} {field}: '{text}'");
            if from == "header" {
                assert_eq!(text, "file (header)", "{field}");
            }
        }
    }
}

/// `encoding: hex` (teem writes it: the raw bytes as hex digits, any case,
/// whitespace between them ignored; `byte skip` skips the file's bytes, as
/// for ascii) reads the samples of the raw file, attached or detached. It
/// was refused ("encoding 'hex' is not supported"). Bad digits, an odd
/// digit count and short data are one line each.
#[test]
fn hex_encoding_reads_as_raw() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let raw = data_dir().join("nrrd_raw_le_f32.nrrd");
    let want = all_samples(volume::open(&raw, None).unwrap().as_ref());
    let bytes = fs::read(&raw).unwrap();
    let end = bytes.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let header = std::str::from_utf8(&bytes[..end])
        .unwrap()
        .replace("encoding: raw", "encoding: hex");
    // Lines of 15 bytes (so that samples straddle lines), upper case on odd lines.
    let hex: String = bytes[end..]
        .chunks(15)
        .enumerate()
        .map(|(i, line)| {
            let text: String = line.iter().map(|b| format!("{b:02x} ")).collect();
            let text = if i % 2 == 1 {
                text.to_uppercase()
            } else {
                text
            };
            format!("{text}\r\n")
        })
        .collect();
    let attached = d.join("hex.nrrd");
    fs::write(&attached, format!("{header}{hex}")).unwrap();
    let detached = d.join("hex.nhdr");
    let data = d.join("hex.txt");
    fs::write(&data, format!("skip me\n{hex}")).unwrap();
    let head = header.trim_end().replace(
        "encoding: hex",
        "encoding: hex\nbyte skip: 8\ndata file: hex.txt",
    );
    fs::write(&detached, format!("{head}\n")).unwrap();
    for path in [&attached, &detached] {
        let vol = volume::open(path, None).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(vol.grid().dims, [9, 7, 6]);
        assert_eq!(all_samples(vol.as_ref()), want, "{}", path.display());
    }
    let digits: String = hex.chars().filter(|c| c.is_ascii_hexdigit()).collect();
    for (text, phrase) in [
        (format!("{}zz", &digits[..10]), "'z' is not a hex digit"),
        (
            digits[..digits.len() - 1].to_string(),
            "odd number of hex digits",
        ),
        (
            digits[..digits.len() - 8].to_string(),
            "hex data holds 1508 bytes",
        ),
    ] {
        fs::write(&attached, format!("{header}{text}")).unwrap();
        let e = open_err(&attached);
        assert!(e.contains(phrase), "{phrase}: {e}");
    }
}
