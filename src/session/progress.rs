//! The progress line of a long `Cycle` or `RELax` on a terminal (cycle, simulated time,
//! particle-steps per second and the time left) or of a long generation command (how far it
//! has got and the time left), redrawn in place on standard error about
//! twice a second once the command has run for two seconds, and erased when it ends.
//! Nothing of it reaches a file, a pipe or `--json` output.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Seconds before the line appears (`TRUBAL_PROGRESS_AFTER` overrides it, for tests).
const AFTER: f64 = 2.0;

pub struct Progress {
    enabled: bool,
    start: Instant,
    next_draw: Instant,
    drawn: bool,
    /// Steps to run in all, and the steps done before this watch began (RELax's chunks).
    total: u64,
    offset: u64,
}

impl Progress {
    /// A progress line for a command of `total` steps; drawn only when standard error is a
    /// terminal and the output is not JSON.
    pub fn new(total: u64, json: bool) -> Progress {
        let after = std::env::var("TRUBAL_PROGRESS_AFTER")
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s >= 0.0)
            .unwrap_or(AFTER);
        let start = Instant::now();
        let after = Duration::from_secs_f64(after);
        Progress {
            enabled: !json && std::io::stderr().is_terminal(),
            start,
            next_draw: start + after,
            drawn: false,
            total,
            offset: 0,
        }
    }

    /// Steps done before the next watched run (RELax runs in chunks).
    pub fn set_offset(&mut self, done: u64) {
        self.offset = done;
    }

    /// The seconds since the start when the line is due to be redrawn (and the next time
    /// set), else `None`.
    fn due(&mut self) -> Option<f64> {
        if !self.enabled {
            return None;
        }
        let now = Instant::now();
        if now < self.next_draw {
            return None;
        }
        self.next_draw = now + Duration::from_millis(500);
        Some((now - self.start).as_secs_f64())
    }

    /// Called before each step: redraws the line when it is time.
    pub fn tick(&mut self, cycle: u64, time: f64, particles: usize, done: u64) {
        let Some(elapsed) = self.due() else { return };
        let done = self.offset + done;
        let rate = done as f64 * particles as f64 / elapsed.max(1e-9);
        let left = if done > 0 {
            let secs = elapsed / done as f64 * (self.total - done.min(self.total)) as f64;
            format!("about {} left", duration(secs))
        } else {
            "time left unknown".into()
        };
        let pct = 100.0 * done as f64 / self.total.max(1) as f64;
        let line = format!(
            "cycle {cycle} ({done} of {} done, {pct:.0} %)  t = {time:.4e} s  {rate:.3e} particle-steps/s  {left}  (Ctrl-C stops)",
            self.total
        );
        self.draw(&line);
    }

    /// A long generation command's line (`sim::generate::Advance`): how far it has got and
    /// the time left (for RGEnerate at the recent rate of placement, which can only fall:
    /// "at least").
    pub fn tick_advance(&mut self, a: &crate::sim::generate::Advance) {
        let Some(elapsed) = self.due() else { return };
        let pct = 100.0 * a.done as f64 / a.total.max(1) as f64;
        let mut line = format!(
            "{}: {} of {} {} ({pct:.0} %)",
            a.command, a.done, a.total, a.what
        );
        let left = if a.tries > 0 {
            line.push_str(&format!(
                ", {} tries, {:.2} % of the recent ones placed one",
                a.tries,
                100.0 * a.rate
            ));
            let need = a.total.saturating_sub(a.done) as f64;
            (a.rate > 0.0).then(|| {
                format!(
                    "at least {} left",
                    duration(need / a.rate * elapsed / a.tries as f64)
                )
            })
        } else {
            (a.done > 0).then(|| {
                let secs = elapsed / a.done as f64 * a.total.saturating_sub(a.done) as f64;
                format!("about {} left", duration(secs))
            })
        };
        let left = left.unwrap_or_else(|| "time left unknown".into());
        self.draw(&format!("{line}  {left}  (Ctrl-C stops)"));
    }

    fn draw(&mut self, line: &str) {
        let mut e = std::io::stderr().lock();
        let _ = write!(e, "\r\x1b[K{line}");
        let _ = e.flush();
        self.drawn = true;
    }

    /// Erases the line (at the end of the command, however it ended).
    pub fn finish(&mut self) {
        if self.drawn {
            let mut e = std::io::stderr().lock();
            let _ = write!(e, "\r\x1b[K");
            let _ = e.flush();
            self.drawn = false;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// A duration as people read it: 42 s, 3 min 5 s, 2 h 10 min.
pub fn duration(secs: f64) -> String {
    let s = secs.round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {} s", s / 60, s % 60)
    } else {
        format!("{} h {} min", s / 3600, (s % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(super::duration(42.4), "42 s");
        assert_eq!(super::duration(185.0), "3 min 5 s");
        assert_eq!(super::duration(7800.0), "2 h 10 min");
    }
}
