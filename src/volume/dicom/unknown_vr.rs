//! Attributes stored with VR UN (unknown), re-read under the VR the
//! standard's dictionary gives their tag.
//!
//! Some converters and anonymisers write every element of an explicit VR
//! data set as UN; its value is then the bytes the element would have had
//! under its own VR, which the parser leaves as bytes. Before anything reads
//! the data set (tmc's header reading, and the pixel decoder, which reads
//! `Rows`, `BitsAllocated` and the rest itself), each top-level UN element
//! whose tag the dictionary knows is replaced by the same element under its
//! dictionary VR: binary numbers (US, UL, SS, SL, FL, FD) from their
//! little-endian bytes, text (DS, IS, CS, UI ...) from the text of its
//! bytes split at backslashes. Elements of other VRs (sequences, bytes),
//! of unknown tags, and values that do not fit their VR stay as they are.
//! Only little-endian data sets hold UN values read here (the big-endian
//! transfer syntax is retired).

use dicom_core::dictionary::{DataDictionary, VirtualVr};
use dicom_core::header::Header;
use dicom_core::value::{PrimitiveValue, C};
use dicom_core::{DataElement, VR};
use dicom_dictionary_std::StandardDataDictionary;
use dicom_object::InMemDicomObject;

/// Replaces the top-level UN elements of `obj` whose VR the dictionary
/// knows by the same elements under that VR.
pub(super) fn resolve(obj: &mut InMemDicomObject) {
    let fixed: Vec<_> = obj
        .iter()
        .filter(|e| e.vr() == VR::UN)
        .filter_map(|e| {
            let vr = match StandardDataDictionary.by_tag(e.tag())?.vr {
                VirtualVr::Exact(vr) => vr,
                _ => return None,
            };
            let bytes = e.value().to_bytes().ok()?;
            Some(DataElement::new(e.tag(), vr, reread(vr, &bytes)?))
        })
        .collect();
    for e in fixed {
        obj.put(e);
    }
}

/// The value of `bytes` under `vr`, if `vr` is a number or text VR and the
/// bytes fit it.
fn reread(vr: VR, bytes: &[u8]) -> Option<PrimitiveValue> {
    fn numbers<const N: usize, T>(bytes: &[u8], f: fn([u8; N]) -> T) -> Option<C<T>> {
        bytes.len().is_multiple_of(N).then(|| {
            bytes
                .chunks_exact(N)
                .map(|c| f(c.try_into().expect("chunks of N")))
                .collect()
        })
    }
    Some(match vr {
        VR::US => PrimitiveValue::U16(numbers(bytes, u16::from_le_bytes)?),
        VR::UL => PrimitiveValue::U32(numbers(bytes, u32::from_le_bytes)?),
        VR::SS => PrimitiveValue::I16(numbers(bytes, i16::from_le_bytes)?),
        VR::SL => PrimitiveValue::I32(numbers(bytes, i32::from_le_bytes)?),
        VR::FL => PrimitiveValue::F32(numbers(bytes, f32::from_le_bytes)?),
        VR::FD => PrimitiveValue::F64(numbers(bytes, f64::from_le_bytes)?),
        VR::AE
        | VR::AS
        | VR::CS
        | VR::DA
        | VR::DS
        | VR::DT
        | VR::IS
        | VR::LO
        | VR::LT
        | VR::PN
        | VR::SH
        | VR::ST
        | VR::TM
        | VR::UC
        | VR::UI
        | VR::UR
        | VR::UT => {
            let text = std::str::from_utf8(bytes).ok()?;
            let text = text.trim_end_matches(['\0', ' ']);
            PrimitiveValue::Strs(text.split('\\').map(|s| s.trim().to_string()).collect())
        }
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use dicom_dictionary_std::tags;

    #[test]
    fn numbers_and_text_stored_as_un_are_reread() {
        let mut obj = InMemDicomObject::new_empty();
        let un = |tag, bytes: &[u8]| {
            DataElement::new(
                tag,
                VR::UN,
                PrimitiveValue::U8(bytes.iter().copied().collect()),
            )
        };
        obj.put(un(tags::ROWS, &[0x00, 0x02]));
        obj.put(un(tags::PIXEL_SPACING, b"0.5\\0.75"));
        obj.put(un(tags::SERIES_INSTANCE_UID, b"1.2.3\0"));
        obj.put(un(tags::BITS_ALLOCATED, &[1, 2, 3])); // does not fit US
        resolve(&mut obj);
        let rows = obj.element(tags::ROWS).unwrap();
        assert_eq!((rows.vr(), rows.to_int::<u32>().unwrap()), (VR::US, 512));
        let spacing = obj.element(tags::PIXEL_SPACING).unwrap();
        assert_eq!(spacing.to_multi_float64().unwrap(), [0.5, 0.75]);
        let uid = obj.element(tags::SERIES_INSTANCE_UID).unwrap();
        assert_eq!(uid.to_str().unwrap(), "1.2.3");
        assert_eq!(obj.element(tags::BITS_ALLOCATED).unwrap().vr(), VR::UN);
    }
}
