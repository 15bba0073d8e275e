//! Renders side by side: each worker owns a one-thread rayon pool (so a render that uses rayon
//! internally stays on that one thread and is timed by its thread clock) and takes the next slot
//! from a shared queue.

use super::clock::{thread_cpu_s, wall_s};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// How long one timed call took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Time {
    /// CPU time of the worker's thread ([`super::clock`]): the figure of record.
    pub cpu_s: f64,
    /// Wall time, for comparison (larger when the machine was busy).
    pub wall_s: f64,
}

/// One of the run's workers.
pub struct Worker {
    pub index: usize,
    pool: rayon::ThreadPool,
    /// Scenes warmed up (a Mutex, not a RefCell: a worker's whole job runs on its own thread,
    /// which borrows the worker).
    warmed: Mutex<Vec<usize>>,
}

impl Worker {
    pub fn new(index: usize) -> Result<Self, String> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .thread_name(move |_| format!("hemilab-timed-{index}"))
            .build()
            .map_err(|e| format!("cannot start a worker thread: {e}"))?;
        Ok(Self { index, pool, warmed: Mutex::new(Vec::new()) })
    }

    /// Runs `f` on this worker's thread and returns its value with the time it took there.
    pub fn timed<R: Send>(&self, f: impl FnOnce() -> R + Send) -> (R, Time) {
        self.pool.install(|| {
            let (c0, w0) = (thread_cpu_s(), wall_s());
            let r = f();
            let (c1, w1) = (thread_cpu_s(), wall_s());
            (r, Time { cpu_s: c1 - c0, wall_s: w1 - w0 })
        })
    }

    /// The first time `key` (e.g. a scene) is seen: calls `f` untimed on this worker's thread until
    /// it has used `min_s` CPU seconds (at most 1000 calls), so the first timed render does not pay
    /// for cold caches, page faults and the clock ramping up.
    pub fn warm_up(&self, key: usize, min_s: f64, f: impl Fn() + Sync) {
        if self.warmed.lock().unwrap_or_else(|p| p.into_inner()).contains(&key) {
            return;
        }
        self.pool.install(|| {
            let start = thread_cpu_s();
            for _ in 0..1000 {
                f();
                if thread_cpu_s() - start >= min_s {
                    break;
                }
            }
        });
        self.warmed.lock().unwrap_or_else(|p| p.into_inner()).push(key);
    }
}

/// `n` workers (at least one).
pub fn workers(n: usize) -> Result<Vec<Worker>, String> {
    (0..n.max(1)).map(Worker::new).collect()
}

/// Runs `work` on every slot with the given workers, which take slots in order from a shared
/// queue, and hands each result to `done` (one at a time, in completion order). The first error
/// from either stops the queue: slots not yet started are not run, and that error is returned.
pub fn run_queue<S, T, E>(
    slots: &[S],
    workers: Vec<Worker>,
    work: impl Fn(&Worker, &S) -> Result<T, E> + Sync,
    done: impl FnMut(&S, T) -> Result<(), E> + Send,
) -> Result<(), E>
where
    S: Sync,
    T: Send,
    E: Send,
{
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let done = Mutex::new(done);
    let first_error: Mutex<Option<E>> = Mutex::new(None);
    let fail = |e: E| {
        stop.store(true, Ordering::SeqCst);
        let mut slot = first_error.lock().unwrap_or_else(|p| p.into_inner());
        slot.get_or_insert(e);
    };
    std::thread::scope(|scope| {
        for worker in workers.into_iter().take(slots.len().max(1)) {
            let (next, stop, done, work, fail) = (&next, &stop, &done, &work, &fail);
            scope.spawn(move || {
                while !stop.load(Ordering::SeqCst) {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(slot) = slots.get(i) else { break };
                    // The whole job on the worker's own thread, its untimed work too: done from
                    // this spawning thread, that work left the worker's pool thread spinning for
                    // its next job beside it (2 threads wanting each core; the integrands spec's
                    // 2,544 small jobs kept both cores 30 % idle).
                    let result = worker.pool.install(|| work(&worker, slot)).and_then(|t| {
                        let mut d = done.lock().unwrap_or_else(|p| p.into_inner());
                        (*d)(slot, t)
                    });
                    if let Err(e) = result {
                        return fail(e);
                    }
                }
            });
        }
    });
    match first_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_slot_runs_once_and_timed_work_is_measured() {
        let slots: Vec<usize> = (0..50).collect();
        let mut seen = Vec::new();
        run_queue(
            &slots,
            workers(2).unwrap(),
            |w, &s| {
                let (v, t) = w.timed(|| {
                    // rayon inside a timed call stays on the worker's one thread.
                    use rayon::prelude::*;
                    let name = std::thread::current().name().map(String::from);
                    let all_here = (0..64)
                        .into_par_iter()
                        .all(|_| std::thread::current().name().map(String::from) == name);
                    (s * 2, all_here)
                });
                assert!(t.cpu_s >= 0.0 && t.wall_s >= 0.0);
                Ok::<_, String>(v)
            },
            |&s, (v, all_here)| {
                assert_eq!(v, s * 2);
                assert!(all_here, "a timed render runs on one thread");
                seen.push(s);
                Ok(())
            },
        )
        .unwrap();
        seen.sort();
        assert_eq!(seen, slots);
    }

    #[test]
    fn the_first_error_stops_the_queue() {
        let slots: Vec<usize> = (0..1000).collect();
        let ran = AtomicUsize::new(0);
        let r = run_queue(
            &slots,
            workers(2).unwrap(),
            |_, &s| {
                ran.fetch_add(1, Ordering::SeqCst);
                if s == 3 { Err(format!("slot {s} failed")) } else { Ok(()) }
            },
            |_, ()| Ok(()),
        );
        assert_eq!(r, Err("slot 3 failed".to_string()));
        assert!(ran.load(Ordering::SeqCst) < 100, "later slots are not run");
    }

    #[test]
    fn warm_up_runs_once_per_key() {
        let w = Worker::new(0).unwrap();
        let calls = AtomicUsize::new(0);
        w.warm_up(1, 0.0, || {
            calls.fetch_add(1, Ordering::SeqCst);
        });
        w.warm_up(1, 0.0, || {
            calls.fetch_add(1, Ordering::SeqCst);
        });
        assert_eq!(calls.load(Ordering::SeqCst), 1);
        w.warm_up(2, 0.0, || {
            calls.fetch_add(1, Ordering::SeqCst);
        });
        assert_eq!(calls.load(Ordering::SeqCst), 2);
    }
}
