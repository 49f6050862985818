//! Extractions with the GIL released that stop on Ctrl-C.
//!
//! Python runs signal handlers only on the main thread and only while it
//! holds the GIL, so an extraction that releases the GIL would not notice
//! Ctrl-C until it finished. Here the work runs on its own thread while
//! the calling thread waits for it with the GIL released, waking every
//! [`POLL`] to take the GIL briefly and run the pending handlers. When one
//! raises (`KeyboardInterrupt`, or whatever a user's handler raises), the
//! library's cancel flag stops the work at the next slab, nothing is left
//! at the output path, and the handler's exception is raised.

use crate::errors::to_py;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread looks for signals: well under the half
/// second in which Ctrl-C must stop an extraction.
const POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a new thread with the GIL released, passing it the
/// cancel flag that a Python signal handler's exception sets.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> tmc::Result<T> + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = mpsc::channel::<()>();
            let cancel = &cancel;
            let worker = scope.spawn(move || {
                let result = work(cancel);
                // The receiver lives until the worker is joined.
                let _ = done.send(());
                result
            });
            let mut raised = None;
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if raised.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        cancel.store(true, Ordering::Relaxed);
                        raised = Some(e);
                    }
                }
            }
            let result = worker.join();
            if let Some(e) = raised {
                return Err(e);
            }
            match result {
                Ok(result) => result.map_err(to_py),
                Err(_) => Err(PyRuntimeError::new_err(
                    "tmc: the extraction panicked (a bug: please report it with the input)",
                )),
            }
        })
    })
}
