//! The local pool: up to `jobs` runs at once on this machine, with the progress of the sweep
//! on standard error (a line redrawn on a terminal, one line per finished run elsewhere).

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::expand::Run;
use super::store::{Manifest, Outcome, Store};
use crate::session::progress::duration;

enum Event {
    Started(usize),
    Ended(usize, Result<Option<Outcome>, String>),
}

/// What the pool did.
#[derive(Default)]
pub struct Summary {
    pub ok: usize,
    /// Failed runs (and runs that could not start: name, message).
    pub failed: Vec<Outcome>,
    pub errors: Vec<(String, String)>,
}

/// The progress line: counts and the time left at the pace so far.
fn line(done: usize, running: usize, failed: usize, waiting: usize, left: Option<f64>) -> String {
    let mut s =
        format!("sweep: {done} done, {running} running, {failed} failed, {waiting} waiting");
    if let Some(t) = left {
        s.push_str(&format!("; about {} left", duration(t)));
    }
    s
}

/// Runs `todo` with `jobs` workers. Failures are reported and do not stop the others.
pub fn run(
    store: &Store,
    m: &Manifest,
    todo: &[&Run],
    jobs: usize,
    exe: &Path,
    terminal: bool,
) -> Summary {
    let jobs = jobs.max(1).min(todo.len().max(1));
    let next = AtomicUsize::new(0);
    let (tx, rx) = mpsc::channel::<Event>();
    let mut sum = Summary::default();
    let mut err = std::io::stderr();
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            let tx = tx.clone();
            let next = &next;
            scope.spawn(move || {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= todo.len() {
                        break;
                    }
                    let _ = tx.send(Event::Started(i));
                    let r = store.run(m, todo[i], exe);
                    let _ = tx.send(Event::Ended(i, r));
                }
            });
        }
        drop(tx);
        let mut started: Vec<Option<Instant>> = vec![None; todo.len()];
        let mut durations: Vec<f64> = Vec::new();
        let (mut done, mut failed, mut running) = (0usize, 0usize, 0usize);
        let mut drawn = false;
        loop {
            let ev = rx.recv_timeout(Duration::from_millis(500));
            if drawn {
                let _ = write!(err, "\r\x1b[2K");
                drawn = false;
            }
            match ev {
                Ok(Event::Started(i)) => {
                    started[i] = Some(Instant::now());
                    running += 1;
                }
                Ok(Event::Ended(i, r)) => {
                    running -= 1;
                    let t = started[i]
                        .take()
                        .map(|s| s.elapsed().as_secs_f64())
                        .unwrap_or(0.0);
                    let name = &todo[i].name;
                    match r {
                        Ok(Some(o)) if o.status.ok() => {
                            done += 1;
                            durations.push(t);
                            sum.ok += 1;
                            let _ = writeln!(err, "  ok      {name}  ({})", duration(t));
                        }
                        Ok(Some(o)) => {
                            failed += 1;
                            durations.push(t);
                            let why = match o.status.exit {
                                Some(c) => format!("exit {c}"),
                                None => "killed by a signal".into(),
                            };
                            let last = o.stderr_tail.lines().last().unwrap_or("").to_string();
                            let _ = writeln!(err, "  FAILED  {name}  ({why}): {last}");
                            sum.failed.push(o);
                        }
                        Ok(None) => {
                            done += 1;
                            sum.ok += 1;
                        }
                        Err(e) => {
                            failed += 1;
                            let _ = writeln!(err, "  FAILED  {name}: {e}");
                            sum.errors.push((name.clone(), e));
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if terminal {
                let waiting = todo.len() - done - failed - running;
                let left = if durations.is_empty() {
                    None
                } else {
                    let mean = durations.iter().sum::<f64>() / durations.len() as f64;
                    let in_flight: f64 = started
                        .iter()
                        .flatten()
                        .map(|s| (mean - s.elapsed().as_secs_f64()).max(0.0))
                        .sum();
                    Some((waiting as f64 * mean + in_flight) / jobs as f64)
                };
                let _ = write!(err, "{}", line(done, running, failed, waiting, left));
                let _ = err.flush();
                drawn = true;
            }
        }
        if drawn {
            let _ = write!(err, "\r\x1b[2K");
        }
    });
    sum
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_progress_line() {
        assert_eq!(
            super::line(3, 2, 1, 12, Some(250.0)),
            "sweep: 3 done, 2 running, 1 failed, 12 waiting; about 4 min 10 s left"
        );
        assert_eq!(
            super::line(0, 1, 0, 4, None),
            "sweep: 0 done, 1 running, 0 failed, 4 waiting"
        );
    }
}
