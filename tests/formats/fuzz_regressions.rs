//! Inputs the fuzzers (`scripts/fuzz`, `fuzz/`) found to crash a reader,
//! kept in `tests/data/fuzz/`, and a deflate bomb made here: each must now
//! give one clear error line.

use crate::common;

use common::formats::{data_dir, open_err};
use std::path::Path;

/// A TIFF tag claiming 2^31 values in a 3 KB file made the decoder reserve
/// 32 GiB (the reader had lifted the decoder's limits) and abort.
#[test]
fn tiff_tag_with_a_huge_count_is_an_error() {
    let e = open_err(&data_dir().join("fuzz/tiff_huge_tag_count.tif"));
    assert!(e.contains("tiff_huge_tag_count.tif"), "{e}");
}

/// An implicit VR slice whose `RescaleIntercept` claims 0xFFFFFFF0 bytes in
/// an 824-byte file made the DICOM parser allocate and zero-fill 4 GiB
/// (4.5 s, 4.2 GB peak) before its error. The element lengths are now
/// checked against the file size first: the error names the element, comes
/// at once and fits under a 1 GiB address-space limit (where the old
/// allocation aborted).
#[test]
fn dicom_element_longer_than_the_file_fails_fast() {
    let fuzz = data_dir().join("fuzz/dicom_huge_element_length.dcm");
    dicom_fails_fast(&fuzz, &["(0028,1052)", "4294967280"]);
}

/// A 539-byte slice whose meta group (by its group length) holds a foreign
/// tag and then (0002,0013) with an unknown VR, which the parser reads like
/// UN, with a 4-byte length of 0xFF595000: 3.5 s and 4.2 GB before the
/// parser's error. The length check now walks the meta group as the parser
/// does.
#[test]
fn dicom_meta_element_with_an_unknown_vr_fails_fast() {
    let fuzz = data_dir().join("fuzz/dicom_meta_unknown_vr.dcm");
    dicom_fails_fast(&fuzz, &["(0002,0013)", "4284043264"]);
}

/// `tmc extract` of a copy of `source` fails, under a 1 GiB address-space
/// limit and a 10 s CPU-time limit (resource bounds, not a timing: a run
/// that exceeds either is killed or fails to allocate, and then does not
/// give the expected line), with one line naming the file and holding each
/// of `expected`, and writes nothing.
fn dicom_fails_fast(source: &Path, expected: &[&str]) {
    use common::cli::{assert_one_line, s, tmc_path};
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("slice.dcm");
    std::fs::copy(source, &input).unwrap();
    let out_path = dir.path().join("out.ply");
    let args = [
        tmc_path(),
        "extract",
        s(&input),
        "--iso",
        "0",
        "-o",
        s(&out_path),
    ];
    let limited = Command::new("prlimit")
        .args(["--as=1073741824", "--cpu=10", "--"])
        .args(args)
        .output();
    let out = match limited {
        Ok(out) => out,
        Err(_) => {
            eprintln!("prlimit not found: running without the resource limits");
            Command::new(args[0]).args(&args[1..]).output().unwrap()
        }
    };
    let e = assert_one_line(&out, 1);
    assert!(
        e.contains("slice.dcm") && expected.iter().all(|x| e.contains(x)),
        "{e}"
    );
    assert!(!out_path.exists());
}

/// A deflated DICOM data set (transfer syntax 1.2.840.10008.1.2.1.99) of
/// 1.25 GiB in a 1.3 MB file: the length walk inflated it twice and the
/// parser then held it in memory. It is now refused once it inflates past
/// `inflate_cap` (256 MiB for a small file), in one streaming pass.
#[test]
fn a_deflate_bomb_fails_fast() {
    let dir = tempfile::tempdir().unwrap();
    let bomb = dir.path().join("bomb.dcm");
    std::fs::write(&bomb, deflate_bomb(80 << 24)).unwrap();
    dicom_fails_fast(
        &bomb,
        &["deflated data set inflates to more than 268435456 bytes"],
    );
}

/// A deflated DICOM file whose data set is one (0042,0011) OB element of
/// `zeros` zero bytes (a multiple of 16 MiB), deflated to about 1/1000.
fn deflate_bomb(zeros: usize) -> Vec<u8> {
    let syntax = b"1.2.840.10008.1.2.1.99\0";
    let mut file = vec![0u8; 128];
    file.extend_from_slice(b"DICM");
    file.extend_from_slice(&[0x02, 0x00, 0x00, 0x00, b'U', b'L', 4, 0]);
    file.extend_from_slice(&(8 + syntax.len() as u32).to_le_bytes());
    file.extend_from_slice(&[0x02, 0x00, 0x10, 0x00, b'U', b'I']);
    file.extend_from_slice(&(syntax.len() as u16).to_le_bytes());
    file.extend_from_slice(syntax);
    let mut head = vec![0x42, 0x00, 0x11, 0x00, b'O', b'B', 0, 0];
    head.extend_from_slice(&(zeros as u32).to_le_bytes());
    file.extend(flushed(&head));
    file.extend(zeros_deflated(zeros));
    file
}

/// A raw deflate stream of `zeros` zero bytes (a multiple of 16 MiB), about
/// 1/1000 of that.
fn zeros_deflated(zeros: usize) -> Vec<u8> {
    let block = flushed(&vec![0u8; 1 << 24]);
    let mut stream = Vec::with_capacity(block.len() * (zeros >> 24) + 2);
    for _ in 0..zeros >> 24 {
        stream.extend_from_slice(&block);
    }
    // A final, empty block (fixed Huffman codes: the end-of-block code).
    stream.extend_from_slice(&[0x03, 0x00]);
    stream
}

/// `bytes` as deflate blocks ending with a full flush: self-contained and
/// byte aligned, so that copies of them can follow each other (the stream
/// is not final).
fn flushed(bytes: &[u8]) -> Vec<u8> {
    use flate2::{Compress, Compression, FlushCompress};
    let mut c = Compress::new(Compression::best(), false);
    let mut out = Vec::with_capacity(bytes.len() / 100 + 1024);
    c.compress_vec(bytes, &mut out, FlushCompress::Full)
        .unwrap();
    assert_eq!(c.total_in(), bytes.len() as u64);
    out
}

/// A multi-frame file in Deflated Image Frame Compression
/// (1.2.840.10008.1.2.8.1) whose first frame, 9x7 samples of 16 bits (126
/// bytes), is a 1 MB fragment inflating to 1 GiB: the decoder of
/// dicom-transfer-syntax-registry inflates a frame without limit, so it
/// ran out of the 1 GiB address space (an abort). Each frame is now
/// refused once it inflates past its 126 bytes, before the decoder.
#[test]
fn a_deflated_frame_beyond_its_size_fails_fast() {
    use dicom_core::value::{PixelFragmentSequence, Value};
    use dicom_core::{DataElement, VR};
    use dicom_dictionary_std::tags;
    let dir = tempfile::tempdir().unwrap();
    let bomb = dir.path().join("frames.dcm");
    let mut obj = dicom_object::open_file(data_dir().join("dicom_multiframe.dcm")).unwrap();
    let frames: usize = obj
        .element(tags::NUMBER_OF_FRAMES)
        .unwrap()
        .to_int()
        .unwrap();
    let mut fragments = vec![zeros_deflated(1 << 30)];
    let mut small = flushed(&[0; 126]);
    small.extend_from_slice(&[0x03, 0x00]);
    fragments.resize(frames, small);
    let pixels = Value::PixelSequence(PixelFragmentSequence::new_fragments(fragments));
    obj.put(DataElement::new(tags::PIXEL_DATA, VR::OB, pixels));
    let meta = obj.meta_mut();
    meta.transfer_syntax = "1.2.840.10008.1.2.8.1".to_string();
    meta.update_information_group_length();
    obj.write_to_file(&bomb).unwrap();
    dicom_fails_fast(
        &bomb,
        &["frame 1 of its deflated pixel data inflates to more than the 126 bytes of a 9x7 frame at 16 bits"],
    );
}

/// A slice of a fuzzed 3-slice series with RLE pixel data made the RLE
/// decoder of dicom-transfer-syntax-registry 0.9.1 index past its buffer and
/// panic. A panic in a pixel-data decoder is now the error of that file.
#[test]
fn a_panicking_pixel_decoder_is_an_error() {
    let path = data_dir().join("fuzz/dicom_rle_panic/s0.dcm");
    let volume = tmc::volume::open(&path, None).unwrap();
    let plane = volume.grid().plane_len();
    let mut out = vec![0.0; plane];
    let errors: Vec<String> = (0..volume.grid().dims[2])
        .filter_map(|z| volume.read_plane(z, &mut out).err())
        .map(|e| e.to_string())
        .collect();
    assert!(
        errors
            .iter()
            .any(|e| e.contains("s2.dcm") && e.contains("the decoder failed")),
        "{errors:?}"
    );
}
