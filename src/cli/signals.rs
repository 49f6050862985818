//! Signals: SIGINT, SIGTERM and SIGHUP cancel a run cleanly (exit status
//! 130, 143 or 129), and a SIGBUS from a memory-mapped input that shrank is
//! reported as one line instead of a crash.

use signal_hook::consts::{SIGBUS, SIGHUP, SIGINT, SIGTERM};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The signals that cancel a run.
const CANCELLING: [i32; 3] = [SIGINT, SIGTERM, SIGHUP];

/// The cancel flag that SIGINT, SIGTERM and SIGHUP set, and which of them
/// came.
#[derive(Debug, Clone, Default)]
pub(crate) struct Interrupts {
    /// Set by either signal; passed to the pipeline as its cancel flag.
    flag: Arc<AtomicBool>,
    /// The number of the last of them that arrived (0: none).
    signal: Arc<AtomicUsize>,
}

impl Interrupts {
    /// Installs the handlers. The first SIGINT, SIGTERM or SIGHUP only
    /// sets the flag, so the run stops at its next block of rows, plane,
    /// chunk or MiB and removes its temporary output; a second one exits at
    /// once (status 128 + the signal's number) in case something does not
    /// look at the flag, after removing the registered temporary outputs
    /// (see [`tmc::files::fatal_cleanup`]), so that nothing is left at the
    /// output path then either.
    ///
    /// A signal that the process inherited as ignored (SIGINT of a
    /// background job started by a non-interactive shell, SIGHUP under
    /// `nohup`) stays ignored, as the shell convention asks.
    pub(crate) fn install() -> std::io::Result<Interrupts> {
        let interrupts = Interrupts::default();
        let ignored = inherited_ignored();
        for signal in CANCELLING {
            if ignored.contains(&signal) {
                continue;
            }
            // Registered first, so that it runs before the flag is set and
            // only fires on a second signal.
            let flag = Arc::clone(&interrupts.flag);
            let second = move || {
                if flag.load(Ordering::SeqCst) {
                    remove_say_exit(TWICE_MESSAGE, 128 + signal);
                }
            };
            // SAFETY: the action only loads an atomic and, on a second
            // signal, calls `remove_say_exit`, which is async-signal-safe (see
            // there) and never returns; it touches no lock, allocator or
            // Rust state beyond the `Arc`'s atomic, which lives as long as
            // the handler.
            unsafe { signal_hook::low_level::register(signal, second) }?;
            signal_hook::flag::register_usize(
                signal,
                Arc::clone(&interrupts.signal),
                signal as usize,
            )?;
            signal_hook::flag::register(signal, Arc::clone(&interrupts.flag))?;
        }
        Ok(interrupts)
    }

    /// The cancel flag.
    pub(crate) fn flag(&self) -> &AtomicBool {
        &self.flag
    }

    /// The name of the signal that interrupted the run and the exit status
    /// that goes with it (128 + its number), if one did.
    pub(crate) fn received(&self) -> Option<(&'static str, u8)> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            s if s == SIGTERM as usize => Some(("SIGTERM", 128 + SIGTERM as u8)),
            s if s == SIGHUP as usize => Some(("SIGHUP", 128 + SIGHUP as u8)),
            _ => Some(("SIGINT", 128 + SIGINT as u8)),
        }
    }
}

/// Runs `open` (an open or read that can block for good: a FIFO with no
/// writer or reader at the other end) on a thread of its own, and gives up
/// with [`tmc::Error::Interrupted`] once `cancel` is set, so that SIGINT or
/// SIGTERM stops the run there as anywhere else. Nothing has been written
/// when it gives up; the blocked thread ends with the process.
pub(crate) fn interruptible<T: Send + 'static>(
    cancel: Option<&AtomicBool>,
    open: impl FnOnce() -> tmc::Result<T> + Send + 'static,
) -> tmc::Result<T> {
    let Some(cancel) = cancel else {
        return open();
    };
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        // The receiver is gone only if the run gave up: nothing to tell.
        let _ = tx.send(open());
    });
    loop {
        match rx.recv_timeout(std::time::Duration::from_millis(50)) {
            Ok(result) => return result,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                if cancel.load(Ordering::SeqCst) {
                    return Err(tmc::Error::Interrupted);
                }
            }
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err(tmc::Error::Invalid("the opening thread stopped".into()))
            }
        }
    }
}

/// Those of [`CANCELLING`] that the process inherited as ignored, from the
/// `SigIgn` mask of `/proc/self/status` (read before any handler is
/// installed; no `unsafe` needed). Where that file cannot be read (not
/// Linux), none: the handlers are installed as before.
fn inherited_ignored() -> Vec<i32> {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let mask = status
        .lines()
        .find_map(|line| line.strip_prefix("SigIgn:"))
        .and_then(|hex| u64::from_str_radix(hex.trim(), 16).ok())
        .unwrap_or(0);
    ignored_in(mask)
}

/// Those of [`CANCELLING`] set in a signal mask (bit `n - 1` for signal `n`).
fn ignored_in(mask: u64) -> Vec<i32> {
    CANCELLING
        .into_iter()
        .filter(|&signal| mask >> (signal - 1) & 1 == 1)
        .collect()
}

/// The line written on a second SIGINT, SIGTERM or SIGHUP.
const TWICE_MESSAGE: &[u8] =
    b"tmc: error: interrupted twice; stopped at once, the output in progress was removed\n";

/// The line written instead of a fatal handler's `message` when the run
/// had put label files in place that it would have removed had it failed
/// cleanly (see `tmc::files::fatal_cleanup::kept_in_place`).
const KEPT_MESSAGE: &[u8] = b"tmc: error: stopped at once (a second signal, or SIGBUS: the input \
changed under the memory map); the output in progress was removed, but label files finished \
before it were left in place\n";

/// Removes the registered temporary outputs, writes `message` (or
/// [`KEPT_MESSAGE`]) to stderr and exits with `status`, from a signal
/// handler: async-signal-safe (atomic loads, unlink(2), write(2),
/// _exit(2)); never returns.
fn remove_say_exit(message: &'static [u8], status: i32) -> ! {
    tmc::files::fatal_cleanup::unlink_registered();
    let message = match tmc::files::fatal_cleanup::kept_in_place() {
        true => KEPT_MESSAGE,
        false => message,
    };
    // SAFETY: write(2) and _exit(2) are async-signal-safe; the buffer is a
    // static byte string, valid for the whole call. A short or failed write
    // changes nothing: the process exits either way.
    unsafe {
        libc::write(libc::STDERR_FILENO, message.as_ptr().cast(), message.len());
        libc::_exit(status)
    }
}

/// The line written on SIGBUS.
const SIGBUS_MESSAGE: &[u8] = b"tmc: error: input file changed under the memory map (SIGBUS): \
it was truncated or rewritten by another program during the run; no output was written\n";

/// Installs a SIGBUS handler that removes the temporary output, writes one
/// line to stderr and exits with status 1. A memory-mapped input that
/// another program truncates raises SIGBUS on the next read of a lost page;
/// the pipeline's check of the file size before each slab catches most such
/// cases with a clean error, this catches the rest. The temporary output
/// files are registered in [`tmc::files::fatal_cleanup`], whose removal is
/// async-signal-safe; nothing appears at the output path.
pub(crate) fn install_sigbus() -> std::io::Result<()> {
    tmc::files::fatal_cleanup::enable();
    let action = || remove_say_exit(SIGBUS_MESSAGE, 1);
    // SAFETY: the action only calls async-signal-safe functions (see
    // `remove_say_exit`) and never returns, so the faulting instruction is not retried; it
    // touches no lock, allocator or Rust state.
    unsafe { signal_hook::low_level::register(SIGBUS, action) }.map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sigign_mask_names_the_ignored_signals() {
        // SIGHUP is 1, SIGINT 2, SIGTERM 15; bit 12 (SIGPIPE, 13) is not ours.
        assert_eq!(ignored_in(0), Vec::<i32>::new());
        assert_eq!(ignored_in(0b11 | 1 << 12), vec![SIGINT, SIGHUP]);
        assert_eq!(ignored_in(1 << 14), vec![SIGTERM]);
    }
}
