//! The items of a batch: from a manifest file or from the command line, with
//! the output naming rule ({stem}, {iso}).

use super::values;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use tmc::{Error, Result};

/// One input of a batch with its isovalues and one output per isovalue.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Item {
    /// The input volume.
    pub input: PathBuf,
    /// The isovalues, extracted in one pass.
    pub isos: Vec<f64>,
    /// The output of each isovalue.
    pub outputs: Vec<PathBuf>,
    /// The manifest line the item comes from (1-based), if any.
    pub line: Option<usize>,
    /// The DICOM series its line chose (`series=N|UID`), which wins over
    /// `--series`.
    pub series: Option<String>,
    /// The DICOM Segmentation segment its line chose (`segment=N`), which
    /// wins over `--segment`.
    pub segment: Option<u32>,
}

/// The items of `inputs` extracted at `isos` into outputs named by
/// `template`; several inputs need `{stem}` so that outputs differ.
pub(crate) fn from_args(inputs: &[PathBuf], isos: &[f64], template: &Path) -> Result<Vec<Item>> {
    if inputs.len() > 1 && !template.to_string_lossy().contains("{stem}") {
        return Err(Error::Invalid(format!(
            "{}: with several inputs the output must contain {{stem}} (e.g. -o 'out/{{stem}}.ply')",
            template.display()
        )));
    }
    let items = inputs
        .iter()
        .map(|input| Item {
            input: input.clone(),
            isos: isos.to_vec(),
            outputs: outputs(template, input, isos),
            line: None,
            series: None,
            segment: None,
        })
        .collect();
    check_unique(items)
}

/// Parses a manifest: one item per line, `INPUT ISO[,ISO...] OUTPUT`,
/// then optional `series=N|UID` and `segment=N` (a DICOM input's series
/// and a Segmentation's segment), separated by tabs if the line has a tab
/// (paths with spaces), else by whitespace; blank lines and lines starting
/// with `#` are skipped.
pub(crate) fn parse(text: &str, name: &Path) -> Result<Vec<Item>> {
    let mut items = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let at =
            |message: String| Error::Invalid(format!("{}:{}: {message}", name.display(), n + 1));
        let fields: Vec<&str> = if trimmed.contains('\t') {
            trimmed.split('\t').map(str::trim).collect()
        } else {
            trimmed.split_whitespace().collect()
        };
        let (Some(&[input, isos, output]), options) =
            (fields.first_chunk::<3>(), &fields[3.min(fields.len())..])
        else {
            return Err(at(format!(
                "expected 3 fields 'INPUT ISO[,ISO...] OUTPUT' (then series=N|UID, segment=N), found {}",
                fields.len()
            )));
        };
        let (mut series, mut segment) = (None, None);
        for option in options {
            match option.split_once('=') {
                Some(("series", v)) if !v.is_empty() && series.is_none() => {
                    series = Some(v.to_string())
                }
                Some(("segment", v)) if segment.is_none() => {
                    segment = Some(v.parse::<u32>().map_err(|_| {
                        at(format!("bad segment {v:?} (a segment number, 1 or more)"))
                    })?)
                }
                _ => {
                    return Err(at(format!(
                        "unexpected field {option:?} after OUTPUT (expected series=N|UID or segment=N, each once)"
                    )))
                }
            }
        }
        let isos = isos
            .split(',')
            .map(values::finite)
            .collect::<std::result::Result<Vec<f64>, String>>()
            .map_err(|e| at(format!("bad isovalue: {e}")))?;
        let known = [super::placeholders::STEM, super::placeholders::ISO];
        super::placeholders::check(Path::new(output), "OUTPUT", &known)
            .map_err(|e| at(e.to_string()))?;
        let input = PathBuf::from(input);
        items.push(Item {
            outputs: outputs(Path::new(output), &input, &isos),
            input,
            isos,
            line: Some(n + 1),
            series,
            segment,
        });
    }
    if items.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: the manifest lists no input",
            name.display()
        )));
    }
    check_unique(items)
}

/// Reads and parses the manifest at `path`.
pub(crate) fn read(path: &Path) -> Result<Vec<Item>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    // A byte order mark (Windows editors write one) is no part of the first input's name.
    parse(text.strip_prefix('\u{feff}').unwrap_or(&text), path)
}

/// Fails when two items would write the same output, however its path is
/// spelled (`a.ply`, `./a.ply`, `out/../a.ply`, a link to the directory):
/// the second replaced the first without a word.
fn check_unique(items: Vec<Item>) -> Result<Vec<Item>> {
    let mut seen = HashSet::new();
    for item in &items {
        for output in &item.outputs {
            if !seen.insert(file_key(output)) {
                return Err(Error::Invalid(format!(
                    "{}: two outputs of the batch have this name; use {{stem}} and {{iso}} in the output name",
                    output.display()
                )));
            }
        }
    }
    Ok(items)
}

/// The file `path` names, as one key for every spelling of it: its
/// directory's canonical path (where the directory exists) joined with its
/// name, else the path made absolute (without `.` components). Equal keys
/// are one file; distinct keys may still be one (hard links), as a file
/// system can tell only for files that exist.
pub(crate) fn file_key(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let parent = absolute
        .parent()
        .and_then(|dir| std::fs::canonicalize(dir).ok());
    match (parent, absolute.file_name()) {
        (Some(dir), Some(name)) => dir.join(name),
        _ => absolute,
    }
}

/// The outputs of `input` at `isos`: `template` with `{stem}` and `{iso}`
/// replaced; with several isovalues and no `{iso}`, `_iso{iso}` goes before
/// the extension.
pub(crate) fn outputs(template: &Path, input: &Path, isos: &[f64]) -> Vec<PathBuf> {
    use tmc::files::{fill_placeholder, has_placeholder, insert_before_extension};
    let mut path = fill_placeholder(template, "{stem}", &stem(input));
    if isos.len() > 1 && !has_placeholder(&path, "{iso}") {
        path = insert_before_extension(&path, "_iso{iso}");
    }
    isos.iter()
        .map(|iso| fill_placeholder(&path, "{iso}", &iso_text(*iso)))
        .collect()
}

/// `iso` as `{iso}` writes it: as a decimal (`1600`, `0.25`), or with an
/// exponent (`1e300`, `1.5e-30`) where the decimal would be longer than a
/// file name should be ([`tmc::params::number_text`]). Zero is `0` whichever
/// its sign: `-0` compares equal to `0` and cuts the same surface, so it
/// gets the same name (and `--iso 0,-0` two outputs of one name, refused).
fn iso_text(iso: f64) -> String {
    tmc::params::number_text(if iso == 0.0 { 0.0 } else { iso })
}

/// The input's name without its extension, and without a compression
/// extension before it (`head.nii.gz` -> `head`). For a glob pattern of
/// TIFF pages, the pattern's name without its wildcards
/// (`scan/slice_*.tif` -> `slice`), or the folder's name if nothing is
/// left (`scan/*.tif` -> `scan`). For an HDF5 dataset given as
/// `FILE.h5:/path/to/data`, the file's (`FILE`), as with `FILE.h5
/// --dataset /path/to/data`: one input, one name, however the dataset is
/// chosen (the path's last component, `data`, is often the same in every
/// file of a batch). Likewise a node of a Zarr store given as
/// `STORE.zarr/scans/ct` is named by the store (`STORE`), as with
/// `STORE.zarr --array scans/ct`. For a path without a last name (`.`, `./`, `..`,
/// `dir/..`: a DICOM or TIFF directory one is in), the name of the
/// directory it is, so that `{stem}.ply` is never the hidden `.ply` (whose
/// format was then unknown) or `{stem}_x.ply` the nameless `_x.ply`;
/// `volume` for the root.
pub(crate) fn stem(input: &Path) -> String {
    if let Some((file, _)) = tmc::volume::hdf5::split_path(input) {
        return stem(&file);
    }
    if let Some(store) = zarr_store(input) {
        return stem(store);
    }
    if input.file_name().is_none() {
        return std::fs::canonicalize(input)
            .ok()
            .filter(|dir| dir.file_name().is_some())
            .map_or_else(|| "volume".into(), |dir| stem(&dir));
    }
    let name = input
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.contains(['*', '?']) {
        let plain: String = name.chars().filter(|c| !matches!(c, '*' | '?')).collect();
        let base = plain.rfind('.').map_or(plain.as_str(), |i| &plain[..i]);
        let base = base.trim_matches(|c: char| matches!(c, '_' | '-' | '.' | ' '));
        if !base.is_empty() {
            return base.to_string();
        }
        let folder = input.parent().and_then(Path::file_name);
        return folder.map_or_else(|| "volume".into(), |f| f.to_string_lossy().into_owned());
    }
    let strip = |s: &str| s.rfind('.').filter(|&i| i > 0).map(|i| s[..i].to_string());
    let lower = name.to_ascii_lowercase();
    let once = strip(&name).unwrap_or_else(|| name.clone());
    if [".gz", ".bz2", ".zst"].iter().any(|e| lower.ends_with(e)) {
        strip(&once).unwrap_or(once)
    } else {
        once
    }
}

/// The store that `input` is a node inside of (an array or group below a
/// Zarr store's root: the outermost directory up from it that holds Zarr
/// metadata), or `None` when `input` is no node or is the root itself.
fn zarr_store(input: &Path) -> Option<&Path> {
    let is_node = |dir: &Path| {
        dir.is_dir()
            && [".zarray", ".zgroup", ".zattrs", "zarr.json"]
                .iter()
                .any(|m| dir.join(m).is_file())
    };
    if !is_node(input) {
        return None;
    }
    let root = input
        .ancestors()
        .take_while(|dir| !dir.as_os_str().is_empty() && is_node(dir))
        .last()?;
    (root != input).then_some(root)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `{iso}` of an isovalue far from 1 is a name a file system takes
    /// (a decimal of 1e300 has 301 digits, more than a name's 255 bytes).
    #[test]
    fn iso_names_stay_short() {
        let names = outputs(
            Path::new("out/{iso}.ply"),
            Path::new("v.nrrd"),
            &[1600.0, 0.25, -0.0, 1e300, -1.5e-30, 1e-7, 0.0, 1e3],
        );
        let names: Vec<String> = names.iter().map(|p| p.display().to_string()).collect();
        assert_eq!(
            names,
            [
                "out/1600.ply",
                "out/0.25.ply",
                "out/0.ply",
                "out/1e300.ply",
                "out/-1.5e-30.ply",
                "out/0.0000001.ply",
                "out/0.ply",
                "out/1000.ply"
            ]
        );
    }

    /// A directory given as `.`, `./`, `..` or `sub/..` is named by
    /// itself (its stem was empty: `-o '{stem}.ply'` wrote to `.ply`).
    #[test]
    fn a_directory_without_a_last_name_is_named_by_itself() {
        let dir = tempfile::tempdir().unwrap();
        let scan = dir.path().join("scan_07");
        std::fs::create_dir_all(scan.join("sub")).unwrap();
        for path in [scan.join("."), scan.join("sub/.."), scan.join("sub/../")] {
            assert_eq!(stem(&path), "scan_07", "{}", path.display());
        }
        let here = std::env::current_dir().unwrap();
        let name = here.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!(stem(Path::new(".")), stem(Path::new(&name)));
        assert_eq!(stem(Path::new("./")), stem(Path::new(&name)));
        assert_eq!(stem(Path::new("/")), "volume");
        assert_eq!(stem(Path::new("scan/slice_*.tif")), "slice");
    }

    #[test]
    fn outputs_are_templated_or_suffixed() {
        let input = Path::new("data/head.nii.gz");
        assert_eq!(
            outputs(Path::new("o/{stem}_{iso}.ply"), input, &[550.0, -0.5]),
            [PathBuf::from("o/head_550.ply"), "o/head_-0.5.ply".into()]
        );
        assert_eq!(
            outputs(Path::new("o.d/mesh.tmesh"), input, &[1.0, 2.0]),
            [
                PathBuf::from("o.d/mesh_iso1.tmesh"),
                "o.d/mesh_iso2.tmesh".into()
            ]
        );
        assert_eq!(
            outputs(Path::new("m.ply"), input, &[1.0]),
            [PathBuf::from("m.ply")]
        );
    }

    #[test]
    fn a_glob_pattern_has_a_stem_without_wildcards() {
        assert_eq!(stem(Path::new("scan/slice_*.tif")), "slice");
        assert_eq!(stem(Path::new("scan/*.tif")), "scan");
        assert_eq!(stem(Path::new("scan/p??_*.tiff")), "p");
        assert_eq!(stem(Path::new("*.tif")), "volume");
        assert_eq!(stem(Path::new("data/head.nii.gz")), "head");
    }

    #[test]
    fn manifest_lines_parse_and_errors_name_the_line() {
        let text = "# comment\n\na.npy 1,2 out/{stem}.ply\nb c.npy\t3\tb c.ply\n";
        let items = parse(text, Path::new("m.txt")).unwrap();
        assert_eq!(items.len(), 2);
        assert_eq!(items[0].isos, [1.0, 2.0]);
        assert_eq!(items[0].outputs[1], PathBuf::from("out/a_iso2.ply"));
        assert_eq!(items[1].input, PathBuf::from("b c.npy"));
        assert_eq!(items[1].line, Some(4));
        let err = parse("a.npy 1 x.ply\nb.npy 1\n", Path::new("m.txt")).unwrap_err();
        assert!(
            err.to_string().starts_with("m.txt:2: expected 3 fields"),
            "{err}"
        );
        let err = parse("a.npy 1,x a.ply\n", Path::new("m.txt")).unwrap_err();
        assert!(
            err.to_string().starts_with("m.txt:1: bad isovalue"),
            "{err}"
        );
        let items = parse(
            "d 1 a.ply series=4 segment=2\nd\t2\tb.ply\tseries=1.2.3\n",
            Path::new("m"),
        )
        .unwrap();
        assert_eq!(items[0].series.as_deref(), Some("4"));
        assert_eq!(items[0].segment, Some(2));
        assert_eq!(
            (items[1].series.as_deref(), items[1].segment),
            (Some("1.2.3"), None)
        );
        for bad in [
            "d 1 a.ply series=",
            "d 1 a.ply seg=2",
            "d 1 a.ply segment=x",
            "d 1 a.ply series=1 series=2",
        ] {
            let err = parse(bad, Path::new("m")).unwrap_err();
            assert!(err.to_string().starts_with("m:1: "), "{bad}: {err}");
        }
        let err = parse("a.npy 1 x.ply\nb.npy 2 x.ply\n", Path::new("m")).unwrap_err();
        assert!(err.to_string().contains("two outputs"), "{err}");
    }
}
