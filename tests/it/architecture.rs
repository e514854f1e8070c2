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

/// The part of a source file before its tests module (`#[cfg(test)]` at the start of a
/// line), or none for a file of tests (`tests.rs`).
fn code_of(f: &Path) -> String {
    if f.file_name().is_some_and(|n| n == "tests.rs") {
        return String::new();
    }
    let text = std::fs::read_to_string(f).unwrap();
    match text.find("\n#[cfg(test)]") {
        Some(k) => text[..k].to_string(),
        None => text,
    }
}

/// A file fits on a few screens: at most 800 lines before its tests (the one table of
/// commands, `src/lang/table.rs`, aside).
#[test]
fn no_source_file_is_longer_than_800_lines() {
    for f in rust_files(&root().join("src")) {
        if f.ends_with("src/lang/table.rs") {
            continue;
        }
        let n = code_of(&f).lines().count();
        assert!(n <= 800, "{}: {n} lines before its tests", f.display());
    }
}

/// A function reads in one go: at most 120 lines (tests aside), from its `fn` line to the
/// closing brace at the same indentation.
#[test]
fn no_function_is_longer_than_120_lines() {
    let mut long = Vec::new();
    for f in rust_files(&root().join("src")) {
        let code = code_of(&f);
        let lines: Vec<&str> = code.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            let l = lines[i];
            let t = l.trim_start();
            let indent = l.len() - t.len();
            let is_fn = [
                "fn ",
                "pub fn ",
                "pub(crate) fn ",
                "pub(super) fn ",
                "const fn ",
            ]
            .iter()
            .any(|p| t.starts_with(p))
                || (t.starts_with("pub(in ") && t.contains(") fn "));
            if is_fn && !t.ends_with(';') {
                let close = format!("{}}}", " ".repeat(indent));
                let end = (i + 1..lines.len())
                    .find(|&j| lines[j].trim_end() == close)
                    .unwrap_or(i);
                if end - i > 120 {
                    long.push(format!("{}:{}: {} lines", f.display(), i + 1, end - i));
                }
                i = end;
            }
            i += 1;
        }
    }
    assert!(
        long.is_empty(),
        "functions over 120 lines:\n{}",
        long.join("\n")
    );
}

/// The Markdown pages of the repository (the crate's root, doc/, scripts/), with their text.
fn pages() -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    let mut stack = vec![root().to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            if p.is_dir() {
                if d == root() && !["doc", "scripts"].contains(&name.as_str()) {
                    continue;
                }
                stack.push(p);
            } else if name.ends_with(".md") {
                let text = std::fs::read_to_string(&p).unwrap();
                out.push((p, text));
            }
        }
    }
    out
}

/// doc/img and doc/data keep only the figures a page shows (per-run pictures go to the run's
/// work directory), and every picture a page shows exists.
#[test]
fn every_figure_in_doc_is_shown_and_every_shown_figure_exists() {
    let pages = pages();
    let mut shown = Vec::new();
    for (page, text) in &pages {
        for part in text.split("](").skip(1) {
            let target = part.split(')').next().unwrap();
            if !target.ends_with(".png") || target.starts_with("http") {
                continue;
            }
            let path = page.parent().unwrap().join(target);
            assert!(
                path.exists(),
                "{} shows {target}, which does not exist",
                page.display()
            );
            shown.push(path.canonicalize().unwrap());
        }
    }
    let mut checked = 0;
    for dir in ["doc/img", "doc/data"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap().flatten() {
            let p = e.path();
            if dir == "doc/data" && p.extension().is_none_or(|x| x != "png") {
                continue;
            }
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let named = pages
                .iter()
                .any(|(_, t)| t.contains(&format!("{dir}/{name}")))
                || pages.iter().any(|(_, t)| t.contains(&format!("`{name}`")));
            assert!(
                shown.contains(&p.canonicalize().unwrap()) || named,
                "{dir}/{name} is shown by no page: delete it, or show it"
            );
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} figures checked");
}
