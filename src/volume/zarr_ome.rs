//! OME-Zarr (NGFF 0.4 and 0.5) `multiscales` metadata: which array holds
//! a level of the pyramid, and its grid (axes, scale and translation).
//!
//! NGFF 0.4 keeps `multiscales` in the group's attributes (`.zattrs` of a
//! Zarr v2 group); 0.5 keeps it under `attributes.ome` of a Zarr v3
//! group's `zarr.json`. Each dataset (level) has `coordinateTransformations`:
//! a `scale` and optionally a `translation`, one value per axis, applied
//! after any transformations of the whole multiscale. Axes have a name, a
//! type (`space`, `time`, `channel`) and, for space, a unit; lengths in a
//! known unit become millimetres (see `units.rs`), also on an axis that
//! states no type (the spec says it SHOULD, not MUST).

use super::units::millimetres_per;
use serde_json::Value;

/// One level of an OME-Zarr pyramid.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct OmeLevel {
    /// The array's path in the group.
    pub path: String,
    /// Axis names, slowest first (`t`, `c`, `z`, `y`, `x`).
    pub axes: Vec<String>,
    /// Scale per axis, in millimetres for space axes of a known unit.
    pub scale: Vec<f64>,
    /// Translation per axis, in the same units as the scale.
    pub translation: Vec<f64>,
    /// The units of the space axes, and whether they were converted.
    pub units: String,
    /// The levels there are.
    pub levels: usize,
}

/// The `multiscales` list of a group's attributes, NGFF 0.4 or 0.5.
fn multiscales(attributes: &Value) -> Option<&Vec<Value>> {
    attributes
        .get("multiscales")
        .or_else(|| attributes.get("ome")?.get("multiscales"))?
        .as_array()
}

/// The label images an OME-Zarr `labels` group lists (NGFF 0.4 `labels`,
/// 0.5 under `ome`), empty for any other group.
pub(crate) fn label_images(attributes: &Value) -> Vec<String> {
    let list = attributes
        .get("labels")
        .or_else(|| attributes.get("ome")?.get("labels"));
    list.and_then(Value::as_array)
        .map(|l| {
            l.iter()
                .filter_map(Value::as_str)
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

/// Whether a group's attributes describe an OME-Zarr image.
pub(crate) fn is_ome(attributes: &Value) -> bool {
    multiscales(attributes).is_some_and(|m| !m.is_empty())
}

/// Applies a list of coordinate transformations to `scale` and
/// `translation` (NGFF: scale first, then translation).
fn apply(list: Option<&Value>, scale: &mut [f64], translation: &mut [f64]) -> Result<(), String> {
    let Some(list) = list.and_then(Value::as_array) else {
        return Ok(());
    };
    for t in list {
        let numbers = |key: &str| -> Result<Vec<f64>, String> {
            let v = t.get(key).and_then(Value::as_array).ok_or_else(|| {
                format!("a '{key}' transformation without a list of numbers (a 'path' to a file of them is not read)")
            })?;
            let v: Option<Vec<f64>> = v.iter().map(Value::as_f64).collect();
            match v {
                Some(v) if v.len() == scale.len() => Ok(v),
                _ => Err(format!(
                    "a '{key}' transformation needs {} numbers",
                    scale.len()
                )),
            }
        };
        match t.get("type").and_then(Value::as_str) {
            Some("scale") => {
                let s = numbers("scale")?;
                for i in 0..scale.len() {
                    scale[i] *= s[i];
                    translation[i] *= s[i];
                }
            }
            Some("translation") => {
                let s = numbers("translation")?;
                for (t, d) in translation.iter_mut().zip(s) {
                    *t += d;
                }
            }
            Some("identity") => {}
            other => {
                return Err(format!(
                    "coordinate transformation {other:?} is not supported"
                ))
            }
        }
    }
    Ok(())
}

/// Level `level` of the first multiscale image in `attributes`.
pub(crate) fn level(attributes: &Value, level: usize) -> Result<OmeLevel, String> {
    let image = multiscales(attributes)
        .and_then(|m| m.first())
        .ok_or("no OME-Zarr multiscales in the group's attributes")?;
    let axes: Vec<&Value> = image
        .get("axes")
        .and_then(Value::as_array)
        .map(|a| a.iter().collect())
        .unwrap_or_default();
    let datasets = image
        .get("datasets")
        .and_then(Value::as_array)
        .filter(|d| !d.is_empty())
        .ok_or("OME-Zarr multiscales without datasets")?;
    let levels = datasets.len();
    let dataset = datasets.get(level).ok_or_else(|| {
        format!(
            "--level {level}: the image has {levels} levels (0 to {})",
            levels - 1
        )
    })?;
    let path = dataset
        .get("path")
        .and_then(Value::as_str)
        .ok_or("an OME-Zarr dataset without a path")?
        .to_string();
    // NGFF 0.3 and older name axes by strings; 0.4 and 0.5 by objects.
    let names: Vec<String> = axes
        .iter()
        .map(|a| {
            a.get("name")
                .and_then(Value::as_str)
                .or_else(|| a.as_str())
                .unwrap_or("")
                .to_string()
        })
        .collect();
    let n = names.len();
    let mut scale = vec![1.0; n];
    let mut translation = vec![0.0; n];
    apply(
        dataset.get("coordinateTransformations"),
        &mut scale,
        &mut translation,
    )?;
    apply(
        image.get("coordinateTransformations"),
        &mut scale,
        &mut translation,
    )?;
    let mut units = Vec::new();
    for (i, a) in axes.iter().enumerate() {
        let Some(unit) = a.get("unit").and_then(Value::as_str) else {
            continue;
        };
        // An axis SHOULD state its type: one without is a space axis when
        // its unit is a length (a time axis has seconds).
        match a.get("type").and_then(Value::as_str) {
            Some("space") => {}
            None if millimetres_per(unit).is_some() => {}
            _ => continue,
        }
        if let Some(f) = millimetres_per(unit) {
            scale[i] *= f;
            translation[i] *= f;
        }
        let known = millimetres_per(unit).is_some();
        let said = if known {
            format!("{unit} in mm")
        } else {
            format!("unit '{unit}' not known: values as stated")
        };
        if !units.contains(&said) {
            units.push(said);
        }
    }
    Ok(OmeLevel {
        path,
        axes: names,
        scale,
        translation,
        units: if units.is_empty() {
            "no unit: values as stated".to_string()
        } else {
            units.join(", ")
        },
        levels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn image(version_05: bool) -> Value {
        let m = json!([{
            "version": if version_05 { "0.5" } else { "0.4" },
            "axes": [
                {"name": "c", "type": "channel"},
                {"name": "z", "type": "space", "unit": "micrometer"},
                {"name": "y", "type": "space", "unit": "micrometer"},
                {"name": "x", "type": "space", "unit": "micrometer"}
            ],
            "datasets": [
                {"path": "0", "coordinateTransformations": [
                    {"type": "scale", "scale": [1.0, 2000.0, 1000.0, 500.0]},
                    {"type": "translation", "translation": [0.0, 10.0, 20.0, 30.0]}]},
                {"path": "1", "coordinateTransformations": [
                    {"type": "scale", "scale": [1.0, 4000.0, 2000.0, 1000.0]}]}
            ]
        }]);
        if version_05 {
            json!({"ome": {"version": "0.5", "multiscales": m}})
        } else {
            json!({ "multiscales": m })
        }
    }

    #[test]
    fn levels_of_ngff_04_and_05_in_millimetres() {
        for v05 in [false, true] {
            let a = image(v05);
            assert!(is_ome(&a));
            let l = level(&a, 0).unwrap();
            assert_eq!(l.path, "0");
            assert_eq!(l.axes, ["c", "z", "y", "x"]);
            assert_eq!(l.scale, [1.0, 2.0, 1.0, 0.5]);
            assert_eq!(l.translation, [0.0, 0.01, 0.02, 0.03]);
            assert_eq!(l.levels, 2);
            assert_eq!(level(&a, 1).unwrap().scale, [1.0, 4.0, 2.0, 1.0]);
            let e = level(&a, 2).unwrap_err();
            assert!(e.contains("2 levels (0 to 1)"), "{e}");
        }
        assert!(!is_ome(&json!({"foo": 1})));
    }
}
