//! DICOM series reader against fixtures written by pydicom
//! (`scripts/fixtures/make_dicom.py`): geometry (slices sorted by position
//! along the normal, PixelSpacing order, orientation), samples after the
//! per-slice rescale, meshes equal to those of the `.npy` twins mapped by the
//! full affine, and one clear error per bad series.

mod clinical;
mod segmentation;
use crate::common;

use common::formats::{check_grid, data_dir, fixtures, open_err, samples_in_order};
use dicom_core::{DataElement, PrimitiveValue, VR};
use dicom_dictionary_std::tags;
use dicom_object::Tag;
use std::fs;
use std::path::{Path, PathBuf};
use tmc::volume::{self, dicom};
use tmc::{ExtractParams, SampleSource};

#[test]
fn manifest_lists_every_kind() {
    let names: Vec<String> = fixtures("dicom_manifest.json")
        .into_iter()
        .map(|f| f.name)
        .collect();
    for want in [
        "dicom_ct",
        "dicom_shuffled",
        "dicom_oblique",
        "dicom_implicit_u8",
        "dicom_big_endian",
        "dicom_rle",
        "dicom_enhanced",
        "dicom_multiframe",
    ] {
        assert!(names.iter().any(|n| n == want), "no {want} in {names:?}");
    }
}

#[test]
fn fixtures_match_their_npy_twins() {
    for f in fixtures("dicom_manifest.json") {
        let vol = volume::open(&f.file, None).unwrap_or_else(|e| panic!("{}: {e}", f.name));
        let twin = data_dir().join(format!("{}.expected.npy", f.name));
        let npy = volume::open(&twin, None).unwrap();
        let grid = *vol.grid();
        check_grid(&grid, &f, 1e-9, 1e-9);
        assert_eq!(npy.grid().dims, f.dims, "{}", f.name);

        let nz = grid.dims[2];
        let forward: Vec<usize> = (0..nz).collect();
        let scrambled: Vec<usize> = (0..nz).map(|k| (k * 5 + 3) % nz).collect();
        let want = samples_in_order(npy.as_ref(), &forward);
        assert_eq!(
            samples_in_order(vol.as_ref(), &forward),
            want,
            "{}: samples differ",
            f.name
        );
        assert_eq!(
            samples_in_order(vol.as_ref(), &scrambled),
            want,
            "{}: samples differ when read out of order",
            f.name
        );

        // Same mesh once the full index-to-world map is applied.
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
        let extent = grid
            .world([0.0; 3])
            .iter()
            .fold(1.0f64, |m, v| m.max(v.abs()));
        for (v, w) in mesh.vertices.iter().zip(&mesh_npy.vertices) {
            let mapped = grid.world(w.map(f64::from));
            for i in 0..3 {
                assert!(
                    (f64::from(v[i]) - mapped[i]).abs() <= 1e-5 * extent,
                    "{}: vertex {v:?} vs {w:?} mapped {mapped:?}",
                    f.name
                );
            }
        }
    }
}

#[test]
fn slices_are_sorted_by_position_not_name() {
    let s = dicom::open(&data_dir().join("dicom_shuffled")).unwrap();
    assert_eq!(s.sample_bytes(), 2);
    // Each file holds its own rescale; sorted by position they are these.
    let want = [
        (1.0, 0.0),
        (2.0, -10.0),
        (0.5, 3.0),
        (1.0, -7.0),
        (4.0, 1.5),
        (0.25, 0.0),
    ];
    for (z, w) in want.iter().enumerate() {
        assert_eq!(s.rescale(z), Some(*w), "plane {z}");
    }
    let names: Vec<String> = (0..6)
        .map(|z| {
            let file = s.plane_file(z).unwrap().file_name().unwrap();
            file.to_string_lossy().to_string()
        })
        .collect();
    let mut by_name = names.clone();
    by_name.sort();
    assert_ne!(names, by_name, "name order happens to be position order");
    assert!(s.series_uid().starts_with("1.2.826.0.1.3680043.8.498"));
}

#[test]
fn one_slice_file_opens_its_series() {
    let dir = data_dir().join("dicom_oblique");
    let whole = dicom::open(&dir).unwrap();
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let one = volume::open(&files[2], None).unwrap();
    assert_eq!(one.grid(), whole.grid());
    // A file of one of two series selects that series.
    let two = data_dir().join("dicom_bad_two_series");
    let s = volume::open(&two.join("other_0.dcm"), None).unwrap();
    assert_eq!(s.grid().dims, [3, 2, 3]);
    let s = volume::open(&two.join("slice_000.dcm"), None).unwrap();
    assert_eq!(s.grid().dims, [3, 2, 2]);
}

#[test]
fn a_series_can_be_chosen_by_uid() {
    let two = data_dir().join("dicom_bad_two_series");
    let uid = "1.2.826.0.1.3680043.8.498.7777.32";
    let s = dicom::open_series(&two, Some(uid)).unwrap();
    assert_eq!(s.series_uid(), uid);
    assert_eq!(s.grid().dims, [3, 2, 3]);
    let e = dicom::open_series(&two, Some("1.2.3"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("no DICOM series 1.2.3"), "{e}");
}

#[test]
fn bad_series_are_errors() {
    let e = open_err(&data_dir().join("dicom_bad_gap"));
    assert!(
        e.contains("slice gap 2.5 mm between positions 2.5 and 5 differs from the usual 1.25 mm"),
        "{e}"
    );
    assert!(e.contains("missing slice"), "{e}");

    // A slice of another size is left out, with a note.
    let s = dicom::open(&data_dir().join("dicom_bad_rows")).unwrap();
    assert_eq!(s.grid().dims, [3, 2, 3]);
    assert_left_out(
        &s,
        "slice_003.dcm: left out: 3x3 slice (Columns x Rows) differs from the 3x2",
    );

    let e = open_err(&data_dir().join("dicom_bad_two_series"));
    assert!(e.contains("2 DICOM series in one directory"), "{e}");
    assert!(
        e.contains("1.2.826.0.1.3680043.8.498.7777.31 (CT, 2 files)"),
        "{e}"
    );
    assert!(
        e.contains("1.2.826.0.1.3680043.8.498.7777.32 (CT, 3 files)"),
        "{e}"
    );
    assert!(e.contains("--series"), "{e}");

    // JPEG 2000 is decoded now; this file's code stream is damaged.
    let vol = volume::open(&data_dir().join("dicom_bad_j2k"), None).unwrap();
    let mut plane = vec![0.0; vol.grid().plane_len()];
    let e = vol.read_plane(0, &mut plane).unwrap_err().to_string();
    assert!(e.contains("j2k.dcm: cannot decode the pixel data"), "{e}");
    assert!(
        e.contains("(transfer syntax JPEG 2000 Image Compression (Lossless Only) (1.2.840.10008.1.2.4.90))"),
        "{e}"
    );
    assert!(e.contains("gdcmconv --raw"), "{e}");
}

/// A transfer syntax tmc has no decoder for is refused at open in one line
/// that names it (name and UID) and says how to decompress the files;
/// a series of many such files names the first and counts the others.
#[test]
fn unsupported_transfer_syntaxes_are_named_with_what_to_do() {
    let e = open_err(&data_dir().join("dicom_bad_jpegls"));
    assert!(
        e.contains(".dcm: transfer syntax JPEG-LS Lossless Image Compression (1.2.840.10008.1.2.4.80) is not supported"),
        "{e}"
    );
    assert_eq!(e.matches("jpegls_").count(), 1, "{e}");
    assert!(e.contains("'gdcmconv --raw IN.dcm OUT.dcm'"), "{e}");
    assert!(e.contains("'dcmdjpls IN.dcm OUT.dcm'"), "{e}");
    assert!(e.contains("and 2 more files not read"), "{e}");
    let one = open_err(&data_dir().join("dicom_bad_jpegls/jpegls_1.dcm"));
    assert!(one.contains("JPEG-LS Lossless"), "{one}");

    // A syntax no registry knows: the parser fails, the meta group says why.
    let e = open_err(&data_dir().join("dicom_bad_syntax/private.dcm"));
    assert!(
        e.contains(
            "transfer syntax 1.2.826.0.1.3680043.8.498.7777.99.1 (unknown) is not supported"
        ),
        "{e}"
    );
    assert!(e.contains("gdcmconv --raw"), "{e}");
}

/// HTJ2K (lossless, written by OpenJPH) is decoded by the JPEG 2000
/// decoder: the samples equal the twin's.
#[test]
fn htj2k_is_decoded() {
    let vol = volume::open(&data_dir().join("dicom_htj2k"), None).unwrap();
    let npy = volume::open(&data_dir().join("dicom_htj2k.expected.npy"), None).unwrap();
    assert_eq!(vol.grid().dims, [9, 7, 6]);
    assert_eq!(vol.grid().spacing, [1.0, 1.0, 2.0]);
    let order: Vec<usize> = (0..6).collect();
    let got = samples_in_order(vol.as_ref(), &order);
    assert_eq!(got, samples_in_order(npy.as_ref(), &order));
    assert!(got.iter().any(|&v| v > 60000.0), "the high bits are used");
}

/// A copy of fixture directory `name` in a temporary directory.
fn copy_series(name: &str) -> tempfile::TempDir {
    let tmp = tempfile::tempdir().unwrap();
    for entry in fs::read_dir(data_dir().join(name)).unwrap() {
        let path = entry.unwrap().path();
        fs::copy(&path, tmp.path().join(path.file_name().unwrap())).unwrap();
    }
    tmp
}

#[test]
fn damaged_series_are_errors() {
    // A file with the magic that does not parse is skipped, and named.
    let tmp = copy_series("dicom_ct");
    let mut bytes = vec![0u8; 128];
    bytes.extend_from_slice(b"DICM\x02\x00\x00\x00garbage");
    fs::write(tmp.path().join("broken"), &bytes).unwrap();
    let s = dicom::open(tmp.path()).unwrap();
    assert_eq!(s.grid().dims, [9, 7, 6]);
    assert_left_out(&s, "broken: not a readable DICOM file");
    // Opened alone it is an error about itself.
    let e = open_err(&tmp.path().join("broken"));
    assert!(e.contains("broken: not a readable DICOM file"), "{e}");

    // A copy of a slice (the same SOPInstanceUID) counts once.
    let tmp = copy_series("dicom_ct");
    fs::copy(
        tmp.path().join("slice_002.dcm"),
        tmp.path().join("copy_of_2.dcm"),
    )
    .unwrap();
    let s = dicom::open(tmp.path()).unwrap();
    assert_eq!(s.grid().dims, [9, 7, 6]);
    assert_left_out(&s, "(the same SOPInstanceUID)");

    // Two images (other SOPInstanceUIDs) at one position.
    edit_file(tmp.path(), "copy_of_2.dcm", |o| {
        o.put(DataElement::new(
            tags::SOP_INSTANCE_UID,
            VR::UI,
            PrimitiveValue::from("1.2.3.4.5.6.7"),
        ));
    });
    let e = open_err(tmp.path());
    assert!(e.contains("two slices at the same position"), "{e}");

    // Too few bytes: truncated pixel data.
    let tmp = copy_series("dicom_ct");
    let path = tmp.path().join("slice_004.dcm");
    let bytes = fs::read(&path).unwrap();
    fs::write(&path, &bytes[..bytes.len() - 40]).unwrap();
    let result = volume::open(tmp.path(), None).and_then(|v| {
        let mut plane = vec![0.0; v.grid().plane_len()];
        (0..v.grid().dims[2]).try_for_each(|z| v.read_plane(z, &mut plane))
    });
    let e = result.unwrap_err().to_string();
    assert!(e.contains("slice_004.dcm"), "{e}");
    assert!(!e.contains('\n'), "{e}");

    // An empty directory is not DICOM: it goes to the TIFF reader; a
    // directory with only non-DICOM files is not a DICOM series either.
    let tmp = tempfile::tempdir().unwrap();
    fs::write(tmp.path().join("README"), b"hello").unwrap();
    assert!(!dicom::dir_has_dicom(tmp.path()));
    let e = dicom::open(tmp.path()).unwrap_err().to_string();
    assert!(e.contains("no DICOM image files found"), "{e}");
}

/// The frames of a multi-frame file come from one parse of it (the file
/// was parsed whole for every frame: a 256-frame file of 33 MB took 6 s):
/// once a frame is read, the others are read from that parse, even if
/// the file is then overwritten.
#[test]
fn multi_frame_files_are_parsed_once() {
    for name in ["dicom_multiframe", "dicom_enhanced"] {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join(format!("{name}.dcm"));
        fs::copy(data_dir().join(format!("{name}.dcm")), &path).unwrap();
        let vol = volume::open(&path, None).unwrap();
        let npy = volume::open(&data_dir().join(format!("{name}.expected.npy")), None).unwrap();
        let grid = *vol.grid();
        let (n, nz) = (grid.plane_len(), grid.dims[2]);
        let mut plane = vec![0.0; n];
        vol.read_plane(nz - 1, &mut plane).unwrap();
        fs::write(&path, b"not DICOM any more").unwrap();
        let order: Vec<usize> = (0..nz).rev().collect();
        assert_eq!(
            samples_in_order(vol.as_ref(), &order),
            samples_in_order(npy.as_ref(), &order),
            "{name}"
        );
        // A source opened afresh sees the new bytes.
        assert!(volume::open(&path, None).is_err(), "{name}");
    }
}

#[test]
fn non_dicom_files_are_skipped() {
    let dir = data_dir().join("dicom_shuffled");
    assert!(dir.join("README").exists());
    assert!(!dicom::has_magic(&dir.join("README")));
    assert!(dicom::dir_has_dicom(&dir));
    assert_eq!(dicom::open(&dir).unwrap().grid().dims, [9, 7, 6]);
}

/// Rewrites file `name` of directory `dir` after `edit`.
fn edit_file(dir: &Path, name: &str, edit: impl FnOnce(&mut dicom_object::DefaultDicomObject)) {
    let path = dir.join(name);
    let mut obj = dicom_object::open_file(&path).unwrap();
    edit(&mut obj);
    obj.write_to_file(&path).unwrap();
}

fn put_ds(obj: &mut dicom_object::DefaultDicomObject, tag: Tag, text: &str) {
    obj.put(DataElement::new(tag, VR::DS, PrimitiveValue::from(text)));
}

#[test]
fn image_sizes_beyond_the_pixel_data_are_refused_before_reading() {
    // Rows x Columns or NumberOfFrames far beyond the pixel data: one
    // error from the header, not an allocation of gigabytes (an abort).
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_002.dcm", |o| {
        for tag in [tags::ROWS, tags::COLUMNS] {
            o.put(DataElement::new(
                tag,
                VR::US,
                PrimitiveValue::from(65535u16),
            ));
        }
    });
    let e = open_err(tmp.path());
    assert!(
        e.contains("slice_002.dcm: damaged image header: 126 bytes of pixel data, but 1 frame(s) of 65535x65535 at 16 bits need 8589672450"),
        "{e}"
    );
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_004.dcm", |o| {
        o.put(DataElement::new(
            tags::NUMBER_OF_FRAMES,
            VR::IS,
            PrimitiveValue::from("2147483647"),
        ));
    });
    let e = open_err(tmp.path());
    assert!(
        e.contains(
            "slice_004.dcm: damaged image header: 126 bytes of pixel data, but 2147483647 frame(s)"
        ),
        "{e}"
    );
}

#[test]
fn inconsistent_headers_are_errors() {
    // No ImagePositionPatient.
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_003.dcm", |o| {
        o.remove_element(tags::IMAGE_POSITION_PATIENT);
    });
    let e = open_err(tmp.path());
    assert!(e.contains("slice_003.dcm: no ImagePositionPatient"), "{e}");

    // Colour samples: the slice is left out, and the gap it leaves says so.
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_001.dcm", |o| {
        o.put(DataElement::new(
            tags::SAMPLES_PER_PIXEL,
            VR::US,
            PrimitiveValue::from(3u16),
        ));
    });
    let e = open_err(tmp.path());
    assert!(e.contains("3 samples per pixel"), "{e}");

    // Another BitsAllocated (8: the 16-bit pixel data holds enough bytes).
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_005.dcm", |o| {
        o.put(DataElement::new(
            tags::BITS_ALLOCATED,
            VR::US,
            PrimitiveValue::from(8u16),
        ));
        o.put(DataElement::new(
            tags::BITS_STORED,
            VR::US,
            PrimitiveValue::from(8u16),
        ));
    });
    let s = dicom::open(tmp.path()).unwrap();
    assert_eq!(s.grid().dims, [9, 7, 5]);
    assert_left_out(&s, "slice_005.dcm: left out: sample type (8 bits allocated");

    // BitsAllocated 32 over 16-bit pixel data: too few bytes, refused from
    // the header before any plane is read (and the slice left out).
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_005.dcm", |o| {
        o.put(DataElement::new(
            tags::BITS_ALLOCATED,
            VR::US,
            PrimitiveValue::from(32u16),
        ));
    });
    let s = dicom::open(tmp.path()).unwrap();
    assert_eq!(s.grid().dims, [9, 7, 5]);
    assert_left_out(&s, "slice_005.dcm: damaged image header: 126 bytes of pixel data, but 1 frame(s) of 9x7 at 32 bits need 252");

    // Another orientation.
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_002.dcm", |o| {
        put_ds(o, tags::IMAGE_ORIENTATION_PATIENT, "0\\1\\0\\1\\0\\0");
    });
    let e = open_err(tmp.path());
    assert!(e.contains("ImageOrientationPatient"), "{e}");
    assert!(e.contains("differs from"), "{e}");

    // A slice shifted sideways (gantry tilt).
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_004.dcm", |o| {
        put_ds(o, tags::IMAGE_POSITION_PATIENT, "-19\\15\\15");
    });
    let e = open_err(tmp.path());
    assert!(e.contains("not stacked along their normal"), "{e}");

    // Another pixel spacing.
    let tmp = copy_series("dicom_ct");
    edit_file(tmp.path(), "slice_000.dcm", |o| {
        put_ds(o, tags::PIXEL_SPACING, "0.6\\0.8");
    });
    let s = dicom::open(tmp.path()).unwrap();
    assert_eq!(s.grid().dims, [9, 7, 5]);
    assert_left_out(&s, "slice_000.dcm: left out: PixelSpacing");
}

/// `series` left out (or skipped) a file with a note containing `words`.
fn assert_left_out(series: &dicom::DicomSeries, words: &str) {
    assert!(
        series.skipped().iter().any(|n| n.contains(words)),
        "no note with {words:?} in {:?}",
        series.skipped()
    );
}

#[test]
fn jpeg_baseline_is_decoded() {
    // Lossy: the decoded samples approximate the encoded ones.
    let vol = volume::open(&data_dir().join("dicom_jpeg"), None).unwrap();
    let npy = volume::open(&data_dir().join("dicom_jpeg.expected.npy"), None).unwrap();
    let grid = *vol.grid();
    assert_eq!(grid.dims, [9, 7, 6]);
    assert_eq!(grid.spacing, [1.0, 1.0, 2.0]);
    let order: Vec<usize> = (0..6).rev().collect();
    let got = samples_in_order(vol.as_ref(), &order);
    let want = samples_in_order(npy.as_ref(), &order);
    let worst = got
        .iter()
        .zip(&want)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst <= 12.0, "JPEG samples off by {worst}");
    let mean = got.iter().sum::<f64>() / got.len() as f64;
    let mean_want = want.iter().sum::<f64>() / want.len() as f64;
    assert!((mean - mean_want).abs() < 2.0, "{mean} vs {mean_want}");
}
