//! What `tmc extract` reports: the statistics table (stderr) and the JSON
//! object (stdout).

use serde::Serialize;
use std::io::{self, Write};
use std::path::Path;
use tmc::{ExtractParams, Grid, Inside, Method, Stats};

/// Everything known about one finished extraction.
pub(crate) struct Run<'a> {
    /// Input volume path.
    pub input: &'a Path,
    /// Output mesh path.
    pub output: &'a Path,
    /// The extraction parameters.
    pub params: &'a ExtractParams,
    /// Worker threads actually meant by `params.threads`.
    pub threads: usize,
    /// The input grid.
    pub grid: &'a Grid,
    /// The statistics of the run.
    pub stats: &'a Stats,
}

/// The JSON object printed by `--json`.
#[derive(Serialize)]
struct JsonRun<'a> {
    input: String,
    output: String,
    iso: f64,
    method: &'static str,
    inside: &'static str,
    close: bool,
    threads: usize,
    dims: [usize; 3],
    spacing: [f64; 3],
    origin: [f64; 3],
    #[serde(flatten)]
    stats: &'a Stats,
}

/// The CLI name of a method.
fn method_name(method: Method) -> &'static str {
    match method {
        Method::Tmc => "tmc",
        Method::Mc => "mc",
    }
}

/// The CLI name of a side.
fn inside_name(inside: Inside) -> &'static str {
    match inside {
        Inside::High => "high",
        Inside::Low => "low",
    }
}

/// Writes the run as one JSON object on one line.
pub(crate) fn write_json(w: &mut impl Write, run: &Run<'_>) -> io::Result<()> {
    let json = JsonRun {
        input: run.input.display().to_string(),
        output: run.output.display().to_string(),
        iso: run.params.iso,
        method: method_name(run.params.method),
        inside: inside_name(run.params.inside),
        close: run.params.close,
        threads: run.threads,
        dims: run.grid.dims,
        spacing: run.grid.spacing,
        origin: run.grid.origin,
        stats: run.stats,
    };
    serde_json::to_writer(&mut *w, &json)?;
    writeln!(w)
}

/// Writes the paper's Table 1 plus sizes and time as an aligned table.
pub(crate) fn write_table(w: &mut impl Write, run: &Run<'_>) -> io::Result<()> {
    let s = run.stats;
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

    let [x, y, z] = run.grid.dims;
    writeln!(
        w,
        "{} ({x}x{y}x{z}) -> {}: iso {}, method {}, inside {}{}, {} threads",
        run.input.display(),
        run.output.display(),
        run.params.iso,
        method_name(run.params.method),
        inside_name(run.params.inside),
        if run.params.close { ", closed" } else { "" },
        run.threads
    )?;
    let label_width = rows.iter().map(|(l, _)| l.len()).max().unwrap_or(0);
    let value_width = rows.iter().map(|(_, v)| v.len()).max().unwrap_or(0);
    for (label, value) in &rows {
        writeln!(w, "  {label:<label_width$}  {value:>value_width$}")?;
    }
    Ok(())
}
