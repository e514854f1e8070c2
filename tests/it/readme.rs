//! The command files in README.md (blocks preceded by `<!-- file: NAME -->`) run as shown, and
//! the save/restart example continues exactly like the uninterrupted run.

use std::path::Path;

fn blocks() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(l) = lines.next() {
        if let Some(name) = l
            .trim()
            .strip_prefix("<!-- file: ")
            .and_then(|r| r.strip_suffix(" -->"))
        {
            assert_eq!(
                lines.next().map(str::trim),
                Some("```"),
                "{name}: a block must follow"
            );
            let body: Vec<&str> = lines.by_ref().take_while(|l| l.trim() != "```").collect();
            out.push((name.to_string(), body.join("\n") + "\n"));
        }
    }
    out
}

fn run(dir: &Path, file: &str) -> String {
    let out = crate::common::trubal()
        .args([file, "--json"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{file}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn json(out: &str) -> Vec<String> {
    out.lines()
        .filter(|l| l.starts_with('{'))
        .map(String::from)
        .collect()
}

#[test]
fn readme_command_files_run_and_save_restart_is_exact() {
    let dir = std::env::temp_dir().join(format!("trubal-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let blocks = blocks();
    let get = |n: &str| {
        blocks
            .iter()
            .find(|(name, _)| name == n)
            .unwrap_or_else(|| panic!("README.md has no block {n}"))
            .1
            .clone()
    };
    for (name, body) in &blocks {
        std::fs::write(dir.join(name), body).unwrap();
    }
    let bcc = json(&run(&dir, "bcc.tru"));
    assert!(bcc[0].contains("\"balls\":2000"), "{bcc:?}");

    run(&dir, "prepare.tru");
    assert!(dir.join("prepared.sav").exists());
    let continued = json(&run(&dir, "continue.tru"));
    assert_eq!(continued.len(), 2);
    // The same in one run: prepare without the save, then the continuation's commands.
    let prepare = get("prepare.tru");
    let cont = get("continue.tru");
    let whole: String = prepare
        .lines()
        .filter(|l| !l.starts_with("save"))
        .chain(cont.lines().filter(|l| !l.starts_with("restart")))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("whole.tru"), whole).unwrap();
    let uninterrupted = json(&run(&dir, "whole.tru"));
    assert_eq!(continued, uninterrupted);
    let _ = std::fs::remove_dir_all(&dir);
}

/// CI runs exactly the README's test line.
#[test]
fn ci_runs_the_readme_test_command() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let line = readme
        .lines()
        .find(|l| l.contains("# the tests (what CI runs)"))
        .expect("the README's test line");
    let command = line.split('#').next().unwrap().trim();
    // The README names .ci/run itself (it installs the VTK reader first), which runs the
    // checks one a line (under `set -e` a failure inside an `a && b` list would not stop it),
    // or a line it runs.
    let checks = [
        "cargo fmt --check",
        "cargo clippy --profile ci --all-targets -- -D warnings",
        "cargo test --profile ci",
    ];
    let runs = |c: &str| ci.lines().any(|l| l.trim() == c);
    assert!(
        (command == ".ci/run"
            && checks.iter().all(|c| runs(c))
            && ci.contains("set -euo pipefail"))
            || runs(command),
        ".ci/run does not run `{command}`"
    );
    assert!(
        !ci.lines()
            .any(|l| !l.trim_start().starts_with('#') && l.contains("&& cargo")),
        ".ci/run chains its checks with &&, which `set -e` does not stop on"
    );
}
