//! Element headers of a DICOM data set read one at a time, with the
//! position and the size of the input known: the reader `lengths.rs`
//! walks a file with, seeking over values instead of reading them.

use dicom_core::dictionary::{DataDictionary, VirtualVr};
use dicom_core::{Tag, VR};
use dicom_dictionary_std::StandardDataDictionary;
use std::io::{Read, Seek};

/// How the data set after the meta group is encoded.
#[derive(Clone, Copy)]
pub(super) struct Encoding {
    pub(super) explicit_vr: bool,
    pub(super) big_endian: bool,
}

/// A reader of element headers that knows its position and the file size.
pub(super) struct Walker<R> {
    pub(super) input: R,
    pub(super) pos: u64,
    pub(super) size: u64,
    /// What `size` is the size of, for messages.
    pub(super) what: &'static str,
}

impl<R: Read + Seek> Walker<R> {
    /// Reads `N` bytes; `None` at the end of the file.
    pub(super) fn bytes<const N: usize>(&mut self) -> Option<[u8; N]> {
        let mut b = [0u8; N];
        self.input.read_exact(&mut b).ok()?;
        self.pos += N as u64;
        Some(b)
    }

    pub(super) fn u16(&mut self, big: bool) -> Option<u16> {
        let b = self.bytes::<2>()?;
        Some(if big {
            u16::from_be_bytes(b)
        } else {
            u16::from_le_bytes(b)
        })
    }

    pub(super) fn u32(&mut self, big: bool) -> Option<u32> {
        let b = self.bytes::<4>()?;
        Some(if big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    /// Checks that a value of `len` bytes starting here fits in the file.
    pub(super) fn fits(&self, tag: Tag, len: u32) -> Result<(), String> {
        let left = self.size.saturating_sub(self.pos);
        if u64::from(len) > left {
            return Err(format!(
                "not a readable DICOM file: element ({:04X},{:04X}) at byte {} claims {len} bytes, but only {left} are left in {} (damaged or truncated)",
                tag.0, tag.1, self.pos, self.what
            ));
        }
        Ok(())
    }

    /// Seeks over a value of `len` bytes (already checked to fit).
    pub(super) fn skip(&mut self, len: u32) -> Option<()> {
        self.input.seek_relative(i64::from(len)).ok()?;
        self.pos += u64::from(len);
        Some(())
    }

    /// One element header: tag, VR (explicit only) and length.
    pub(super) fn header(&mut self, enc: Encoding) -> Option<(Tag, Option<VR>, u32)> {
        let big = enc.big_endian;
        let tag = Tag(self.u16(big)?, self.u16(big)?);
        // Items and delimiters have no VR in any encoding.
        if tag.0 == 0xFFFE || !enc.explicit_vr {
            return Some((tag, None, self.u32(big)?));
        }
        // As the parser reads it: an unknown VR is UN, and only the VRs
        // below have a 2-byte length; all others a reserved field and 4 bytes.
        let code = self.bytes::<2>()?;
        let vr = VR::from_binary(code).unwrap_or(VR::UN);
        let short = matches!(
            vr,
            VR::AE
                | VR::AS
                | VR::AT
                | VR::CS
                | VR::DA
                | VR::DS
                | VR::DT
                | VR::FL
                | VR::FD
                | VR::IS
                | VR::LO
                | VR::LT
                | VR::PN
                | VR::SH
                | VR::SL
                | VR::SS
                | VR::ST
                | VR::TM
                | VR::UI
                | VR::UL
                | VR::US
        );
        let len = if short {
            u32::from(self.u16(big)?)
        } else {
            self.bytes::<2>()?;
            self.u32(big)?
        };
        let vr = Some(vr);
        Some((tag, vr, len))
    }
}

/// Is the value of `tag` (with explicit VR `vr`, if any) a sequence, whose
/// items hold elements to check rather than bytes to skip?
pub(super) fn is_sequence(tag: Tag, vr: Option<VR>) -> bool {
    match vr {
        Some(vr) => vr == VR::SQ,
        None => StandardDataDictionary
            .by_tag(tag)
            .is_some_and(|e| e.vr == VirtualVr::Exact(VR::SQ)),
    }
}
