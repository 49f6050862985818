//! The sample types read as `f64` (i64, u64, f16) and numpy bools, read
//! as u8: the same samples and meshes as the same values in a type the
//! slab loop reads as stored.

use super::readers::{npy_bytes, raw_volume, write_file};
use tmc::volume::{self, Endian, RawOptions, ScalarType};
/// The types read as `f64` (64-bit integers, half floats) give the mesh
/// of the same values stored in a type the slab loop reads as stored,
/// threads 1 and 2, `--close` or not; a numpy bool is read as the u8 of
/// its bytes; 64-bit integers are exact within ±2^53 and round beyond.
#[test]
fn wide_types_give_the_mesh_of_the_same_values_in_a_narrow_type() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [13usize, 11, 9];
    // Integer distances from an off-centre point, with plateaus (ties).
    let value = |i: usize| {
        let [x, y, z] = [i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1])];
        let d = (x as f64 - 6.3).powi(2) + (y as f64 - 5.1).powi(2) + (z as f64 - 3.7).powi(2);
        (d / 3.0).floor()
    };
    let native = Endian::native();
    let other = match native {
        Endian::Little => Endian::Big,
        Endian::Big => Endian::Little,
    };
    for (wide, narrow) in [
        (ScalarType::I64, ScalarType::I32),
        (ScalarType::U64, ScalarType::U32),
        (ScalarType::F16, ScalarType::F32),
    ] {
        let want = raw_volume(dir.path(), "narrow.raw", (dims, narrow, native, 0), value);
        for (endian, header) in [(native, 0), (native, 3), (other, 0)] {
            let got = raw_volume(dir.path(), "wide.raw", (dims, wide, endian, header), value);
            assert_eq!(
                crate::common::formats::all_samples(&got),
                crate::common::formats::all_samples(&want)
            );
            for (iso, threads, close) in [(4.0, 1, false), (4.5, 2, true), (9.0, 2, false)] {
                let params = tmc::ExtractParams {
                    iso,
                    threads,
                    close,
                    ..Default::default()
                };
                let (a, _) = tmc::extract(&got, &params).unwrap();
                let (b, _) = tmc::extract(&want, &params).unwrap();
                assert!(!b.triangles.is_empty());
                assert_eq!(a.vertices, b.vertices, "{wide} {endian:?} {iso}");
                assert_eq!(a.triangles, b.triangles, "{wide} {endian:?} {iso}");
            }
        }
    }
    // 2^53 + 1 is not an f64: it reads as 2^53 (numpy's astype(float64)).
    let mut bytes = Vec::new();
    for v in [(1i64 << 53) + 1, -(1i64 << 53) - 1] {
        bytes.extend(v.to_ne_bytes());
    }
    let path = write_file(dir.path(), "beyond.raw", &bytes);
    let options = RawOptions {
        dims: [2, 1, 1],
        scalar: ScalarType::I64,
        endian: native,
        header_bytes: 0,
        spacing: [1.0; 3],
        origin: [0.0; 3],
    };
    let beyond = volume::RawVolume::open(&path, &options).unwrap();
    let two53 = 9_007_199_254_740_992.0;
    assert_eq!(
        crate::common::formats::all_samples(&beyond),
        [two53, -two53]
    );

    // A bool mask: the same samples as its bytes read as u8.
    let mask: Vec<u8> = (0..dims.iter().product::<usize>())
        .map(|i| u8::from(value(i) < 5.0))
        .collect();
    let shape = format!("({}, {}, {})", dims[2], dims[1], dims[0]);
    let as_bool = write_file(
        dir.path(),
        "mask.npy",
        &npy_bytes(
            1,
            &format!("{{'descr': '|b1', 'fortran_order': False, 'shape': {shape}, }}"),
            &mask,
        ),
    );
    let as_u8 = write_file(
        dir.path(),
        "mask_u8.npy",
        &npy_bytes(
            1,
            &format!("{{'descr': '|u1', 'fortran_order': False, 'shape': {shape}, }}"),
            &mask,
        ),
    );
    let a = volume::npy::open(&as_bool).unwrap();
    let b = volume::npy::open(&as_u8).unwrap();
    assert_eq!(a.scalar(), ScalarType::U8);
    assert_eq!(
        crate::common::formats::all_samples(&a),
        crate::common::formats::all_samples(&b)
    );
}
