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
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

/// How often the waiting thread looks for signals: well under the half
/// second in which Ctrl-C must stop an extraction.
const POLL: Duration = Duration::from_millis(50);

/// What the waiting thread and the work share: the cancel flag, and the
/// cell layers done and in all as the work reports them
/// ([`Watch::progress`], for `PipelineOptions::progress`).
pub(crate) struct Watch {
    /// Set when a signal handler or the progress callback raised.
    pub cancel: AtomicBool,
    counts: Arc<Counts>,
    report: Box<dyn Fn(&tmc::Progress) + Sync + Send>,
}

/// Cell layers done and in all; `usize::MAX` done before the first report.
struct Counts {
    done: AtomicUsize,
    total: AtomicUsize,
}

impl Watch {
    fn new() -> Watch {
        let counts = Arc::new(Counts {
            done: AtomicUsize::new(usize::MAX),
            total: AtomicUsize::new(0),
        });
        let kept = Arc::clone(&counts);
        Watch {
            cancel: AtomicBool::new(false),
            counts,
            report: Box::new(move |p: &tmc::Progress| {
                kept.total.store(p.layers_total, Ordering::Relaxed);
                kept.done.store(p.layers_done, Ordering::Relaxed);
            }),
        }
    }

    /// The callback for `PipelineOptions::progress`: it only stores the
    /// counts, which the waiting thread hands to Python.
    pub(crate) fn progress(&self) -> &(dyn Fn(&tmc::Progress) + Sync) {
        &*self.report
    }

    /// `(done, total)` as last reported, `None` before the first report.
    fn counts(&self) -> Option<(usize, usize)> {
        let done = self.counts.done.load(Ordering::Relaxed);
        (done != usize::MAX).then(|| (done, self.counts.total.load(Ordering::Relaxed)))
    }
}

/// Runs `work` on a new thread with the GIL released, passing it the
/// cancel flag that a Python signal handler's exception sets.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> tmc::Result<T> + Send,
) -> PyResult<T> {
    run_watched(py, None, |watch| work(&watch.cancel))
}

/// [`run`], with `progress` (a Python callable, or `None`) called as
/// `progress(done, total)` in cell layers on the calling thread, with the
/// GIL, when the counts the work reports through [`Watch::progress`] have
/// changed since the last call (at most every [`POLL`]), and once more at
/// the end of a run that succeeded. An exception it raises stops the work
/// as Ctrl-C does and is raised.
pub(crate) fn run_watched<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Watch) -> tmc::Result<T> + Send,
) -> PyResult<T> {
    let watch = Watch::new();
    let progress = progress.map(|p| p.clone().unbind());
    let mut sent = None;
    let mut tell = |py: Python<'_>| -> PyResult<()> {
        match (&progress, watch.counts()) {
            (Some(callback), Some(counts)) if sent != Some(counts) => {
                sent = Some(counts);
                callback.call1(py, counts).map(drop)
            }
            _ => Ok(()),
        }
    };
    let outcome = py.detach(|| {
        std::thread::scope(|scope| {
            let (done, finished) = mpsc::channel::<()>();
            let watch = &watch;
            let worker = scope.spawn(move || {
                let result = work(watch);
                // The receiver lives until the worker is joined.
                let _ = done.send(());
                result
            });
            let mut raised = None;
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if raised.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals().and_then(|()| tell(py)))
                    {
                        watch.cancel.store(true, Ordering::Relaxed);
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
    })?;
    // The last counts (all layers done) of a run that succeeded.
    tell(py)?;
    Ok(outcome)
}
