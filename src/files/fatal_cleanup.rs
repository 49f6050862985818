//! The temporary output files a fatal-signal handler removes before the
//! process exits (the CLI's SIGBUS handler: a memory-mapped input that
//! shrank under the map; and its handler of a second SIGINT, SIGTERM or
//! SIGHUP, which exits at once).
//!
//! A signal handler may not allocate, lock or run destructors, so the
//! paths are kept as C strings behind atomic pointers in a fixed table: the
//! handler only loads the pointers and calls `unlink(2)`, which is
//! async-signal-safe. A registered string is never freed (another thread's
//! handler could be reading it), so each registration leaks its path,
//! which is why registering is off until [`enable`] is called (the CLI
//! does, once per run; a library user who installs no handler leaks
//! nothing).

use std::ffi::{c_char, CString};
use std::path::Path;
use std::ptr::null_mut;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicUsize, Ordering};

/// Temporary files that can be registered at once (an extraction has one
/// output; more are simply not removed by the handler).
const SLOTS: usize = 8;

/// A table of registered paths. The process has one, [`TABLE`]; the unit
/// test below uses its own, so that it never unlinks the temporary files
/// of tests running beside it.
pub(crate) struct Table {
    enabled: AtomicBool,
    paths: [AtomicPtr<c_char>; SLOTS],
}

/// The process's table, the one the signal handlers empty.
static TABLE: Table = Table::new();

/// Makes [`AtomicFile`](super::AtomicFile) register its temporary file for
/// [`unlink_registered`] from now on.
pub fn enable() {
    TABLE.enable();
}

/// Registers `path` in the process's table (see [`Table::register`]).
pub(crate) fn register(path: &Path) -> Option<Registered> {
    TABLE.register(path)
}

/// Outputs put in place by a run that may still fail: a label pass's
/// files finished during the pass (`export::LabelFiles::finish_early`),
/// which the run removes again if it fails. A fatal handler cannot (it
/// removes registered temporary files only), so it asks
/// [`kept_in_place`] and says they were left.
static KEPT: AtomicUsize = AtomicUsize::new(0);

/// `count` more (or, negative, fewer) outputs put in place by a run that
/// may still fail (see [`kept_in_place`]).
pub fn note_kept_in_place(count: isize) {
    match usize::try_from(count) {
        Ok(more) => KEPT.fetch_add(more, Ordering::Relaxed),
        Err(_) => KEPT.fetch_sub(count.unsigned_abs(), Ordering::Relaxed),
    };
}

/// Whether a run that may still fail has put outputs in place that a fatal
/// handler would leave there. Async-signal-safe: one atomic load.
pub fn kept_in_place() -> bool {
    KEPT.load(Ordering::Relaxed) > 0
}

/// Removes every path registered in the process's table.
/// Async-signal-safe: atomic loads and `unlink(2)` only, no allocation or
/// lock; meant for a signal handler that exits right after.
pub fn unlink_registered() {
    TABLE.unlink_registered();
}

/// A registration of one temporary path: its slot in a table, emptied
/// when this is dropped (the file is committed or removed); the string is
/// leaked on purpose (see the module documentation).
#[derive(Debug)]
pub(crate) struct Registered {
    table: &'static Table,
    slot: usize,
}

impl std::fmt::Debug for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("fatal_cleanup::Table")
    }
}

impl Drop for Registered {
    fn drop(&mut self) {
        self.table.paths[self.slot].store(null_mut(), Ordering::SeqCst);
    }
}

impl Table {
    /// An empty table with registering off.
    const fn new() -> Table {
        Table {
            enabled: AtomicBool::new(false),
            paths: [const { AtomicPtr::new(null_mut()) }; SLOTS],
        }
    }

    fn enable(&self) {
        self.enabled.store(true, Ordering::SeqCst);
    }

    /// Registers `path` to be removed by [`Table::unlink_registered`];
    /// `None` when registering is not enabled, the table is full or the
    /// path holds a NUL.
    fn register(&'static self, path: &Path) -> Option<Registered> {
        if !self.enabled.load(Ordering::SeqCst) {
            return None;
        }
        use std::os::unix::ffi::OsStrExt;
        let raw = CString::new(path.as_os_str().as_bytes()).ok()?.into_raw();
        for (slot, entry) in self.paths.iter().enumerate() {
            if entry
                .compare_exchange(null_mut(), raw, Ordering::SeqCst, Ordering::SeqCst)
                .is_ok()
            {
                return Some(Registered { table: self, slot });
            }
        }
        // Every slot is taken: the string stays leaked (a few bytes, and only
        // with more than SLOTS outputs open at once), which keeps this module's
        // unsafe code to the handler's unlink.
        None
    }

    /// Removes every registered path (async-signal-safe, see
    /// [`unlink_registered`]).
    fn unlink_registered(&self) {
        for entry in &self.paths {
            let path = entry.load(Ordering::SeqCst);
            if !path.is_null() {
                // SAFETY: a non-null slot holds a NUL-terminated string from
                // `CString::into_raw` that is never freed, so the pointer stays
                // valid; unlink(2) is async-signal-safe. A failure (the file was
                // already renamed or removed) changes nothing.
                unsafe {
                    libc::unlink(path);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Not the process's table: unlinking everything in that one would
    /// remove the temporary outputs of other tests running at the same time.
    static TEST_TABLE: Table = Table::new();

    #[test]
    fn a_registered_file_is_unlinked_and_an_unregistered_one_is_not() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.tmp"), dir.path().join("b.tmp"));
        std::fs::write(&a, b"a").unwrap();
        std::fs::write(&b, b"b").unwrap();
        assert!(TEST_TABLE.register(&a).is_none(), "registering is off");
        TEST_TABLE.enable();
        let ra = TEST_TABLE.register(&a).expect("a slot");
        let rb = TEST_TABLE.register(&b).expect("a slot");
        drop(rb);
        TEST_TABLE.unlink_registered();
        assert!(!a.exists());
        assert!(b.exists());
        drop(ra);
    }
}
