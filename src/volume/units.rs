//! Lengths in metadata (ImageJ, OME-TIFF, OME-Zarr, NRRD `space units`)
//! converted to millimetres, the unit of the medical formats tmc reads
//! (NRRD, NIfTI and DICOM volumes are in millimetres unless they say
//! otherwise), so that meshes of different inputs line up.

/// Millimetres per unit `name`, for the unit names ImageJ, OME and
/// tifffile write; `None` if unknown.
pub(crate) fn millimetres_per(name: &str) -> Option<f64> {
    let name = name.trim().replace("\\u00B5", "µ").replace("\\u00b5", "µ");
    Some(match name.to_ascii_lowercase().as_str() {
        "pm" | "picometer" | "picometre" => 1e-9,
        "å" | "angstrom" => 1e-7,
        "nm" | "nanometer" | "nanometre" => 1e-6,
        "µm" | "μm" | "um" | "micron" | "microns" | "micrometer" | "micrometre" => 1e-3,
        "mm" | "millimeter" | "millimetre" => 1.0,
        "cm" | "centimeter" | "centimetre" => 10.0,
        "m" | "meter" | "metre" => 1000.0,
        "in" | "inch" | "inches" => 25.4,
        _ => return None,
    })
}
