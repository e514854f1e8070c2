//! The map and the rules of ARCHITECTURE.md hold: every path it names exists, the core
//! imports nothing from the command language, and the core reads no environment beyond its
//! one documented knob.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out
}

/// Every path or file name in backquotes exists: from the crate's root, or (a file in a
/// module's list, `lexer.rs` under `src/lang/`) as the end of a path in the tree.
#[test]
fn every_path_the_map_names_exists() {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let mut tree = Vec::new();
    let mut stack: Vec<PathBuf> = ["src", "tests", "doc", "scripts", "golden"]
        .iter()
        .map(|d| root().join(d))
        .collect();
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(d).unwrap().flatten() {
            let p = e.path();
            let rel = p
                .strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            if p.is_dir() {
                tree.push(format!("{rel}/"));
                stack.push(p);
            } else {
                tree.push(rel);
            }
        }
    }
    let mut checked = 0;
    for (k, part) in text.split('`').enumerate() {
        let looks_like_path = part.contains('/') || part.ends_with(".rs") || part.ends_with(".md");
        if k % 2 == 0 || !looks_like_path || part.contains(' ') || part.contains("::") {
            continue;
        }
        let name = part.trim_end_matches('/');
        let found = root().join(name).exists()
            || tree.iter().any(|t| {
                let t = t.trim_end_matches('/');
                t == name || t.ends_with(&format!("/{name}"))
            });
        assert!(
            found,
            "ARCHITECTURE.md names `{part}`, which does not exist"
        );
        checked += 1;
    }
    assert!(checked > 40, "only {checked} paths checked");
}

#[test]
fn the_core_imports_nothing_from_the_language() {
    for dir in ["src/sim", "src/physics"] {
        for f in rust_files(&root().join(dir)) {
            let text = std::fs::read_to_string(&f).unwrap();
            assert!(
                !text.contains("crate::lang") && !text.contains("super::lang"),
                "{} uses the command language",
                f.display()
            );
        }
    }
}

#[test]
fn the_core_reads_no_environment_but_its_knob() {
    for dir in ["src/sim", "src/physics"] {
        for f in rust_files(&root().join(dir)) {
            let text = std::fs::read_to_string(&f).unwrap();
            for (k, line) in text.lines().enumerate() {
                if line.contains("env::var") {
                    assert!(
                        line.contains("TRUBAL_STEP_REGIONS"),
                        "{}:{}: the core reads the environment: {line}",
                        f.display(),
                        k + 1
                    );
                }
            }
        }
    }
}
