//! Output names with placeholders (`{stem}`, `{iso}`, `{label}`) filled
//! in, byte for byte: the rest of the name is kept as it is, bytes that
//! are no UTF-8 included (a name through `to_string_lossy` would lose
//! them and name a directory that does not exist).

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// `path` with every `placeholder` replaced by `value`.
pub fn fill_placeholder(path: &Path, placeholder: &str, value: &str) -> PathBuf {
    let (bytes, from) = (to_bytes(path), placeholder.as_bytes());
    if from.is_empty() {
        return path.to_path_buf();
    }
    let mut out = Vec::with_capacity(bytes.len() + value.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i..].starts_with(from) {
            out.extend_from_slice(value.as_bytes());
            i += from.len();
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    from_bytes(out)
}

/// `path` with `text` inserted before the extension of its last
/// component (at its end when the name has no dot): `out/m.ply` and
/// `_iso{iso}` give `out/m_iso{iso}.ply`.
pub fn insert_before_extension(path: &Path, text: &str) -> PathBuf {
    let mut bytes = to_bytes(path);
    let name_start = bytes.iter().rposition(|&b| b == b'/').map_or(0, |i| i + 1);
    let dot = bytes[name_start..]
        .iter()
        .rposition(|&b| b == b'.')
        .map_or(bytes.len(), |i| name_start + i);
    bytes.splice(dot..dot, text.bytes());
    from_bytes(bytes)
}

/// The first placeholder-like `{NAME}` in `path` that is none of `known`
/// (each written with its braces, `"{stem}"`), if any. `NAME` is one or
/// more ASCII letters, digits or underscores: a mistyped or unsupported
/// placeholder (`{Stem}`, `{nonsense}`) would otherwise be written into
/// the file's name without a word, while other braces (`{}`, `{a b}`,
/// `{1.5}`... and a lone `{`) stay literal text, as they always were.
pub fn unknown_placeholder(path: &Path, known: &[&str]) -> Option<String> {
    let bytes = to_bytes(path);
    let is_name = |b: &u8| b.is_ascii_alphanumeric() || *b == b'_';
    let mut i = 0;
    while let Some(open) = bytes[i..].iter().position(|&b| b == b'{').map(|p| p + i) {
        let name_len = bytes[open + 1..].iter().take_while(|b| is_name(b)).count();
        let close = open + 1 + name_len;
        if name_len > 0 && bytes.get(close) == Some(&b'}') {
            let found = String::from_utf8_lossy(&bytes[open..=close]).into_owned();
            if !known.contains(&found.as_str()) {
                return Some(found);
            }
            i = close + 1;
        } else {
            i = open + 1;
        }
    }
    None
}

/// Whether `path` contains `placeholder`.
pub fn has_placeholder(path: &Path, placeholder: &str) -> bool {
    let from = placeholder.as_bytes();
    !from.is_empty() && to_bytes(path).windows(from.len()).any(|w| w == from)
}

#[cfg(unix)]
fn to_bytes(path: &Path) -> Vec<u8> {
    use std::os::unix::ffi::OsStrExt;
    path.as_os_str().as_bytes().to_vec()
}

#[cfg(unix)]
fn from_bytes(bytes: Vec<u8>) -> PathBuf {
    use std::os::unix::ffi::OsStringExt;
    PathBuf::from(OsString::from_vec(bytes))
}

#[cfg(not(unix))]
fn to_bytes(path: &Path) -> Vec<u8> {
    path.to_string_lossy().into_owned().into_bytes()
}

#[cfg(not(unix))]
fn from_bytes(bytes: Vec<u8>) -> PathBuf {
    PathBuf::from(OsString::from(String::from_utf8_lossy(&bytes).into_owned()))
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::ffi::OsStrExt;

    #[test]
    fn names_that_are_no_utf8_keep_their_bytes() {
        let dir = std::ffi::OsStr::from_bytes(b"nu\xffd");
        let template = Path::new(dir).join("{stem}_{label}.ply");
        let filled = fill_placeholder(&fill_placeholder(&template, "{stem}", "v"), "{label}", "7");
        assert_eq!(filled, Path::new(dir).join("v_7.ply"));
        assert!(has_placeholder(&template, "{label}"));
        assert!(!has_placeholder(&filled, "{label}"));
        let inserted = insert_before_extension(&Path::new(dir).join("m.ply"), "_iso{iso}");
        assert_eq!(inserted, Path::new(dir).join("m_iso{iso}.ply"));
        assert_eq!(
            insert_before_extension(Path::new("a.d/mesh"), "_x"),
            Path::new("a.d/mesh_x")
        );
    }

    /// `{NAME}` outside `known` is found (the first one), whatever the
    /// bytes around it; other braces are literal text.
    #[test]
    fn unknown_placeholders_are_found_and_other_braces_are_text() {
        let known = ["{stem}", "{iso}"];
        let dir = std::ffi::OsStr::from_bytes(b"nu\xffd");
        for (name, unknown) in [
            ("{stem}_{iso}.ply", None),
            ("{nonsense}.ply", Some("{nonsense}")),
            ("{stem}_{Stem}_{x}.ply", Some("{Stem}")),
            ("{{stem}}.ply", None),
            ("{}_{a b}_{1.5}_{_.ply", None),
            ("{lab{label}.ply", Some("{label}")),
            ("a{iso}{part}", Some("{part}")),
        ] {
            let path = Path::new(dir).join(name);
            assert_eq!(
                unknown_placeholder(&path, &known).as_deref(),
                unknown,
                "{name}"
            );
        }
        assert_eq!(
            unknown_placeholder(Path::new("{label}.ply"), &[]).as_deref(),
            Some("{label}")
        );
    }
}
