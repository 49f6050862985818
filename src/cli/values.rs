//! Parsers of option values: finite numbers, `X,Y,Z` triples, sample types.

use tmc::volume::ScalarType;

/// Parses a finite number (`--iso`).
pub(crate) fn finite(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("'{text}' is not a finite number"))
    }
}

/// Parses a label (`--background`): an integer, or a whole number written
/// as a float (`3.0`, `-0`, `1e3`), as a float label map stores its labels,
/// within ±2^53 (the labels a label map's scan accepts).
pub(crate) fn label(text: &str) -> Result<i64, String> {
    const LIMIT: f64 = (1u64 << 53) as f64;
    if let Ok(v) = text.trim().parse::<i64>() {
        return Ok(v);
    }
    match text.trim().parse::<f64>() {
        Ok(v) if v.fract() == 0.0 && v.abs() <= LIMIT => Ok(v as i64),
        _ => Err(format!(
            "'{text}' is not a label: a label is a whole number within ±2^53"
        )),
    }
}

/// What `--labels` asks for: every label of the map, or a list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum LabelSpec {
    /// `all`: every value present but the background.
    All,
    /// `L1,L2,...`: these labels, in this order, each once.
    List(Vec<i64>),
}

/// Parses `--labels`: `all` or `L1,L2,...`, integers, each once (a usage
/// error otherwise, found before the map is read).
pub(crate) fn label_spec(text: &str) -> Result<LabelSpec, String> {
    if text == "all" {
        return Ok(LabelSpec::All);
    }
    let mut labels = Vec::new();
    for item in text.split(',') {
        let l: i64 = item
            .trim()
            .parse()
            .map_err(|_| format!("'{item}' is not an integer (give 'all' or L1,L2,...)"))?;
        if labels.contains(&l) {
            return Err(format!("{l} is given twice"));
        }
        labels.push(l);
    }
    Ok(LabelSpec::List(labels))
}

/// The most worker threads `--threads` takes: more is a typo, and starting
/// that many threads would take longer than any extraction.
const MAX_THREADS: usize = 1024;

/// Parses `--threads N` (0: all cores; at most [`MAX_THREADS`]).
pub(crate) fn threads(text: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number of threads"))?;
    if n > MAX_THREADS {
        return Err(format!("{n} threads: at most {MAX_THREADS}"));
    }
    Ok(n)
}

/// Parses three comma-separated values (an `x` also separates: `64x64x93`).
fn triple<T: std::str::FromStr>(text: &str) -> Result<[T; 3], String> {
    let parts: Vec<&str> = text.split([',', 'x', 'X']).map(str::trim).collect();
    let bad = || format!("'{text}' is not three comma-separated values X,Y,Z");
    match parts[..] {
        [a, b, c] => Ok([
            a.parse().map_err(|_| bad())?,
            b.parse().map_err(|_| bad())?,
            c.parse().map_err(|_| bad())?,
        ]),
        _ => Err(bad()),
    }
}

/// Parses `--dims X,Y,Z` (each at least 1).
pub(crate) fn dims(text: &str) -> Result<[usize; 3], String> {
    let d: [usize; 3] = triple(text)?;
    if d.contains(&0) {
        return Err(format!("'{text}': every dimension must be at least 1"));
    }
    Ok(d)
}

/// Parses `--spacing X,Y,Z` (finite, positive).
pub(crate) fn spacing(text: &str) -> Result<[f64; 3], String> {
    let s: [f64; 3] = triple_floats(text)?;
    if s.iter().any(|v| *v <= 0.0) {
        return Err(format!("'{text}': spacing must be positive"));
    }
    Ok(s)
}

/// Parses `--origin X,Y,Z` (finite).
pub(crate) fn origin(text: &str) -> Result<[f64; 3], String> {
    triple_floats(text)
}

/// Three finite numbers separated by commas (no `x`: it is not a number).
fn triple_floats(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let bad = || format!("'{text}' is not three comma-separated finite numbers X,Y,Z");
    match parts[..] {
        [a, b, c] => {
            let mut out = [0.0; 3];
            for (o, p) in out.iter_mut().zip([a, b, c]) {
                *o = finite(p).map_err(|_| bad())?;
            }
            Ok(out)
        }
        _ => Err(bad()),
    }
}

/// Parses `--dtype`.
pub(crate) fn dtype(text: &str) -> Result<ScalarType, String> {
    text.parse::<ScalarType>().map_err(|e| e.to_string())
}

/// Parses a byte count with an optional binary suffix: `1048576`, `512K`,
/// `512M`, `4G`, `1T` (also `512MiB`, `4GB`: powers of 1024 either way).
pub(crate) fn bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let bad = || {
        format!(
            "'{text}' is not a byte count (a whole number, optionally with K, M, G or T: e.g. 1048576, 512M, 4G)"
        )
    };
    let too_large = || format!("'{text}' is too large");
    let digits = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, suffix) = t.split_at(digits);
    let number: u64 = match number.parse() {
        Ok(n) => n,
        // All digits, but more than 64 bits hold.
        Err(_) if digits > 0 => return Err(too_large()),
        Err(_) => return Err(bad()),
    };
    let shift = match suffix.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 0,
        "K" | "KB" | "KIB" => 10,
        "M" | "MB" | "MIB" => 20,
        "G" | "GB" | "GIB" => 30,
        "T" | "TB" | "TIB" => 40,
        _ => return Err(bad()),
    };
    number.checked_mul(1u64 << shift).ok_or_else(too_large)
}

#[cfg(test)]
mod tests {
    use super::bytes;

    #[test]
    fn byte_counts_take_binary_suffixes() {
        assert_eq!(bytes("1000"), Ok(1000));
        assert_eq!(bytes("512M"), Ok(512 << 20));
        assert_eq!(bytes("4G"), Ok(4 << 30));
        assert_eq!(bytes("2gib"), Ok(2 << 30));
        assert_eq!(bytes("64k"), Ok(64 << 10));
        assert!(bytes("").is_err());
        assert!(bytes("M").is_err());
        assert!(bytes("1.5G").is_err());
        assert!(bytes("-1").is_err());
        assert_eq!(
            bytes("99999999999T"),
            Err("'99999999999T' is too large".into())
        );
        assert_eq!(
            bytes("99999999999999999999"),
            Err("'99999999999999999999' is too large".into())
        );
        assert!(bytes("1.5G").unwrap_err().contains("a whole number"));
    }
}
