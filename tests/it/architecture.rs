//! The map and the rules of ARCHITECTURE.md hold: every path it names exists, the core
//! imports nothing from the command language, the core reads no environment beyond its
//! one documented knob, `src/sim` stands in the layers its module doc declares, and files
//! and functions stay short.

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

/// The layers of `src/sim`, lowest first, as its module doc declares them (`N. **name**
/// (`module`, …)`): for each layer its modules, named by their path under `src/sim` without
/// `.rs` (`cycle`, `scene/edit`; `sim` is `src/sim/mod.rs` itself).
fn declared_layers() -> Vec<(String, Vec<String>)> {
    let text = std::fs::read_to_string(root().join("src/sim/mod.rs")).unwrap();
    let doc: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("//!"))
        .map(str::trim)
        .collect();
    let doc = doc.join(" ");
    let mut layers = Vec::new();
    let mut rest = doc.as_str();
    while let Some(k) = rest.find(". **") {
        let numbered = rest[..k]
            .rsplit(' ')
            .next()
            .is_some_and(|n| !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()));
        rest = &rest[k + 4..];
        if !numbered {
            continue;
        }
        let end = rest.find("**").expect("a layer's name in bold");
        let name = rest[..end].to_string();
        rest = &rest[end + 2..];
        let list = rest.trim_start();
        assert!(
            list.starts_with('('),
            "src/sim/mod.rs: layer {name} lists no modules"
        );
        let close = list.find(')').expect("the layer's module list closes");
        let modules = list[1..close]
            .split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect();
        layers.push((name, modules));
    }
    layers
}

/// The source files of `src/sim` by module path (`cycle/update`; `cycle` for
/// `cycle/mod.rs`, `sim` for `mod.rs`), with their code before the tests.
fn sim_sources() -> Vec<(String, String)> {
    let base = root().join("src/sim");
    let mut out: Vec<(String, String)> = rust_files(&base)
        .into_iter()
        .filter(|f| f.file_name().is_none_or(|n| n != "tests.rs"))
        .map(|f| {
            let rel = f.strip_prefix(&base).unwrap().with_extension("");
            let rel = rel.to_string_lossy().replace('\\', "/");
            let module = match rel.strip_suffix("mod") {
                Some("") => "sim".to_string(),
                Some(dir) => dir.trim_end_matches('/').to_string(),
                None => rel,
            };
            (module, code_of(&f))
        })
        .collect();
    out.sort();
    out
}

/// The code without comments, string and character literals (each replaced by a space).
fn strip_comments_and_strings(code: &str) -> String {
    let c: Vec<char> = code.chars().collect();
    let mut out = String::with_capacity(code.len());
    let mut i = 0;
    while i < c.len() {
        let at = |k: usize| c.get(k).copied().unwrap_or(' ');
        if c[i] == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if c[i] == '/' && at(i + 1) == '*' {
            i += 2;
            while i < c.len() && !(c[i] == '*' && at(i + 1) == '/') {
                i += 1;
            }
            i += 2;
            out.push(' ');
        } else if c[i] == 'r' && (at(i + 1) == '"' || (at(i + 1) == '#' && at(i + 2) == '"')) {
            // A raw string r"…" or r#"…"#.
            let hashes = if at(i + 1) == '#' { 1 } else { 0 };
            i += 2 + hashes;
            while i < c.len() && !(c[i] == '"' && (hashes == 0 || at(i + 1) == '#')) {
                i += 1;
            }
            i += 1 + hashes;
            out.push(' ');
        } else if c[i] == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
        } else if c[i] == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            // A character literal ('x', '\n', '\''); a lifetime ('a) is kept.
            i += if at(i + 1) == '\\' { 2 } else { 1 };
            while i < c.len() && c[i] != '\'' {
                i += 1;
            }
            i += 1;
            out.push(' ');
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// Tokens: identifiers, `::` and single punctuation characters.
fn tokens(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if c[i].is_alphanumeric() || c[i] == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(c[start..i].iter().collect());
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".to_string());
            i += 2;
        } else {
            if !c[i].is_whitespace() {
                out.push(c[i].to_string());
            }
            i += 1;
        }
    }
    out
}

/// The paths of a use tree starting at `t[*k]` (after `use`), each with `prefix` before it;
/// leaves `*k` after the tree.
fn use_tree(t: &[String], k: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
    let mut path = prefix.to_vec();
    while *k < t.len() {
        let tok = t[*k].as_str();
        if tok == "{" {
            *k += 1;
            while *k < t.len() && t[*k] != "}" {
                use_tree(t, k, &path, out);
                if *k < t.len() && t[*k] == "," {
                    *k += 1;
                }
            }
            *k += 1;
            return;
        } else if tok == "::" || tok == "*" || tok == "self" {
            *k += 1;
        } else if tok == "as" {
            *k += 2;
        } else if tok == "," || tok == "}" || tok == ";" {
            break;
        } else {
            path.push(tok.to_string());
            *k += 1;
        }
    }
    out.push(path);
}

/// Every path a piece of code names: the paths of its `use` trees and every `a::b…`
/// written in it.
fn paths_named(code: &str) -> Vec<Vec<String>> {
    let t = tokens(&strip_comments_and_strings(code));
    let mut out = Vec::new();
    let mut k = 0;
    while k < t.len() {
        if t[k] == "use" {
            k += 1;
            use_tree(&t, &mut k, &[], &mut out);
            continue;
        }
        if t[k] == "pub" && t.get(k + 1).is_some_and(|s| s == "(") {
            // A visibility, `pub(in crate::sim)`, names no module it uses.
            while k < t.len() && t[k] != ")" {
                k += 1;
            }
            continue;
        }
        let is_ident = |s: &str| {
            s.chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_')
        };
        if is_ident(&t[k]) && t.get(k + 1).is_some_and(|s| s == "::") {
            let mut path = vec![t[k].clone()];
            k += 1;
            while t.get(k).is_some_and(|s| s == "::") && t.get(k + 1).is_some_and(|s| is_ident(s)) {
                path.push(t[k + 1].clone());
                k += 2;
            }
            out.push(path);
            continue;
        }
        k += 1;
    }
    out
}

/// The module of `src/sim` a path written in module `from` leads to (the longest prefix of
/// it that is a module), or `None` for a path outside `sim`.
fn resolve(from: &str, path: &[String], modules: &[String]) -> Option<String> {
    let mut at: Vec<String> = if from == "sim" {
        Vec::new()
    } else {
        from.split('/').map(str::to_string).collect()
    };
    let rest: Vec<String> = match path.first().map(String::as_str) {
        Some("crate") if path.get(1).is_some_and(|s| s == "sim") => {
            at.clear();
            path[2..].to_vec()
        }
        Some("crate") => return None,
        Some("sim") => {
            at.clear();
            path[1..].to_vec()
        }
        Some("super") => {
            let mut p = path;
            while p.first().is_some_and(|s| s == "super") {
                at.pop();
                p = &p[1..];
            }
            p.to_vec()
        }
        Some("self") => path[1..].to_vec(),
        Some(first) => {
            // A child module named without `self::`.
            let mut child = at.clone();
            child.push(first.to_string());
            if !modules.contains(&child.join("/")) {
                return None;
            }
            path.to_vec()
        }
        None => return None,
    };
    let full: Vec<String> = at.into_iter().chain(rest).collect();
    for n in (1..=full.len()).rev() {
        let m = full[..n].join("/");
        if modules.contains(&m) {
            return Some(m);
        }
    }
    Some("sim".to_string())
}

/// What breaks the layers in `sources` (module path, code): modules without a declared
/// layer, imports from a higher layer, and import circles. A module's files that are not
/// declared themselves count as the module (its nearest declared ancestor).
fn layer_violations(layers: &[(String, Vec<String>)], sources: &[(String, String)]) -> Vec<String> {
    let mut bad = Vec::new();
    let level = |m: &str| layers.iter().position(|(_, ms)| ms.iter().any(|x| x == m));
    let modules: Vec<String> = sources.iter().map(|s| s.0.clone()).collect();
    for (name, ms) in layers {
        for m in ms {
            if !modules.contains(m) {
                bad.push(format!(
                    "layer {name} names `{m}`, which is no module of src/sim"
                ));
            }
        }
    }
    // The declared module a file counts as.
    let unit = |m: &str| -> Option<String> {
        let mut p = m.to_string();
        loop {
            if level(&p).is_some() {
                return Some(p);
            }
            p = p.rsplit_once('/')?.0.to_string();
        }
    };
    let mut edges: std::collections::BTreeMap<String, std::collections::BTreeSet<String>> =
        Default::default();
    for (m, code) in sources {
        let Some(from) = unit(m) else {
            bad.push(format!("src/sim/{m}: no layer declared (src/sim/mod.rs)"));
            continue;
        };
        edges.entry(from.clone()).or_default();
        for path in paths_named(code) {
            let Some(target) = resolve(m, &path, &modules) else {
                continue;
            };
            let Some(to) = unit(&target) else { continue };
            if to == from {
                continue;
            }
            let (lf, lt) = (level(&from).unwrap(), level(&to).unwrap());
            if lt > lf {
                bad.push(format!(
                    "src/sim/{m} ({}) names `{}`, of the higher layer {}",
                    layers[lf].0,
                    path.join("::"),
                    layers[lt].0
                ));
            }
            edges.entry(from.clone()).or_default().insert(to);
        }
    }
    // Circles: a depth-first search; a module met again on the current path closes one.
    fn visit(
        m: &str,
        edges: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut std::collections::BTreeSet<String>,
        bad: &mut Vec<String>,
    ) {
        if let Some(k) = path.iter().position(|p| p == m) {
            bad.push(format!("import circle: {} → {m}", path[k..].join(" → ")));
            return;
        }
        if !done.insert(m.to_string()) {
            return;
        }
        path.push(m.to_string());
        for n in edges.get(m).into_iter().flatten() {
            visit(n, edges, path, done, bad);
        }
        path.pop();
    }
    let mut done = std::collections::BTreeSet::new();
    for m in edges.keys() {
        visit(m, &edges, &mut Vec::new(), &mut done, &mut bad);
    }
    bad
}

/// `src/sim` in layers (its module doc): every module has one, none imports from a higher
/// one, and no modules import each other around a circle.
#[test]
fn the_simulation_core_stands_in_layers() {
    let layers = declared_layers();
    assert!(
        layers.len() >= 6,
        "src/sim/mod.rs declares {} layers",
        layers.len()
    );
    let bad = layer_violations(&layers, &sim_sources());
    assert!(bad.is_empty(), "the layers of src/sim:\n{}", bad.join("\n"));
}

/// The check itself finds an upward import in each form a path takes, and a circle.
#[test]
fn the_layer_check_finds_an_upward_import_and_a_circle() {
    let layers = declared_layers();
    let mut sources = sim_sources();
    let add = |sources: &mut Vec<(String, String)>, m: &str, code: &str| {
        let s = sources.iter_mut().find(|s| s.0 == m).unwrap();
        s.1.push_str(code);
    };
    for (module, code) in [
        ("scene", "\nuse super::cycle::run;\n"),
        ("scene", "\nfn f() { crate::sim::cycle::run(); }\n"),
        (
            "cycle/update",
            "\nuse crate::{sim::{probe::probe, model}};\n",
        ),
        ("walls", "\nfn f(s: &sim::params::Model) {}\n"),
        ("contacts/state", "\nuse super::super::energy;\n"),
    ] {
        let mut s = sources.clone();
        add(&mut s, module, code);
        let bad = layer_violations(&layers, &s);
        assert!(
            bad.iter().any(|b| b.contains("higher layer")),
            "{module} + {code:?} passed: {bad:?}"
        );
    }
    // `// use super::cycle;` in a comment or a string is no import.
    add(
        &mut sources,
        "scene",
        "\n// super::cycle::run\nconst S: &str = \"super::cycle\";\n",
    );
    assert!(layer_violations(&layers, &sources).is_empty());
    add(
        &mut sources,
        "energy",
        "\nfn f() { super::stress::of(); }\n",
    );
    add(
        &mut sources,
        "stress",
        "\nfn g() { super::energy::stored(); }\n",
    );
    let bad = layer_violations(&layers, &sources);
    assert!(
        bad.iter().any(|b| b.starts_with("import circle")),
        "{bad:?}"
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
