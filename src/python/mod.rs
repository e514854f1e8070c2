//! The Python module `trubal` (`import trubal`; doc/python.md): built only with the cargo
//! feature `python`, which maturin turns on (pyproject.toml); the binary and the crate's
//! tests build without it and without Python.
//!
//! - `session.rs` — `trubal.Session`: the session of `src/session/` (the binary's own) run
//!   from Python, commands as text, `cycle` with a callback, positions and velocities set
//!   from arrays;
//! - `released.rs` — running the session with the interpreter released, Ctrl-C polled;
//! - `state.rs` — the scene read into numpy arrays through the read API
//!   (`sim/scene/access.rs`), copies, no text in between.

mod released;
mod session;
mod state;

use pyo3::prelude::*;

pyo3::create_exception!(
    trubal,
    CommandError,
    pyo3::exceptions::PyException,
    "A command refused or failed: `message`, `line` (1-based, of the text given to `run`), `column` (1-based); str() is the located message the binary prints. The session is as before the failing command."
);

/// trubal: the DEM session as a library, its state as numpy arrays (doc/python.md).
#[pymodule]
fn trubal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<session::PySession>()?;
    let error = m.py().get_type::<CommandError>();
    // An error of no command line (an array call on a session without a scene) has none.
    for name in ["message", "line", "column"] {
        error.setattr(name, m.py().None())?;
    }
    m.add("CommandError", error)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("HISTORY_COLUMNS", crate::sim::history::COLUMNS.to_vec())?;
    Ok(())
}
