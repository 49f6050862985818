//! What tmc says of a file's transfer syntax when it cannot read the pixel
//! data: the syntax by name and UID, and what to do about it.
//!
//! A compressed syntax tmc has no decoder for (JPEG-LS, JPEG XL, a UID the
//! registry does not know) is refused at open; pixel data a decoder fails
//! on (damaged, or a codec feature the pure-Rust decoders lack) fails when
//! its plane is read. Either way the user's way out is the same: decompress
//! the files with a DICOM toolkit and read those, so both messages name the
//! syntax and a command that does it.

use dicom_encoding::TransferSyntaxIndex;
use dicom_object::meta::FileMetaTable;
use dicom_transfer_syntax_registry::TransferSyntaxRegistry;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// The compressed syntaxes tmc decodes, for the messages.
const DECODED: &str =
    "uncompressed, deflate, RLE, JPEG baseline/extended/lossless, JPEG 2000 and HTJ2K";

/// `NAME (UID)` of the transfer syntax `uid`, or `UID (unknown)` when the
/// registry does not know it.
pub(super) fn describe(uid: &str) -> String {
    match TransferSyntaxRegistry.get(uid) {
        Some(ts) => format!("{} ({uid})", ts.name()),
        None => format!("{uid} (unknown)"),
    }
}

/// The refusal of a file whose transfer syntax `uid` tmc cannot decode.
pub(super) fn unsupported(uid: &str) -> String {
    format!(
        "transfer syntax {} is not supported (tmc decodes {DECODED} data); {}",
        describe(uid),
        decompress_hint(uid)
    )
}

/// Why the file at `path`, which did not parse, did not: its file meta
/// group names a transfer syntax whose data set tmc cannot read (one the
/// registry does not know, a private one); `None` when the meta group does
/// not parse or its syntax is known (the parser's error is the reason).
pub(super) fn unreadable(path: &Path) -> Option<String> {
    let mut file = std::fs::File::open(path).ok()?;
    file.seek(SeekFrom::Start(128)).ok()?;
    // The meta group is small; a damaged length cannot make it read more.
    let meta = FileMetaTable::from_reader(file.take(1 << 20)).ok()?;
    let uid = super::lengths::unpadded(meta.transfer_syntax());
    let known = TransferSyntaxRegistry
        .get(uid)
        .is_some_and(|ts| !ts.is_unsupported());
    (!known).then(|| unsupported(uid))
}

/// The error of pixel data in syntax `uid` that its decoder failed on
/// (`reason`: the decoder's words).
pub(super) fn undecodable(uid: &str, reason: &str) -> String {
    format!(
        "cannot decode the pixel data (transfer syntax {}): {reason}; the data may be damaged, or use a feature the decoder lacks: {}",
        describe(uid),
        decompress_hint(uid)
    )
}

/// What to run: decompress with GDCM (any syntax it knows), or the DCMTK
/// tool for the syntax's family where there is one.
fn decompress_hint(uid: &str) -> String {
    let dcmtk = match uid {
        // JPEG baseline, extended, lossless (process 14, SV1).
        "1.2.840.10008.1.2.4.50"
        | "1.2.840.10008.1.2.4.51"
        | "1.2.840.10008.1.2.4.57"
        | "1.2.840.10008.1.2.4.70" => " or DCMTK's 'dcmdjpeg IN.dcm OUT.dcm'",
        // JPEG-LS lossless and near-lossless.
        "1.2.840.10008.1.2.4.80" | "1.2.840.10008.1.2.4.81" => {
            " or DCMTK's 'dcmdjpls IN.dcm OUT.dcm'"
        }
        "1.2.840.10008.1.2.5" => " or DCMTK's 'dcmdrle IN.dcm OUT.dcm'",
        _ => "",
    };
    format!("decompress the files first, e.g. with GDCM's 'gdcmconv --raw IN.dcm OUT.dcm'{dcmtk}, and read those")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_syntax_by_name_and_uid_and_says_what_to_do() {
        let line = unsupported("1.2.840.10008.1.2.4.80");
        assert!(line.contains("JPEG-LS Lossless"), "{line}");
        assert!(line.contains("(1.2.840.10008.1.2.4.80)"), "{line}");
        assert!(line.contains("gdcmconv --raw"), "{line}");
        assert!(line.contains("dcmdjpls"), "{line}");
        let line = unsupported("1.2.3.4");
        assert!(line.contains("1.2.3.4 (unknown)"), "{line}");
        let line = undecodable("1.2.840.10008.1.2.4.201", "bad marker");
        assert!(line.contains("High-Throughput JPEG 2000"), "{line}");
        assert!(line.contains("(1.2.840.10008.1.2.4.201)"), "{line}");
        assert!(line.contains("bad marker"), "{line}");
        assert!(line.contains("gdcmconv --raw"), "{line}");
    }
}
