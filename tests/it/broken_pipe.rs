//! Output to a pipe whose reader has gone (`trubal file | head -1`) never panics: write errors
//! on standard output and standard error are ignored and the run finishes normally.

use std::process::Stdio;

/// A pipe whose read end is already closed: every write to it fails with EPIPE.
fn broken() -> Stdio {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    Stdio::from(writer)
}

fn script(dir: &std::path::Path, text: &str) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("run.tru"), text).unwrap();
}

fn scratch(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("trubal-pipe-{tag}-{}", std::process::id()))
}

#[test]
fn closed_stdout_does_not_panic() {
    let dir = scratch("out");
    let mut text = String::from("start 1 1 1 10 10 1\n");
    for _ in 0..500 {
        text.push_str("print grid settings info\n");
    }
    // The run goes on after the reader left: the checkpoint is still written.
    text.push_str("save end.sav\n");
    script(&dir, &text);
    for json in [false, true] {
        let mut cmd = crate::common::trubal();
        cmd.arg("run.tru").current_dir(&dir);
        if json {
            cmd.arg("--json");
        }
        let out = cmd
            .stdout(broken())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(out.status.code(), Some(0), "{err}");
        assert!(dir.join("end.sav").exists());
        std::fs::remove_file(dir.join("end.sav")).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn closed_stderr_does_not_panic() {
    let dir = scratch("err");
    let mut text = String::from("start 1 1 1 10 10 1\n");
    for _ in 0..500 {
        text.push_str("print nonsense\n");
    }
    text.push_str("save end.sav\n");
    script(&dir, &text);
    // Both streams into one closed pipe (`trubal file 2>&1 | head -1`).
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let status = crate::common::trubal()
        .args(["run.tru", "--keep-going"])
        .current_dir(&dir)
        .stdout(Stdio::from(writer.try_clone().unwrap()))
        .stderr(Stdio::from(writer))
        .status()
        .unwrap();
    // 1 = errors were reported (500 unknown items), not 101 = panic.
    assert_eq!(status.code(), Some(1));
    assert!(dir.join("end.sav").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn help_and_version_into_a_closed_pipe() {
    for arg in ["--help", "--version", "--bogus"] {
        let out = crate::common::trubal()
            .arg(arg)
            .stdout(broken())
            .stderr(broken())
            .status()
            .unwrap();
        assert_ne!(out.code(), Some(101), "{arg} panicked");
    }
}
