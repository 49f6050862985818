//! Third-party decoders run so that a panic in them is an error, not a crash.
//!
//! Pixel-data codecs (RLE, JPEG) are other crates' code; a damaged file can
//! make one of them panic (an index out of bounds in the RLE decoder was
//! found by fuzzing). [`guarded`] turns such a panic into an error for that
//! file. While it runs, [`in_guarded_call`] is true on the thread, so that a
//! panic hook can stay silent about a panic that will be reported as an
//! error line.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};

thread_local! {
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`; a panic in it becomes `Err` with the panic's message.
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    let outer = GUARDED.with(|g| g.replace(true));
    // Nothing `f` borrows is used after a panic but to drop it.
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(outer));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into())
    })
}

/// Whether this thread is inside a guarded decoder call (a panic here is caught and
/// reported as an error by the reader).
pub fn in_guarded_call() -> bool {
    GUARDED.with(|g| g.get())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_error_and_the_flag_is_restored() {
        assert!(!in_guarded_call());
        assert_eq!(guarded(|| 7), Ok(7));
        let e = guarded(|| -> u8 {
            assert!(in_guarded_call());
            panic!("index out of bounds")
        });
        assert_eq!(e, Err("index out of bounds".to_string()));
        assert!(!in_guarded_call());
    }
}
