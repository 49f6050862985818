//! `tmc merge`: part files, given in any order, stitched into one mesh in
//! any output format, one chunk in memory at a time.

use super::PartRecord;
use crate::meshfile::TmeshReader;
use crate::sink::Totals;
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// An open part file.
struct Part {
    path: PathBuf,
    record: PartRecord,
    reader: TmeshReader,
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
    let mut opened = Vec::with_capacity(parts.len());
    for path in parts {
        let record = PartRecord::read(path)?;
        let reader = TmeshReader::open(path)?;
        opened.push(Part {
            path: path.clone(),
            record,
            reader,
        });
    }
    let parts = order(opened)?;
    let mut sink = crate::export::create_sink(output)?;
    sink.begin(parts[0].reader.info())?;
    let mut totals = Totals::default();
    let count = parts.len();
    let mut parts = parts;
    for k in 0..count {
        // The next chunk after this part (parts may be empty), which the
        // last chunk may point into.
        let next_first = parts[k + 1..]
            .iter()
            .find_map(|p| p.reader.entries().first().copied());
        let part = &mut parts[k];
        let entries = part.reader.entries().to_vec();
        for (j, e) in entries.iter().enumerate() {
            let next = match entries.get(j + 1) {
                Some(n) => n.vertex_count,
                None => next_first
                    .filter(|n| n.plane == e.plane + 1)
                    .map_or(0, |n| n.vertex_count),
            };
            interrupted()?;
            let chunk = part.reader.chunk_then(j, next)?;
            sink.chunk(totals.vertices + e.vertex_base, &chunk)?;
            totals.chunks += 1;
        }
        totals.vertices += part.reader.vertices();
        totals.triangles += part.reader.triangles();
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
        if a.input != b.input || a.total_layers != b.total_layers {
            return differ(&format!("inputs ({} vs {})", a.input_name, b.input_name));
        }
        let (x, y) = (first.reader.info(), p.reader.info());
        if x.grid != y.grid {
            return differ("grids");
        }
        if x.iso.to_bits() != y.iso.to_bits() {
            return differ(&format!("isovalues ({} vs {})", x.iso, y.iso));
        }
        if (x.method, x.inside, x.close) != (y.method, y.inside, y.close) {
            return differ("options (--method, --inside, --close)");
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
    Ok(parts)
}
