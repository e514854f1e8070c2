//! The terminal session and Ctrl-C as a user meets them: through a pseudo-terminal (the
//! program is the session leader of its own terminal, so Ctrl-C typed there is a real
//! SIGINT from the line discipline), and command-file runs interrupted by a signal.

use std::io::{Read, Write};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A trubal session on a pseudo-terminal.
struct Pty {
    child: Child,
    master: std::fs::File,
    seen: Arc<Mutex<Vec<u8>>>,
    dir: std::path::PathBuf,
}

fn tmpdir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("trubal-pty-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

impl Pty {
    fn start(tag: &str, args: &[&str]) -> Pty {
        let dir = tmpdir(tag);
        let pty = nix::pty::openpty(None, None).unwrap();
        let slave = std::fs::File::from(pty.slave);
        // `setsid -c`: a new session whose controlling terminal is the pseudo-terminal.
        let child = Command::new("setsid")
            .arg("-c")
            .arg(env!("CARGO_BIN_EXE_trubal"))
            .args(args)
            .current_dir(&dir)
            .env("HOME", &dir)
            .env("TERM", "xterm")
            .env("TRUBAL_PROGRESS_AFTER", "0.2")
            .env("RAYON_NUM_THREADS", "1")
            .stdin(Stdio::from(slave.try_clone().unwrap()))
            .stdout(Stdio::from(slave.try_clone().unwrap()))
            .stderr(Stdio::from(slave))
            .spawn()
            .unwrap();
        let master = std::fs::File::from(pty.master);
        let seen = Arc::new(Mutex::new(Vec::new()));
        let (mut reader, log) = (master.try_clone().unwrap(), seen.clone());
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = reader.read(&mut buf) {
                if n == 0 {
                    break;
                }
                log.lock().unwrap().extend_from_slice(&buf[..n]);
            }
        });
        Pty {
            child,
            master,
            seen,
            dir,
        }
    }

    fn send(&mut self, text: &str) {
        self.master.write_all(text.as_bytes()).unwrap();
    }

    fn text(&self) -> String {
        String::from_utf8_lossy(&self.seen.lock().unwrap()).into_owned()
    }

    /// Waits (at most 60 s) until the output holds `what` `times` times; returns the output.
    fn wait_for(&self, what: &str, times: usize) -> String {
        let t0 = Instant::now();
        loop {
            let t = self.text();
            if t.matches(what).count() >= times {
                return t;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "no `{what}` (x{times}) in the terminal after 60 s:\n{t}"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Ends the session with `stop` and returns the exit code.
    fn stop(mut self) -> (Option<i32>, String, std::path::PathBuf) {
        self.send("stop\r");
        let t0 = Instant::now();
        loop {
            if let Some(st) = self.child.try_wait().unwrap() {
                std::thread::sleep(Duration::from_millis(100));
                return (st.code(), self.text(), self.dir.clone());
            }
            assert!(t0.elapsed() < Duration::from_secs(60), "{}", self.text());
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Pty {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Two spheres that fly side by side forever: a Cycle as long as one likes.
const SCENE: &str = "start 1e-3 1e-3 1e-3 1000 10 2
rad 3e-5 1
density 2650 1
ymd 7e10 1
pra 0.3 1
create 5e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
create 5e-4 5e-4 5.7e-4 0 0 -1 0 0 0 1 1
";

#[test]
fn banner_comes_first_and_typed_ahead_lines_all_run() {
    let mut t = Pty::start("ahead", &[]);
    let first = t.wait_for("trubal> ", 1);
    assert!(
        first.find("DEM of spheres").unwrap() < first.find("trubal> ").unwrap(),
        "the banner comes before the first prompt:\n{first}"
    );
    // Six lines at once, as typed ahead or pasted without bracketing.
    t.send("start 0.1 0.1 0.1 1000 2000 2\rrad 0.004330127 1\ragen 1 1 1 0 0 0 0.01 0.01 0.01\ragen 1 1 1 0.005 0.005 0.005 0.01 0.01 0.01\rprint info\rprint settings\r");
    t.wait_for("2000 in all", 1);
    t.wait_for("balls 2000", 1);
    t.wait_for("TANgential", 1);
    // A bracketed paste of two lines, accepted with Enter: both run.
    t.send("\x1b[200~print info\nprint settings\x1b[201~\r");
    t.wait_for("balls 2000", 2);
    t.wait_for("TANgential", 2);
    let (code, _, dir) = t.stop();
    assert_eq!(code, Some(0));
    let hist = std::fs::read_to_string(dir.join(".trubal_history")).unwrap();
    assert!(hist.contains("agen 1 1 1 0.005"), "history kept:\n{hist}");
}

#[test]
fn ctrl_c_stops_a_cycle_at_a_step_and_the_state_continues_bitwise() {
    let mut t = Pty::start("ctrlc", &[]);
    t.wait_for("trubal> ", 1);
    for l in SCENE.lines() {
        t.send(&format!("{l}\r"));
    }
    // A line typed during the Cycle waits for it.
    t.send("cycle 100000000\rprint info\r");
    // The progress line, then Ctrl-C typed on the terminal.
    t.wait_for("particle-steps/s", 1);
    t.send("\x03");
    let out = t.wait_for("interrupted: Cycle stopped after ", 1);
    let after = out
        .split("interrupted: Cycle stopped after ")
        .nth(1)
        .unwrap();
    let ran: u64 = after.split_whitespace().next().unwrap().parse().unwrap();
    assert!(ran > 0 && ran < 100_000_000);
    // The line typed ahead ran after the interrupt.
    t.wait_for(&format!("cycle {ran}  time"), 1);
    // The progress line was erased (the last one is followed by the erase sequence).
    let tail = &out[out.rfind("particle-steps/s").unwrap()..];
    assert!(tail.contains("\r\x1b[K"), "{tail:?}");
    t.send("save cut.sav\r");
    t.wait_for("saved cycle", 1);
    let (code, _, dir) = t.stop();
    assert_eq!(code, Some(0));
    // The same scene run for exactly that many cycles in a file: the same bytes.
    let script = format!("{SCENE}cycle {ran}\nsave whole.sav\n");
    std::fs::write(dir.join("whole.tru"), script).unwrap();
    let st = crate::common::trubal()
        .arg("whole.tru")
        .current_dir(&dir)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(st.success());
    let a = std::fs::read(dir.join("cut.sav")).unwrap();
    let b = std::fs::read(dir.join("whole.sav")).unwrap();
    assert!(a == b, "the interrupted state is that of `Cycle {ran}`");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 51, item 2: a line typed while a Cycle runs (after the line editor has handed the
/// Cycle over) runs after a Ctrl-C too; the terminal does not drop it.
#[test]
fn lines_typed_during_a_cycle_run_after_its_ctrl_c() {
    let mut t = Pty::start("ahead-ctrlc", &[]);
    t.wait_for("trubal> ", 1);
    for l in SCENE.lines() {
        t.send(&format!("{l}\r"));
    }
    t.send("cycle 100000000\r");
    t.wait_for("particle-steps/s", 1);
    // Typed during the Cycle: it waits in the terminal's queue.
    t.send("print info\r");
    std::thread::sleep(Duration::from_millis(300));
    t.send("\x03");
    let out = t.wait_for("interrupted: Cycle stopped after ", 1);
    let after = out
        .split("interrupted: Cycle stopped after ")
        .nth(1)
        .unwrap();
    let ran: u64 = after.split_whitespace().next().unwrap().parse().unwrap();
    t.wait_for(&format!("cycle {ran}  time"), 1);
    let (code, _, dir) = t.stop();
    assert_eq!(code, Some(0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn no_progress_line_with_json_on_a_terminal() {
    let mut t = Pty::start("json", &["--json"]);
    t.wait_for("trubal> ", 1);
    for l in SCENE.lines() {
        t.send(&format!("{l}\r"));
    }
    t.send("cycle 300000\rprint info\r");
    let out = t.wait_for("\"print\":\"info\"", 1);
    assert!(!out.contains("particle-steps/s"), "{out}");
}

/// A command-file run with its output in a file and its diagnostics in a pipe, stopped by
/// SIGINT as a shell's Ctrl-C would.
fn interrupted_file_run(tag: &str, script: &str, signals: &[f64]) -> (Option<i32>, String, String) {
    let dir = tmpdir(tag);
    std::fs::write(dir.join("run.tru"), script).unwrap();
    let out = std::fs::File::create(dir.join("out.txt")).unwrap();
    let mut child = crate::common::trubal()
        .arg("run.tru")
        .current_dir(&dir)
        .env("TRUBAL_PROGRESS_AFTER", "0")
        .stdout(out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    for &after in signals {
        std::thread::sleep(Duration::from_secs_f64(after));
        let st = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
    }
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let st = child.wait().unwrap();
    let stdout = std::fs::read_to_string(dir.join("out.txt")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (st.code(), stdout, err)
}

#[test]
fn ctrl_c_in_a_file_run_keeps_the_output_and_exits_130() {
    let script = format!("{SCENE}print info\ncycle 100000000\nprint info\n");
    let (code, out, err) = interrupted_file_run("file", &script, &[1.0]);
    assert_eq!(code, Some(130), "{err}");
    // What was printed before the Cycle is in the file; the line after it never ran.
    assert_eq!(out.matches("balls 2").count(), 1, "{out}");
    assert!(err.contains("interrupted: Cycle stopped after "), "{err}");
    assert!(err.contains("run.tru:9: interrupted (Ctrl-C)"), "{err}");
    // No progress line in a pipe.
    assert!(!err.contains("particle-steps/s"), "{err}");
}

/// A second Ctrl-C quits at once when the first has not been answered: here the session is
/// stuck writing to a pipe that nobody reads (every long command answers the first press at
/// its next step, `ctrl_c_stops_rgenerate_and_changes_nothing`).
#[test]
fn a_second_ctrl_c_quits_at_once() {
    let dir = tmpdir("twice");
    std::fs::write(dir.join("run.tru"), "help\n".repeat(5000)).unwrap();
    let mut child = crate::common::trubal()
        .arg("run.tru")
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    for after in [0.5, 0.2] {
        std::thread::sleep(Duration::from_secs_f64(after));
        let st = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
    }
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let st = child.wait().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(st.code(), Some(130), "{err}");
    assert!(err.contains("interrupted twice"), "{err}");
    assert!(t0.elapsed() < Duration::from_secs(20));
}

/// A program that drives trubal through a pipe gets each answer before it sends the next
/// command (the output is written as it is produced, not when the input ends).
#[test]
fn a_pipe_gets_each_answer_as_it_is_produced() {
    let mut child = crate::common::trubal()
        .arg("-")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut input = child.stdin.take().unwrap();
    let mut output = std::io::BufReader::new(child.stdout.take().unwrap());
    input
        .write_all(b"start 1 1 1 10 10 1\nprint info\n")
        .unwrap();
    input.flush().unwrap();
    let mut line = String::new();
    // Read while the input is still open: the answer must already be there.
    std::io::BufRead::read_line(&mut output, &mut line).unwrap();
    assert!(line.starts_with("cycle 0"), "{line}");
    input.write_all(b"stop\n").unwrap();
    drop(input);
    assert!(child.wait().unwrap().success());
}

#[test]
fn ctrl_c_stops_relax_too_with_its_progress_line() {
    let mut t = Pty::start("relax", &[]);
    t.wait_for("trubal> ", 1);
    for l in SCENE.lines() {
        t.send(&format!("{l}\r"));
    }
    // Two spheres flying forever: never relaxed.
    t.send("relax 1e-30 1e-30 100000000\r");
    t.wait_for("particle-steps/s", 1);
    t.send("\x03");
    let out = t.wait_for("interrupted: RELax stopped after ", 1);
    assert!(out.contains("RELax: interrupted after"), "{out}");
    t.send("print info\r");
    t.wait_for("balls 2", 1);
    let (code, _, _) = t.stop();
    assert_eq!(code, Some(0));
}

/// Issue 51 item 1: RGEnerate and RGEnerate Seed show the progress line and stop at Ctrl-C
/// without changing anything: the session goes on from the scene (and the random numbers)
/// as before them, to the byte.
#[test]
fn ctrl_c_stops_rgenerate_and_changes_nothing() {
    // 100 large spheres, then two million small ones (room enough, but each try searches
    // the large spheres' coarse cells: it runs long).
    let head = "start 1 1 1 10 3000000 2\nrad 0.05 1\nrad 0.001 2\nrgen 100 1 1 0\n";
    let mut t = Pty::start("rgen", &[]);
    t.wait_for("trubal> ", 1);
    for l in head.lines() {
        t.send(&format!("{l}\r"));
    }
    t.wait_for("100 particles placed", 1);
    t.send("rgen 2000000 2 1 0\r");
    t.wait_for("of 2000000 particles placed (", 1);
    t.send("\x03");
    let out = t.wait_for("interrupted: RGEnerate stopped after", 1);
    assert!(out.contains("nothing was placed"), "{out}");
    t.send("rge seed 1000000000000000\r");
    t.wait_for("numbers drawn (", 1);
    t.send("\x03");
    t.wait_for("interrupted: RGEnerate Seed stopped after", 1);
    t.send("rgen 5 1 1 0\rprint info\r");
    t.wait_for("balls 105 ", 1);
    t.send("save cut.sav\r");
    t.wait_for("saved cycle", 1);
    let (code, out, dir) = t.stop();
    assert_eq!(code, Some(0), "{out}");
    // The progress lines were erased.
    let tail = &out[out.rfind("(Ctrl-C stops)").unwrap()..];
    assert!(tail.contains("\r\x1b[K"), "{tail:?}");
    std::fs::write(
        dir.join("whole.tru"),
        format!("{head}rgen 5 1 1 0\nsave whole.sav\n"),
    )
    .unwrap();
    let st = crate::common::trubal()
        .arg("whole.tru")
        .current_dir(&dir)
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(st.success());
    let a = std::fs::read(dir.join("cut.sav")).unwrap();
    let b = std::fs::read(dir.join("whole.sav")).unwrap();
    assert!(
        a == b,
        "the scene after the interrupted commands is as without them"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// AGEnerate of 15.6 million lattice sites: the progress line, Ctrl-C, nothing placed.
#[test]
fn ctrl_c_stops_agenerate_and_changes_nothing() {
    let mut t = Pty::start("agen", &[]);
    t.wait_for("trubal> ", 1);
    t.send("start 1 1 1 10 200000 2\rrad 0.01 1\ragen 1 1 0 0 0 0 0.004 0.004 0.004\r");
    t.wait_for("sites examined (", 1);
    t.send("\x03");
    let out = t.wait_for("interrupted: AGEnerate stopped after", 1);
    assert!(out.contains("nothing was placed"), "{out}");
    t.send("print info\r");
    t.wait_for("balls 0 ", 1);
    let (code, out, dir) = t.stop();
    assert_eq!(code, Some(0), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// PRObe (1250 cycles of a copy of the scene) shows the progress line and stops at Ctrl-C
/// with the scene as before: the state saved afterwards is the same bytes as before it.
#[test]
fn ctrl_c_stops_a_probe_and_changes_nothing() {
    let mut t = Pty::start("probe", &[]);
    t.wait_for("trubal> ", 1);
    let head = "start 0.02 0.02 0.02 100000 100000 0\nrad 1e-4 1\ndensity 2600 1\nymd 6e8 1\n\
                pra 0.25 1\nfriction 0 1\nrge 100000 1 1 0\ngrid -1 -1 -1 0 0 0\ncycle 20\n\
                grid 0 0 0 0 0 0\nsave before.sav\n";
    for l in head.lines() {
        t.send(&format!("{l}\r"));
    }
    t.wait_for("saved cycle", 1);
    t.send("probe e11\r");
    t.wait_for("of 1250 done", 1);
    t.send("\x03");
    t.wait_for("interrupted: PRObe E11 stopped at Ctrl-C", 1);
    t.send("save after.sav\r");
    t.wait_for("saved cycle", 2);
    let (code, out, dir) = t.stop();
    assert_eq!(code, Some(0), "{out}");
    let a = std::fs::read(dir.join("before.sav")).unwrap();
    let b = std::fs::read(dir.join("after.sav")).unwrap();
    assert!(a == b, "the interrupted probe changed the scene");
    let _ = std::fs::remove_dir_all(&dir);
}
