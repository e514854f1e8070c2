//! Ctrl-C. The first press asks the running `Cycle`/`RELax` to stop at the end of its
//! current step (or a command file to stop after its current line); a second press before
//! the session has answered the first quits at once, with exit code 130.
//!
//! At the interactive prompt the terminal is in raw mode and Ctrl-C is a key, read by the
//! line editor (it clears the line); the signal only arrives while a command runs.

use std::io::Write;
use std::sync::atomic::{AtomicU32, Ordering};

/// Presses not yet answered.
static PENDING: AtomicU32 = AtomicU32::new(0);

/// Installs the handler (once per process; later calls do nothing).
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if PENDING.fetch_add(1, Ordering::SeqCst) >= 1 {
            let _ = writeln!(std::io::stderr(), "\ninterrupted twice: quitting at once");
            std::process::exit(130);
        }
    });
}

/// Whether Ctrl-C was pressed since the last [`clear`].
pub fn requested() -> bool {
    PENDING.load(Ordering::SeqCst) > 0
}

/// A press made by other means than the signal: the Python module's, whose interpreter
/// keeps the SIGINT handler and tells the running command through this (`src/python/released.rs`).
pub fn request() {
    PENDING.fetch_add(1, Ordering::SeqCst);
}

/// The press has been answered: the next one is a first press again.
pub fn clear() {
    PENDING.store(0, Ordering::SeqCst);
}
