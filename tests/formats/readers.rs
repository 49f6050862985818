//! Volume readers: `.npy` (every dtype, both byte orders, C and Fortran
//! order, versions 1-3), raw (header bytes, big-endian), NRRD (raw and gzip),
//! the real volumes of `../shared/data`, and errors (not panics) on
//! truncated files and bad headers.

use std::io::Write;
use std::path::{Path, PathBuf};
use tmc::volume::{self, Endian, RawOptions, ScalarType};
use tmc::SampleSource;

/// Values exercising the range of `scalar`, then distinct small integers.
fn sample_value(scalar: ScalarType, i: usize) -> f64 {
    let extremes: Vec<f64> = match scalar {
        ScalarType::U8 => vec![0.0, 255.0, 1.0],
        ScalarType::I8 => vec![-128.0, 127.0, -1.0],
        ScalarType::U16 => vec![0.0, 65535.0, 256.0],
        ScalarType::I16 => vec![-32768.0, 32767.0, -2.0],
        ScalarType::U32 => vec![0.0, 4_294_967_295.0, 16_777_217.0],
        ScalarType::I32 => vec![-2_147_483_648.0, 2_147_483_647.0, -16_777_217.0],
        ScalarType::F32 => vec![
            f64::NAN,
            f64::from(f32::MAX),
            f64::from(f32::MIN_POSITIVE),
            -1.5,
            f64::INFINITY,
        ],
        ScalarType::F64 => vec![f64::NAN, f64::MAX, -1e-300, 0.1, f64::NEG_INFINITY],
        // Read as f64: exact within ±2^53.
        ScalarType::I64 => vec![-9_007_199_254_740_992.0, 9_007_199_254_740_992.0, -1.0],
        ScalarType::U64 => vec![0.0, 9_007_199_254_740_992.0, 4_294_967_297.0],
        ScalarType::F16 => vec![f64::NAN, 65504.0, 2f64.powi(-24), -1.5, f64::INFINITY],
    };
    extremes.get(i).copied().unwrap_or(i as f64)
}

/// `v` stored as `scalar` in byte order `endian`.
fn encode(scalar: ScalarType, endian: Endian, v: f64) -> Vec<u8> {
    macro_rules! enc {
        ($t:ty) => {{
            let x = v as $t;
            match endian {
                Endian::Little => x.to_le_bytes().to_vec(),
                Endian::Big => x.to_be_bytes().to_vec(),
            }
        }};
    }
    match scalar {
        ScalarType::U8 => enc!(u8),
        ScalarType::I8 => enc!(i8),
        ScalarType::U16 => enc!(u16),
        ScalarType::I16 => enc!(i16),
        ScalarType::U32 => enc!(u32),
        ScalarType::I32 => enc!(i32),
        ScalarType::F32 => enc!(f32),
        ScalarType::F64 => enc!(f64),
        ScalarType::I64 => enc!(i64),
        ScalarType::U64 => enc!(u64),
        ScalarType::F16 => {
            let x = half::f16::from_f64(v);
            match endian {
                Endian::Little => x.to_le_bytes().to_vec(),
                Endian::Big => x.to_be_bytes().to_vec(),
            }
        }
    }
}

/// The numpy dtype code of `scalar`.
fn numpy_code(scalar: ScalarType) -> &'static str {
    match scalar {
        ScalarType::U8 => "u1",
        ScalarType::I8 => "i1",
        ScalarType::U16 => "u2",
        ScalarType::I16 => "i2",
        ScalarType::U32 => "u4",
        ScalarType::I32 => "i4",
        ScalarType::F32 => "f4",
        ScalarType::F64 => "f8",
        ScalarType::I64 => "i8",
        ScalarType::U64 => "u8",
        ScalarType::F16 => "f2",
    }
}

/// A `.npy` file: preamble, header dict padded to 64 bytes, then `data`.
pub(crate) fn npy_bytes(major: u8, dict: &str, data: &[u8]) -> Vec<u8> {
    let prefix = if major == 1 { 10 } else { 12 };
    let mut header = dict.to_string();
    while !(prefix + header.len() + 1).is_multiple_of(64) {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY".to_vec();
    out.extend_from_slice(&[major, 0]);
    if major == 1 {
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    }
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

/// The header dict of a 3-D array of shape `(nz, ny, nx)`.
fn npy_dict(descr: &str, fortran: bool, dims: [usize; 3]) -> String {
    format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': ({}, {}, {}), }}",
        if fortran { "True" } else { "False" },
        dims[2],
        dims[1],
        dims[0]
    )
}

/// The raw volume of `dims` samples `value(i)` (`i` in file order) of
/// type `scalar` in byte order `endian`, after `header` bytes, written to
/// `name` in `dir`.
pub(crate) fn raw_volume(
    dir: &Path,
    name: &str,
    (dims, scalar, endian, header): ([usize; 3], ScalarType, Endian, u64),
    value: impl Fn(usize) -> f64,
) -> volume::RawVolume {
    let mut bytes = vec![0u8; header as usize];
    for i in 0..dims.iter().product() {
        bytes.extend(encode(scalar, endian, value(i)));
    }
    let path = write_file(dir, name, &bytes);
    let options = RawOptions {
        dims,
        scalar,
        endian,
        header_bytes: header,
        spacing: [1.0; 3],
        origin: [0.0; 3],
    };
    volume::RawVolume::open(&path, &options).unwrap()
}

/// Writes `bytes` to `name` in `dir`.
pub(crate) fn write_file(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Reads every plane of `source`, x fastest.
fn read_all(source: &dyn SampleSource) -> Vec<f64> {
    let grid = *source.grid();
    let mut all = Vec::new();
    let mut plane = vec![0.0; grid.plane_len()];
    for z in 0..grid.dims[2] {
        source.read_plane(z, &mut plane).unwrap();
        all.extend_from_slice(&plane);
    }
    all
}

/// Exact comparison, NaN equal to NaN.
fn assert_same(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()),
            "{what}: sample {i} is {g}, expected {w}"
        );
    }
}

/// The error message of a failed open.
fn open_err(path: &Path, raw: Option<&RawOptions>) -> String {
    match volume::open(path, raw) {
        Ok(_) => panic!("{}: opened, expected an error", path.display()),
        Err(e) => {
            let text = e.to_string();
            assert!(!text.contains('\n'), "multi-line error: {text}");
            text
        }
    }
}

#[test]
fn npy_every_dtype_endianness_order_and_version() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [4usize, 3, 2];
    let [nx, ny, nz] = dims;
    let mut case = 0;
    for scalar in ScalarType::ALL {
        for endian in [Endian::Little, Endian::Big] {
            for fortran in [false, true] {
                case += 1;
                let major = [1u8, 2, 3][case % 3];
                let value =
                    |x: usize, y: usize, z: usize| sample_value(scalar, x + nx * (y + ny * z));
                let mut data = Vec::new();
                if fortran {
                    for x in 0..nx {
                        for y in 0..ny {
                            for z in 0..nz {
                                data.extend(encode(scalar, endian, value(x, y, z)));
                            }
                        }
                    }
                } else {
                    for z in 0..nz {
                        for y in 0..ny {
                            for x in 0..nx {
                                data.extend(encode(scalar, endian, value(x, y, z)));
                            }
                        }
                    }
                }
                let order = match (scalar.size(), endian) {
                    (1, _) => "|",
                    (_, Endian::Little) => "<",
                    (_, Endian::Big) => ">",
                };
                let descr = format!("{order}{}", numpy_code(scalar));
                let bytes = npy_bytes(major, &npy_dict(&descr, fortran, dims), &data);
                let path = write_file(dir.path(), &format!("case{case}.npy"), &bytes);

                let source = volume::open(&path, None).unwrap();
                let grid = *source.grid();
                assert_eq!(grid.dims, dims);
                assert_eq!(grid.spacing, [1.0; 3]);
                assert_eq!(grid.origin, [0.0; 3]);
                let mut want = Vec::new();
                for z in 0..nz {
                    for y in 0..ny {
                        for x in 0..nx {
                            want.push(value(x, y, z));
                        }
                    }
                }
                let what = format!("{descr} fortran={fortran} v{major}");
                assert_same(&read_all(source.as_ref()), &want, &what);
            }
        }
    }
}

#[test]
fn npy_accepts_python2_longs_and_double_quotes() {
    let dir = tempfile::tempdir().unwrap();
    let dict = "{\"descr\": \"<f8\", \"shape\": (2L, 2L, 2L), \"fortran_order\": False}";
    let data: Vec<u8> = (0..8).flat_map(|i| f64::from(i).to_le_bytes()).collect();
    let path = write_file(dir.path(), "a.npy", &npy_bytes(1, dict, &data));
    let source = volume::open(&path, None).unwrap();
    assert_same(
        &read_all(source.as_ref()),
        &(0..8).map(f64::from).collect::<Vec<_>>(),
        "python2",
    );
}

/// A leading axis of size 1 (a batch or channel axis from PyTorch or
/// numpy) is one volume, in C and Fortran order, as NIfTI readers take a
/// 4-D file of one time point; any other extra axis is refused naming it.
#[test]
fn npy_leading_unit_axes_are_one_volume() {
    let dir = tempfile::tempdir().unwrap();
    let data: Vec<u8> = (0..24u16).flat_map(|v| v.to_le_bytes()).collect();
    for fortran in [false, true] {
        let order = if fortran { "True" } else { "False" };
        let three = npy_bytes(1, &npy_dict("<u2", fortran, [4, 3, 2]), &data);
        let want = read_all(
            volume::open(&write_file(dir.path(), "3d.npy", &three), None)
                .unwrap()
                .as_ref(),
        );
        for shape in ["(1, 2, 3, 4)", "(1, 1, 2, 3, 4)"] {
            let dict = format!("{{'descr': '<u2', 'fortran_order': {order}, 'shape': {shape}, }}");
            let path = write_file(dir.path(), "4d.npy", &npy_bytes(1, &dict, &data));
            let source = volume::open(&path, None).unwrap_or_else(|e| panic!("{shape}: {e}"));
            assert_eq!(source.grid().dims, [4, 3, 2], "{shape} {order}");
            assert_same(&read_all(source.as_ref()), &want, shape);
        }
    }
    let cases = [
        (
            "(2, 1, 3, 4)",
            "shape (2, 1, 3, 4) is not one volume: axis 0 has size 2, not 1",
        ),
        ("(1, 2, 1, 3, 4)", "axis 1 has size 2, not 1"),
        // A channel axis last: the volume is a[..., 0] (a[0] is a plane).
        ("(2, 3, 4, 1)", "axis 0 has size 2, not 1"),
        ("(2, 3, 4, 1)", "np.save(path, a[..., 0])"),
        ("(1, 2, 3, 4, 1)", "np.save(path, a[..., 0])"),
        ("(2, 1, 3, 4)", "np.save(path, a[0])"),
    ];
    for (shape, expected) in cases {
        let dict = format!("{{'descr': '<u2', 'fortran_order': False, 'shape': {shape}, }}");
        let err = open_err(
            &write_file(dir.path(), "bad.npy", &npy_bytes(1, &dict, &data)),
            None,
        );
        assert!(
            err.contains(expected) && err.contains("np.save"),
            "{shape}: {err}"
        );
    }
}

#[test]
fn npy_read_plane_rejects_bad_requests() {
    let dir = tempfile::tempdir().unwrap();
    let dict = npy_dict("|u1", false, [2, 2, 2]);
    let path = write_file(dir.path(), "a.npy", &npy_bytes(1, &dict, &[0; 8]));
    let source = volume::open(&path, None).unwrap();
    let mut plane = vec![0.0; 4];
    assert!(source.read_plane(2, &mut plane).is_err());
    assert!(source.read_plane(0, &mut [0.0; 3]).is_err());
}

#[test]
fn npy_bad_files_give_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = npy_dict("<u2", false, [4, 3, 2]);
    let data = vec![0u8; 4 * 3 * 2 * 2];
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "not a .npy file"),
        ("magic", b"\x93NUMPX\x01\x00\x10\x00".to_vec(), "bad magic"),
        ("version", npy_bytes(1, &good, &data)[..6].to_vec(), "too short"),
        (
            "v4",
            {
                let mut b = npy_bytes(1, &good, &data);
                b[6] = 4;
                b
            },
            "unsupported .npy version 4.0",
        ),
        (
            "header cut",
            npy_bytes(1, &good, &data)[..40].to_vec(),
            "truncated .npy header",
        ),
        (
            "data cut",
            {
                let b = npy_bytes(1, &good, &data);
                b[..b.len() - 1].to_vec()
            },
            "dims 4x3x2 u16 need 48 after a 128-byte header",
        ),
        (
            "2-D",
            npy_bytes(1, "{'descr': '<u2', 'fortran_order': False, 'shape': (3, 4), }", &data),
            "expected a 3-D array of shape (nz, ny, nx), found shape (3, 4)",
        ),
        (
            "1-D",
            npy_bytes(1, "{'descr': '<u2', 'fortran_order': False, 'shape': (24,), }", &data),
            "found shape (24,)",
        ),
        (
            "complex",
            npy_bytes(1, &npy_dict("<c8", false, [4, 3, 2]), &data),
            "unsupported dtype '<c8'",
        ),
        (
            "int128",
            npy_bytes(1, &npy_dict("<i16", false, [4, 3, 2]), &data),
            "unsupported dtype '<i16'",
        ),
        (
            "structured",
            npy_bytes(
                1,
                "{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (2, 2, 2), }",
                &data,
            ),
            "structured dtypes are not supported",
        ),
        (
            "missing shape",
            npy_bytes(1, "{'descr': '<u2', 'fortran_order': False, }", &data),
            "missing 'shape'",
        ),
        (
            "garbage",
            npy_bytes(1, "{'descr': '<u2', 'fortran_order': Maybe}", &data),
            "bad .npy header",
        ),
        (
            "not a dict",
            npy_bytes(1, "descr", &data),
            "bad .npy header",
        ),
        (
            "zero dim",
            npy_bytes(1, "{'descr': '<u2', 'fortran_order': False, 'shape': (0, 3, 4), }", &[]),
            "contain a zero",
        ),
        (
            "huge",
            npy_bytes(
                1,
                "{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999, 99999999999, 99999999999), }",
                &data,
            ),
            "too large",
        ),
    ];
    for (name, bytes, expected) in cases {
        let path = write_file(
            dir.path(),
            &format!("{}.npy", name.replace(' ', "_")),
            &bytes,
        );
        let err = open_err(&path, None);
        assert!(
            err.contains(expected),
            "{name}: got '{err}', expected '{expected}'"
        );
        assert!(
            err.contains(&*path.to_string_lossy()),
            "{name}: no path in '{err}'"
        );
    }
}

#[test]
fn raw_with_header_bytes_big_endian_spacing_origin() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [3usize, 2, 2];
    let mut bytes = vec![0xAB; 7];
    for i in 0..12 {
        bytes.extend_from_slice(&(i as i16 * 1000 - 6000).to_be_bytes());
    }
    bytes.extend_from_slice(b"trailing bytes are ignored");
    let path = write_file(dir.path(), "v.raw", &bytes);
    let options = RawOptions {
        dims,
        scalar: ScalarType::I16,
        endian: Endian::Big,
        header_bytes: 7,
        spacing: [0.5, 1.0, 2.5],
        origin: [-1.0, 0.0, 10.0],
    };
    let source = volume::open(&path, Some(&options)).unwrap();
    let grid = *source.grid();
    assert_eq!(grid.dims, dims);
    assert_eq!(grid.spacing, [0.5, 1.0, 2.5]);
    assert_eq!(grid.origin, [-1.0, 0.0, 10.0]);
    let want: Vec<f64> = (0..12).map(|i| f64::from(i * 1000 - 6000)).collect();
    assert_same(&read_all(source.as_ref()), &want, "raw");

    // The same bytes read by the concrete type.
    let raw = volume::RawVolume::open(&path, &options).unwrap();
    assert_eq!(raw.scalar(), ScalarType::I16);
    assert_eq!(raw.endian(), Endian::Big);
    assert!(!raw.is_z_fastest());
}

#[test]
fn raw_bad_inputs_give_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_file(dir.path(), "in.raw", &[0u8; 1000]);
    let options = |dims: [usize; 3]| RawOptions {
        dims,
        scalar: ScalarType::U16,
        endian: Endian::Little,
        header_bytes: 0,
        spacing: [1.0; 3],
        origin: [0.0; 3],
    };
    let err = open_err(&path, Some(&options([10, 10, 10])));
    assert_eq!(
        err,
        format!(
            "{}: file has 1000 bytes, dims 10x10x10 u16 need 2000 after a 0-byte header",
            path.display()
        )
    );

    let mut o = options([10, 10, 5]);
    o.header_bytes = 1;
    assert!(open_err(&path, Some(&o)).contains("need 1000 after a 1-byte header"));
    o.header_bytes = u64::MAX;
    assert!(open_err(&path, Some(&o)).contains("file has 1000 bytes"));

    assert!(open_err(&path, Some(&options([usize::MAX, 2, 2]))).contains("too large"));
    assert!(open_err(&path, Some(&options([usize::MAX, usize::MAX, 2]))).contains("too large"));
    assert!(open_err(&path, Some(&options([0, 2, 2]))).contains("contain a zero"));

    for spacing in [[0.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, f64::NAN]] {
        let mut o = options([2, 2, 2]);
        o.spacing = spacing;
        assert!(open_err(&path, Some(&o)).contains("finite and positive"));
    }
    let mut o = options([2, 2, 2]);
    o.origin = [f64::INFINITY, 0.0, 0.0];
    assert!(open_err(&path, Some(&o)).contains("origin"));

    let missing = dir.path().join("missing.raw");
    assert!(open_err(&missing, Some(&options([2, 2, 2]))).contains("missing.raw"));
    assert!(open_err(dir.path(), Some(&options([2, 2, 2]))).contains("not a regular file"));

    // Dims of 1 are legal to read (the CLI rejects them for extraction).
    let one = volume::open(&path, Some(&options([1, 1, 1]))).unwrap();
    assert_eq!(one.grid().dims, [1, 1, 1]);
}

#[test]
fn unknown_extension_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_file(dir.path(), "v.xyz", b"data");
    assert!(open_err(&path, None).contains("unknown input format"));
}

/// A NRRD file: `header` lines, a blank line, then `data`.
fn nrrd_bytes(header: &[&str], data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    for line in header {
        out.extend_from_slice(line.as_bytes());
        out.push(b'\n');
    }
    out.push(b'\n');
    out.extend_from_slice(data);
    out
}

#[test]
fn nrrd_raw_big_endian_directions_origin_byte_skip() {
    let dir = tempfile::tempdir().unwrap();
    let mut data = vec![9u8; 4];
    for i in 0..24 {
        data.extend_from_slice(&(i as i16 - 12).to_be_bytes());
    }
    let header = [
        "NRRD0004",
        "# a comment",
        "content: test",
        "type: short",
        "dimension: 3",
        "space: left-posterior-superior",
        "sizes: 4 3 2",
        "space directions: (0.5,0,0) (0,-2,0) (0, 0, 3)",
        "spacings: 7 7 7",
        "space origin: (1,2,3)",
        "kinds: domain domain domain",
        "endian: big",
        "encoding: raw",
        "byte skip: 4",
        "my key:=my: value",
    ];
    let path = write_file(dir.path(), "v.nrrd", &nrrd_bytes(&header, &data));
    let source = volume::open(&path, None).unwrap();
    let grid = *source.grid();
    assert_eq!(grid.dims, [4, 3, 2]);
    assert_eq!(grid.spacing, [0.5, 2.0, 3.0]);
    assert_eq!(grid.origin, [1.0, 2.0, 3.0]);
    let want: Vec<f64> = (0..24).map(|i| f64::from(i - 12)).collect();
    assert_same(&read_all(source.as_ref()), &want, "nrrd");
}

#[test]
fn nrrd_spacings_crlf_line_skip_and_byte_skip_minus_one() {
    let dir = tempfile::tempdir().unwrap();
    let floats: Vec<u8> = (0..8)
        .flat_map(|i| (i as f32 * 0.5).to_le_bytes())
        .collect();
    let want: Vec<f64> = (0..8).map(|i| f64::from(i as f32 * 0.5)).collect();

    let mut crlf = b"NRRD0001\r\ntype: float\r\ndimension: 3\r\nsizes: 2 2 2\r\nspacings: 1 2 -3\r\nendian: little\r\nencoding: raw\r\nline skip: 1\r\n\r\nskipped line\n".to_vec();
    crlf.extend_from_slice(&floats);
    let path = write_file(dir.path(), "crlf.nrrd", &crlf);
    let source = volume::open(&path, None).unwrap();
    assert_eq!(source.grid().spacing, [1.0, 2.0, 3.0]);
    // The negative spacing mirrors the z axis (teem and ITK keep its sign).
    let mirror_z = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];
    assert_eq!(source.grid().direction, mirror_z);
    assert_same(&read_all(source.as_ref()), &want, "crlf");

    let mut data = b"some junk before the data".to_vec();
    data.extend_from_slice(&floats);
    let header = [
        "NRRD0004",
        "type: float",
        "dimension: 3",
        "sizes: 2 2 2",
        "endian: little",
        "encoding: raw",
        "byte skip: -1",
    ];
    let path = write_file(dir.path(), "end.nrrd", &nrrd_bytes(&header, &data));
    let source = volume::open(&path, None).unwrap();
    assert_eq!(source.grid().spacing, [1.0; 3]);
    assert_same(&read_all(source.as_ref()), &want, "byte skip -1");
}

#[test]
fn nrrd_gzip() {
    let dir = tempfile::tempdir().unwrap();
    let mut plain = vec![1u8, 2, 3];
    plain.extend((0..27u32).flat_map(|i| (i * 1_000_000).to_le_bytes()));
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(&plain).unwrap();
    let gz = encoder.finish().unwrap();
    let header = [
        "NRRD0004",
        "type: unsigned int",
        "dimension: 3",
        "sizes: 3 3 3",
        "endian: little",
        "encoding: gzip",
        "byte skip: 3",
    ];
    let path = write_file(dir.path(), "v.nrrd", &nrrd_bytes(&header, &gz));
    let source = volume::open(&path, None).unwrap();
    let want: Vec<f64> = (0..27u32).map(|i| f64::from(i * 1_000_000)).collect();
    assert_same(&read_all(source.as_ref()), &want, "gzip");

    let cut = write_file(
        dir.path(),
        "cut.nrrd",
        &nrrd_bytes(&header, &gz[..gz.len() / 2]),
    );
    open_err(&cut, None);
    let mut corrupt_gz = gz.clone();
    for b in corrupt_gz.iter_mut().skip(12).take(20) {
        *b ^= 0x5A;
    }
    let corrupt = write_file(
        dir.path(),
        "corrupt.nrrd",
        &nrrd_bytes(&header, &corrupt_gz),
    );
    open_err(&corrupt, None);
    let mut big = header;
    big[3] = "sizes: 3 3 4";
    let short = write_file(dir.path(), "short.nrrd", &nrrd_bytes(&big, &gz));
    assert!(open_err(&short, None).contains("gzip data holds"));
}

#[test]
fn nrrd_bad_files_give_errors() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "NRRD0004",
        "type: uint16",
        "dimension: 3",
        "sizes: 2 2 2",
        "endian: little",
        "encoding: raw",
    ];
    let data = vec![0u8; 16];
    let with = |replace: &str, by: Option<&str>| -> Vec<u8> {
        let lines: Vec<&str> = base
            .iter()
            .filter_map(|l| if l.starts_with(replace) { by } else { Some(*l) })
            .collect();
        nrrd_bytes(&lines, &data)
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "empty file"),
        ("magic", with("NRRD", Some("PNRR0004")), "not a NRRD file"),
        (
            "dimension",
            with("dimension", Some("dimension: 2")),
            "dimension 2 is not supported",
        ),
        (
            "no dimension",
            with("dimension", None),
            "missing 'dimension'",
        ),
        (
            "sizes",
            with("sizes", Some("sizes: 2 2")),
            "'sizes' has 2 values",
        ),
        (
            "bad sizes",
            with("sizes", Some("sizes: 2 two 2")),
            "bad 'sizes'",
        ),
        ("no sizes", with("sizes", None), "missing 'sizes'"),
        ("no type", with("type", None), "missing 'type'"),
        (
            "block",
            with("type", Some("type: block")),
            "type 'block' is not supported",
        ),
        (
            "hex",
            with("encoding", Some("encoding: hex")),
            "bad hex data: '\\x00' is not a hex digit",
        ),
        ("no encoding", with("encoding", None), "missing 'encoding'"),
        ("no endian", with("endian", None), "missing 'endian'"),
        (
            "bad endian",
            with("endian", Some("endian: middle")),
            "bad 'endian'",
        ),
        (
            "detached",
            with("endian", Some("endian: little\ndata file: v.raw")),
            "detached.nrrd: data file ",
        ),
        (
            "directions",
            with("sizes", Some("space directions: (1,0,0) (0,1,0)")),
            "'space directions' has 2 vectors",
        ),
        (
            "bad directions",
            with("sizes", Some("space directions: (1,0,0) (0,x,0) (0,0,1)")),
            "bad 'space directions'",
        ),
        (
            "bad origin",
            with("sizes", Some("space origin: (1,2)")),
            "bad 'space origin'",
        ),
        (
            "nan spacing",
            with("encoding", Some("spacings: 1 nan 1\nencoding: raw")),
            "'spacings' 1 NaN 1 must be finite and nonzero",
        ),
        (
            "bad line",
            with("encoding", Some("encoding raw")),
            "bad header line",
        ),
        (
            "byte skip",
            with("encoding", Some("encoding: raw\nbyte skip: -2")),
            "bad 'byte skip'",
        ),
        (
            "line skip",
            with("encoding", Some("encoding: raw\nline skip: 99")),
            "past the end",
        ),
        ("truncated", nrrd_bytes(&base, &data[..15]), "file has"),
        (
            "no blank line",
            base.join("\n").into_bytes(),
            "does not end with a blank line",
        ),
    ];
    for (name, bytes, expected) in cases {
        let path = write_file(
            dir.path(),
            &format!("{}.nrrd", name.replace(' ', "_")),
            &bytes,
        );
        let err = open_err(&path, None);
        assert!(
            err.contains(expected),
            "{name}: got '{err}', expected '{expected}'"
        );
    }
}

/// The real volumes of `../shared/data` (see its README.md): file, dims,
/// type, spacing.
const SHARED: &[(&str, [usize; 3], ScalarType, [f64; 3])] = &[
    (
        "cthead.nrrd",
        [256, 256, 113],
        ScalarType::U16,
        [1.0, 1.0, 2.0],
    ),
    (
        "headsq_quarter.nrrd",
        [64, 64, 93],
        ScalarType::I16,
        [3.2, 3.2, 1.5],
    ),
    (
        "engine.nrrd",
        [256, 256, 128],
        ScalarType::U8,
        [1.0, 1.0, 1.0],
    ),
    (
        "bonsai.nrrd",
        [256, 256, 256],
        ScalarType::U8,
        [1.0, 1.0, 1.0],
    ),
    (
        "stent_ct.nrrd",
        [128, 128, 256],
        ScalarType::I16,
        [1.0, 1.0, 1.0],
    ),
    (
        "lidc_chest_ct.nrrd",
        [256, 256, 133],
        ScalarType::U8,
        [1.40625, 1.40625, 2.5],
    ),
    (
        "mni152_2009a_gm.nrrd",
        [197, 233, 189],
        ScalarType::U8,
        [1.0, 1.0, 1.0],
    ),
    (
        "hydrogen.nrrd",
        [64, 64, 64],
        ScalarType::F32,
        [1.0, 1.0, 1.0],
    ),
    ("neghip.nrrd", [66, 66, 66], ScalarType::U8, [1.0, 1.0, 1.0]),
    ("fuel.nrrd", [64, 33, 32], ScalarType::U8, [1.0, 1.0, 1.0]),
    (
        "carotid.nrrd",
        [76, 49, 45],
        ScalarType::F32,
        [1.0, 1.0, 1.0],
    ),
    ("bolt.nrrd", [70, 123, 66], ScalarType::U8, [1.0, 1.0, 1.0]),
    (
        "frog_tissues.nrrd",
        [500, 470, 136],
        ScalarType::U8,
        [1.0, 1.0, 1.5],
    ),
    (
        "sdf_bunny_128.nrrd",
        [128, 128, 128],
        ScalarType::F32,
        [0.001373, 0.001373, 0.001373],
    ),
    (
        "mayavi_heart.nrrd",
        [32, 32, 12],
        ScalarType::F32,
        [1.0, 1.0, 4.0],
    ),
    (
        "ironprot.nrrd",
        [68, 68, 68],
        ScalarType::U8,
        [1.0, 1.0, 1.0],
    ),
];

/// Loads `path` as NRRD and checks it against the table row.
fn check_shared(path: &Path, dims: [usize; 3], scalar: ScalarType, spacing: [f64; 3]) {
    let volume = volume::nrrd::open(path).unwrap();
    let grid = *volume.grid();
    assert_eq!(grid.dims, dims, "{}", path.display());
    assert_eq!(volume.scalar(), scalar, "{}", path.display());
    for (got, want) in grid.spacing.iter().zip(spacing) {
        assert!(
            (got - want).abs() < 1e-9 * want,
            "{}: spacing {:?}",
            path.display(),
            grid.spacing
        );
    }
    assert_eq!(grid.origin, [0.0; 3]);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in read_all(&volume) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    assert!(lo < hi, "{}: constant volume", path.display());
}

#[test]
fn shared_real_volumes_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    if !dir.is_dir() {
        println!("skipped: {} is absent", dir.display());
        return;
    }
    for &(name, dims, scalar, spacing) in SHARED {
        check_shared(&dir.join(name), dims, scalar, spacing);
    }
}

#[test]
fn bundled_demo_volume_loads() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/headsq_quarter.nrrd");
    check_shared(&path, [64, 64, 93], ScalarType::I16, [3.2, 3.2, 1.5]);
}

#[test]
fn scalar_names_and_numpy_descrs() {
    for t in ScalarType::ALL {
        assert_eq!(ScalarType::from_name(t.name()), Some(t));
        assert_eq!(t.name().parse::<ScalarType>().unwrap(), t);
        let code = numpy_code(t);
        assert_eq!(
            ScalarType::from_numpy_descr(&format!("<{code}")),
            Some((t, Endian::Little))
        );
        assert_eq!(
            ScalarType::from_numpy_descr(&format!(">{code}")),
            Some((t, Endian::Big))
        );
    }
    assert_eq!(
        ScalarType::from_numpy_descr("|u1"),
        Some((ScalarType::U8, Endian::Little))
    );
    assert_eq!(ScalarType::from_name("float"), Some(ScalarType::F32));
    assert_eq!(ScalarType::from_name("int64"), Some(ScalarType::I64));
    assert_eq!(ScalarType::from_name("half"), Some(ScalarType::F16));
    assert_eq!(ScalarType::from_name("u128"), None);
    // A numpy bool is its bytes, 0 and 1: read as u8.
    assert_eq!(
        ScalarType::from_numpy_descr("|b1"),
        Some((ScalarType::U8, Endian::Little))
    );
    assert_eq!(ScalarType::from_numpy_descr("<c8"), None);
    assert_eq!(ScalarType::from_numpy_descr(""), None);
    assert!("int128"
        .parse::<ScalarType>()
        .unwrap_err()
        .to_string()
        .contains("u8, i8"));
    assert_eq!(ScalarType::F64.size(), 8);
}

#[test]
fn decode_is_exact_and_keeps_nan() {
    let bytes: Vec<u8> = [u32::MAX, 0, 16_777_217]
        .iter()
        .flat_map(|v| v.to_be_bytes())
        .collect();
    let mut out = [0.0; 3];
    volume::decode_samples(ScalarType::U32, Endian::Big, &bytes, &mut out);
    assert_eq!(out, [4_294_967_295.0, 0.0, 16_777_217.0]);

    let nan = f32::NAN.to_le_bytes();
    let mut one = [0.0];
    volume::decode_samples(ScalarType::F32, Endian::Little, &nan, &mut one);
    assert!(one[0].is_nan());

    // Every second sample of a strided run.
    let bytes = [1u8, 0, 2, 0, 3, 0];
    let mut out = [0.0; 3];
    volume::decode_strided(ScalarType::U8, Endian::Little, &bytes, 0, 2, &mut out);
    assert_eq!(out, [1.0, 2.0, 3.0]);
}

/// Lent planes (memory-mapped samples used as stored) hold the same values
/// as `read_plane`, for every type and alignment; planes that cannot be
/// lent (foreign byte order) are not; and an extraction gives the same mesh
/// either way.
#[test]
fn lent_planes_match_read_planes_and_give_the_same_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [9usize, 7, 5];
    for scalar in ScalarType::ALL {
        // A blob with a few extremes first (NaN, infinities for floats).
        let value = |i: usize| {
            let [x, y, z] = [i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1])];
            let r =
                ((x as f64 - 4.0).powi(2) + (y as f64 - 3.0).powi(2) + (z as f64 - 2.0).powi(2))
                    .sqrt();
            if i < 5 {
                sample_value(scalar, i)
            } else {
                (r * 20.0).round()
            }
        };
        let mut lent_paths = Vec::new();
        for (header, endian) in [
            (0u64, Endian::native()),
            (1, Endian::native()),
            (0, Endian::Big),
        ] {
            let name = format!("v{header}{endian:?}.raw");
            let raw = raw_volume(dir.path(), &name, (dims, scalar, endian, header), value);
            let what = format!("{scalar:?} header {header} {endian:?}");
            // Planes are lent at any alignment (misaligned ones as byte
            // arrays: `LentPlane::U16Bytes` ...) and in either byte order
            // (foreign ones swapped as read: `LentPlane::U16Swapped` ...).
            let mut plane = vec![0.0; dims[0] * dims[1]];
            for z in 0..dims[2] {
                raw.read_plane(z, &mut plane).unwrap();
                match raw.lend_plane(z) {
                    Some(lent) => {
                        let got: Vec<f64> = (0..lent.len()).map(|i| lent.get(i)).collect();
                        assert_same(&got, &plane, &what);
                    }
                    // The types read as f64 lend nothing.
                    None if !scalar.is_lent() => {}
                    None => panic!("{what}: did not lend plane {z}"),
                }
            }
            lent_paths.push((raw, what));
        }
        let params = tmc::ExtractParams {
            iso: 30.5,
            threads: 1,
            ..Default::default()
        };
        let meshes: Vec<_> = lent_paths
            .iter()
            .map(|(raw, what)| (tmc::extract(raw, &params).unwrap().0, what))
            .collect();
        assert!(!meshes[0].0.triangles.is_empty(), "{scalar:?}: empty mesh");
        for (mesh, what) in &meshes[1..] {
            assert_eq!(mesh, &meshes[0].0, "{what}: mesh differs from the lent one");
        }
    }
}
