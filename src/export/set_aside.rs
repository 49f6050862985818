//! [`SetAside`]: the file a label's new file replaces, kept under a second
//! name until the run is settled, so that a run that fails puts it back.
//!
//! A label pass renames each label's finished file over the path it was
//! asked for, some while the pass still runs
//! ([`super::LabelFiles::finish_early`]). A run that then fails (an error
//! in a later label, Ctrl-C) takes its files back: without this, a file
//! that replaced one of an earlier run into the same directory was
//! removed, and the earlier file with it. Linked aside first, the earlier
//! file is renamed back instead; a run that succeeds drops the link.

use crate::files::fatal_cleanup::{self, Registered};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// A second name (a hard link in the same directory) of the file at
/// `target`, taken before a new file is renamed over it. Dropped, the
/// second name goes (the new file stays); [`SetAside::restore`] renames it
/// back over `target`.
pub(super) struct SetAside {
    link: tempfile::TempPath,
    target: PathBuf,
    /// A run stopped at once (a second signal) removes the link, keeping
    /// the new file (what it says it leaves, see `fatal_cleanup`).
    _registered: Option<Registered>,
}

impl SetAside {
    /// Links the regular file at `target`, if there is one, aside; `None`
    /// when there is nothing to keep (no file, or not a regular one).
    pub fn before_replacing(target: &Path) -> Result<Option<SetAside>> {
        match std::fs::symlink_metadata(target) {
            Ok(meta) if meta.is_file() => {}
            _ => return Ok(None),
        }
        let dir = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let link = tempfile::Builder::new()
            .prefix(".tmc-")
            .suffix(".old")
            .make_in(dir, |path| std::fs::hard_link(target, path))
            .map_err(|e| {
                Error::Invalid(format!(
                    "{}: cannot keep the existing file while it is replaced: {e}",
                    target.display()
                ))
            })?
            .into_temp_path();
        Ok(Some(SetAside {
            _registered: fatal_cleanup::register(&link),
            link,
            target: target.to_path_buf(),
        }))
    }

    /// Puts the file set aside back at its path, over the new one.
    pub fn restore(self) -> Result<()> {
        let SetAside { link, target, .. } = self;
        link.persist(&target)
            .map_err(|e| Error::io(&target, e.error))
    }
}

#[cfg(test)]
mod tests {
    use super::SetAside;

    /// The earlier file comes back after a new one replaced it, or goes
    /// (its second name) when the new one is kept; no file, nothing kept.
    #[test]
    fn an_earlier_file_is_put_back_or_let_go() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("1.tmesh");
        assert!(SetAside::before_replacing(&target).unwrap().is_none());
        let replace = |text: &str| {
            let new = dir.path().join("new");
            std::fs::write(&new, text).unwrap();
            std::fs::rename(&new, &target).unwrap();
        };
        std::fs::write(&target, "earlier").unwrap();
        let aside = SetAside::before_replacing(&target).unwrap().unwrap();
        replace("later");
        aside.restore().unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "earlier");
        let aside = SetAside::before_replacing(&target).unwrap().unwrap();
        replace("later");
        drop(aside);
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "later");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "only the file, no second name left");
    }
}
