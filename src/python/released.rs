//! Running the session with the interpreter released (other Python threads run meanwhile),
//! on the session's own worker pool as the binary runs it (`main.rs`: the session on a
//! worker, so that one thread runs every parallel loop inline). The calling thread waits,
//! and every 50 ms takes the interpreter back to run Python's signal handlers
//! (`check_signals`): a Ctrl-C, which Python's handler turns into KeyboardInterrupt, becomes
//! the session's own interrupt request (`session::interrupt::request`), so the running
//! `Cycle` stops at the end of its step exactly as in the binary, and the KeyboardInterrupt
//! is raised once the session is back.

use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

use pyo3::prelude::*;

use crate::session::{Session, interrupt};

/// Runs `f` on the session in `pool`, the interpreter released; returns its result and the
/// exception a signal handler raised meanwhile (KeyboardInterrupt), if any.
pub fn run<T: Send>(
    py: Python<'_>,
    pool: &rayon::ThreadPool,
    session: &mut Session,
    f: impl FnOnce(&mut Session) -> T + Send,
) -> (T, Option<PyErr>) {
    let (out, err) = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = channel();
            let worker = scope.spawn(move || {
                let r = pool.install(|| f(session));
                let _ = tx.send(());
                r
            });
            let mut err = None;
            loop {
                match rx.recv_timeout(Duration::from_millis(50)) {
                    Ok(()) | Err(RecvTimeoutError::Disconnected) => break,
                    Err(RecvTimeoutError::Timeout) => {
                        if err.is_none()
                            && let Err(e) = Python::attach(|py| py.check_signals())
                        {
                            interrupt::request();
                            err = Some(e);
                        }
                    }
                }
            }
            match worker.join() {
                Ok(r) => (r, err),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        })
    });
    // A request the session did not answer (it came during a command that does not poll)
    // must not stop the next Cycle.
    interrupt::clear();
    (out, err)
}
