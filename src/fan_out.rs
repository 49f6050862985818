//! Independent jobs spread over scoped threads, their results in the jobs'
//! order: the label scan's runs of planes (`volume::labels`) and the label
//! files finished after a one-pass extraction (`tmc extract --labels`).
//!
//! The calling thread works too, taking jobs from the same queue as the
//! threads it starts, so every job is done even when no thread starts (a
//! failed spawn costs time, never a job), and a panic in a job is resumed
//! in the caller. Which thread did which job never shows in the result.

use std::sync::{Mutex, PoisonError};

/// `work(k, job)` for every `k`-th job of `jobs`, on up to `threads`
/// threads (this one among them; 0 and 1 mean this one alone); the results
/// in the order of `jobs`.
pub fn fan_out<J, R, F>(jobs: Vec<J>, threads: usize, work: F) -> Vec<R>
where
    J: Send,
    R: Send,
    F: Fn(usize, J) -> R + Sync,
{
    let threads = threads.clamp(1, jobs.len().max(1));
    let queue = Mutex::new(jobs.into_iter().enumerate());
    let next = || queue.lock().unwrap_or_else(PoisonError::into_inner).next();
    let run = || {
        let mut done = Vec::new();
        while let Some((k, job)) = next() {
            done.push((k, work(k, job)));
        }
        done
    };
    let mut done: Vec<(usize, R)> = if threads == 1 {
        run()
    } else {
        std::thread::scope(|scope| {
            let helpers: Vec<_> = (1..threads)
                .filter_map(|_| std::thread::Builder::new().spawn_scoped(scope, run).ok())
                .collect();
            let mut done = run();
            for helper in helpers {
                done.extend(
                    helper
                        .join()
                        .unwrap_or_else(|p| std::panic::resume_unwind(p)),
                );
            }
            done
        })
    };
    done.sort_unstable_by_key(|&(k, _)| k);
    done.into_iter().map(|(_, result)| result).collect()
}

#[cfg(test)]
mod tests {
    use super::fan_out;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn results_come_in_the_jobs_order_whatever_the_threads() {
        for threads in [0, 1, 2, 3, 8, 100] {
            let calls = AtomicUsize::new(0);
            let jobs: Vec<u64> = (0..50).map(|j| j * 7 + 1).collect();
            let out = fan_out(jobs.clone(), threads, |k, job| {
                calls.fetch_add(1, Ordering::Relaxed);
                // Uneven work, so threads finish out of order.
                std::thread::sleep(std::time::Duration::from_micros((job % 5) * 100));
                (k, job * 2)
            });
            let expected: Vec<(usize, u64)> =
                jobs.iter().enumerate().map(|(k, &j)| (k, j * 2)).collect();
            assert_eq!(out, expected, "threads {threads}");
            assert_eq!(calls.load(Ordering::Relaxed), 50, "threads {threads}");
        }
    }

    #[test]
    fn no_jobs_give_no_results() {
        let out: Vec<u8> = fan_out(Vec::<u8>::new(), 4, |_, j| j);
        assert!(out.is_empty());
    }

    #[test]
    fn a_panic_in_a_job_reaches_the_caller() {
        let caught = std::panic::catch_unwind(|| {
            fan_out((0..8).collect::<Vec<u32>>(), 3, |_, j| {
                assert!(j != 5, "job five fails");
                j
            })
        });
        assert!(caught.is_err());
    }
}
