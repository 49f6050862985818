//! [`Finisher`]: label files finished while the pass still runs.
//!
//! Finishing a label's file is mostly waiting for the disk: its last bytes
//! written, the file synced, renamed into place (on ext4, a rename over
//! an older file of the same name waits for the disk as well). Done for
//! every label after the pass, that waiting came after all the work, a
//! sixth of a 114-label pass's time. A label whose samples end before the
//! last plane has its whole mesh long before the pass ends (see
//! [`crate::stream::last_label_chunks`]), so its file is handed to one of
//! these threads then and finished while the workers go on.
//!
//! The threads only finish files; what they report is settled with the
//! other labels' files when the pass has ended ([`super::LabelFiles`]):
//! all are kept, or none, a file that one replaced put back
//! ([`SetAside`]).

use super::set_aside::SetAside;
use crate::mesh::{MeshSink, Totals};
use crate::Result;
use crossbeam::channel::{unbounded, Receiver, Sender};
use std::path::PathBuf;
use std::thread::JoinHandle;

/// A label's file to finish: the label's index, its sink, the totals of
/// the chunks it was given and the path the sink puts it at.
pub(super) struct Job {
    pub index: usize,
    pub sink: Box<dyn MeshSink + Send>,
    pub totals: Totals,
    pub target: PathBuf,
}

/// What finishing a label's file gave: the file it replaced, if any, or
/// the error.
pub(super) type Finished = Result<Option<SetAside>>;

/// Threads that finish label files handed to them (see the module
/// documentation). Dropped, it waits for the files handed over.
pub(super) struct Finisher {
    jobs: Option<Sender<Job>>,
    done: Receiver<(usize, Finished)>,
    threads: Vec<JoinHandle<()>>,
}

impl Finisher {
    /// Starts `threads` threads (at least one).
    pub fn start(threads: usize) -> Finisher {
        let (jobs, queue) = unbounded::<Job>();
        let (report, done) = unbounded();
        let threads = (0..threads.max(1))
            .map(|_| {
                let queue = queue.clone();
                let report = report.clone();
                std::thread::spawn(move || {
                    for mut job in queue {
                        let result = SetAside::before_replacing(&job.target)
                            .and_then(|aside| job.sink.finish(&job.totals).map(|()| aside));
                        if result.is_ok() {
                            crate::files::fatal_cleanup::note_kept_in_place(1);
                        }
                        // The receiver lives as long as the finisher.
                        let _ = report.send((job.index, result));
                    }
                })
            })
            .collect();
        Finisher {
            jobs: Some(jobs),
            done,
            threads,
        }
    }

    /// Where files are handed over.
    pub fn sender(&self) -> Sender<Job> {
        self.jobs.clone().expect("the finisher runs until joined")
    }

    /// Waits for every file handed over (the senders given out must be
    /// dropped first) and gives each one's result, by label index, in the
    /// order they were finished.
    pub fn join(mut self) -> Vec<(usize, Finished)> {
        self.stop();
        self.done.try_iter().collect()
    }

    /// Lets the threads run out of files and waits for them.
    fn stop(&mut self) {
        self.jobs = None;
        for thread in self.threads.drain(..) {
            // A finishing thread that panicked has reported nothing for its
            // file, which then counts as not finished.
            let _ = thread.join();
        }
    }
}

impl Drop for Finisher {
    fn drop(&mut self) {
        self.stop();
    }
}
