//! `tmc merge`: part files, given in any order, stitched into one mesh in
//! any output format, one chunk in memory and one part file open at a time.

use super::PartRecord;
use crate::mesh::{MeshInfo, Totals};
use crate::meshfile::{ChunkEntry, TmeshReader};
use crate::params::Method;
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A part file, as its header, index and record describe it.
struct Part {
    path: PathBuf,
    record: PartRecord,
    info: MeshInfo,
    /// Its first chunk, which the previous part's last chunk may point into.
    first: Option<ChunkEntry>,
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
pub fn merge(parts: &[PathBuf], output: &Path, cancel: &AtomicBool) -> Result<Totals> {
    let interrupted = || {
        if cancel.load(Ordering::Relaxed) {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    };
    crate::export::check_output_path(output)?;
    let scanned = parts.iter().map(|p| Part::scan(p)).collect::<Result<_>>()?;
    let parts = order(scanned)?;
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
fn order(mut parts: Vec<Part>) -> Result<Vec<Part>> {
    let invalid = |m: String| Err(Error::Invalid(m));
    let Some(first) = parts.first() else {
        return invalid("no part files given".into());
    };
    let n = first.record.count;
    for p in &parts {
        let (a, b) = (&first.record, &p.record);
        let name = |q: &Part| q.path.display().to_string();
        let differ = |what: &str| {
            invalid(format!(
                "{} and {} are parts of different runs: {what} differ",
                name(first),
                name(p)
            ))
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
            return differ("the options reading headerless samples (--dtype, --dims, --endian, --header-bytes)");
        }
        if a.input != b.input || a.total_layers != b.total_layers {
            return differ(&format!("inputs ({} vs {})", a.input_name, b.input_name));
        }
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
