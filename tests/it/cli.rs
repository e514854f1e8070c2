//! End-to-end tests: command files and standard input through the binary; errors name
//! file:line:column, show a caret, change nothing and never panic.

use std::io::Write;
use std::process::Stdio;

pub(crate) fn run(input: &str, args: &[&str]) -> (bool, String, String) {
    let dir = std::env::temp_dir().join(format!(
        "trubal-cli-{}-{}",
        std::process::id(),
        rand_tag(input)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let mut child = crate::common::trubal()
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
        ("start 1 1 1 10 10 1\nst\n", "too short"),
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
            "start 1 1 1 10 10 1\nrad 0.1 1\ncreate 0.5 0.5 0.5 0 0 0 0 0 0 1 3\ncycle 1\n",
            "material 3 has no Young's modulus",
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
    // Generation into a full region gives up (one particle fits) and says so.
    let (ok, out, err) = run(
        "start 1 1 1 10 100 1\nrad 0.1 1\nymd 1e9 1\npra 0.3 1\ndensity 1000 1\naggl 1 0.5 0.5 0.5 0.15\nrge 50 1 1 1\nprint info\n",
        &["-"],
    );
    assert!(ok, "{err}");
    assert!(
        out.contains("only 1 of 50 particles placed") && out.contains("try limit"),
        "{out}"
    );
    assert!(out.contains("balls 1 "), "{out}");
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
    let out = crate::common::trubal()
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
    let out = crate::common::trubal()
        .arg("in.tru")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    let log = std::fs::read_to_string(dir.join("TRUBAL.OUT")).unwrap();
    assert!(log.contains("> print grid"), "{log}");
    assert_eq!(log.matches("work-space").count(), 2, "{log}");
    // `start ... log` (the line that opened it, first), `print grid` and `log off`.
    assert!(log.starts_with("> start 1 1 1 1 1 1 log\n"), "{log}");
    assert_eq!(log.matches("> ").count(), 3, "{log}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs raw bytes as a command file (`trubal FILE`), in a scratch folder.
fn run_file_bytes(tag: &str, bytes: &[u8], args: &[&str]) -> (Option<i32>, String, String) {
    let dir = std::env::temp_dir().join(format!("trubal-clif-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("in.tru"), bytes).unwrap();
    let out = crate::common::trubal()
        .arg("in.tru")
        .args(args)
        .current_dir(&dir)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// Every command sequence the thesis quotes (Lian 1994 §5.3 and Appendix B), verbatim and in
/// its order: generation before the material, `p c`, `Pr cO`, several commands on a line.
#[test]
fn the_thesis_examples_run_verbatim() {
    let bcc = "start 0.1 0.1 0.1 1000 2000 2 log\n\nrad 0.004330127 1\n\nagen 1 1 1 0 0 0 0.01 0.01 0.01\n\nagen 1 1 1 0.005 0.005 0.005 0.01 0.01 0.01\n";
    let (code, out, err) = run_file_bytes("thesis", bcc.as_bytes(), &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("2000 in all"), "{out}");
    // Then the material, and Appendix B's examples.
    let rest = "density 2650 1\nymd 70e9 1\npra 0.3 1\nplot save cycle 200 plot bou rdisp\nPrint G C I\np c\nPr cO\nRGE Seed 5\nprint info\n";
    let (code, out, err) = run_file_bytes("thesis2", format!("{bcc}{rest}").as_bytes(), &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("plot written to plot_c00000200_bou_rdisp.png"),
        "{out}"
    );
    assert!(out.contains("cycle 200  time"), "{out}");
    // `p c` and `Pr cO` print the contacts' table as `Print C` does.
    assert_eq!(out.matches("normal_force").count(), 3, "{out}");
}

#[test]
fn the_material_is_asked_for_by_the_first_command_that_needs_it() {
    let input = "start 0.1 0.1 0.1 1000 2000 2\nrad 0.004330127 1\nagen 1 1 1 0 0 0 0.01 0.01 0.01\ncycle 1\n";
    let err = err_of(input);
    assert!(
        err.contains("<stdin>:4:1: error: material 1 has no Young's modulus"),
        "{err}"
    );
    // Density given after generation sets the masses: the same as given before.
    let before = "start 0.1 0.1 0.1 1000 2000 2\nrad 0.004330127 1\ndensity 2650 1\nymd 70e9 1\npra 0.3 1\nagen 1 1 1 0 0 0 0.01 0.01 0.01\nvelocity 1 0 0 0\nprint energy\n";
    let after = "start 0.1 0.1 0.1 1000 2000 2\nrad 0.004330127 1\nagen 1 1 1 0 0 0 0.01 0.01 0.01\nvelocity 1 0 0 0\ndensity 2650 1\nymd 70e9 1\npra 0.3 1\nprint energy\n";
    let kin = |s: &str| {
        let (ok, out, err) = run(s, &["-", "--json"]);
        assert!(ok, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
        v["kinetic"]
            .as_f64()
            .or_else(|| v["stored"]["kinetic"].as_f64())
            .unwrap_or_else(|| panic!("{v}"))
    };
    let (a, b) = (kin(before), kin(after));
    // 1000 spheres of R = 4.33 mm, 2650 kg/m^3, at 1 m/s: sum of m v^2 / 2.
    let m = 2650.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.004330127f64.powi(3);
    assert!((a - 500.0 * m).abs() < 1e-9 * a, "{a} vs {}", 500.0 * m);
    assert_eq!(a, b);
}

#[test]
fn version_quit_and_help_of_a_command() {
    for flag in ["-V", "--version"] {
        let out = crate::common::trubal().arg(flag).output().unwrap();
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).starts_with("trubal "));
    }
    // `quit` and `exit` end the session as STOp does; `bye` is still pointed to STOp.
    for word in ["quit", "exit", "QUIT"] {
        let (ok, out, err) = run(
            &format!("start 1 1 1 10 10 1\n{word}\nprint info\n"),
            &["-"],
        );
        assert!(ok, "{err}");
        assert!(!out.contains("balls"), "{word} ended the session: {out}");
    }
    let err = err_of("bye\n");
    assert!(err.contains("STOp ends the session"), "{err}");
    let (ok, out, _) = run("help print\nhelp plot\nhelp p\n", &["-"]);
    assert!(ok);
    for item in [
        "ENErgy", "SETtings", "Walls", "RDIsp", "LCLuster", "HIStory",
    ] {
        assert!(out.contains(item), "help lists {item}:\n{out}");
    }
    // `help p` is PRint's help (Appendix B.1's alias).
    assert_eq!(out.matches("PRint item").count(), 2, "{out}");
}

#[test]
fn dollar_in_a_comment_is_not_a_variable() {
    let (ok, _, err) = run(
        "start 1 1 1 10 10 1 ; costs $5\n# $HOME is not asked for\n",
        &["-"],
    );
    assert!(ok, "{err}");
    let err = err_of("start 1 1 1 10 10 $n\n");
    assert!(err.contains("`$n` has no value"), "{err}");
}

#[test]
fn byte_order_marks_and_encodings() {
    let (code, out, err) = run_file_bytes(
        "bom8",
        b"\xef\xbb\xbfstart 1 1 1 10 10 1\nprint info\n",
        &[],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("balls 0"), "{out}");
    let utf16: Vec<u8> = [0xff, 0xfe]
        .into_iter()
        .chain(
            "start 1 1 1 10 10 1\n"
                .encode_utf16()
                .flat_map(|u| u.to_le_bytes()),
        )
        .collect();
    let (code, _, err) = run_file_bytes("bom16", &utf16, &[]);
    assert_eq!(code, Some(1));
    assert!(err.contains("encoded as UTF-16 (little-endian)"), "{err}");
}

#[test]
fn a_huge_line_is_refused_with_its_length_and_an_excerpt() {
    let mut text = b"start 1 1 1 10 10 1\nprint ".to_vec();
    text.extend(std::iter::repeat_n(b'x', 3 << 20));
    text.extend(b"\nprint info\n");
    for keep in [false, true] {
        let args: &[&str] = if keep { &["--keep-going"] } else { &[] };
        let (code, out, err) = run_file_bytes(&format!("huge{keep}"), &text, args);
        assert_eq!(code, Some(1));
        assert!(
            err.contains("in.tru:2: error: the line is 3145734 bytes long"),
            "{}",
            &err[..err.len().min(500)]
        );
        assert!(
            err.len() < 400,
            "the error quotes an excerpt only ({} bytes)",
            err.len()
        );
        // With --keep-going the next line runs.
        assert_eq!(out.contains("balls 0"), keep);
    }
    // Standard input: the same, without holding the line.
    let text = String::from_utf8(text).unwrap();
    let (ok, out, err) = run(&text, &["-", "--keep-going"]);
    assert!(!ok);
    assert!(
        err.contains("<stdin>:2: error: the line is 3145734 bytes long"),
        "{}",
        &err[..err.len().min(500)]
    );
    assert!(out.contains("balls 0"));
    // A long line under the limit: its error shows an excerpt around the error.
    let line = format!("print info {} zz\n", "y".repeat(5000));
    let err = err_of(&format!("start 1 1 1 10 10 1\n{line}"));
    assert!(err.len() < 1200, "{err}");
}

/// The documents that messages and docs point users to exist, with the sections named.
#[test]
fn referenced_doc_sections_exist() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut sources = Vec::new();
    let mut stack = vec![root.join("src")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                sources.push(p);
            }
        }
    }
    let mut checked = 0;
    for p in sources {
        // Comment lines joined, so that a title wrapped over two reads as one.
        let text: String = std::fs::read_to_string(&p)
            .unwrap()
            .lines()
            .map(|l| l.trim_start().trim_start_matches('/').trim_start())
            .collect::<Vec<_>>()
            .join(" ");
        // `doc/NAME.md, \"Section\"` or `doc/NAME.md, "Section"` in messages and comments.
        let mut rest = text.as_str();
        while let Some(i) = rest.find("doc/") {
            rest = &rest[i..];
            let end = rest.find(".md").filter(|&e| e < 40);
            if let Some(e) = end {
                let file = &rest[..e + 3];
                if file
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "/_-.".contains(c))
                {
                    let path = root.join(file);
                    assert!(path.exists(), "{}: {file} does not exist", p.display());
                    let after = rest[e + 3..]
                        .trim_start_matches(", ")
                        .trim_start_matches('\\');
                    if let Some(q) = after.strip_prefix('"') {
                        let title = q.split(['"', '\\']).next().unwrap();
                        let doc = std::fs::read_to_string(&path).unwrap();
                        assert!(
                            doc.lines().any(|l| l.starts_with('#') && l.contains(title)),
                            "{}: {file} has no section \"{title}\"",
                            p.display()
                        );
                    }
                    checked += 1;
                }
            }
            rest = &rest[4..];
        }
    }
    assert!(checked > 10, "{checked}");
}

#[test]
fn the_readme_says_how_to_install() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    assert!(readme.contains("cargo install --path ."));
    assert!(readme.contains("Ctrl-C"));
}

/// Issue 51, item 5: messages that misled a new user.
#[test]
fn messages_say_what_is_wrong() {
    // A whole number too large: said so, with the limit.
    let err = err_of("start 1 1 1 10 10 1\ncycle 99999999999999999999999\n");
    assert!(
        err.contains("is too large: at most 9000000000000000"),
        "{err}"
    );
    assert!(!err.contains("whole number"), "{err}");
    // A size type: the limit is the number of size types.
    let err = err_of("start 1 1 1 10 10 1\nrad 0.001 0\n");
    assert!(
        err.contains("`isize` must be between 1 and 64, got 0"),
        "{err}"
    );
    let err = err_of("start 1 1 1 10 10 1\ndensity 2000 65\n");
    assert!(err.contains("`mtyp` must be between 1 and 64"), "{err}");
    // Did-you-mean prefers the item whose name the word starts.
    let err = err_of("start 1 1 1 10 10 1\npr energies\n");
    assert!(err.contains("did you mean ENErgy?"), "{err}");
    let err = err_of("j\n");
    assert!(err.contains("unknown command `j`"), "{err}");
    assert!(!err.contains("did you mean"), "{err}");
    // A prefix of two commands names both with their shortest forms.
    let err = err_of("e\n");
    assert!(
        err.contains("`e` is too short to choose: ELSE (else) or END (end)?"),
        "{err}"
    );
    // PRint Info on an empty scene: what the step waits for, not `inf`.
    let (ok, out, err) = run(
        "start 1 1 1 10 10 1\nprint info\nrad 0.01 1\nrgen 1 1 1 0\nprint info\n",
        &["-"],
    );
    assert!(ok, "{err}");
    assert!(out.contains("dt not yet known (no particles)"), "{out}");
    assert!(
        out.contains("dt not yet known (a material property is missing"),
        "{out}"
    );
    assert!(!out.contains("inf"), "{out}");
}

/// Issue 51, item 5: help is wrapped (80 columns when not a terminal), SET's items have help
/// of their own, and the index is in alphabetical order.
#[test]
fn help_is_wrapped_and_covers_set_items() {
    let (ok, out, err) = run("help set\nhelp\nhelp cycle\n", &["-"]);
    assert!(ok, "{err}");
    let longest = out.lines().map(|l| l.chars().count()).max().unwrap();
    assert!(longest <= 80, "a help line of {longest} characters:\n{out}");
    assert!(out.contains("  - TUNnel STOP|DELETE"), "{out}");
    let names: Vec<&str> = out
        .lines()
        .skip_while(|l| !l.starts_with("Commands"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let i_move = names.iter().position(|n| *n == "MOVe").unwrap();
    assert_eq!(names[i_move - 1], "Mode", "{names:?}");
    assert_eq!(names[i_move + 1], "New", "{names:?}");
    let (ok, out, err) = run("help set outdir\nhelp set tun\nhelp print energy\n", &["-"]);
    assert!(ok, "{err}");
    assert!(out.contains("SET OUTdir\n  OUTdir path"), "{out}");
    assert!(out.contains("must be quoted"), "{out}");
    assert!(out.contains("SET TUNnel\n  TUNnel STOP|DELETE"), "{out}");
    assert!(out.contains("PRint ENErgy"), "{out}");
    let err = err_of("help set zz\n");
    assert!(err.contains("unknown SET item `zz`"), "{err}");
    // The unquoted path gets SAve's quoting hint.
    let err = err_of("start 1 1 1 10 10 1\nset outdir runs/a\n");
    assert!(err.contains("with `/` must be quoted"), "{err}");
    let (ok, _, err) = run("start 1 1 1 10 10 1\nset outdir \"runs/a\"\n", &["-"]);
    assert!(ok, "{err}");
}

/// Issue 51, item 4: a binary file is named as such (once, and not read further), and no
/// message writes raw control bytes of the input to the terminal.
#[test]
fn binary_files_are_named_and_never_echoed_raw() {
    let elf = std::fs::read(env!("CARGO_BIN_EXE_trubal")).unwrap();
    let mut gzip = vec![0x1f, 0x8b, 0x08, 0x00, 0, 0, 0, 0, 0, 3];
    let mut x = 12345u64;
    let mut noise = Vec::new();
    for _ in 0..4000 {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        noise.push((x >> 56) as u8);
    }
    gzip.extend(&noise);
    // Compressed data without a NUL on its first line: mostly bytes that are not text.
    let no_nul: Vec<u8> = noise
        .iter()
        .map(|&b| if b == 0 || b == b'\n' { 0xa7 } else { b })
        .take(300)
        .chain(*b"\n")
        .collect();
    let utf16: Vec<u8> = "start 1 1 1 10 10 1\nprint info\n"
        .encode_utf16()
        .flat_map(|u| u.to_le_bytes())
        .collect();
    for (tag, bytes, expect) in [
        ("elf", &elf[..elf.len().min(1 << 16)], "NUL bytes"),
        ("gzip", &gzip[..], "NUL bytes"),
        ("nonul", &no_nul[..], "are not text"),
        ("utf16", &utf16[..], "UTF-16 without a byte-order mark"),
    ] {
        for args in [&[][..], &["--keep-going"][..]] {
            let (code, out, err) = run_file_bytes(tag, bytes, args);
            assert_eq!(code, Some(1), "{tag}: {err}");
            assert!(
                err.contains("in.tru:1: error: this looks like a binary file"),
                "{tag}: {err}"
            );
            assert!(err.contains(expect), "{tag}: {err}");
            assert_eq!(
                err.lines().count(),
                1,
                "{tag}: one error, nothing more read: {err}"
            );
            assert!(out.is_empty(), "{tag}: {out}");
        }
    }
    // A stray control byte in an ordinary line: the message shows `?`, not the byte.
    let (code, _, err) = run_file_bytes("esc", b"start 1 1 1 10 10 1\nprint \x1b[2Jinfo\n", &[]);
    assert_eq!(code, Some(1));
    assert!(err.contains("unknown print item `?[2Jinfo`"), "{err}");
    assert!(!err.chars().any(|c| c.is_control() && c != '\n'), "{err:?}");
}

/// Issue 51, item 6: values a user cannot have meant are refused with the accepted range, and
/// change nothing.
#[test]
fn values_out_of_physical_sense_are_refused() {
    let err = err_of("start 0.1 0.1 0.1 10 10 1\nrad 1e308 1\n");
    assert!(
        err.contains("a radius of 1e308 m is larger than the work-space (its largest side is 0.1 m): accepted 0 < r <= 0.1 m"),
        "{err}"
    );
    let err = err_of("start 0.1 0.1 0.1 10 10 1\nrad 0.01 1 uniform 0.005 0.5\n");
    assert!(
        err.contains("a radius of 0.5 m is larger than the work-space"),
        "{err}"
    );
    let err = err_of("start 0.1 0.1 0.1 10 10 1\nfraction 1e9\n");
    assert!(
        err.contains("FRAction 1e9 is above 10: accepted 0 < f <= 10"),
        "{err}"
    );
    // The blow-up tests' values and TRUBAL's default stay accepted.
    let (ok, out, err) = run(
        "start 0.1 0.1 0.1 10 10 1\nrad 0.1 1\nfraction 10\nfraction 1\nrad 1e308 1\nprint settings\n",
        &["-", "--keep-going"],
    );
    assert!(
        !ok && err.lines().filter(|l| l.contains("error")).count() == 1,
        "{err}"
    );
    assert!(
        out.contains("fraction") || out.contains("FRAction"),
        "{out}"
    );
}

/// Issue 51 item 1: a target that random placement cannot reach is given up in well under a
/// second (it took 196 s to reach the try limit), keeping the particles that found room, and
/// saying why.
#[test]
fn an_impossible_rgenerate_gives_up_at_once() {
    let t0 = std::time::Instant::now();
    let (ok, out, err) = run(
        "start 1 1 1 10 200000 2\nrad 0.02 1\nrgen 100000 1 1 0\nprint info\n",
        &["-"],
    );
    assert!(ok, "{err}");
    assert!(t0.elapsed() < std::time::Duration::from_secs(10));
    let line = out.lines().next().unwrap();
    assert!(line.starts_with("RGEnerate: only "), "{line}");
    assert!(line.contains("of 100000 particles placed in"), "{line}");
    assert!(line.contains("the rate of placement"), "{line}");
    let placed: usize = line["RGEnerate: only ".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(out.contains(&format!("balls {placed} ")), "{out}");
}

/// The give-up rule refuses no target the try limit lets random placement reach: 670
/// spheres of R = 0.05 in a 1 m box (with the default seed the 670th is placed at try
/// 666,286 of the 680,000 allowed, a volume fraction of 0.35) succeed; 672 reach the limit.
#[test]
fn a_dense_rgenerate_near_the_try_limit_still_succeeds() {
    let head = "start 1 1 1 10 2000 2\nrad 0.05 1\n";
    let (ok, out, err) = run(&format!("{head}rgen 670 1 1 0\n"), &["-"]);
    assert!(ok, "{err}");
    assert!(
        out.contains("670 particles placed in 666286 tries"),
        "{out}"
    );
    let (ok, out, err) = run(&format!("{head}rgen 672 1 1 0\n"), &["-"]);
    assert!(ok, "{err}");
    assert!(
        out.contains("only 670 of 672 particles placed in 682000 tries: the try limit"),
        "{out}"
    );
}
