//! `tmc merge`: part files, given in any order, stitched into one mesh in
//! any output format, one chunk in memory and one part file open at a time.

use super::PartRecord;
use crate::mesh::{MeshInfo, Totals};
use crate::meshfile::{ChunkEntry, TmeshReader};
use crate::params::Method;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A part file, as its header, index and record describe it.
pub(super) struct Part {
    pub(super) path: PathBuf,
    pub(super) record: PartRecord,
    pub(super) info: MeshInfo,
    /// Its first chunk, which the previous part's last chunk may point into.
    pub(super) first: Option<ChunkEntry>,
}

impl Part {
    /// Reads the record, header and index of the part file `path`.
    fn scan(path: &Path) -> Result<Part> {
        let record = PartRecord::read(path)?;
        let reader = TmeshReader::open(path)?;
        Ok(Part {
            path: path.to_path_buf(),
            record,
            info: reader.info().clone(),
            first: reader.entries().first().copied(),
        })
    }
}

/// Stitches the part files `parts` (any order) into the mesh at `output`,
/// whose format comes from its extension; the result is byte-identical to a
/// single run. Refuses parts of different runs, missing or repeated parts.
///
/// Setting `cancel` (from a signal handler, say) stops the merge before the
/// next chunk with [`Error::Interrupted`]; the output is then not written.
///
/// Parts of `tmc extract --labels --part I/N` (their records name a label)
/// are grouped by label and merged label by label: `output` containing
/// `{label}` gets one mesh per label, otherwise it is one `.ply` or
/// `.tmesh` holding every label in increasing order with a per-face label,
/// as one run writes it.
pub fn merge(parts: &[PathBuf], output: &Path, cancel: &AtomicBool) -> Result<Totals> {
    let scanned: Vec<Part> = parts.iter().map(|p| Part::scan(p)).collect::<Result<_>>()?;
    if scanned.iter().any(|p| p.record.label.is_some()) {
        return merge_labels(scanned, output, cancel);
    }
    // An isosurface is one mesh: `{label}` was written into its name.
    if crate::files::has_placeholder(output, "{label}") {
        return Err(Error::Invalid(format!(
            "{}: {{label}} names the files of label parts (tmc extract --labels --part); these parts are of an isosurface: give one output file",
            output.display()
        )));
    }
    crate::export::check_output_path(output)?;
    let parts = order(scanned)?;
    stitch(&parts, output, cancel)
}

/// Writes the ordered parts of one run into the mesh at `output`.
pub(super) fn stitch(parts: &[Part], output: &Path, cancel: &AtomicBool) -> Result<Totals> {
    let interrupted = || {
        if cancel.load(Ordering::Relaxed) {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    };
    let mut sink = crate::export::create_sink(output)?;
    sink.begin(&parts[0].info)?;
    let mut totals = Totals::default();
    for (k, part) in parts.iter().enumerate() {
        // The next chunk after this part (parts may be empty), which the
        // last chunk may point into.
        let next_first = parts[k + 1..].iter().find_map(|p| p.first);
        let mut reader = TmeshReader::open(&part.path)?;
        if reader.info() != &part.info || reader.entries().first() != part.first.as_ref() {
            return Err(Error::Invalid(format!(
                "{}: the part file changed during the merge",
                part.path.display()
            )));
        }
        let entries = reader.entries().to_vec();
        for (j, e) in entries.iter().enumerate() {
            let next = match entries.get(j + 1) {
                Some(n) => n.vertex_count,
                None => next_first
                    .filter(|n| n.plane == e.plane + 1)
                    .map_or(0, |n| n.vertex_count),
            };
            interrupted()?;
            let chunk = reader.chunk_then(j, next)?;
            sink.chunk_cancellable(totals.vertices + e.vertex_base, &chunk, cancel)?;
            totals.chunks += 1;
        }
        totals.vertices += reader.vertices();
        totals.triangles += reader.triangles();
    }
    interrupted()?;
    sink.finish_cancellable(&totals, cancel)?;
    Ok(totals)
}

/// Checks that the parts are all the parts of one run, once each, and puts
/// them in order.
pub(super) fn order(mut parts: Vec<Part>) -> Result<Vec<Part>> {
    let invalid = |m: String| Err(Error::Invalid(m));
    let Some(first) = parts.first() else {
        return invalid("no part files given".into());
    };
    let n = first.record.count;
    for p in &parts {
        same_run(first, p)?;
    }
    let name = |q: &Part| q.path.display().to_string();
    for p in &parts {
        let b = &p.record;
        let expect = super::layer_range(b.total_layers, b.index, b.count)?;
        if b.layers != [expect.start, expect.end] {
            return invalid(format!(
                "{}: part {}/{n} records layers {:?}, not {expect:?}",
                name(p),
                b.index,
                b.layers
            ));
        }
    }
    parts.sort_by_key(|p| p.record.index);
    for w in parts.windows(2) {
        if w[0].record.index == w[1].record.index {
            return invalid(format!(
                "part {}/{n} is given twice ({} and {})",
                w[0].record.index,
                w[0].path.display(),
                w[1].path.display()
            ));
        }
    }
    for (k, p) in parts.iter().enumerate() {
        if p.record.index != k + 1 {
            return invalid(format!("part {}/{n} is missing", k + 1));
        }
    }
    if parts.len() != n {
        return invalid(format!("part {}/{n} is missing", parts.len() + 1));
    }
    for w in parts.windows(2) {
        if w[0].record.seam_crc[1] != w[1].record.seam_crc[0] {
            return invalid(format!(
                "parts {} and {} disagree on the samples of plane {}: they were made from different inputs",
                w[0].path.display(),
                w[1].path.display(),
                w[0].record.layers[1]
            ));
        }
    }
    Ok(parts)
}

/// Checks that `p` is a part of the same run as `first`: same tmc version,
/// part count, options, grid, isovalue, input, what was read of it and
/// label.
pub(super) fn same_run(first: &Part, p: &Part) -> Result<()> {
    let (a, b) = (&first.record, &p.record);
    let name = |q: &Part| q.path.display().to_string();
    let differ = |what: &str| {
        Err(Error::Invalid(format!(
            "{} and {} are parts of different runs: {what} differ",
            name(first),
            name(p)
        )))
    };
    if a.tmc_version != b.tmc_version {
        return differ(&format!(
            "tmc versions ({} vs {})",
            a.tmc_version, b.tmc_version
        ));
    }
    if a.count != b.count {
        return differ(&format!("part counts ({} vs {})", a.count, b.count));
    }
    let (x, y) = (&first.info, &p.info);
    if let Some(options) = options_differ(x, y) {
        return differ(&options);
    }
    if x.grid != y.grid {
        return differ("grids");
    }
    // 0 and -0 are the same isovalue.
    if x.iso != y.iso {
        return differ(&format!("isovalues ({} vs {})", x.iso, y.iso));
    }
    if a.reading != b.reading {
        return differ(
            "the options reading headerless samples (--dtype, --dims, --endian, --header-bytes)",
        );
    }
    if a.input != b.input || a.total_layers != b.total_layers {
        return differ(&format!("inputs ({} vs {})", a.input_name, b.input_name));
    }
    if a.selection != b.selection {
        let chosen = |s: &Option<String>| s.clone().unwrap_or_else(|| "none".to_string());
        return differ(&format!(
            "selections of the input ({} vs {})",
            chosen(&a.selection),
            chosen(&b.selection)
        ));
    }
    if a.label_count != b.label_count {
        let count = |n: Option<usize>| n.map_or("none".to_string(), |n| n.to_string());
        return differ(&format!(
            "label counts ({} vs {})",
            count(a.label_count),
            count(b.label_count)
        ));
    }
    if a.label != b.label {
        let label = |l: Option<i64>| l.map_or("none".to_string(), |l| l.to_string());
        return differ(&format!(
            "labels ({} vs {})",
            label(a.label),
            label(b.label)
        ));
    }
    Ok(())
}

/// The extraction options (`--method`, `--inside`, `--close`, `--normals`) in which `x`
/// and `y` differ, as "options (--close: on vs off)", if any.
fn options_differ(x: &MeshInfo, y: &MeshInfo) -> Option<String> {
    let on = |b: bool| if b { "on" } else { "off" };
    let method = |m: Method| if m == Method::Mc { "mc" } else { "tmc" };
    let mut differ = Vec::new();
    if x.method != y.method {
        differ.push(format!(
            "--method: {} vs {}",
            method(x.method),
            method(y.method)
        ));
    }
    if x.inside != y.inside {
        differ.push(format!("--inside: {:?} vs {:?}", x.inside, y.inside).to_lowercase());
    }
    if x.close != y.close {
        differ.push(format!("--close: {} vs {}", on(x.close), on(y.close)));
    }
    if x.normals != y.normals {
        differ.push(format!("--normals: {} vs {}", on(x.normals), on(y.normals)));
    }
    (!differ.is_empty()).then(|| format!("options ({})", differ.join(", ")))
}

/// Merges label part files (each record names its label), given in any
/// order: every label needs all its parts, and all are of one run.
/// `output` containing `{label}` gets one mesh per label (`{label}`
/// replaced by the label), each byte for byte what one run writes there;
/// otherwise `output` is one `.ply` or `.tmesh` holding every label with a
/// per-face label, in increasing label order: what one run with `--labels
/// all` (or an increasing list) writes. Returns the totals of all labels.
fn merge_labels(parts: Vec<Part>, output: &Path, cancel: &AtomicBool) -> Result<Totals> {
    let mut groups: BTreeMap<i64, Vec<Part>> = BTreeMap::new();
    for part in parts {
        let Some(label) = part.record.label else {
            return Err(Error::Invalid(format!(
                "{}: an isosurface part among label parts (of 'tmc extract --labels')",
                part.path.display()
            )));
        };
        groups.entry(label).or_default().push(part);
    }
    let groups: Vec<(i64, Vec<Part>)> = groups
        .into_iter()
        .map(|(label, group)| match order(group) {
            Ok(group) => Ok((label, group)),
            Err(Error::Invalid(m)) => Err(Error::Invalid(format!("label {label}: {m}"))),
            Err(e) => Err(e),
        })
        .collect::<Result<_>>()?;
    let first = &groups[0].1[0];
    let given = || {
        let labels: Vec<String> = groups.iter().map(|(l, _)| l.to_string()).collect();
        labels.join(", ")
    };
    if let Some(n) = first.record.label_count.filter(|&n| n > groups.len()) {
        return Err(Error::Invalid(format!(
            "the parts are of a run with {n} labels, but only those of {} are given (labels {}): all the part files of {} label(s) are missing",
            groups.len(),
            given(),
            n - groups.len()
        )));
    }
    // Parts of an earlier run with as many other labels agree with these
    // on all but the label: only their number tells them apart.
    if let Some(n) = first.record.label_count.filter(|&n| n < groups.len()) {
        return Err(Error::Invalid(format!(
            "the parts are of runs with {n} labels, but those of {} are given (labels {}): parts of another run with other labels are among them (left from an earlier run?)",
            groups.len(),
            given(),
        )));
    }
    for (_, group) in &groups {
        let other = &group[0];
        // One run: everything but the label agrees.
        let relabelled = Part {
            path: other.path.clone(),
            record: super::PartRecord {
                label: first.record.label,
                ..other.record.clone()
            },
            info: other.info.clone(),
            first: other.first,
        };
        same_run(first, &relabelled)?;
    }
    let mut totals = Totals::default();
    if crate::files::has_placeholder(output, "{label}") {
        let outputs: Vec<PathBuf> = groups
            .iter()
            .map(|(l, _)| crate::files::fill_placeholder(output, "{label}", &l.to_string()))
            .collect();
        for path in &outputs {
            // A label's file over a part file (`-o 'parts/{label}.1.tmesh'`)
            // would destroy an input, as a merge of one mesh refuses to.
            for (_, group) in &groups {
                for part in group {
                    crate::files::check_distinct(&part.path, path)?;
                }
            }
            crate::export::check_output_path(path)?;
        }
        // All or none: the labels merged before a failure are taken back.
        for (k, ((_, group), path)) in groups.iter().zip(&outputs).enumerate() {
            let t = match stitch(group, path, cancel) {
                Ok(t) => t,
                Err(Error::Interrupted) => {
                    crate::files::withdraw(
                        outputs[..k].iter().map(PathBuf::as_path),
                        Error::Interrupted,
                    );
                    return Err(Error::Interrupted);
                }
                Err(e) => {
                    return Err(crate::files::withdraw(
                        outputs[..k].iter().map(PathBuf::as_path),
                        e,
                    ))
                }
            };
            totals.vertices += t.vertices;
            totals.triangles += t.triangles;
            totals.chunks += t.chunks;
        }
        return Ok(totals);
    }
    if output
        .extension()
        .is_none_or(|e| e != "ply" && e != "tmesh")
    {
        return Err(Error::Invalid(format!(
            "{}: label parts merge into one file per label ({{label}} in the output) or one .ply or .tmesh",
            output.display()
        )));
    }
    if let Some((l, _)) = groups.iter().find(|(l, _)| u32::try_from(*l).is_err()) {
        return Err(Error::Invalid(format!(
            "label {l} does not fit the uint32 per-face label of one file; merge into one file per label with {{label}}"
        )));
    }
    crate::export::check_output_path(output)?;
    // Each label merged into a .tmesh beside the output, then assembled.
    let dir = output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let spool = tempfile::Builder::new()
        .prefix(".tmc-merge-labels-")
        .tempdir_in(dir)
        .map_err(|e| Error::io(dir, e))?;
    let mut merged = Vec::with_capacity(groups.len());
    for (label, group) in &groups {
        let path = spool.path().join(format!("{label}.tmesh"));
        stitch(group, &path, cancel)?;
        merged.push((*label as u32, path));
    }
    let parts: Vec<(u32, &Path)> = merged.iter().map(|(l, p)| (*l, p.as_path())).collect();
    let totals = crate::export::write_labelled(output, &parts, cancel)?;
    spool.close().map_err(|e| Error::io(output, e))?;
    Ok(totals)
}
