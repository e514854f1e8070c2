//! `trubal.Session`: the binary's session (`src/session/`) driven from Python.

use std::io::Write;
use std::sync::{Arc, Mutex, MutexGuard};

use numpy::PyReadonlyArray2;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{CommandError, released, state};
use crate::session::{Flow, LineError, Session, Source, format_error, interrupt};

/// Where the session writes: kept until the call that made it returns.
#[derive(Clone, Default)]
struct Buffer(Arc<Mutex<Vec<u8>>>);

impl Write for Buffer {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        if let Ok(mut v) = self.0.lock() {
            v.extend_from_slice(b);
        }
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Buffer {
    fn take(&self) -> String {
        match self.0.lock() {
            Ok(mut v) => String::from_utf8_lossy(&std::mem::take(&mut *v)).into_owned(),
            Err(_) => String::new(),
        }
    }
}

/// A trubal session: the command language of the binary, the same session code, its scene
/// readable as numpy arrays. `threads`: worker threads (default: RAYON_NUM_THREADS or all
/// cores; results are bitwise the same for any number). `json`: PRint writes JSON lines, as
/// `trubal --json`. `dir`: the directory of relative file names of RESTart, SAve and Log
/// (default: the current one).
#[pyclass(name = "Session", module = "trubal")]
pub struct PySession {
    session: Mutex<Session>,
    pool: rayon::ThreadPool,
    out: Buffer,
    diag: Buffer,
}

/// How a run of lines ended.
enum End {
    Done,
    Stopped,
    Interrupted,
    Failed(usize, String, LineError),
}

impl PySession {
    fn lock(&self) -> PyResult<MutexGuard<'_, Session>> {
        self.session.try_lock().map_err(|_| {
            PyRuntimeError::new_err(
                "the session is busy (another thread is running a command on it)",
            )
        })
    }

    /// Runs the lines of `text` (stopping at the first error, a STOp or Ctrl-C); returns
    /// what they printed, or raises.
    fn run_text(&self, py: Python<'_>, text: &str) -> PyResult<String> {
        let mut guard = self.lock()?;
        let lines: Vec<&str> = text.lines().collect();
        let (end, err) = released::run(py, &self.pool, &mut guard, |s| {
            for (k, line) in lines.iter().enumerate() {
                let r = s.run_line(line);
                s.flush();
                match r {
                    Ok(Flow::Continue) => {}
                    Ok(Flow::Stop) => return End::Stopped,
                    Ok(Flow::Interrupted) => return End::Interrupted,
                    Err(e) => return End::Failed(k + 1, line.to_string(), e),
                }
                if interrupt::requested() {
                    return End::Interrupted;
                }
            }
            End::Done
        });
        drop(guard);
        self.forward_diagnostics(py);
        let output = self.out.take();
        match end {
            End::Failed(line, text, e) => Err(command_error(py, line, &text, &e)),
            End::Interrupted => {
                Err(err
                    .unwrap_or_else(|| PyKeyboardInterrupt::new_err("the command was interrupted")))
            }
            End::Done | End::Stopped => match err {
                Some(e) => Err(e),
                None => Ok(output),
            },
        }
    }

    /// Warnings and messages of the last call go to Python's `sys.stderr` (a notebook shows
    /// them).
    fn forward_diagnostics(&self, py: Python<'_>) {
        let text = self.diag.take();
        if text.is_empty() {
            return;
        }
        if let Ok(stderr) = py.import("sys").and_then(|s| s.getattr("stderr")) {
            let _ = stderr.call_method1("write", (text,));
        }
    }

    /// Runs an array edit as one command: a refused array changes nothing.
    fn edit(
        &self,
        what: &str,
        a: PyReadonlyArray2<'_, f64>,
        f: impl FnOnce(&mut Session, &[[f64; 3]]) -> Result<(), String>,
    ) -> PyResult<()> {
        let v = a.as_array();
        if v.ncols() != 3 {
            return Err(PyValueError::new_err(format!(
                "{what}: the array must have 3 columns (x, y, z); it has shape {:?}",
                v.shape()
            )));
        }
        let rows: Vec<[f64; 3]> = v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
        let mut s = self.lock()?;
        f(&mut s, &rows).map_err(|m| PyValueError::new_err(format!("{what}: {m}")))
    }
}

/// The exception of a failed line: its message, line and column, and the binary's located
/// text as str().
fn command_error(py: Python<'_>, line: usize, text: &str, e: &LineError) -> PyErr {
    let src = Source {
        name: "<python>".into(),
        line,
    };
    let shown = format_error(&src, text, e);
    let column = text[..e.start.min(text.len())].chars().count() + 1;
    let err = CommandError::new_err(shown);
    let v = err.value(py);
    let _ = v.setattr("message", e.message.clone());
    let _ = v.setattr("line", line);
    let _ = v.setattr("column", column);
    err
}

#[pymethods]
impl PySession {
    #[new]
    #[pyo3(signature = (threads=None, json=false, dir=None))]
    fn new(threads: Option<usize>, json: bool, dir: Option<std::path::PathBuf>) -> PyResult<Self> {
        let mut builder = rayon::ThreadPoolBuilder::new().stack_size(16 << 20);
        if let Some(n) = threads {
            if n == 0 {
                return Err(PyValueError::new_err("threads must be positive"));
            }
            builder = builder.num_threads(n);
        }
        let pool = builder.build().map_err(|e| {
            PyRuntimeError::new_err(format!("cannot start the worker threads: {e}"))
        })?;
        let (out, diag) = (Buffer::default(), Buffer::default());
        let mut session =
            Session::new(Box::new(out.clone()), json).with_diagnostics(Box::new(diag.clone()));
        if let Some(d) = dir {
            session.dir = d;
        }
        Ok(PySession {
            session: Mutex::new(session),
            pool,
            out,
            diag,
        })
    }

    /// Runs commands: one line or many, `$name` replaced by the session's variables (the
    /// keyword arguments set them first, as `trubal --set name=value`). Returns what they
    /// printed; raises CommandError at the first failing line (earlier lines stay done) and
    /// KeyboardInterrupt after a Ctrl-C (a Cycle stopped at the end of its step).
    #[pyo3(signature = (text, **vars))]
    fn run(
        &self,
        py: Python<'_>,
        text: &str,
        vars: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<String> {
        self.set_vars(vars)?;
        self.run_text(py, text)
    }

    /// `Cycle n`, in runs of `every` cycles with `callback(session)` called after each (it may
    /// read arrays and run commands; returning False stops the cycling there). The same bits
    /// as one `Cycle n` (a Cycle split in runs continues exactly). The interpreter is released
    /// while cycling; Ctrl-C raises KeyboardInterrupt with the scene as a shorter Cycle
    /// leaves it. Returns the cycles run.
    #[pyo3(signature = (n, every=None, callback=None))]
    fn cycle(
        slf: &Bound<'_, Self>,
        n: u64,
        every: Option<u64>,
        callback: Option<Bound<'_, PyAny>>,
    ) -> PyResult<u64> {
        let py = slf.py();
        let every = match every {
            Some(0) => return Err(PyValueError::new_err("every must be positive")),
            Some(k) => k,
            None => n.max(1),
        };
        let me = slf.borrow();
        let mut done = 0;
        loop {
            // `Cycle 0` runs once too (it evaluates the contacts and the time step).
            let m = every.min(n - done);
            let before = me.lock()?.scene.as_ref().map(|s| s.cycle());
            me.run_text(py, &format!("Cycle {m}"))?;
            let after = me.lock()?.scene.as_ref().map(|s| s.cycle());
            done += match (before, after) {
                (Some(b), Some(a)) => a - b,
                _ => m,
            };
            if let Some(cb) = &callback
                && m > 0
                && matches!(cb.call1((slf,))?.extract::<bool>(), Ok(false))
            {
                break;
            }
            if done >= n {
                break;
            }
        }
        Ok(done)
    }

    /// Sets variables for `$name` in later commands.
    #[pyo3(signature = (**vars))]
    fn set_vars(&self, vars: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let Some(vars) = vars else { return Ok(()) };
        let mut s = self.lock()?;
        for (k, v) in vars.iter() {
            s.vars.insert(k.str()?.to_string(), v.str()?.to_string());
        }
        Ok(())
    }

    /// Whether a problem is defined (STArt or RESTart given).
    #[getter]
    fn started(&self) -> PyResult<bool> {
        Ok(self.lock()?.scene.is_some())
    }

    /// Cycles done so far.
    #[getter]
    fn cycles(&self) -> PyResult<u64> {
        self.with_scene(|_, s| Ok(s.cycle()))
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> PyResult<f64> {
        self.with_scene(|_, s| Ok(s.time()))
    }

    /// The particles as arrays (copies, in the scene's order): id, position, velocity,
    /// spin, force, moment, radius, mass, material, size, agglomerate, fixed.
    fn particles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::particles(py, s))
    }

    /// The contacts as arrays (doc/python.md): the pairs that touch or hold a bridge, or
    /// with `all=True` every candidate pair kept.
    #[pyo3(signature = (all=false))]
    fn contacts<'py>(&self, py: Python<'py>, all: bool) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::contacts(py, s, all))
    }

    /// The particle–wall contacts as arrays.
    #[pyo3(signature = (all=false))]
    fn wall_contacts<'py>(&self, py: Python<'py>, all: bool) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::wall_contacts(py, s, all))
    }

    /// The walls as arrays: force, normal_force, velocity, displacement, material.
    fn walls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::walls(py, s))
    }

    /// The energy ledger and the energy stored (J), as `PRint ENergy` has them.
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::energy(py, s))
    }

    /// The average stress (Pa, compression positive), as `PRint Stress`: total, contact and
    /// kinetic 3×3 arrays (row: force component, column: branch component), mean.
    fn stress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::stress(py, s))
    }

    /// The history (`SET HIStory n`): one array per column of `trubal.HISTORY_COLUMNS`.
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::history(py, s))
    }

    /// The coarse-grained fields of `FIEld nx ny nz w [LUCy]` on the grid's nodes as arrays
    /// indexed [z, y, x] (x, y, z: the nodes' coordinates).
    #[pyo3(signature = (nodes, width, lucy=false))]
    fn field<'py>(
        &self,
        py: Python<'py>,
        nodes: [usize; 3],
        width: f64,
        lucy: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.with_scene(|_, s| state::field(py, s, nodes, width, lucy))
    }

    /// Sets every particle's position from an (n, 3) array, as one command: the whole array
    /// checked first (finite, in the work-space, none behind a wall), or nothing changes.
    /// Contacts are re-made at the next Cycle, as after MOve.
    fn set_positions(&self, positions: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        self.edit("set_positions", positions, |s, rows| s.set_positions(rows))
    }

    /// Sets every particle's velocity from an (n, 3) array, as one command (checked whole
    /// first); the kinetic energy it adds or removes is booked in the ledger's `commands`
    /// input, as VELocity's is.
    fn set_velocities(&self, velocities: PyReadonlyArray2<'_, f64>) -> PyResult<()> {
        self.edit("set_velocities", velocities, |s, rows| {
            s.set_velocities(rows)
        })
    }
}

impl PySession {
    fn with_scene<T>(
        &self,
        f: impl FnOnce(&Session, &crate::sim::Scene) -> PyResult<T>,
    ) -> PyResult<T> {
        let s = self.lock()?;
        match s.scene.as_ref() {
            Some(scene) => f(&s, scene),
            None => Err(CommandError::new_err(
                "no problem is defined yet: give STArt (or RESTart) first",
            )),
        }
    }
}
