//! How many threads a Cycle's steps use, measured as it runs.
//!
//! The pool's threads are a ceiling, not a promise: on a workstation or a cluster node where
//! another program holds a core (or `trubal sweep` runs several trubals side by side) a
//! parallel region waits for a worker the kernel does not schedule, and two threads ran 3.6 ×
//! slower than one on the S1 bed (doc/performance.md). So every [`WINDOW`] steps a Cycle times
//! [`PROBE`] steps with all its threads and [`PROBE`] steps on one thread, and runs the rest
//! of the window in the faster way (the median step of each probe: a rebuild in a probe does
//! not decide). While it runs on one thread the pool's other workers sleep
//! (`awake::Rest`). Which way a step runs never changes a result (the sums are formed per
//! fixed chunk and added in order, `tests/it/threads.rs`), so this is a matter of time only.

use std::time::{Duration, Instant};

use super::awake::Rest;

/// Steps timed in each way at the start of every window.
pub const PROBE: u32 = 16;

/// Steps from the start of one probe to the next.
pub const WINDOW: u32 = 4096;

/// The measured choice of a Cycle's threads.
pub struct Adapt {
    /// The pool's threads.
    threads: usize,
    /// The step's place in the window.
    phase: u32,
    /// The steps' times in the probes: with all threads, on one.
    times: [Vec<Duration>; 2],
    /// The rest of the window runs on one thread.
    serial: bool,
    /// When the step began.
    started: Option<Instant>,
}

impl Adapt {
    pub fn new(threads: usize) -> Adapt {
        Adapt {
            threads,
            phase: 0,
            times: [Vec::new(), Vec::new()],
            serial: false,
            started: None,
        }
    }

    /// The threads of the next step (`rest` tells the pool's other workers to sleep when it
    /// is one).
    pub fn before_step(&mut self, rest: &Rest) -> usize {
        if self.threads < 2 {
            return self.threads;
        }
        let serial = match self.phase {
            p if p < PROBE => false,
            p if p < 2 * PROBE => true,
            _ => self.serial,
        };
        rest.set(serial);
        self.started = Some(Instant::now());
        if serial { 1 } else { self.threads }
    }

    /// The step is done: its time goes to its probe; after the second probe the way of the
    /// rest of the window is chosen.
    pub fn after_step(&mut self) {
        let Some(t0) = self.started.take() else {
            return;
        };
        let t = t0.elapsed();
        if self.phase < PROBE {
            self.times[0].push(t);
        } else if self.phase < 2 * PROBE {
            self.times[1].push(t);
            if self.phase + 1 == 2 * PROBE {
                let [parallel, serial] = &mut self.times;
                self.serial = median(serial) < median(parallel);
                parallel.clear();
                serial.clear();
            }
        }
        self.phase = (self.phase + 1) % WINDOW;
    }
}

fn median(t: &mut [Duration]) -> Duration {
    t.sort_unstable();
    t.get(t.len() / 2).copied().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The probes' medians decide: one thread when its steps were faster, all otherwise;
    /// with one thread in the pool nothing is timed.
    #[test]
    fn the_faster_way_wins_the_window() {
        let rest = Rest::default();
        let mut a = Adapt::new(2);
        for k in 0..2 * PROBE {
            let threads = a.before_step(&rest);
            assert_eq!(threads, if k < PROBE { 2 } else { 1 });
            a.started = Some(Instant::now() - Duration::from_millis(if k < PROBE { 3 } else { 1 }));
            a.after_step();
        }
        assert_eq!(a.before_step(&rest), 1);
        a.after_step();
        let mut b = Adapt::new(1);
        assert_eq!(b.before_step(&rest), 1);
        b.after_step();
        assert_eq!(b.phase, 0);
    }
}
