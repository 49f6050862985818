//! `tmc info` on a DICOM directory of several series: the series listed
//! (number, modality, description, slices, dims, transfer syntax, whether
//! tmc reads it) instead of an error, so that one can be chosen with
//! `--series`.

use super::raw_input::RawArgs;
use std::io::{self, Write};
use std::path::Path;
use tmc::volume::dicom::SeriesSummary;
use tmc::volume::dicom_series_to_choose;
use tmc::Result;

/// The series of `input` when it is a DICOM directory of more than one
/// series and no `--series` (nor raw option) was given; `None` otherwise
/// (the input is then opened as one volume).
pub(crate) fn several(input: &Path, raw: &RawArgs) -> Result<Option<Vec<SeriesSummary>>> {
    if raw.series.is_some() || raw.segment.is_some() || raw.options().is_some() {
        return Ok(None);
    }
    dicom_series_to_choose(input)
}

/// The listing as `tmc info --json` prints it: one object on one line.
pub(crate) fn write_json(
    w: &mut impl Write,
    input: &Path,
    series: &[SeriesSummary],
) -> io::Result<()> {
    let value = serde_json::json!({
        "input": input.display().to_string(),
        "format": "DICOM",
        "series": series,
    });
    serde_json::to_writer(&mut *w, &value)?;
    writeln!(w)
}

/// The listing as text: one line per series.
pub(crate) fn write_text(
    w: &mut impl Write,
    input: &Path,
    series: &[SeriesSummary],
) -> io::Result<()> {
    writeln!(w, "input   {}", input.display())?;
    writeln!(
        w,
        "format  DICOM, {} series (read one with --series NUMBER or UID)",
        series.len()
    )?;
    for s in series {
        let dims = s
            .dims
            .map_or("-".to_string(), |[x, y, z]| format!("{x} x {y} x {z}"));
        let readable = if s.readable {
            "readable"
        } else {
            "not readable"
        };
        writeln!(
            w,
            "series {}  {}  {}  {} files, {} slices  {dims}  {}  {readable}",
            s.number.as_deref().unwrap_or("-"),
            s.modality.as_deref().unwrap_or("-"),
            s.description
                .as_deref()
                .map_or("(no description)".to_string(), |d| format!("\"{d}\"")),
            s.files,
            s.slices,
            s.transfer_syntaxes.join(", "),
        )?;
        writeln!(w, "  uid   {}", s.uid)?;
        if let Some(note) = &s.note {
            writeln!(w, "  note  {note}")?;
        }
    }
    Ok(())
}
