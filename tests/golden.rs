//! Golden files: every `golden/NAME.tru` is run through the binary (in a scratch directory,
//! `--json` if the file's first line says `# json`) and its standard output is compared with
//! `golden/NAME.out` number by number. The relative tolerance is stated in the command file as
//! `# tolerance: 1e-9` (default 1e-12). `TRUBAL_BLESS=1 cargo test --release --test golden`
//! rewrites the expected files.

use std::path::Path;
use std::process::Command;

fn tokens(s: &str) -> Vec<String> {
    s.split(|c: char| c.is_whitespace() || "[]{},:\"()".contains(c))
        .filter(|t| !t.is_empty())
        .map(|t| t.to_string())
        .collect()
}

fn close(a: &str, b: &str, tol: f64) -> bool {
    if a == b {
        return true;
    }
    match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) => (x - y).abs() <= tol * x.abs().max(y.abs()) + 1e-300,
        _ => false,
    }
}

fn run_one(tru: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(tru).unwrap();
    let tol = text
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("# tolerance:")
                .map(|t| t.trim().parse::<f64>().unwrap())
        })
        .unwrap_or(1e-12);
    let json = text.lines().next().is_some_and(|l| l.trim() == "# json");
    let dir = std::env::temp_dir().join(format!(
        "trubal-golden-{}-{}",
        tru.file_stem().unwrap().to_string_lossy(),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_trubal"));
    cmd.arg(std::fs::canonicalize(tru).unwrap())
        .current_dir(&dir);
    if json {
        cmd.arg("--json");
    }
    let out = cmd.output().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let got = String::from_utf8_lossy(&out.stdout).to_string();
    if !out.status.success() {
        return Err(format!(
            "{}: exit status {:?}\nstderr:\n{}",
            tru.display(),
            out.status.code(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let expected_path = tru.with_extension("out");
    if std::env::var_os("TRUBAL_BLESS").is_some() {
        std::fs::write(&expected_path, &got).unwrap();
        return Ok(());
    }
    let expected = std::fs::read_to_string(&expected_path).map_err(|_| {
        format!(
            "{} is missing: run with TRUBAL_BLESS=1",
            expected_path.display()
        )
    })?;
    let (g, e) = (tokens(&got), tokens(&expected));
    for (k, (a, b)) in g.iter().zip(e.iter()).enumerate() {
        if !close(a, b, tol) {
            return Err(format!(
                "{}: token {k} differs: got `{a}`, expected `{b}` (tolerance {tol})\n--- got ---\n{got}\n--- expected ---\n{expected}",
                tru.display()
            ));
        }
    }
    if g.len() != e.len() {
        return Err(format!(
            "{}: {} tokens, expected {}\n--- got ---\n{got}\n--- expected ---\n{expected}",
            tru.display(),
            g.len(),
            e.len()
        ));
    }
    Ok(())
}

#[test]
fn golden_files() {
    let mut failures = Vec::new();
    let mut n = 0;
    let mut files: Vec<_> = std::fs::read_dir("golden")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "tru"))
        .collect();
    files.sort();
    for f in files {
        n += 1;
        if let Err(e) = run_one(&f) {
            failures.push(e);
        }
    }
    assert!(n > 0, "no golden files");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
