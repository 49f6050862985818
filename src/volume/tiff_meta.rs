//! The voxel size of a TIFF stack, from the metadata that ImageJ and OME
//! write into the first page: the ImageJ description (`unit=`, `spacing=`
//! for z) with the XResolution and YResolution tags (pixels per unit) for
//! x and y, or the OME-XML `Pixels` element's `PhysicalSizeX/Y/Z` and their
//! `PhysicalSize*Unit` (micrometres when no unit is given, as OME says).
//!
//! Lengths are converted to millimetres, the unit of the medical formats
//! tmc reads (NRRD, NIfTI and DICOM volumes are in millimetres), so that
//! meshes of different inputs line up; a unit tmc does not know is kept as
//! stated, and the report says so. A plain TIFF's resolution tags (often
//! 72 dots per inch from a scanner or an image editor) are not a voxel
//! size and are ignored.

use super::units::millimetres_per;

/// A voxel size read from the metadata.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct VoxelSize {
    /// Spacing along x, y, z in millimetres (or the stated unit, if
    /// unknown); 1 along an axis the metadata does not give.
    pub spacing: [f64; 3],
    /// Where it came from and in which unit, for reports.
    pub what: String,
}

/// The voxel size stated by a TIFF's first page: its ImageDescription
/// `description`, and `resolution`, its XResolution and YResolution
/// (pixels per unit), if present. `None` when neither ImageJ nor OME
/// metadata give one.
pub(crate) fn voxel_size(
    description: Option<&str>,
    resolution: Option<(f64, f64)>,
) -> Option<VoxelSize> {
    let text = description?;
    if text.contains("<OME") {
        return ome(text);
    }
    if text.starts_with("ImageJ=") {
        return imagej(text, resolution);
    }
    None
}

/// From ImageJ's description: `unit=`, `spacing=` and the resolution tags.
fn imagej(text: &str, resolution: Option<(f64, f64)>) -> Option<VoxelSize> {
    let value = |key: &str| {
        text.lines()
            .filter_map(|l| l.split_once('='))
            .find(|(k, _)| k.trim() == key)
            .map(|(_, v)| v.trim().to_string())
    };
    let unit = value("unit").filter(|u| !u.is_empty() && u != "pixel");
    let z = value("spacing").and_then(|v| v.parse::<f64>().ok());
    let xy = resolution
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0)
        .map(|(x, y)| (1.0 / x, 1.0 / y));
    if unit.is_none() && z.is_none() {
        // Uncalibrated: ImageJ writes resolution 1 and no unit.
        return None;
    }
    let (x, y) = xy.unwrap_or((1.0, 1.0));
    let stated = [x, y, z.filter(|z| z.is_finite() && *z > 0.0).unwrap_or(1.0)];
    Some(convert(stated, unit.as_deref(), "ImageJ metadata"))
}

/// From OME-XML: the first `Pixels` element's physical sizes.
fn ome(text: &str) -> Option<VoxelSize> {
    let start = text.find("<Pixels ").or_else(|| text.find(":Pixels "))?;
    let element = &text[start..];
    let element = &element[..element.find('>')?];
    let attr = |name: &str| {
        let key = format!(" {name}=\"");
        let at = element.find(&key)? + key.len();
        let rest = &element[at..];
        Some(rest[..rest.find('"')?].to_string())
    };
    let mut spacing = [1.0; 3];
    let mut units = Vec::new();
    let mut found = false;
    for (i, axis) in ["X", "Y", "Z"].iter().enumerate() {
        let Some(size) = attr(&format!("PhysicalSize{axis}")).and_then(|v| v.parse::<f64>().ok())
        else {
            continue;
        };
        if !(size.is_finite() && size > 0.0) {
            continue;
        }
        found = true;
        let unit = attr(&format!("PhysicalSize{axis}Unit")).unwrap_or_else(|| "µm".to_string());
        match millimetres_per(&unit) {
            Some(f) => spacing[i] = size * f,
            None => spacing[i] = size,
        }
        if !units.contains(&unit) {
            units.push(unit);
        }
    }
    if !found {
        return None;
    }
    let known = units.iter().all(|u| millimetres_per(u).is_some());
    let what = if known {
        format!("OME-XML PhysicalSize, {} in mm", units.join(", "))
    } else {
        format!(
            "OME-XML PhysicalSize, unit {} not known: values as stated",
            units.join(", ")
        )
    };
    Some(VoxelSize { spacing, what })
}

/// `stated` lengths in `unit`, in millimetres when the unit is known.
fn convert(stated: [f64; 3], unit: Option<&str>, source: &str) -> VoxelSize {
    match unit {
        None => VoxelSize {
            spacing: stated,
            what: format!("{source}, no unit: values as stated"),
        },
        Some(u) => match millimetres_per(u) {
            Some(f) => VoxelSize {
                spacing: stated.map(|v| v * f),
                what: format!("{source}, {u} in mm"),
            },
            None => VoxelSize {
                spacing: stated,
                what: format!("{source}, unit '{u}' not known: values as stated"),
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imagej_microns_become_millimetres() {
        let d = "ImageJ=1.11a\nimages=4\nslices=4\nunit=micron\nspacing=1.6\nloop=false\n";
        let v = voxel_size(Some(d), Some((1.0 / 0.8, 1.25))).unwrap();
        let expect = [0.0008, 0.0008, 0.0016];
        for (a, b) in v.spacing.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{:?}", v.spacing);
        }
        assert!(v.what.contains("micron in mm"), "{}", v.what);
    }

    #[test]
    fn uncalibrated_imagej_and_plain_tiffs_state_nothing() {
        assert_eq!(
            voxel_size(Some("ImageJ=1.11a\nimages=4\n"), Some((1.0, 1.0))),
            None
        );
        assert_eq!(voxel_size(Some("a scanner"), Some((72.0, 72.0))), None);
        assert_eq!(voxel_size(None, Some((72.0, 72.0))), None);
    }

    #[test]
    fn ome_sizes_with_units_and_default_micrometres() {
        let d = r#"<?xml version="1.0"?><OME xmlns="x"><Image ID="Image:0"><Pixels DimensionOrder="XYZCT" ID="Pixels:0" PhysicalSizeX="0.5" PhysicalSizeXUnit="mm" PhysicalSizeY="0.5" PhysicalSizeYUnit="mm" PhysicalSizeZ="2000" SizeX="4"></Pixels></Image></OME>"#;
        let v = voxel_size(Some(d), None).unwrap();
        assert_eq!(v.spacing, [0.5, 0.5, 2.0]);
        let odd = d.replace("PhysicalSizeXUnit=\"mm\"", "PhysicalSizeXUnit=\"parsec\"");
        let v = voxel_size(Some(&odd), None).unwrap();
        assert_eq!(v.spacing[0], 0.5);
        assert!(v.what.contains("not known"), "{}", v.what);
    }
}
