//! `--collect`: what every run printed with `--json` → DIR/results.csv, and the charts.

use std::fs;
use std::path::Path;

use serde_json::Value;

use super::chart;
use super::store::{Manifest, OUTPUT, Status, Store, write_atomic};

/// A column taken from the runs' JSON output: `[ALIAS=]KIND.FIELD[#K]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Measure {
    pub column: String,
    pub kind: String,
    pub path: Vec<String>,
    /// Which print of that kind: 1 the first, -1 the last (the default).
    pub index: i64,
}

impl Measure {
    pub fn parse(text: &str) -> Result<Measure, String> {
        let (alias, rest) = match text.split_once('=') {
            Some((a, r)) => (Some(a.trim()), r.trim()),
            None => (None, text.trim()),
        };
        let (spec, index) = match rest.split_once('#') {
            Some((s, k)) => match k.parse::<i64>() {
                Ok(k) if k != 0 => (s, k),
                _ => {
                    return Err(format!(
                        "--measure {text}: after `#` a print number: 1 the first, -1 the last"
                    ));
                }
            },
            None => (rest, -1),
        };
        let mut parts = spec.split('.');
        let kind = parts.next().unwrap_or("").to_string();
        let path: Vec<String> = parts.map(String::from).collect();
        if kind.is_empty() || path.is_empty() || path.iter().any(|p| p.is_empty()) {
            return Err(format!(
                "--measure {text}: give KIND.FIELD, the PRint item and its JSON field (doc/output.md), e.g. bonds.damage_ratio"
            ));
        }
        if alias.is_some_and(|a| a.is_empty() || a.contains(',')) {
            return Err(format!(
                "--measure {text}: the column name before `=` is empty or has a comma"
            ));
        }
        Ok(Measure {
            column: alias.map(String::from).unwrap_or_else(|| rest.to_string()),
            kind,
            path,
            index,
        })
    }

    fn value(&self, objects: &[Value]) -> String {
        let of_kind: Vec<&Value> = objects
            .iter()
            .filter(|o| o.get("print").and_then(|p| p.as_str()) == Some(self.kind.as_str()))
            .collect();
        let n = of_kind.len() as i64;
        let k = if self.index > 0 {
            self.index - 1
        } else {
            n + self.index
        };
        let Some(mut v) = (0..n).contains(&k).then(|| of_kind[k as usize]) else {
            return String::new();
        };
        for key in &self.path {
            v = match (v, key.parse::<usize>()) {
                (Value::Array(a), Ok(i)) => match a.get(i) {
                    Some(x) => x,
                    None => return String::new(),
                },
                _ => match v.get(key) {
                    Some(x) => x,
                    None => return String::new(),
                },
            };
        }
        scalar(v).unwrap_or_default()
    }
}

/// A chart: `Y:X[:GROUP]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartSpec {
    pub y: String,
    pub x: String,
    pub group: Option<String>,
}

impl ChartSpec {
    pub fn parse(text: &str) -> Result<ChartSpec, String> {
        let p: Vec<&str> = text.split(':').map(str::trim).collect();
        match p.as_slice() {
            [y, x] if !y.is_empty() && !x.is_empty() => Ok(ChartSpec {
                y: y.to_string(),
                x: x.to_string(),
                group: None,
            }),
            [y, x, g] if !y.is_empty() && !x.is_empty() && !g.is_empty() => Ok(ChartSpec {
                y: y.to_string(),
                x: x.to_string(),
                group: Some(g.to_string()),
            }),
            _ => Err(format!(
                "--chart {text}: give MEASURE:PARAMETER or MEASURE:PARAMETER:GROUP (e.g. bonds.damage_ratio:v:eta)"
            )),
        }
    }

    pub fn file_name(&self) -> String {
        let clean = |s: &str| -> String {
            s.chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect()
        };
        format!("{}_vs_{}.png", clean(&self.y), clean(&self.x))
    }
}

/// A JSON scalar as CSV text (objects and arrays: None).
fn scalar(v: &Value) -> Option<String> {
    match v {
        Value::Null => Some(String::new()),
        Value::Bool(b) => Some(b.to_string()),
        Value::Number(n) => Some(n.to_string()),
        Value::String(s) => Some(s.clone()),
        _ => None,
    }
}

/// Every scalar of an object, flattened to `prefix.key.sub`.
fn flatten(prefix: &str, v: &Value, top: bool, out: &mut Vec<(String, String)>) {
    if let Value::Object(map) = v {
        for (k, x) in map {
            if top && k == "print" {
                continue;
            }
            let key = format!("{prefix}.{k}");
            match x {
                Value::Object(_) => flatten(&key, x, false, out),
                _ => {
                    if let Some(s) = scalar(x) {
                        out.push((key, s));
                    }
                }
            }
        }
    }
}

/// The JSON objects a run printed (other lines, such as `saved cycle ...`, are skipped).
pub fn objects(path: &Path) -> Vec<Value> {
    let text = fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .filter(|l| l.starts_with('{'))
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect()
}

/// The default columns of one run: every scalar of the last print of each kind.
fn default_measures(objects: &[Value]) -> Vec<(String, String)> {
    let mut kinds: Vec<&str> = Vec::new();
    for o in objects {
        if let Some(k) = o.get("print").and_then(|p| p.as_str())
            && !kinds.contains(&k)
        {
            kinds.push(k);
        }
    }
    let mut out = Vec::new();
    for k in kinds {
        // (Invariant: `k` was taken from one of `objects`.)
        let last = objects
            .iter()
            .rev()
            .find(|o| o.get("print").and_then(|p| p.as_str()) == Some(k))
            .expect("a kind seen");
        flatten(k, last, true, &mut out);
    }
    out
}

fn csv_cell(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// What `collect` did.
pub struct Collected {
    pub rows: usize,
    pub ok: usize,
    pub files: Vec<String>,
    pub notes: Vec<String>,
}

/// Writes DIR/results.csv (one line per run of the manifest, finished or not) and the charts.
pub fn collect(store: &Store, m: &Manifest) -> Result<Collected, String> {
    let measures: Vec<Measure> = m
        .measures
        .iter()
        .map(|t| Measure::parse(t))
        .collect::<Result<_, _>>()?;
    let charts: Vec<ChartSpec> = m
        .charts
        .iter()
        .map(|t| ChartSpec::parse(t))
        .collect::<Result<_, _>>()?;
    let mut header: Vec<String> = vec!["run".into(), "status".into()];
    header.extend(m.params.iter().cloned());
    header.extend(m.let_names.iter().cloned());
    header.push("wall_s".into());
    let fixed = header.len();
    let mut extra: Vec<String> = measures.iter().map(|x| x.column.clone()).collect();
    let mut table: Vec<Vec<(String, String)>> = Vec::new();
    let mut ok = 0;
    for run in &m.runs {
        let status = store.status(&run.name);
        let mut row: Vec<(String, String)> = vec![
            ("run".into(), run.name.clone()),
            (
                "status".into(),
                match &status {
                    None => "not run".into(),
                    Some(s) if s.ok() => "ok".into(),
                    Some(Status { exit: Some(c), .. }) => format!("failed (exit {c})"),
                    Some(_) => "killed".into(),
                },
            ),
        ];
        for n in m.params.iter().chain(&m.let_names) {
            row.push((n.clone(), run.get(n).unwrap_or("").to_string()));
        }
        row.push((
            "wall_s".into(),
            status
                .as_ref()
                .map(|s| s.wall_s.to_string())
                .unwrap_or_default(),
        ));
        if status.as_ref().is_some_and(|s| s.ok()) {
            ok += 1;
            let objs = objects(&store.run_dir(&run.name).join(OUTPUT));
            if measures.is_empty() {
                for (k, v) in default_measures(&objs) {
                    if !extra.contains(&k) && !header[..fixed].contains(&k) {
                        extra.push(k.clone());
                    }
                    row.push((k, v));
                }
            } else {
                for x in &measures {
                    row.push((x.column.clone(), x.value(&objs)));
                }
            }
        }
        table.push(row);
    }
    header.extend(extra);
    let path = store.dir.join("results.csv");
    write_atomic(&path, csv_text(&header, &table).as_bytes())?;
    let mut files = vec![path.display().to_string()];
    let mut notes = Vec::new();
    for c in &charts {
        match chart_png(c, &table, m.logx)? {
            Some(png) => {
                let p = store.dir.join(c.file_name());
                write_atomic(&p, &png)?;
                files.push(p.display().to_string());
            }
            None => notes.push(format!(
                "chart {}: no finished run has a number for `{}` and `{}`",
                c.file_name(),
                c.y,
                c.x
            )),
        }
    }
    Ok(Collected {
        rows: table.len(),
        ok,
        files,
        notes,
    })
}

/// The CSV text of the table: the header, then one line per row in the header's order.
fn csv_text(header: &[String], table: &[Vec<(String, String)>]) -> String {
    let mut csv = header
        .iter()
        .map(|h| csv_cell(h))
        .collect::<Vec<_>>()
        .join(",");
    csv.push('\n');
    for row in table {
        let cells: Vec<String> = header
            .iter()
            .map(|h| {
                row.iter()
                    .find(|(k, _)| k == h)
                    .map(|(_, v)| csv_cell(v))
                    .unwrap_or_default()
            })
            .collect();
        csv.push_str(&cells.join(","));
        csv.push('\n');
    }
    csv
}

/// The chart of one measure against a parameter (by a group if given) over the finished
/// runs; `None` if no finished run has numbers for both.
fn chart_png(
    c: &ChartSpec,
    table: &[Vec<(String, String)>],
    logx: bool,
) -> Result<Option<Vec<u8>>, String> {
    let get = |row: &Vec<(String, String)>, k: &str| {
        row.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone())
    };
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for row in table
        .iter()
        .filter(|r| get(r, "status").as_deref() == Some("ok"))
    {
        let x = get(row, &c.x).and_then(|v| crate::lang::lexer::parse_real(&v));
        let y = get(row, &c.y).and_then(|v| v.parse::<f64>().ok());
        let (Some(x), Some(y)) = (x, y) else { continue };
        let label = match &c.group {
            Some(g) => format!("{g} = {}", get(row, g).unwrap_or_default()),
            None => c.y.clone(),
        };
        match series.iter_mut().find(|(l, _)| *l == label) {
            Some((_, pts)) => pts.push((x, y)),
            None => series.push((label, vec![(x, y)])),
        }
    }
    if series.is_empty() {
        return Ok(None);
    }
    let title = match &c.group {
        Some(g) => format!("{} against {} by {g}", c.y, c.x),
        None => format!("{} against {}", c.y, c.x),
    };
    chart::xy_png(&title, &c.x, &c.y, &mut series, logx).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn objs(lines: &[&str]) -> Vec<Value> {
        lines
            .iter()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    }

    #[test]
    fn measures_pick_the_last_or_the_kth_print() {
        let o = objs(&[
            r#"{"print":"energy","kinetic":1.5,"dissipated":{"viscous":0.25}}"#,
            r#"{"print":"bonds","damage_ratio":0.1,"sizes":[5,3]}"#,
            r#"{"print":"energy","kinetic":0.5,"dissipated":{"viscous":0.75}}"#,
        ]);
        let m = |t: &str| Measure::parse(t).unwrap().value(&o);
        assert_eq!(m("energy.kinetic"), "0.5");
        assert_eq!(m("energy.kinetic#1"), "1.5");
        assert_eq!(m("e0=energy.dissipated.viscous#-2"), "0.25");
        assert_eq!(m("bonds.sizes.1"), "3");
        assert_eq!(m("bonds.missing"), "");
        assert_eq!(m("energy.kinetic#3"), "");
        assert_eq!(Measure::parse("e0=energy.kinetic#1").unwrap().column, "e0");
        for bad in ["energy", "energy.", "a=energy.kinetic#0", "=energy.x"] {
            assert!(Measure::parse(bad).is_err(), "{bad}");
        }
        let d = default_measures(&o);
        assert_eq!(
            d,
            [
                ("energy.dissipated.viscous".to_string(), "0.75".to_string()),
                ("energy.kinetic".into(), "0.5".into()),
                ("bonds.damage_ratio".into(), "0.1".into()),
            ]
        );
    }

    #[test]
    fn chart_specs() {
        let c = ChartSpec::parse("bonds.damage_ratio:v:eta").unwrap();
        assert_eq!(c.group.as_deref(), Some("eta"));
        assert_eq!(c.file_name(), "bonds_damage_ratio_vs_v.png");
        assert!(ChartSpec::parse("y").is_err());
        assert!(ChartSpec::parse("y::g").is_err());
    }

    #[test]
    fn csv_cells_are_quoted_when_needed() {
        assert_eq!(csv_cell("a,b"), "\"a,b\"");
        assert_eq!(csv_cell("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_cell("0.5"), "0.5");
    }
}
