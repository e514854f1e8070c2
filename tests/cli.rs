//! End-to-end tests: command files and standard input through the binary; errors name
//! file:line:column, show a caret, change nothing and never panic.

use std::io::Write;
use std::process::{Command, Stdio};

fn run(input: &str, args: &[&str]) -> (bool, String, String) {
    let dir = std::env::temp_dir().join(format!(
        "trubal-cli-{}-{}",
        std::process::id(),
        rand_tag(input)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_trubal"))
        .args(args)
        .current_dir(&dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn rand_tag(s: &str) -> u64 {
    s.bytes().fold(1469598103934665603u64, |h, b| {
        (h ^ b as u64).wrapping_mul(1099511628211)
    })
}

const SETUP: &str =
    "start 0.1 0.1 0.1 1000 2000 2\nrad 0.004330127 1\nymd 1e9 1\npra 0.3 1\ndensity 2500 1\n";

fn err_of(lines: &str) -> String {
    let (ok, _, err) = run(lines, &["-"]);
    assert!(!ok, "expected failure for:\n{lines}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

#[test]
fn bcc_example_generates_2000() {
    let input = format!(
        "{SETUP}agen 1 1 1 0 0 0 0.01 0.01 0.01\nagen 1 1 1 0.005 0.005 0.005 0.01 0.01 0.01\n--json\n"
    );
    let input = input.replace("--json\n", "print info\n");
    let (ok, out, err) = run(&input, &["-", "--json"]);
    assert!(ok, "{err}");
    let info: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    assert_eq!(info["print"], "info");
    assert_eq!(info["balls"], 2000);
}

#[test]
fn errors_are_located_with_a_caret() {
    let err = err_of("start 1 1 1 10 10 1\nrad -3 1\n");
    assert!(err.contains("<stdin>:2:5: error"), "{err}");
    assert!(err.contains("must be positive"), "{err}");
    assert!(err.contains("    ^^"), "{err}");
}

#[test]
fn typos_and_bad_parameters() {
    let cases: &[(&str, &str)] = &[
        ("start 1 1 1 10 10 1\nprnt info\n", "did you mean PRint"),
        ("start 1 1 1 10 10 1\np info\n", "too short"),
        ("start 1 1 1 10 10 1\nrad 0.1\n", "needs an integer `isize`"),
        ("start 1 1 1 10 10 1\nrad 0.1 1 7\n", "unexpected `7`"),
        ("start 1 1 1 10 10 1\nrad abc 1\n", "expected a number"),
        ("start 1 1 1 10 10 1\nrad 0.1 1.5\n", "whole number"),
        ("start 1 1 1 10 10 1\ndensity -5 1\n", "must be positive"),
        ("cycle 10\n", "give STArt"),
        (
            "start 1 1 1 10 10 1\nstart 1 1 1 10 10 1\n",
            "already defined",
        ),
        (
            "start 1 1 1 10 10 1\nrad 0.1 1\ncreate 0.5 0.5 0.5 0 0 0 0 0 0 1 3\n",
            "material type 3 is not defined",
        ),
        (
            "start 1 1 1 10 10 1\ncohesion -1 1\n",
            "must not be negative",
        ),
        ("start 1 1 1 10 10 1\nrset 1 2\n", "use SET"),
        (
            "start 1 1 1 10 10 1\nliquid 0.1 0.025 95 0\n",
            "contact angle",
        ),
        (
            "start 1 1 1 10 10 1\nvelocity 1 2 3\n",
            "VELocity takes 4 numbers",
        ),
    ];
    for (input, want) in cases {
        let err = err_of(input);
        assert!(
            err.contains(want),
            "input:\n{input}\nwanted `{want}` in:\n{err}"
        );
    }
}

#[test]
fn capacity_and_full_region() {
    let err = err_of(&format!(
        "{SETUP}agen 1 1 1 0 0 0 0.01 0.01 0.01\nagen 1 1 1 0.005 0.005 0.005 0.01 0.01 0.01\ncreate 0.0501 0.0502 0.0 0 0 0 0 0 0 1 1\n"
    ));
    assert!(
        err.contains("exceed nball") || err.contains("overlap"),
        "{err}"
    );
    // Generation into a full region reports the try limit.
    let (ok, out, err) = run(
        "start 1 1 1 10 100 1\nrad 0.1 1\nymd 1e9 1\npra 0.3 1\ndensity 1000 1\naggl 1 0.5 0.5 0.5 0.15\nrge 50 1 1 1\n",
        &["-"],
    );
    assert!(ok, "{err}");
    assert!(out.contains("try limit"), "{out}");
}

#[test]
fn a_failing_command_changes_nothing() {
    let (_, out, _) = run(
        &format!(
            "{SETUP}create 0.05 0.05 0.05 0 0 0 0 0 0 1 1\ncreate 0.051 0.05 0.05 0 0 0 0 0 0 1 1\nprint info\n"
        ),
        &["-", "--keep-going", "--json"],
    );
    let info: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    assert_eq!(info["balls"], 1);
}

#[test]
fn binary_garbage_on_stdin_does_not_panic() {
    let garbage: String = (0u8..=255).map(|b| b as char).cycle().take(5000).collect();
    let (_, _, err) = run(&garbage, &["-", "--keep-going"]);
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn several_commands_on_one_line_and_variables() {
    let (ok, out, err) = run(
        &format!("{SETUP}create 0.05 0.05 0.05 0 0 $v 0 0 0 1 1\nplot save cycle 10 print info\n"),
        &["-", "--json", "--set", "v=-0.5"],
    );
    assert!(ok, "{err}");
    let info: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    assert_eq!(info["cycle"], 10);
    let (ok, _, err) = run("start 1 1 1 1 1 1\ncreate $nope\n", &["-"]);
    assert!(!ok && err.contains("--set nope=VALUE"), "{err}");
}

#[test]
fn batch_mode_reads_trubal_dat() {
    let dir = std::env::temp_dir().join(format!("trubal-batch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("TRUBAL.DIR"), "BATCH\n").unwrap();
    std::fs::write(
        dir.join("TRUBAL.DAT"),
        format!("{SETUP}create 0.05 0.05 0.05 0 0 0 0 0 0 1 1\nprint info\n"),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_trubal"))
        .current_dir(&dir)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("TRUBAL.OUT")).unwrap();
    assert!(text.contains("balls 1"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn log_file_echoes_commands() {
    let dir = std::env::temp_dir().join(format!("trubal-log-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("in.tru"),
        "start 1 1 1 1 1 1 log\nprint grid\nlog off\nprint grid\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_trubal"))
        .arg("in.tru")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let log = std::fs::read_to_string(dir.join("TRUBAL.OUT")).unwrap();
    assert!(log.contains("> print grid"), "{log}");
    assert_eq!(log.matches("work-space").count(), 2, "{log}");
    assert_eq!(log.matches("> ").count(), 2, "{log}"); // `print grid` and `log off`
    let _ = std::fs::remove_dir_all(&dir);
}
