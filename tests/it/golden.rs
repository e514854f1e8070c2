//! Golden files: every `golden/NAME.tru` is run through the binary (in a scratch directory,
//! `--json` if the file's first line says `# json`) and its standard output is compared with
//! `golden/NAME.out` number by number. Header lines of the command file:
//!
//! - `# tolerance: 1e-9 REASON` (required): the relative tolerance and why it is that loose;
//! - `# absolute: 1e-25 REASON` (optional): numbers closer than this always match (for
//!   quantities that are round-off noise around zero, such as an energy residual);
//! - `# run: scripts/NAME.tru` (optional): run that script (path from the crate root) instead
//!   of the golden file's own lines, so that an example is tested without a copy.
//!
//! `TRUBAL_BLESS=1 cargo test --profile ci --test it golden::` rewrites the expected files.

use std::path::Path;

fn tokens(s: &str) -> Vec<String> {
    s.split(|c: char| c.is_whitespace() || "[]{},:\"()".contains(c))
        .filter(|t| !t.is_empty())
        .map(|t| t.to_string())
        .collect()
}

fn close(a: &str, b: &str, tol: f64, abs: f64) -> bool {
    if a == b {
        return true;
    }
    match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) => (x - y).abs() <= (tol * x.abs().max(y.abs())).max(abs) + 1e-300,
        _ => false,
    }
}

/// The value of a `# NAME: VALUE REASON` header line; panics without a reason.
fn header(text: &str, name: &str, file: &Path) -> Option<String> {
    text.lines().find_map(|l| {
        let rest = l.trim().strip_prefix(&format!("# {name}:"))?;
        let mut words = rest.split_whitespace();
        let value = words.next()?.to_string();
        if name != "run" {
            assert!(
                words.next().is_some(),
                "{}: `# {name}: {value}` needs a reason after the value",
                file.display()
            );
        }
        Some(value)
    })
}

fn run_one(tru: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(tru).unwrap();
    let tol: f64 = header(&text, "tolerance", tru)
        .unwrap_or_else(|| panic!("{}: no `# tolerance: x REASON` line", tru.display()))
        .parse()
        .unwrap();
    let abs: f64 = header(&text, "absolute", tru).map_or(0.0, |a| a.parse().unwrap());
    let script = match header(&text, "run", tru) {
        Some(p) => Path::new(env!("CARGO_MANIFEST_DIR")).join(p),
        None => tru.to_path_buf(),
    };
    let json = text.lines().next().is_some_and(|l| l.trim() == "# json");
    let dir = std::env::temp_dir().join(format!(
        "trubal-golden-{}-{}",
        tru.file_stem().unwrap().to_string_lossy(),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut cmd = crate::common::trubal();
    cmd.arg(std::fs::canonicalize(&script).unwrap())
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
        if !close(a, b, tol, abs) {
            return Err(format!(
                "{}: token {k} differs: got `{a}`, expected `{b}` (tolerance {tol}, absolute {abs})\n--- got ---\n{got}\n--- expected ---\n{expected}",
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
