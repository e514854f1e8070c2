//! Helpers shared by the physics tests: build a scene from command lines and step it.

#![allow(dead_code)]

use trubal::session::Session;
use trubal::sim::{Scene, cycle};

/// Runs command lines in a session whose output is discarded; panics on an error.
pub fn session(lines: &str) -> Session {
    let mut s = crate::common::session_with(Box::new(std::io::sink()), false)
        .with_diagnostics(Box::new(std::io::sink()));
    for (k, l) in lines.lines().enumerate() {
        if let Err(e) = s.run_line(l) {
            panic!("line {}: `{l}`: {}", k + 1, e.message);
        }
    }
    s
}

pub fn scene(lines: &str) -> Scene {
    session(lines).scene.expect("a Start in the lines")
}

/// One step.
pub fn step(scene: &mut Scene) {
    cycle::run(scene, 1).unwrap_or_else(|b| panic!("{}", b.message));
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Sets a particle's velocity and books the change of kinetic energy as a command input (as
/// the session does for commands).
pub fn set_velocity(scene: &mut Scene, i: usize, v: trubal::sim::Vec3) {
    let before = trubal::sim::energy::stored(scene).total();
    scene.unchecked().particles.vel[i] = v;
    scene.unchecked().ledger.commands += trubal::sim::energy::stored(scene).total() - before;
}

/// What a run of the binary gave.
pub struct Run {
    pub ok: bool,
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `trubal --json ARGS -` with `script` on its standard input, in a fresh temporary
/// folder.
pub fn trubal_json(script: &str, args: &[&str]) -> Run {
    use std::io::Write;
    use std::process::Stdio;
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("trubal-run-{}-{k}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut child = crate::common::trubal()
        .current_dir(&dir)
        .arg("--json")
        .args(args)
        .arg("-")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(script.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    Run {
        ok: out.status.success(),
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// The JSON objects the run printed with `"print": kind`, in order.
pub fn printed(run: &Run, kind: &str) -> Vec<serde_json::Value> {
    run.stdout
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|v| v["print"] == kind)
        .collect()
}

/// The binary, as the tests run it: one worker thread unless the test gives `--threads`
/// (two test threads each running a two-thread trubal whose idle worker polls through a
/// Cycle would fight over the two cores of the CI machine; `tests/it/threads.rs` asks for
/// its thread counts explicitly).
pub fn trubal() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_trubal"));
    c.env("RAYON_NUM_THREADS", "1");
    c
}

/// A session in the test process, its diagnostics kept out of the runner's output. The
/// test process's global pool gets one thread (the first call makes it, if no test has
/// used the pool yet): two test threads that each cycled on a two-thread pool whose idle
/// worker polls through a Cycle would fight over the two cores; the thread counts
/// themselves are tested through the binary (`tests/it/threads.rs`).
pub fn session_with(out: Box<dyn std::io::Write + Send>, json: bool) -> Session {
    static ONE: std::sync::Once = std::sync::Once::new();
    ONE.call_once(|| {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build_global();
    });
    Session::new(out, json)
}
