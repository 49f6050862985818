//! The placeholders of output names on the command line: which an option
//! may hold, one error line (before anything is read) for any other, and
//! `{part}`, the part's number of `--part I/N`.
//!
//! An output name is filled in byte for byte ([`tmc::files`]); a
//! `{NAME}` that no run fills in would be written into the file's name
//! without a word (`-o '{nonsense}.ply'` wrote `{nonsense}.ply`), so it is
//! refused, naming it and the placeholders the option takes. Other braces
//! (`{}`, `{a b}`) are literal text. The checks look at the name as given,
//! before `{stem}` puts the input's name (which may hold braces) in it.

use std::path::{Path, PathBuf};
use tmc::part::PartSpec;
use tmc::{Error, Result};

/// The input's name (all outputs).
pub(crate) const STEM: &str = "{stem}";
/// The isovalue (an isosurface's outputs).
pub(crate) const ISO: &str = "{iso}";
/// The label (the files of `--labels`).
pub(crate) const LABEL: &str = "{label}";
/// The part's number I of `--part I/N`.
pub(crate) const PART: &str = "{part}";

/// Fails when `template`, given to `option`, holds a `{NAME}` that is
/// none of `known` (the placeholders this run fills in); `{part}` outside
/// a `--part` run is named as such.
pub(crate) fn check(template: &Path, option: &str, known: &[&str]) -> Result<()> {
    let Some(found) = tmc::files::unknown_placeholder(template, known) else {
        return Ok(());
    };
    let name = template.display();
    if found == PART {
        return Err(Error::Invalid(format!(
            "{name}: {PART} in {option} is the part's number of 'tmc extract --part I/N', which this run is not"
        )));
    }
    Err(Error::Invalid(format!(
        "{name}: unknown placeholder {found} in {option}; it may use {}",
        list(known)
    )))
}

/// The placeholders of an isosurface's `-o` and `--preview`:
/// `{stem}`, `{iso}`, and `{part}` with `--part`.
pub(crate) fn isosurface(part: Option<PartSpec>) -> Vec<&'static str> {
    let mut known = vec![STEM, ISO];
    known.extend(part.map(|_| PART));
    known
}

/// The placeholders of `--labels`' `-o`: `{stem}`, `{label}`, and
/// `{part}` with `--part`.
pub(crate) fn labels(part: Option<PartSpec>) -> Vec<&'static str> {
    let mut known = vec![STEM, LABEL];
    known.extend(part.map(|_| PART));
    known
}

/// `template` with `{part}` replaced by the part's number I (`1` to N),
/// as the part files of a run are named (`-o 'parts/{label}.{part}.tmesh'`
/// gives `parts/7.2.tmesh` for label 7 of part 2/N); unchanged without
/// `--part`.
pub(crate) fn fill_part(template: &Path, part: Option<PartSpec>) -> PathBuf {
    match part {
        Some(spec) => tmc::files::fill_placeholder(template, PART, &spec.index.to_string()),
        None => template.to_path_buf(),
    }
}

/// `{stem}, {iso} and {part}`.
fn list(known: &[&str]) -> String {
    match known {
        [] => "none".into(),
        [one] => (*one).into(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line names the placeholder, the option and what it may use.
    #[test]
    fn an_unknown_placeholder_is_named_with_the_known_ones() {
        let line = check(Path::new("out/{nonsense}.ply"), "-o", &isosurface(None))
            .unwrap_err()
            .to_string();
        assert_eq!(
            line,
            "out/{nonsense}.ply: unknown placeholder {nonsense} in -o; it may use {stem} and {iso}"
        );
        let part = Some(PartSpec::parse("2/3").unwrap());
        let line = check(Path::new("{lable}.tmesh"), "-o", &labels(part))
            .unwrap_err()
            .to_string();
        assert!(
            line.ends_with("it may use {stem}, {label} and {part}"),
            "{line}"
        );
        let line = check(Path::new("p{part}.tmesh"), "-o", &isosurface(None))
            .unwrap_err()
            .to_string();
        assert!(line.contains("--part I/N"), "{line}");
        assert!(check(Path::new("p{part}.tmesh"), "-o", &isosurface(part)).is_ok());
        assert!(check(Path::new("{}{a b}.ply"), "-o", &[]).is_ok());
    }

    #[test]
    fn part_is_filled_with_its_number() {
        let part = Some(PartSpec::parse("2/3").unwrap());
        let template = Path::new("parts/{label}.{part}.tmesh");
        assert_eq!(
            fill_part(template, part),
            Path::new("parts/{label}.2.tmesh")
        );
        assert_eq!(fill_part(template, None), template);
    }
}
