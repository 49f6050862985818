//! Lengths in metadata (ImageJ, OME-TIFF, OME-Zarr, NRRD `space units`)
//! converted to millimetres, the unit of the medical formats tmc reads
//! (NRRD, NIfTI and DICOM volumes are in millimetres unless they say
//! otherwise), so that meshes of different inputs line up.

/// Millimetres per unit `name`, for the unit names ImageJ, OME and
/// tifffile write; `None` if unknown. The SI symbols whose case is their
/// meaning (OME's `Mm`, megametre, against `mm`; `Pm`, petametre, against
/// `pm`) are matched as written; otherwise case is ignored, beyond ASCII
/// too: OME's symbol for the ångström is `Å` (also written as U+212B, the
/// ångström sign), which ImageJ writes `\u00C5` (see [`unescaped`]).
pub(crate) fn millimetres_per(name: &str) -> Option<f64> {
    let name = unescaped(name.trim());
    let large = match name.as_str() {
        "km" => Some(1e6),
        "Mm" => Some(1e9),
        "Gm" => Some(1e12),
        "Tm" => Some(1e15),
        "Pm" => Some(1e18),
        _ => None,
    };
    if large.is_some() {
        return large;
    }
    Some(match name.to_lowercase().as_str() {
        "pm" | "picometer" | "picometre" => 1e-9,
        "å" | "angstrom" | "ångström" => 1e-7,
        "nm" | "nanometer" | "nanometre" => 1e-6,
        "µm" | "μm" | "um" | "micron" | "microns" | "micrometer" | "micrometre" => 1e-3,
        "mm" | "millimeter" | "millimetre" => 1.0,
        "cm" | "centimeter" | "centimetre" => 10.0,
        "dm" | "decimeter" | "decimetre" => 100.0,
        "m" | "meter" | "metre" => 1000.0,
        "in" | "inch" | "inches" => 25.4,
        _ => return None,
    })
}

/// `text` with its `\uXXXX` escapes decoded: ImageJ writes every
/// character of its description outside printable ASCII so (`unit=\u00B5m`
/// for `µm`, `\u00C5` for `Å`). An escape that is not four hex digits of
/// a character is kept as written.
fn unescaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("\\u") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        let decoded = after
            .get(..4)
            .filter(|hex| hex.bytes().all(|b| b.is_ascii_hexdigit()))
            .and_then(|hex| u32::from_str_radix(hex, 16).ok())
            .and_then(char::from_u32);
        match decoded {
            Some(c) => {
                out.push(c);
                rest = &after[4..];
            }
            None => {
                out.push_str("\\u");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::millimetres_per;

    #[test]
    fn the_case_of_an_si_symbol_is_its_meaning() {
        assert_eq!(millimetres_per("mm"), Some(1.0));
        assert_eq!(millimetres_per("MM"), Some(1.0));
        assert_eq!(millimetres_per("Millimeter"), Some(1.0));
        assert_eq!(millimetres_per("Mm"), Some(1e9));
        assert_eq!(millimetres_per("pm"), Some(1e-9));
        assert_eq!(millimetres_per("Pm"), Some(1e18));
        assert_eq!(millimetres_per("km"), Some(1e6));
        assert_eq!(millimetres_per(" \\u00B5m "), Some(1e-3));
        assert_eq!(millimetres_per("parsec"), None);
    }
}
