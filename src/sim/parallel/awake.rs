//! The thread pool's other workers kept awake through a `Cycle`, and put to sleep when the
//! machine is too busy for them to help.
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
//! other processes on the machine still get the core.
//!
//! **A busy machine.** A poller that must share its core with another program costs the
//! step twice: its spinning takes the core from the step's own serial parts, and a task it
//! took stalls the region while it waits for the core (two threads ran 3.6 × slower than
//! one on S1 with a busy loop on the other core). So the pollers note the time the system
//! took them off the core while they spun ([`Pacer`]); when that is more than a few per cent
//! of a window, the Cycle's thread times one window with the pollers asleep on a condition
//! variable — it then runs the step on the one-thread plan ([`Pacer::asleep`]) — and keeps whichever way
//! made more steps per second, for a hold that doubles while the choice stays the same. The
//! two mistakes are not alike (pollers awake beside another program: several times slower;
//! asleep on an idle machine: the second thread's gain lost), so awake must beat the asleep
//! hold's mean rate by a margin, and an awake hold ends at once when the rate falls while
//! the pollers are often off their cores.
//! Which thread runs which task never changes a result (the tasks are the same and their
//! sums are made in a fixed order), so all of this is a matter of time only: the bits are
//! the same whatever the pollers do (`tests/it/threads.rs`).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// Idle polls (each 64 spin hints, well under a microsecond) between two `sched_yield`s.
const POLLS_PER_YIELD: u32 = 16;
/// An idle poll that took longer than this: the poller was off its core for that long.
const GAP: Duration = Duration::from_micros(50);
/// The length of a measuring window (at least one step).
const WINDOW: Duration = Duration::from_millis(25);
/// The pollers' time off their cores, as a fraction of a window's, that makes the Cycle
/// time a window with them asleep.
const BUSY: f64 = 0.05;
/// How long a choice is kept before it is timed again: at first, and at most (the hold
/// doubles while the choice stays the same).
const HOLD_FIRST: Duration = Duration::from_millis(250);
const HOLD_MAX: Duration = Duration::from_secs(4);
/// On a machine that takes the pollers off their cores, awake must make this many times the
/// steps per second of asleep to be kept. The two mistakes do not cost the same: pollers kept
/// awake beside another program make the step several times slower (3.6 × on S1), pollers
/// asleep on an idle machine cost at most the second thread's gain (1.5–1.8 ×), and one
/// window's rate differs from the hold's by the rebuilds it happens to hold.
const AWAKE_MARGIN: f64 = 1.15;
/// While awake on a choice's hold, the pollers' time off their cores beyond this fraction of
/// a window, with the rate below [`HOLD_BREAK_RATE`] of the rate that won, ends the hold at
/// once (another program started within it).
const HOLD_BREAK_OFF: f64 = 0.25;
const HOLD_BREAK_RATE: f64 = 0.8;

/// The pollers' changes (to sleep or awake) and nanoseconds asleep in this process, for
/// the benchmark hook (`TRUBAL_TIMING`).
static CHANGES: AtomicU64 = AtomicU64::new(0);
static ASLEEP_NS: AtomicU64 = AtomicU64::new(0);

/// The pollers' changes and seconds asleep since the process started.
pub fn asleep_so_far() -> (u64, f64) {
    (
        CHANGES.load(Ordering::Relaxed),
        ASLEEP_NS.load(Ordering::Relaxed) as f64 * 1e-9,
    )
}

/// For tests: the pollers change (asleep, awake) every this many steps instead of by timing
/// (0: by timing).
static CHANGE_EVERY: AtomicU64 = AtomicU64::new(0);

/// For tests (`tests/it/threads.rs`): every Cycle of the process from now on puts its
/// pollers to sleep and wakes them every `steps` steps, whatever the timing (0: back to
/// timing). The results must not change.
#[doc(hidden)]
pub fn change_every(steps: u64) {
    CHANGE_EVERY.store(steps, Ordering::Relaxed);
}

/// The number of cores the process may run on (asked once).
pub fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// What the Cycle's thread and the pollers share.
#[derive(Default)]
struct Shared {
    stop: AtomicBool,
    /// The pollers sleep (on `wake`) while this is set.
    asleep: AtomicBool,
    lock: Mutex<()>,
    wake: Condvar,
    /// Nanoseconds the pollers were off their cores while polling.
    off_core: AtomicU64,
}

impl Shared {
    /// Sets `flag` (`stop` or `asleep`) under the lock, so that no poller misses the
    /// change between its test and its wait, and wakes the sleepers.
    fn set(&self, flag: &AtomicBool, value: bool) {
        let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        flag.store(value, Ordering::Release);
        self.wake.notify_all();
    }

    /// Sleeps while the pollers are told to and not told to stop.
    fn rest(&self) {
        let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        while self.asleep.load(Ordering::Acquire) && !self.stop.load(Ordering::Acquire) {
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// Runs `f` on the current thread while the pool's other workers poll for work; they stop
/// when `f` returns or unwinds. `f` calls [`Pacer::step_done`] after each step. Without
/// pollers with one thread, or with more threads than the machine has cores (a polling
/// worker would then take a core from a working one).
pub fn while_running<R: Send>(f: impl FnOnce(&mut Pacer) -> R + Send) -> R {
    let threads = rayon::current_num_threads();
    if threads < 2 || threads > cores() {
        return f(&mut Pacer::new(None));
    }
    let shared = Shared::default();
    let shared = &shared;
    rayon::scope(move |s| {
        // Set when `f` returns or panics (a panic must not leave the pollers running, or
        // the scope would wait for them for ever).
        let _stop = StopOnDrop(shared);
        for _ in 1..threads {
            s.spawn(move |_| poll_until(shared));
        }
        f(&mut Pacer::new(Some(shared)))
    })
}

struct StopOnDrop<'a>(&'a Shared);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.set(&self.0.stop, true);
    }
}

/// Takes posted work until told to stop, sleeping while told to; notes the time it spent
/// off its core while it polled.
fn poll_until(sh: &Shared) {
    let mut idle = 0u32;
    let mut last = Instant::now();
    while !sh.stop.load(Ordering::Acquire) {
        if sh.asleep.load(Ordering::Acquire) {
            sh.rest();
            last = Instant::now();
            continue;
        }
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            last = Instant::now();
            continue;
        }
        for _ in 0..64 {
            std::hint::spin_loop();
        }
        idle = idle.wrapping_add(1);
        if idle.is_multiple_of(POLLS_PER_YIELD) {
            std::thread::yield_now();
        }
        let now = Instant::now();
        let gap = now - last;
        if gap > GAP {
            let ns = u64::try_from(gap.as_nanos()).unwrap_or(u64::MAX);
            sh.off_core.fetch_add(ns, Ordering::Relaxed);
        }
        last = now;
    }
}

/// The Cycle's side of the pollers: times windows of steps and puts the pollers to sleep
/// or wakes them ([`Pace`] decides).
pub struct Pacer<'a> {
    shared: Option<&'a Shared>,
    pace: Pace,
    start: Instant,
    steps: u64,
    off_start: u64,
}

impl<'a> Pacer<'a> {
    /// The pacer of a Cycle: the choice the last Cycle of the process left (a busy machine
    /// is still busy at the next Cycle: a script of many short Cycles is not timed anew at
    /// each), with the pollers asleep if that was the choice.
    fn new(shared: Option<&'a Shared>) -> Pacer<'a> {
        let now = Instant::now();
        let pace = match shared {
            Some(sh) => {
                let pace = LAST
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .map_or(Pace::new(now), |p| p.resumed(now));
                sh.asleep.store(pace.asleep(), Ordering::Release);
                pace
            }
            None => Pace::new(now),
        };
        Pacer {
            shared,
            pace,
            start: now,
            steps: 0,
            off_start: 0,
        }
    }

    /// Whether the pollers sleep now: the Cycle's thread is alone, so the next step runs
    /// the one-thread plan (no split of the pair list, no region) — the same bits as the
    /// split step, without the split's shared particles and late chunks to pay for. Beside a
    /// one-thread trubal on the other core (S1 10k), two threads whose pollers slept through
    /// 97 % of the Cycle still ran the split step and took 1.06–1.11 × one thread's time.
    pub fn asleep(&self) -> bool {
        self.shared
            .is_some_and(|sh| sh.asleep.load(Ordering::Relaxed))
    }

    /// Called after every step: at the end of a window, lets [`Pace`] decide whether the
    /// pollers sleep through the next.
    pub fn step_done(&mut self) {
        let Some(sh) = self.shared else {
            return;
        };
        self.steps += 1;
        let every = CHANGE_EVERY.load(Ordering::Relaxed);
        if every > 0 {
            if self.steps.is_multiple_of(every) {
                sh.set(&sh.asleep, !sh.asleep.load(Ordering::Relaxed));
                CHANGES.fetch_add(1, Ordering::Relaxed);
            }
            return;
        }
        let now = Instant::now();
        let span = now - self.start;
        if span < WINDOW {
            return;
        }
        let off = sh.off_core.load(Ordering::Relaxed);
        let secs = span.as_secs_f64();
        let window = Window {
            rate: self.steps as f64 / secs,
            off_core: (off - self.off_start) as f64 * 1e-9 / secs,
            secs,
        };
        if sh.asleep.load(Ordering::Relaxed) {
            let ns = u64::try_from(span.as_nanos()).unwrap_or(u64::MAX);
            ASLEEP_NS.fetch_add(ns, Ordering::Relaxed);
        }
        if let Some(asleep) = self.pace.window(now, window) {
            sh.set(&sh.asleep, asleep);
            CHANGES.fetch_add(1, Ordering::Relaxed);
        }
        self.start = Instant::now();
        self.steps = 0;
        self.off_start = off;
    }
}

impl Drop for Pacer<'_> {
    /// Leaves the choice to the next Cycle.
    fn drop(&mut self) {
        if self.shared.is_some() {
            *LAST.lock().unwrap_or_else(|e| e.into_inner()) = Some(self.pace);
        }
    }
}

/// The choice the last Cycle with pollers left.
static LAST: Mutex<Option<Pace>> = Mutex::new(None);

/// One window's measures: steps per second, and the pollers' time off their cores per
/// second of it.
#[derive(Clone, Copy, Debug)]
struct Window {
    rate: f64,
    off_core: f64,
    /// The window's length (s).
    secs: f64,
}

/// Where the choice between pollers awake and asleep stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Awake, watching the pollers' time off their cores (from `quiet` on; before, only for a
    /// fall below [`HOLD_BREAK_RATE`] of `won`, the rate with which awake won, 0 for none).
    Awake { quiet: Instant, won: f64 },
    /// One window asleep, to compare with the awake window's rate.
    TryAsleep { awake: f64 },
    /// Asleep until `until`, having made `steps` steps in `secs` seconds so far.
    Asleep {
        until: Instant,
        steps: f64,
        secs: f64,
    },
    /// One window awake, to compare with the asleep hold's mean rate.
    TryAwake { asleep: f64 },
}

/// The decision: pollers awake until they are often off their cores; then a window of
/// each, and the faster kept for a hold that doubles while the same way keeps winning.
/// Awake must beat the asleep hold's mean rate by [`AWAKE_MARGIN`] to be chosen on such a
/// machine, and an awake hold ends early when the rate falls and the pollers are off their
/// cores much of the time.
#[derive(Clone, Copy, Debug)]
struct Pace {
    phase: Phase,
    hold: Duration,
    /// The way chosen last (`Some(true)`: asleep).
    chosen: Option<bool>,
}

impl Pace {
    fn new(now: Instant) -> Pace {
        Pace {
            phase: Phase::Awake {
                quiet: now,
                won: 0.0,
            },
            hold: HOLD_FIRST,
            chosen: None,
        }
    }

    /// The pollers sleep in this phase.
    fn asleep(&self) -> bool {
        matches!(self.phase, Phase::TryAsleep { .. } | Phase::Asleep { .. })
    }

    /// The pace at the start of a new Cycle: a trial that was under way is dropped (its
    /// window was cut), the choice and its hold kept.
    fn resumed(mut self, now: Instant) -> Pace {
        self.phase = match self.phase {
            Phase::TryAsleep { .. } => Phase::Awake {
                quiet: now,
                won: 0.0,
            },
            Phase::TryAwake { .. } => Phase::Asleep {
                until: now,
                steps: 0.0,
                secs: 0.0,
            },
            p => p,
        };
        self
    }

    /// The hold of a choice (`asleep` or not), doubled if the same way won last time.
    fn hold_for(&mut self, asleep: bool) -> Duration {
        self.hold = if self.chosen == Some(asleep) {
            (self.hold * 2).min(HOLD_MAX)
        } else {
            HOLD_FIRST
        };
        self.chosen = Some(asleep);
        self.hold
    }

    /// The end of a window at `now`: `Some(asleep)` when the pollers are to change.
    fn window(&mut self, now: Instant, w: Window) -> Option<bool> {
        match self.phase {
            Phase::Awake { quiet, won } => {
                let busy = if now >= quiet {
                    w.off_core > BUSY
                } else {
                    w.off_core > HOLD_BREAK_OFF && w.rate < HOLD_BREAK_RATE * won
                };
                if busy {
                    self.phase = Phase::TryAsleep { awake: w.rate };
                    return Some(true);
                }
                None
            }
            Phase::TryAsleep { awake } => {
                let asleep = w.rate * AWAKE_MARGIN > awake;
                let hold = self.hold_for(asleep);
                if asleep {
                    self.phase = Phase::Asleep {
                        until: now + hold,
                        steps: w.rate * w.secs,
                        secs: w.secs,
                    };
                    None
                } else {
                    self.phase = Phase::Awake {
                        quiet: now + hold,
                        won: awake,
                    };
                    Some(false)
                }
            }
            Phase::Asleep { until, steps, secs } => {
                let (steps, secs) = (steps + w.rate * w.secs, secs + w.secs);
                if now >= until {
                    let mean = if secs > 0.0 { steps / secs } else { w.rate };
                    self.phase = Phase::TryAwake { asleep: mean };
                    return Some(false);
                }
                self.phase = Phase::Asleep { until, steps, secs };
                None
            }
            Phase::TryAwake { asleep } => {
                let stay_asleep = w.rate <= asleep * AWAKE_MARGIN;
                let hold = self.hold_for(stay_asleep);
                if stay_asleep {
                    self.phase = Phase::Asleep {
                        until: now + hold,
                        steps: 0.0,
                        secs: 0.0,
                    };
                    Some(true)
                } else {
                    self.phase = Phase::Awake {
                        quiet: now + hold,
                        won: w.rate,
                    };
                    None
                }
            }
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
            while_running(|_| {
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
            std::panic::catch_unwind(|| while_running(|_| -> u32 { panic!("inside the Cycle") }))
                .is_err()
        });
        assert_eq!(caught, Some(true));
    }

    /// Several parallel regions, as in a Cycle.
    fn regions() -> Vec<u64> {
        (0..50)
            .map(|k| (0..10_000u64).into_par_iter().map(|x| x * k).sum::<u64>())
            .collect()
    }

    #[test]
    fn with_the_pollers_asleep_the_cycles_thread_does_the_work() {
        let sums = in_two_threads(|| {
            while_running(|pacer| {
                let sh = pacer.shared.expect("pollers with two threads");
                sh.set(&sh.asleep, true);
                let asleep = regions();
                sh.set(&sh.asleep, false);
                let awake = regions();
                sh.set(&sh.asleep, true);
                (asleep, awake)
            })
        });
        let expected: Vec<u64> = (0..50).map(|k| k * (9_999 * 10_000 / 2)).collect();
        // (And the sleeping pollers stopped: the pool returned.)
        assert_eq!(sums, Some((expected.clone(), expected)));
    }

    fn window(rate: f64, off_core: f64) -> Window {
        Window {
            rate,
            off_core,
            secs: WINDOW.as_secs_f64(),
        }
    }

    #[test]
    fn an_idle_machine_never_puts_the_pollers_to_sleep() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        for k in 1..1000 {
            let now = t0 + WINDOW * k;
            assert_eq!(pace.window(now, window(1000.0, 0.01)), None);
        }
    }

    #[test]
    fn a_busy_machine_keeps_the_faster_way_and_times_it_again_later() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        // Off their cores 30 % of the time: one window asleep is timed.
        assert_eq!(pace.window(at(25), window(300.0, 0.3)), Some(true));
        // Asleep made more steps: kept (no change) for the first hold.
        assert_eq!(pace.window(at(50), window(500.0, 0.0)), None);
        assert_eq!(pace.window(at(100), window(500.0, 0.0)), None);
        // At the hold's end, one window awake.
        assert_eq!(pace.window(at(50 + 250), window(500.0, 0.0)), Some(false));
        // Awake still slower: asleep again, for twice the hold.
        assert_eq!(pace.window(at(325), window(320.0, 0.3)), Some(true));
        assert_eq!(pace.window(at(325 + 499), window(500.0, 0.0)), None);
        assert_eq!(pace.window(at(325 + 500), window(500.0, 0.0)), Some(false));
        // The other program has gone: awake is faster and stays.
        assert_eq!(pace.window(at(850), window(900.0, 0.0)), None);
        for k in 1..100 {
            assert_eq!(pace.window(at(850 + 25 * k), window(900.0, 0.0)), None);
        }
    }

    #[test]
    fn awake_kept_when_it_wins_even_on_a_busy_machine() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(pace.window(at(25), window(800.0, 0.2)), Some(true));
        // Asleep was slower: awake again, and no new trial within the hold.
        assert_eq!(pace.window(at(50), window(500.0, 0.0)), Some(false));
        assert_eq!(pace.window(at(75), window(800.0, 0.2)), None);
        assert_eq!(pace.window(at(50 + 250), window(800.0, 0.2)), Some(true));
    }

    #[test]
    fn the_next_cycle_keeps_the_choice_and_drops_a_cut_trial() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(pace.window(at(25), window(300.0, 0.3)), Some(true));
        // Cut in its trial: the next Cycle starts awake and may try again at once.
        let next = pace.resumed(at(30));
        assert!(!next.asleep());
        assert_eq!(
            next.phase,
            Phase::Awake {
                quiet: at(30),
                won: 0.0
            }
        );
        // Asleep by choice: the next Cycle starts asleep, with the same hold.
        assert_eq!(pace.window(at(50), window(500.0, 0.0)), None);
        let next = pace.resumed(at(60));
        assert!(next.asleep());
        assert_eq!(next.phase, pace.phase);
        // Cut in a trial awake: asleep, timed awake at the next window.
        assert_eq!(pace.window(at(300), window(500.0, 0.0)), Some(false));
        let mut next = pace.resumed(at(310));
        assert!(next.asleep());
        assert_eq!(next.window(at(335), window(500.0, 0.0)), Some(false));
    }
    #[test]
    fn awake_must_win_by_the_margin_on_a_busy_machine() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(pace.window(at(25), window(300.0, 0.3)), Some(true));
        // Asleep 10 % slower than the awake window: within the margin, asleep is kept.
        assert_eq!(pace.window(at(50), window(272.0, 0.0)), None);
        // The hold's mean, not its last window, is what a trial awake must beat: a slow
        // last window (a rebuild) does not let a trial 10 % above the mean win.
        assert_eq!(pace.window(at(275), window(500.0, 0.0)), None);
        assert_eq!(pace.window(at(300), window(300.0, 0.0)), Some(false));
        let mean = (272.0 + 500.0 + 300.0) / 3.0;
        assert!(1.1 * mean > AWAKE_MARGIN * 300.0);
        assert_eq!(pace.window(at(325), window(1.1 * mean, 0.3)), Some(true));
    }

    #[test]
    fn another_program_starting_within_an_awake_hold_ends_it() {
        let t0 = Instant::now();
        let mut pace = Pace::new(t0);
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        assert_eq!(pace.window(at(25), window(800.0, 0.1)), Some(true));
        assert_eq!(pace.window(at(50), window(500.0, 0.0)), Some(false));
        // Within the hold: a little time off the cores, or a slower window alone, change
        // nothing.
        assert_eq!(pace.window(at(75), window(790.0, 0.2)), None);
        assert_eq!(pace.window(at(100), window(500.0, 0.1)), None);
        // Both at once: asleep is timed at once.
        assert_eq!(pace.window(at(125), window(300.0, 0.5)), Some(true));
    }
}
