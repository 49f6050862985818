//! What `tmc extract` reports: the statistics table (stderr) and the JSON
//! object (stdout).

use serde::Serialize;
use std::io::{self, Write};
use std::path::Path;
use tmc::stream::RunSummary;
use tmc::{Grid, Stats};

/// Everything known about one finished extraction.
pub(crate) struct Run<'a> {
    /// Input volume path.
    pub input: &'a Path,
    /// Output mesh path.
    pub output: &'a Path,
    /// The parameters, grid and statistics of the run.
    pub summary: RunSummary,
    /// Bytes, memory and wall time of the run.
    pub resources: &'a Resources,
}

/// What a run cost, beyond the statistics of the extraction (all in the
/// JSON object under these names).
#[derive(Debug, Clone, Default, Serialize)]
pub(crate) struct Resources {
    /// Cell layers per slab, if `--slab-depth` chose it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slab_depth: Option<usize>,
    /// Bytes of stored samples read from the input (see [`bytes_read`]).
    pub bytes_read: u64,
    /// Size of the output file after the run.
    pub bytes_written: Option<u64>,
    /// Largest anonymous resident memory (`RssAnon`) sampled during the
    /// run, bytes; excludes the pages of memory-mapped input.
    pub peak_rss_anon_bytes: Option<u64>,
    /// Peak resident set (`VmHWM`), bytes; includes mapped input pages.
    pub vm_hwm_bytes: Option<u64>,
    /// Wall time of the whole command (open, extract, write), seconds.
    pub wall_seconds: f64,
}

/// Bytes of stored samples the extraction read: planes read times the
/// input's plane size and sample size. With `close`, the two all-outside
/// planes that the padding adds (read once each) are not counted.
pub(crate) fn bytes_read(stats: &Stats, grid: &Grid, sample_bytes: usize, close: bool) -> u64 {
    let planes = stats.planes_read.saturating_sub(if close { 2 } else { 0 });
    planes * grid.plane_len() as u64 * sample_bytes as u64
}

/// `bytes` with a binary prefix: `12.3 MiB`.
pub(crate) fn human_bytes(bytes: u64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < units.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", units[unit])
    }
}

/// The JSON object printed by `--json`.
#[derive(Serialize)]
struct JsonRun<'a> {
    input: String,
    output: String,
    #[serde(flatten)]
    summary: &'a RunSummary,
    #[serde(flatten)]
    resources: &'a Resources,
}

/// Writes the run as one JSON object on one line.
pub(crate) fn write_json(w: &mut impl Write, run: &Run<'_>) -> io::Result<()> {
    let json = JsonRun {
        input: run.input.display().to_string(),
        output: run.output.display().to_string(),
        summary: &run.summary,
        resources: run.resources,
    };
    serde_json::to_writer(&mut *w, &json)?;
    writeln!(w)
}

/// Writes the paper's Table 1 plus sizes and time as an aligned table.
pub(crate) fn write_table(w: &mut impl Write, run: &Run<'_>) -> io::Result<()> {
    let summary = &run.summary;
    let s = &summary.stats;
    let mut rows: Vec<(String, String)> =
        vec![("ambiguous cells".into(), s.ambiguous_cells.to_string())];
    for (i, n) in s.contours.iter().enumerate() {
        rows.push((format!("contours with {} vertices", i + 3), n.to_string()));
    }
    for (i, n) in s.ambiguous_contours.iter().enumerate() {
        rows.push((
            format!("ambiguous contours with {} vertices", i + 6),
            n.to_string(),
        ));
    }
    rows.push(("tunnels".into(), s.tunnels.to_string()));
    rows.push((
        "contours with 12 vertices".into(),
        s.contours_12.to_string(),
    ));
    rows.push(("vertices".into(), s.vertices.to_string()));
    rows.push(("triangles".into(), s.triangles.to_string()));
    rows.push(("time (s)".into(), format!("{:.3}", s.seconds)));
    let r = run.resources;
    rows.push(("slabs".into(), s.slabs.to_string()));
    if let Some(depth) = r.slab_depth {
        rows.push(("slab depth".into(), depth.to_string()));
    }
    rows.push(("planes read".into(), s.planes_read.to_string()));
    rows.push(("bytes read".into(), human_bytes(r.bytes_read)));
    let unknown = || "unknown".to_string();
    rows.push((
        "bytes written".into(),
        r.bytes_written.map_or_else(unknown, human_bytes),
    ));
    rows.push((
        "read time (s, all threads)".into(),
        format!("{:.3}", s.read_seconds),
    ));
    rows.push((
        "cell time (s, all threads)".into(),
        format!("{:.3}", s.cell_seconds),
    ));
    rows.push(("write time (s)".into(), format!("{:.3}", s.write_seconds)));
    rows.push(("wall time (s)".into(), format!("{:.3}", r.wall_seconds)));
    rows.push((
        "peak anonymous memory".into(),
        r.peak_rss_anon_bytes.map_or_else(unknown, human_bytes),
    ));
    rows.push((
        "peak resident memory".into(),
        r.vm_hwm_bytes.map_or_else(unknown, human_bytes),
    ));

    let [x, y, z] = summary.dims;
    writeln!(
        w,
        "{} ({x}x{y}x{z}) -> {}: iso {}, method {}, inside {}{}, {} threads",
        run.input.display(),
        run.output.display(),
        tmc::params::number_text(summary.iso),
        summary.method,
        summary.inside,
        if summary.close { ", closed" } else { "" },
        summary.threads
    )?;
    let label_width = rows.iter().map(|(l, _)| l.len()).max().unwrap_or(0);
    let value_width = rows.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
    for (label, value) in &rows {
        writeln!(w, "  {label:<label_width$}  {value:>value_width$}")?;
    }
    Ok(())
}
