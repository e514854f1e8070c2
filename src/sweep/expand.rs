//! A sweep's runs: the product of its grids and rows, each with a stable name and the values
//! its command file gets with `--set`; and every check of the parameters against the command
//! file, before anything runs.

use std::collections::{HashMap, HashSet};

use super::expr::{self, Expr};
use super::spec::Spec;
use crate::lang::lexer::parse_real;
use crate::session::vars::placeholders;

/// A text file the sweep reads: the name to show and its text.
#[derive(Clone, Debug)]
pub struct Text {
    pub shown: String,
    pub text: String,
}

/// The files of a sweep, read by the caller.
#[derive(Clone, Debug)]
pub struct Inputs {
    pub script: Text,
    pub prepare: Option<Text>,
    pub rows: Option<Text>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Run {
    /// The run's directory name under DIR/runs: from the `run` column of the rows, or the
    /// parameters' names and values (`v0.5_eta0.01`).
    pub name: String,
    /// What the command file gets with `--set`: the parameters, the `--set` values and the
    /// `--let` values, in that order.
    pub values: Vec<(String, String)>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The parameters that vary: the grids' names, then the rows' columns.
    pub params: Vec<String>,
    /// The `--let` names.
    pub lets: Vec<String>,
    pub runs: Vec<Run>,
}

impl Run {
    pub fn get(&self, name: &str) -> Option<&str> {
        self.values
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

fn valid_name(n: &str) -> bool {
    !n.is_empty() && n.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// A value as part of a run's name: letters, digits and `._+-`; anything else becomes `-`.
fn name_part(v: &str) -> String {
    v.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '+' | '-') {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// FNV-1a, 64 bits: a short stable digest for names too long to spell out.
fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

/// The name of a run with these parameter values: `v0.5_eta0.01` (`run` with none).
pub fn run_name(params: &[(String, String)]) -> String {
    if params.is_empty() {
        return "run".into();
    }
    let full: String = params
        .iter()
        .map(|(k, v)| format!("{k}{}", name_part(v)))
        .collect::<Vec<_>>()
        .join("_");
    if full.len() <= 100 {
        full
    } else {
        format!("{}-{:016x}", &full[..80], fnv(&full))
    }
}

/// The rows of a CSV file: a header of names, then one run per line; `#` lines and blank
/// lines are skipped. No quoting: values hold no commas.
fn read_rows(t: &Text, errors: &mut Vec<String>) -> (Vec<String>, Vec<(usize, Vec<String>)>) {
    let mut header: Option<Vec<String>> = None;
    let mut rows = Vec::new();
    for (k, line) in t.text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<String> = line.split(',').map(|c| c.trim().to_string()).collect();
        let at = format!("{}:{}", t.shown, k + 1);
        if line.contains('"') {
            errors.push(format!(
                "{at}: quoted CSV values are not read (a value holds no comma or quote)"
            ));
            continue;
        }
        match &header {
            None => {
                let mut seen = HashSet::new();
                for c in &cells {
                    if !valid_name(c) {
                        errors.push(format!(
                            "{at}: `{c}` is not a parameter name (letters, digits, _)"
                        ));
                    } else if !seen.insert(c.clone()) {
                        errors.push(format!("{at}: column `{c}` appears twice"));
                    }
                }
                header = Some(cells);
            }
            Some(h) => {
                if cells.len() != h.len() {
                    errors.push(format!(
                        "{at}: {} values for {} columns ({})",
                        cells.len(),
                        h.len(),
                        h.join(",")
                    ));
                } else if let Some(i) = cells.iter().position(|c| c.is_empty()) {
                    errors.push(format!("{at}: no value for `{}`", h[i]));
                } else {
                    rows.push((k + 1, cells));
                }
            }
        }
    }
    let header = header.unwrap_or_default();
    if header.is_empty() {
        errors.push(format!("{}: no header line (the parameter names)", t.shown));
    } else if rows.is_empty() && errors.is_empty() {
        errors.push(format!("{}: no rows: the sweep would have no run", t.shown));
    }
    (header, rows)
}

/// The names a command file gives values itself (LET, LOOP, DEFine's parameters,
/// doc/language.md): its `$name`s of them need no value from the sweep.
fn own_names(t: &Text) -> HashSet<String> {
    let keys = crate::lang::table::command_keywords();
    let mut own = HashSet::new();
    for line in t.text.lines() {
        let toks = crate::lang::lexer::tokenize(line);
        let Some(first) = toks.first() else { continue };
        let all = match crate::lang::table::find_command(&first.text, keys) {
            Ok(i) if matches!(crate::lang::table::COMMANDS[i].name, "LET" | "LOOP") => false,
            Ok(i) if crate::lang::table::COMMANDS[i].name == "DEFine" => true,
            _ => continue,
        };
        let names = toks.iter().skip(1).take(if all { usize::MAX } else { 1 });
        own.extend(names.map(|t| t.text.to_ascii_lowercase()));
    }
    own
}

/// Where each name is used in a command file: name → `FILE:LINE:COL`; syntax errors of the
/// placeholders are added to `errors`.
fn used_names(t: &Text, errors: &mut Vec<String>) -> Vec<(String, String)> {
    let mut used: Vec<(String, String)> = Vec::new();
    for (k, line) in t.text.lines().enumerate() {
        match placeholders(line) {
            Ok(ps) => {
                for p in ps {
                    let at = format!(
                        "{}:{}:{}",
                        t.shown,
                        k + 1,
                        line[..p.start].chars().count() + 1
                    );
                    if p.name.is_empty() {
                        errors.push(format!("{at}: a `$` without a name"));
                    } else if !used.iter().any(|(n, _)| *n == p.name) {
                        used.push((p.name, at));
                    }
                }
            }
            Err(e) => errors.push(format!(
                "{}:{}:{}: {}",
                t.shown,
                k + 1,
                line[..e.start].chars().count() + 1,
                e.message
            )),
        }
    }
    used
}

/// Records a name's definition; a name given twice (or not a name) is an error.
fn define(
    defined: &mut HashMap<String, String>,
    name: &str,
    what: String,
    errors: &mut Vec<String>,
) {
    if !valid_name(name) {
        errors.push(format!(
            "{what}: `{name}` is not a parameter name (letters, digits, _)"
        ));
    } else if name == "pi" {
        errors.push(format!(
            "{what}: `pi` is the constant of --let; choose another name"
        ));
    } else if let Some(first) = defined.get(name) {
        errors.push(format!("{what}: `{name}` is already given ({first})"));
    } else {
        defined.insert(name.to_string(), what);
    }
}

/// The names a sweep defines: every parameter once, with what defines it, the rows' columns
/// and the parsed `--let` expressions.
struct Names {
    defined: HashMap<String, String>,
    columns: Vec<String>,
    rows: Vec<(usize, Vec<String>)>,
    rows_shown: String,
    lets: Vec<(String, Expr)>,
}

/// Expands the sweep into its runs, checking everything first. All errors are returned.
pub fn expand(spec: &Spec, inputs: &Inputs) -> Result<Plan, Vec<String>> {
    let mut errors = Vec::new();
    let names = define_names(spec, inputs, &mut errors);
    check_usage(spec, inputs, &names, &mut errors);
    if !errors.is_empty() {
        return Err(errors);
    }
    let params: Vec<String> = spec
        .grids
        .iter()
        .map(|g| g.value.0.clone())
        .chain(names.columns.iter().filter(|c| *c != "run").cloned())
        .collect();
    if names.columns.iter().any(|c| c == "run") && !spec.grids.is_empty() {
        errors.push(format!(
            "{}: a `run` column names each run, but the --grid values multiply the rows: name the runs by their parameters (drop the column) or put the grid into the rows",
            names.rows_shown
        ));
        return Err(errors);
    }
    let combos = combinations(spec, inputs.rows.is_some(), &names);
    let runs = name_and_evaluate(spec, &names, combos, &mut errors);
    if !errors.is_empty() {
        errors.truncate(20);
        return Err(errors);
    }
    Ok(Plan {
        params,
        lets: names.lets.into_iter().map(|(n, _)| n).collect(),
        runs,
    })
}

/// Every name once, with what defines it: the grids (checked non-empty, no value twice),
/// the rows' columns, the `--set` values and the `--let` expressions (parsed; they read only
/// what is defined before them).
fn define_names(spec: &Spec, inputs: &Inputs, errors: &mut Vec<String>) -> Names {
    let mut defined: HashMap<String, String> = HashMap::new();
    for g in &spec.grids {
        let (name, values) = &g.value;
        define(
            &mut defined,
            name,
            format!("{}: --grid {name}", g.origin),
            errors,
        );
        if values.is_empty() || values.iter().all(|v| v.is_empty()) {
            errors.push(format!(
                "{}: --grid {name}: the grid is empty (give values: --grid {name}=1,2,3)",
                g.origin
            ));
        } else if values.iter().any(|v| v.is_empty()) {
            errors.push(format!(
                "{}: --grid {name}: an empty value in `{}`",
                g.origin,
                values.join(",")
            ));
        } else {
            let mut seen = HashSet::new();
            for v in values {
                if !seen.insert(v) {
                    errors.push(format!("{}: --grid {name}: `{v}` appears twice", g.origin));
                }
            }
        }
    }
    let (columns, rows) = match &inputs.rows {
        Some(t) => read_rows(t, errors),
        None => (Vec::new(), Vec::new()),
    };
    let rows_shown = inputs
        .rows
        .as_ref()
        .map(|t| t.shown.clone())
        .unwrap_or_default();
    for c in columns.iter().filter(|c| *c != "run") {
        define(&mut defined, c, format!("{rows_shown}: column {c}"), errors);
    }
    for s in &spec.sets {
        let (name, value) = &s.value;
        define(
            &mut defined,
            name,
            format!("{}: --set {name}", s.origin),
            errors,
        );
        if value.is_empty() {
            errors.push(format!("{}: --set {name}: no value", s.origin));
        }
    }
    let mut lets: Vec<(String, Expr)> = Vec::new();
    for l in &spec.lets {
        let (name, text) = &l.value;
        let what = format!("{}: --let {name}", l.origin);
        define(&mut defined, name, what.clone(), errors);
        match expr::parse(text) {
            Ok(e) => {
                for n in e.names() {
                    if !defined.contains_key(&n) || n == *name {
                        errors.push(format!(
                            "{what}: `{n}` has no value here (a --let reads the parameters, the --set values and the --let values before it)"
                        ));
                    }
                }
                lets.push((name.clone(), e));
            }
            Err(e) => errors.push(format!("{what}: {e}")),
        }
    }
    Names {
        defined,
        columns,
        rows,
        rows_shown,
        lets,
    }
}

/// The names against the command files: every parameter is used, every `$name` has a value,
/// the prepare file reads only `--set` values.
fn check_usage(spec: &Spec, inputs: &Inputs, names: &Names, errors: &mut Vec<String>) {
    let used = used_names(&inputs.script, errors);
    let used_prep = inputs
        .prepare
        .as_ref()
        .map(|t| used_names(t, errors))
        .unwrap_or_default();
    let read_by_lets: HashSet<String> = names.lets.iter().flat_map(|(_, e)| e.names()).collect();
    let is_used = |n: &str| used.iter().any(|(u, _)| u == n) || read_by_lets.contains(n);
    let file = &inputs.script.shown;
    let rows_shown = &names.rows_shown;
    for g in &spec.grids {
        if !is_used(&g.value.0) {
            errors.push(format!(
                "{}: --grid {}: {file} does not use `${}`",
                g.origin, g.value.0, g.value.0
            ));
        }
    }
    for c in names.columns.iter().filter(|c| *c != "run") {
        if !is_used(c) {
            errors.push(format!(
                "{rows_shown}: column {c}: {file} does not use `${c}`"
            ));
        }
    }
    for l in &spec.lets {
        if !is_used(&l.value.0) {
            errors.push(format!(
                "{}: --let {}: {file} does not use `${}`",
                l.origin, l.value.0, l.value.0
            ));
        }
    }
    for s in &spec.sets {
        let n = &s.value.0;
        if !is_used(n) && !used_prep.iter().any(|(u, _)| u == n) {
            let files = match &inputs.prepare {
                Some(p) => format!("neither {file} nor {} uses", p.shown),
                None => format!("{file} does not use"),
            };
            errors.push(format!("{}: --set {n}: {files} `${n}`", s.origin));
        }
    }
    let own = own_names(&inputs.script);
    for (n, at) in &used {
        if !names.defined.contains_key(n) && !own.contains(&n.to_ascii_lowercase()) {
            errors.push(format!(
                "{at}: `${n}` has no value in the sweep: give it with --grid, --rows, --set or --let"
            ));
        }
    }
    if let Some(prep) = &inputs.prepare {
        // A name the prepare file gives itself (`LET`, `LOOP`, `DEFine`) needs no --set.
        let own_prep = own_names(prep);
        for (n, at) in &used_prep {
            if !spec.sets.iter().any(|s| s.value.0 == *n)
                && !own_prep.contains(&n.to_ascii_lowercase())
            {
                errors.push(format!(
                    "{at}: `${n}`: the prepare file gets only the --set values, and `{n}` is not one"
                ));
            }
        }
    }
}

/// One run before it is named: the row's line (if any), its parameter values, the name the
/// row gives it (a `run` column).
type Combo = (Option<usize>, Vec<(String, String)>, Option<String>);

/// The runs: the rows (or one empty row), times each grid, the last grid fastest.
fn combinations(spec: &Spec, has_rows: bool, names: &Names) -> Vec<Combo> {
    let base_rows: Vec<(Option<usize>, Vec<String>)> = if has_rows {
        names
            .rows
            .iter()
            .map(|(l, r)| (Some(*l), r.clone()))
            .collect()
    } else {
        vec![(None, Vec::new())]
    };
    let mut combos: Vec<Combo> = Vec::new();
    for (line, cells) in base_rows {
        let mut from_row = Vec::new();
        let mut explicit = None;
        for (c, v) in names.columns.iter().zip(cells) {
            if c == "run" {
                explicit = Some(v);
            } else {
                from_row.push((c.clone(), v));
            }
        }
        let mut partial: Vec<Vec<(String, String)>> = vec![Vec::new()];
        for g in &spec.grids {
            let (name, values) = &g.value;
            partial = partial
                .into_iter()
                .flat_map(|p| {
                    values.iter().map(move |v| {
                        let mut q = p.clone();
                        q.push((name.clone(), v.clone()));
                        q
                    })
                })
                .collect();
        }
        for p in partial {
            let mut ps = p;
            ps.extend(from_row.iter().cloned());
            combos.push((line, ps, explicit.clone()));
        }
    }
    combos
}

/// Each run named (by its row or its parameters; two runs may not share a name) and its
/// `--set` and `--let` values added.
fn name_and_evaluate(
    spec: &Spec,
    names: &Names,
    combos: Vec<Combo>,
    errors: &mut Vec<String>,
) -> Vec<Run> {
    let rows_shown = &names.rows_shown;
    let mut runs = Vec::new();
    let mut seen: HashMap<String, String> = HashMap::new();
    for (line, ps, explicit) in combos {
        let at = match line {
            Some(l) => format!("{rows_shown}:{l}"),
            None => "the grid".to_string(),
        };
        let name = match explicit {
            Some(n) => {
                if n.starts_with('.') || name_part(&n) != n {
                    errors.push(format!(
                        "{at}: run name `{n}`: use letters, digits and ._+- (not first .)"
                    ));
                }
                n
            }
            None => run_name(&ps),
        };
        if let Some(first) = seen.insert(name.clone(), at.clone()) {
            errors.push(format!(
                "{at}: the run `{name}` is already in the sweep ({first}): two runs would share a directory"
            ));
        }
        let mut values = ps;
        values.extend(spec.sets.iter().map(|s| s.value.clone()));
        for (lname, e) in &names.lets {
            let got = e.eval(&|n: &str| {
                let v = values
                    .iter()
                    .find(|(k, _)| k == n)
                    .map(|(_, v)| v.as_str())
                    .unwrap_or("");
                parse_real(v).ok_or_else(|| format!("`{n}` = `{v}` is not a number"))
            });
            match got {
                Ok(x) if x.is_finite() => values.push((lname.clone(), expr::format_number(x))),
                Ok(x) => errors.push(format!("run {name}: --let {lname} is {x}")),
                Err(m) => errors.push(format!("run {name}: --let {lname}: {m}")),
            }
        }
        runs.push(Run { name, values });
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(args: &str) -> Spec {
        let mut a: Vec<String> = args.split_whitespace().map(String::from).collect();
        a.extend(["f.tru".to_string(), "--out".into(), "d".into()]);
        Spec::from_args(&a).unwrap()
    }

    fn inputs(script: &str, rows: Option<&str>) -> Inputs {
        Inputs {
            script: Text {
                shown: "f.tru".into(),
                text: script.into(),
            },
            prepare: None,
            rows: rows.map(|r| Text {
                shown: "r.csv".into(),
                text: r.into(),
            }),
        }
    }

    #[test]
    fn grids_multiply_with_the_last_fastest() {
        let p = expand(
            &spec("--grid v=0.5,1 --grid eta=0,0.01 --set n=10"),
            &inputs(
                "velocity 0 0 -$v\nliquid 0.1 0.025 0 ${eta}\ncycle $n ; $unused\n",
                None,
            ),
        )
        .unwrap();
        let names: Vec<&str> = p.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(
            names,
            ["v0.5_eta0", "v0.5_eta0.01", "v1_eta0", "v1_eta0.01"]
        );
        assert_eq!(
            p.runs[3].values,
            [
                ("v".into(), "1".into()),
                ("eta".into(), "0.01".into()),
                ("n".into(), "10".into())
            ]
        );
        assert_eq!(p.params, ["v", "eta"]);
    }

    #[test]
    fn a_files_own_variables_need_no_value() {
        let p = expand(
            &spec("--grid v=1,2"),
            &inputs(
                "loop i 1 2\n  save \"run_$i.sav\"\nend\nlet k = 3\nshow $k $v\n",
                None,
            ),
        )
        .unwrap();
        assert_eq!(p.runs.len(), 2);
        assert!(expand(&spec("--grid v=1,2"), &inputs("show $w $v\n", None)).is_err());
    }

    #[test]
    fn rows_lets_and_explicit_names() {
        let p = expand(
            &spec("--let vx=v/2*cos(theta*pi/180)"),
            &inputs(
                "velocity $vx $theta\n",
                Some("# runs\nrun,v,theta\nnormal,2,0\noblique,2,60\n"),
            ),
        )
        .unwrap();
        assert_eq!(p.runs[0].name, "normal");
        assert_eq!(p.runs[0].get("vx"), Some("1"));
        assert_eq!(
            p.runs[1].get("vx").map(|v| v.parse::<f64>().unwrap()),
            Some((60f64.to_radians()).cos())
        );
        assert_eq!(p.lets, ["vx"]);
        assert_eq!(p.params, ["v", "theta"]);
    }

    #[test]
    fn bad_parameters_are_all_named() {
        let e = expand(
            &spec("--grid v=0.5,1 --grid eta= --set frac=0.2 --grid v=3"),
            &inputs("cycle $n\nvelocity 0 0 $v\nliquid ${eta\n", None),
        )
        .unwrap_err();
        let all = e.join("\n");
        for want in [
            "grid eta: the grid is empty",
            "`v` is already given",
            "--set frac: f.tru does not use `$frac`",
            "f.tru:1:7: `$n` has no value in the sweep",
            "f.tru:3:8: unclosed `${`",
        ] {
            assert!(all.contains(want), "missing `{want}` in:\n{all}");
        }
    }

    #[test]
    fn long_or_odd_values_give_safe_distinct_names() {
        let a = run_name(&[("state".into(), "/a/b c.sav".into())]);
        assert_eq!(a, "state-a-b-c.sav");
        let long = "x".repeat(200);
        let b = run_name(&[("p".into(), long.clone())]);
        let c = run_name(&[("p".into(), long + "y")]);
        assert!(b.len() < 100 && b != c);
    }
}
