//! Samples written as text: NRRD `encoding: ascii`, MetaImage
//! `BinaryData = False`, legacy VTK `ASCII` and `.vti` `format="ascii"`.
//! The numbers are separated by whitespace or commas; there must be one per
//! sample (and no more, unless other data may follow), and each must be a
//! value of the declared type (an integer in range for integer types). The
//! samples are held in memory in that type, so the volume reports it as
//! stored.

use super::raw::{dims_text, Layout, RawVolume};
use super::{encode_samples, Endian, ScalarType};
use crate::error::make_room;
use crate::{Error, Result};
use std::io::BufRead;
use std::path::Path;

/// Parses the text samples of `layout` (whose offset must be 0) from the
/// rest of `reader`, read from `path`. With `more_may_follow` (legacy VTK's
/// further arrays) reading stops after the samples; otherwise a value after
/// them is an error.
pub(crate) fn read_ascii(
    path: &Path,
    mut reader: impl BufRead,
    layout: Layout,
    more_may_follow: bool,
) -> Result<RawVolume> {
    let fail = |what: String| Error::Format(format!("{}: {what}", path.display()));
    let (dims, scalar) = (layout.grid.dims, layout.scalar);
    let count = dims
        .iter()
        .try_fold(1usize, |acc, &d| acc.checked_mul(d))
        .filter(|n| n.checked_mul(scalar.size()).is_some())
        .ok_or_else(|| fail(format!("dims {} are too large", dims_text(dims))))?;
    // Room grows with the values read (up to a first 64 MiB), so that a
    // header declaring far more samples than the text holds ends in the
    // count error below, not in an attempt to allocate them all.
    let mut bytes =
        crate::error::try_vec::<u8>("the ascii samples", (count * scalar.size()).min(1 << 26))?;
    let mut sample = [0u8; 8];
    let mut values = 0usize;
    let mut line = Vec::new();
    while !(more_may_follow && values == count) {
        line.clear();
        if reader
            .read_until(b'\n', &mut line)
            .map_err(|e| Error::io(path, e))?
            == 0
        {
            break;
        }
        let text = String::from_utf8_lossy(&line);
        for word in text.split(|c: char| c.is_whitespace() || c == ',') {
            if word.is_empty() || (more_may_follow && values == count) {
                continue;
            }
            if values == count {
                return Err(fail(format!(
                    "ascii data holds more than the {count} values of {} {scalar}",
                    dims_text(dims)
                )));
            }
            let v = value(word, scalar)
                .map_err(|why| fail(format!("ascii value '{word}' at sample {values} {why}")))?;
            let out = &mut sample[..scalar.size()];
            encode_samples(scalar, Endian::Little, &[v], out);
            make_room(&mut bytes, out.len(), "the ascii samples")?;
            bytes.extend_from_slice(out);
            values += 1;
        }
    }
    if values < count {
        return Err(fail(format!(
            "ascii data holds {values} values, {} {scalar} needs {count}",
            dims_text(dims)
        )));
    }
    let layout = Layout {
        endian: Endian::Little,
        ..layout
    };
    RawVolume::from_bytes(path, bytes, layout)
}

/// The number `word` as a value of `scalar`, or why it is not one.
fn value(word: &str, scalar: ScalarType) -> std::result::Result<f64, String> {
    let v: f64 = word.parse().map_err(|_| "is not a number".to_string())?;
    let (lo, hi) = match scalar {
        ScalarType::U8 => (0.0, f64::from(u8::MAX)),
        ScalarType::I8 => (f64::from(i8::MIN), f64::from(i8::MAX)),
        ScalarType::U16 => (0.0, f64::from(u16::MAX)),
        ScalarType::I16 => (f64::from(i16::MIN), f64::from(i16::MAX)),
        ScalarType::U32 => (0.0, f64::from(u32::MAX)),
        ScalarType::I32 => (f64::from(i32::MIN), f64::from(i32::MAX)),
        ScalarType::F32 if v.is_finite() && !(v as f32).is_finite() => {
            return Err(format!("is outside the range of {scalar}"))
        }
        ScalarType::F32 | ScalarType::F64 => return Ok(v),
        ScalarType::F16 if v.is_finite() && !half::f16::from_f64(v).is_finite() => {
            return Err(format!("is outside the range of {scalar}"))
        }
        ScalarType::F16 => return Ok(v),
        // As `f64` (what the samples are read as): exact within ±2^53.
        ScalarType::I64 => (i64::MIN as f64, i64::MAX as f64),
        ScalarType::U64 => (0.0, u64::MAX as f64),
    };
    if v.fract() != 0.0 || !(lo..=hi).contains(&v) {
        return Err(format!("does not fit {scalar} (integers {lo} to {hi})"));
    }
    Ok(v)
}
