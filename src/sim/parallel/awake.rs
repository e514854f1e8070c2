//! The thread pool's other workers kept awake through a `Cycle`.
//!
//! A step has parallel regions (the force step's tasks with the update of their own
//! chunks, `cycle::fused`; with two regions, then the update's chunks; the rebuild's loops)
//! and short serial parts between them. A rayon worker that finds no work spins for a few dozen
//! `sched_yield`s and then sleeps on a futex; on the project host (a KVM guest) waking it
//! for the next region took about 24 µs, so the second task of each region started that
//! late and the region ended that much later (phase timers, S1 10k bed on two threads:
//! 0.12 s of a 2.3 s run in the force step alone, doc/performance.md). Here each other
//! worker runs a polling job for the length of the `Cycle`: it takes any work that is posted
//! (`rayon::yield_now`) and otherwise spins, calling `sched_yield` now and then so that
//! other processes on the machine still get the core. Which thread runs which task never
//! changes a result (the sums are made in a fixed order), so this is a matter of time only.

use std::sync::atomic::{AtomicBool, Ordering};

/// Idle polls (each 64 spin hints, well under a microsecond) between two `sched_yield`s.
const POLLS_PER_YIELD: u32 = 16;

/// The number of cores the process may run on (asked once).
pub fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Runs `f` on the current thread while the pool's other workers poll for work; they stop
/// when `f` returns or unwinds. Without effect with one thread, or with more threads than
/// the machine has cores (a polling worker would then take a core from a working one).
pub fn while_running<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    let threads = rayon::current_num_threads();
    if threads < 2 || threads > cores() {
        return f();
    }
    let stop = AtomicBool::new(false);
    let stop = &stop;
    rayon::scope(move |s| {
        // Set when `f` returns or panics (a panic must not leave the pollers running, or
        // the scope would wait for them for ever).
        let _stop = StopOnDrop(stop);
        for _ in 1..threads {
            s.spawn(move |_| poll_until(stop));
        }
        f()
    })
}

struct StopOnDrop<'a>(&'a AtomicBool);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Takes posted work until `stop` is set.
fn poll_until(stop: &AtomicBool) {
    let mut idle = 0u32;
    while !stop.load(Ordering::Acquire) {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            continue;
        }
        for _ in 0..64 {
            std::hint::spin_loop();
        }
        idle = idle.wrapping_add(1);
        if idle.is_multiple_of(POLLS_PER_YIELD) {
            std::thread::yield_now();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::sync::mpsc;
    use std::time::Duration;

    /// Runs `job` in a pool of two threads on a thread of its own; `None` if it did not
    /// finish within a minute (the pollers did not stop).
    fn in_two_threads<R: Send + 'static>(job: impl FnOnce() -> R + Send + 'static) -> Option<R> {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .expect("a pool of two threads");
            let _ = tx.send(pool.install(job));
        });
        rx.recv_timeout(Duration::from_secs(60)).ok()
    }

    #[test]
    fn the_work_is_done_and_the_pollers_stop() {
        let sums = in_two_threads(|| {
            while_running(|| {
                // Several parallel regions, as in a Cycle.
                (0..50)
                    .map(|k| (0..10_000u64).into_par_iter().map(|x| x * k).sum::<u64>())
                    .collect::<Vec<_>>()
            })
        });
        let expected: Vec<u64> = (0..50).map(|k| k * (9_999 * 10_000 / 2)).collect();
        assert_eq!(sums, Some(expected));
    }

    #[test]
    fn a_panic_stops_the_pollers_too() {
        let caught = in_two_threads(|| {
            std::panic::catch_unwind(|| while_running(|| -> u32 { panic!("inside the Cycle") }))
                .is_err()
        });
        assert_eq!(caught, Some(true));
    }
}
