//! The voxel size of a TIFF stack, from the metadata that ImageJ and OME
//! write into the first page: the ImageJ description (`unit=`, `spacing=`
//! for z) with the XResolution and YResolution tags (pixels per unit) for
//! x and y, or the OME-XML `Pixels` element's `PhysicalSizeX/Y/Z` and their
//! `PhysicalSize*Unit` (micrometres when no unit is given, as OME says).
//! ImageJ's `xorigin=`, `yorigin=`, `zorigin=` (in pixels) place the first
//! voxel.
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
    /// The position of the first voxel in the same unit, where the
    /// metadata states one (ImageJ's `xorigin=`, `yorigin=`, `zorigin=`).
    pub origin: Option<[f64; 3]>,
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

/// What makes a multi-page TIFF more than one 3-D volume, by its first
/// page's metadata, in words for an error: an ImageJ hyperstack whose
/// pages run over two or more of channels, z slices and time points
/// (`channels=`, `slices=`, `frames=`: the pages interleave them, channel
/// fastest, so stacking every page as a z plane would mix them), or
/// OME-XML whose first image has two or more of `SizeC`, `SizeZ`, `SizeT`
/// above 1, or more than one image. Pages along one of them only (ImageJ
/// writes a z stack as `slices=`, tifffile's `imwrite(..., imagej=True)` of
/// a 3-D array as `channels=`) are one volume, a page per z. `None` for
/// one volume, or when nothing says otherwise.
pub(crate) fn several_volumes(description: Option<&str>) -> Option<String> {
    let text = description?;
    // The axes with more than one entry, named, when two or more are.
    let interleaved = |pairs: [(&str, usize); 3]| {
        let many: Vec<String> = pairs
            .iter()
            .filter(|(_, n)| *n > 1)
            .map(|(what, n)| format!("{n} {what}"))
            .collect();
        (many.len() > 1).then(|| many.join(", "))
    };
    let found = if text.starts_with("ImageJ=") {
        let count = |key: &str| {
            text.lines()
                .filter_map(|l| l.split_once('='))
                .find(|(k, _)| k.trim() == key)
                .and_then(|(_, v)| v.trim().parse::<usize>().ok())
                .unwrap_or(1)
        };
        let axes = [
            ("channels", count("channels")),
            ("z slices", count("slices")),
            ("time points", count("frames")),
        ];
        format!("an ImageJ hyperstack of {}", interleaved(axes)?)
    } else if text.contains("<OME") {
        let pixels: Vec<&str> = text
            .match_indices("<Pixels ")
            .chain(text.match_indices(":Pixels "))
            .filter_map(|(i, _)| text[i..].find('>').map(|end| &text[i..i + end]))
            .collect();
        if pixels.len() > 1 {
            format!("an OME-TIFF of {} images", pixels.len())
        } else {
            let size = |name: &str| {
                let key = format!(" {name}=\"");
                let element = pixels.first()?;
                let at = element.find(&key)? + key.len();
                let rest = &element[at..];
                rest[..rest.find('"')?].parse::<usize>().ok()
            };
            let axes = [
                ("channels", size("SizeC").unwrap_or(1)),
                ("z slices", size("SizeZ").unwrap_or(1)),
                ("time points", size("SizeT").unwrap_or(1)),
            ];
            format!("an OME-TIFF of {}", interleaved(axes)?)
        }
    } else {
        return None;
    };
    Some(format!(
        "{found} in its pages; tmc reads one 3-D volume (a page per z): save one \
         channel and time point as its own TIFF (e.g. tifffile.imwrite(path, \
         data[t, :, c]) for ImageJ's TZCYX order)"
    ))
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
    let mut size = convert(stated, unit.as_deref(), "ImageJ metadata");
    // ImageJ's origin is where the coordinates' zero lies, in pixels
    // (Calibration: position = (pixel - xOrigin) * pixelWidth); it writes
    // each only when not zero.
    let pixels = ["xorigin", "yorigin", "zorigin"].map(|key| {
        value(key)
            .and_then(|v| v.parse::<f64>().ok())
            .filter(|o| o.is_finite())
    });
    if pixels.iter().any(Option::is_some) {
        let [x, y, z] = [0, 1, 2].map(|i| -pixels[i].unwrap_or(0.0) * size.spacing[i]);
        // `-0.0` for a zero origin would print as such.
        size.origin = Some([x, y, z].map(|o| o + 0.0));
    }
    Some(size)
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
    Some(VoxelSize {
        spacing,
        origin: None,
        what,
    })
}

/// `stated` lengths in `unit`, in millimetres when the unit is known.
fn convert(stated: [f64; 3], unit: Option<&str>, source: &str) -> VoxelSize {
    match unit {
        None => VoxelSize {
            spacing: stated,
            origin: None,
            what: format!("{source}, no unit: values as stated"),
        },
        Some(u) => match millimetres_per(u) {
            Some(f) => VoxelSize {
                spacing: stated.map(|v| v * f),
                origin: None,
                what: format!("{source}, {u} in mm"),
            },
            None => VoxelSize {
                spacing: stated,
                origin: None,
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

    /// Pages of several channels or time points beside z slices are
    /// refused, not stacked as z planes (tifffile's ImageJ and OME
    /// descriptions); pages along one axis are a volume, whichever.
    #[test]
    fn hyperstacks_of_several_channels_or_times_are_several_volumes() {
        let channels =
            "ImageJ=1.11a\nimages=12\nchannels=2\nslices=6\nhyperstack=true\nmode=grayscale";
        let frames = "ImageJ=1.11a\nimages=12\nslices=6\nframes=2\nhyperstack=true\nloop=false";
        let why = several_volumes(Some(channels)).unwrap();
        assert!(
            why.starts_with("an ImageJ hyperstack of 2 channels, 6 z slices in"),
            "{why}"
        );
        let why = several_volumes(Some(frames)).unwrap();
        assert!(
            why.starts_with("an ImageJ hyperstack of 6 z slices, 2 time points in"),
            "{why}"
        );
        // One axis: a z stack (ImageJ), or tifffile's default for a 3-D array.
        for one in [
            "ImageJ=1.11a\nimages=6\nchannels=1\nslices=6\nhyperstack=true\nspacing=3.0",
            "ImageJ=1.11a\nimages=6\nchannels=6\nhyperstack=true\nmode=grayscale",
            "ImageJ=1.11a\nimages=6\nframes=6\n",
        ] {
            assert_eq!(several_volumes(Some(one)), None, "{one}");
        }
        let ome = r#"<OME><Image ID="Image:0"><Pixels ID="Pixels:0" DimensionOrder="XYZCT" Type="uint16" SizeX="9" SizeY="7" SizeZ="6" SizeC="2" SizeT="1"></Pixels></Image></OME>"#;
        let why = several_volumes(Some(ome)).unwrap();
        assert!(
            why.starts_with("an OME-TIFF of 2 channels, 6 z slices in"),
            "{why}"
        );
        let plain = ome.replace("SizeC=\"2\"", "SizeC=\"1\"");
        assert_eq!(several_volumes(Some(&plain)), None);
        let two = format!("{}{}", &plain[..plain.len() - 6], &plain[5..]);
        assert!(several_volumes(Some(&two))
            .unwrap()
            .starts_with("an OME-TIFF of 2 images"));
        assert_eq!(several_volumes(Some("a scanner")), None);
        assert_eq!(several_volumes(None), None);
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
