//! `trubal chart`: a PNG line chart of columns of a CSV file, drawn by [`crate::plot::xy`]
//! (doc/plots.md, "Charts of a CSV file"). The figures of doc/ are drawn this way by the
//! scripts (doc/validation.md lists which script draws which figure).

use std::io::Write;
use std::process::ExitCode;

use crate::plot::xy::{AxisSpec, Style, XyChart, XySeries, xy_png};

pub const USAGE: &str =
    "usage: trubal chart FILE.csv --x COL --y COL[,COL...] --out FILE.png [options]
  Draws a PNG line chart of the columns of a CSV file (a header line of names; lines starting
  with # are comments). Each --y column is a series: a solid line with markers; an empty cell
  is no point (a series is drawn where it has data); points are joined in the order of x.
  --x COL             the x column
  --y COL,...         the y columns drawn solid with markers (ours)
  --ref COL,...       y columns drawn dashed without markers (the thesis, a theory)
  --by COL[,COL]      one series per value of COL (values of several joined by /) and y column;
                      a value keeps its colour for all the columns (ours solid, the thesis dashed)
  --keys V1,V2,...    the order of the --by values: the colours go by position in this list, so
                      that a series keeps its colour in every chart of a table (values not
                      listed follow; listed values without data are left out); --key V gives
                      one value (which may hold commas), and may be repeated
  --dashed V          the series of --by value V drawn dashed (a reference), may be repeated
  --omit V            leave the rows of --by value V out, may be repeated
  --label NAME=TEXT   the legend's text for a column or a --by value (\"\" leaves the column's
                      name out: the legend says the --by value only)
  --title TEXT        the title;  --xlabel TEXT, --ylabel TEXT  axis names with units
                      (default: the column names)
  --logx, --logy      log scale (every value must be > 0)
  --xscale F, --yscale F   multiply the values by F (m → mm: 1e3)
  --xmin V --xmax V --ymin V --ymax V   fix an end of an axis (default: round ends around the data)
  --hline V,...       thin grey dashed horizontal lines (borders); --hline-label TEXT their legend
  --points            markers only, no lines";

/// The options of `trubal chart`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    pub file: String,
    pub out: String,
    pub x: String,
    pub y: Vec<String>,
    pub refs: Vec<String>,
    pub by: Vec<String>,
    pub keys: Vec<String>,
    pub dashed: Vec<String>,
    pub omit: Vec<String>,
    pub labels: Vec<(String, String)>,
    pub title: String,
    pub xlabel: Option<String>,
    pub ylabel: Option<String>,
    pub logx: bool,
    pub logy: bool,
    pub xscale: f64,
    pub yscale: f64,
    pub xmin: Option<f64>,
    pub xmax: Option<f64>,
    pub ymin: Option<f64>,
    pub ymax: Option<f64>,
    pub hlines: Vec<f64>,
    pub hline_label: String,
    pub points: bool,
}

fn list(v: &str) -> Vec<String> {
    v.split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

fn number(opt: &str, v: &str) -> Result<f64, String> {
    v.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{opt} needs a number, not `{v}`"))
}

/// The options from the arguments after `chart`.
pub fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        xscale: 1.0,
        yscale: 1.0,
        ..Options::default()
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let flag = matches!(a.as_str(), "--logx" | "--logy" | "--points");
        let value = if a.starts_with("--") && !flag {
            Some(
                it.next()
                    .ok_or_else(|| format!("{a} needs a value"))?
                    .as_str(),
            )
        } else {
            None
        };
        let v = value.unwrap_or_default();
        match a.as_str() {
            "--logx" => o.logx = true,
            "--logy" => o.logy = true,
            "--points" => o.points = true,
            "--x" => o.x = v.to_string(),
            "--y" => o.y.extend(list(v)),
            "--ref" => o.refs.extend(list(v)),
            "--by" => o.by.extend(list(v)),
            "--keys" => o.keys.extend(list(v)),
            "--key" => o.keys.push(v.to_string()),
            "--dashed" => o.dashed.push(v.to_string()),
            "--omit" => o.omit.push(v.to_string()),
            "--out" | "-o" => o.out = v.to_string(),
            "--title" => o.title = v.to_string(),
            "--xlabel" => o.xlabel = Some(v.to_string()),
            "--ylabel" => o.ylabel = Some(v.to_string()),
            "--xscale" => o.xscale = number(a, v)?,
            "--yscale" => o.yscale = number(a, v)?,
            "--xmin" => o.xmin = Some(number(a, v)?),
            "--xmax" => o.xmax = Some(number(a, v)?),
            "--ymin" => o.ymin = Some(number(a, v)?),
            "--ymax" => o.ymax = Some(number(a, v)?),
            "--hline" => {
                for s in list(v) {
                    o.hlines.push(number(a, &s)?);
                }
            }
            "--hline-label" => o.hline_label = v.to_string(),
            "--label" => {
                let (k, t) = v
                    .split_once('=')
                    .ok_or_else(|| format!("--label needs NAME=TEXT, not `{v}`"))?;
                o.labels.push((k.to_string(), t.to_string()));
            }
            s if s.starts_with('-') => return Err(format!("unknown option {s}")),
            s if o.file.is_empty() => o.file = s.to_string(),
            s => {
                return Err(format!(
                    "only one CSV file may be given (`{}`, `{s}`)",
                    o.file
                ));
            }
        }
    }
    if o.file.is_empty() {
        return Err("no CSV file given".into());
    }
    if o.x.is_empty() {
        return Err("--x COL is required".into());
    }
    if o.y.is_empty() && o.refs.is_empty() {
        return Err("--y COL (or --ref COL) is required".into());
    }
    if o.out.is_empty() {
        return Err("--out FILE.png is required".into());
    }
    Ok(o)
}

/// A CSV file: the header's names and the rows of cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    /// (line number, cells)
    pub rows: Vec<(usize, Vec<String>)>,
}

/// The cells of one line: commas, double quotes around a cell that holds commas (`""` a quote).
fn cells(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur).trim().to_string()),
            c => cur.push(c),
        }
    }
    out.push(cur.trim().to_string());
    out
}

/// Reads CSV text: blank lines and lines starting with `#` skipped, the first other line the
/// header. `name` is the file's name for the messages.
pub fn read_csv(text: &str, name: &str) -> Result<Table, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or_else(|| format!("{name}: no header line (the file is empty)"))?;
    let names = cells(header);
    let mut rows = Vec::new();
    for (k, l) in lines {
        let c = cells(l);
        if c.len() > names.len() {
            return Err(format!(
                "{name} line {k}: {} cells, the header names {}",
                c.len(),
                names.len()
            ));
        }
        rows.push((k, c));
    }
    Ok(Table { names, rows })
}

impl Table {
    fn column(&self, name: &str, file: &str) -> Result<usize, String> {
        self.names.iter().position(|n| n == name).ok_or_else(|| {
            format!(
                "{file} has no column `{name}` (its columns: {})",
                self.names.join(", ")
            )
        })
    }
}

/// A number cell: `None` for an empty cell or `nan` (no point), an error for anything else
/// that is not a number.
fn value(
    row: &(usize, Vec<String>),
    c: usize,
    name: &str,
    file: &str,
) -> Result<Option<f64>, String> {
    let s = row.1.get(c).map(String::as_str).unwrap_or("");
    if s.is_empty() || s.eq_ignore_ascii_case("nan") {
        return Ok(None);
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v)),
        _ => Err(format!(
            "{file} line {}: column `{name}` holds `{s}`, not a number",
            row.0
        )),
    }
}

/// The chart of the options over the table.
pub fn build(o: &Options, t: &Table) -> Result<XyChart, String> {
    let file = o.file.as_str();
    let xc = t.column(&o.x, file)?;
    let by: Vec<usize> =
        o.by.iter()
            .map(|n| t.column(n, file))
            .collect::<Result<_, _>>()?;
    let cols: Vec<(usize, &String, Style)> =
        o.y.iter()
            .map(|n| (n, if o.points { Style::Points } else { Style::Line }))
            .chain(o.refs.iter().map(|n| (n, Style::Dashed)))
            .map(|(n, s)| t.column(n, file).map(|c| (c, n, s)))
            .collect::<Result<_, _>>()?;
    // The --by values: those listed in --keys first, in that order, then the others as met.
    let key_of = |row: &(usize, Vec<String>)| {
        by.iter()
            .map(|&c| row.1.get(c).cloned().unwrap_or_default())
            .collect::<Vec<_>>()
            .join("/")
    };
    let mut keys: Vec<String> = o.keys.clone();
    for row in &t.rows {
        let k = key_of(row);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.retain(|k| !o.omit.contains(k));
    let label_of = |name: &str| {
        o.labels
            .iter()
            .rev()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.clone())
    };
    let mut series = Vec::new();
    for (ci, &(c, name, style)) in cols.iter().enumerate() {
        for (ki, key) in keys.iter().enumerate() {
            let mut pts = Vec::new();
            for row in t.rows.iter().filter(|r| key_of(r) == *key) {
                let x = value(row, xc, &o.x, file)?;
                let y = value(row, c, name, file)?;
                if let (Some(x), Some(y)) = (x, y) {
                    pts.push((x * o.xscale, y * o.yscale));
                }
            }
            if pts.is_empty() {
                continue;
            }
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let col_label = label_of(name).unwrap_or_else(|| name.clone());
            let label = if by.is_empty() {
                col_label
            } else {
                let k = label_of(key).unwrap_or_else(|| key.clone());
                if cols.len() == 1 || col_label.is_empty() {
                    k
                } else {
                    format!("{col_label} {k}")
                }
            };
            series.push(XySeries {
                label,
                colour: if by.is_empty() { ci } else { ki },
                style: if o.dashed.contains(key) {
                    Style::Dashed
                } else {
                    style
                },
                points: pts,
            });
        }
    }
    if series.is_empty() {
        return Err(format!(
            "{file}: no row has numbers in both `{}` and {}",
            o.x,
            cols.iter()
                .map(|(_, n, _)| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(" or ")
        ));
    }
    let axis = |label: &Option<String>, name: &str, log, min, max| AxisSpec {
        label: label.clone().unwrap_or_else(|| name.to_string()),
        log,
        min,
        max,
    };
    Ok(XyChart {
        title: o.title.clone(),
        x: axis(&o.xlabel, &o.x, o.logx, o.xmin, o.xmax),
        y: axis(&o.ylabel, &o.y.join(", "), o.logy, o.ymin, o.ymax),
        series,
        hlines: o.hlines.iter().map(|v| v * o.yscale).collect(),
        hline_label: o.hline_label.clone(),
    })
}

/// Reads the CSV file, draws the chart and writes the PNG; returns what was written.
pub fn run(o: &Options) -> Result<String, String> {
    let text =
        std::fs::read_to_string(&o.file).map_err(|e| format!("cannot read {}: {e}", o.file))?;
    let table = read_csv(&text, &o.file)?;
    let chart = build(o, &table)?;
    let png = xy_png(&chart)?;
    if let Some(dir) = std::path::Path::new(&o.out).parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create the directory {}: {e}", dir.display()))?;
    }
    std::fs::write(&o.out, png).map_err(|e| format!("cannot write {}: {e}", o.out))?;
    let n: usize = chart.series.iter().map(|s| s.points.len()).sum();
    Ok(format!(
        "wrote {} ({} series, {n} points)",
        o.out,
        chart.series.len()
    ))
}

/// `trubal chart ARGS`.
pub fn main(args: &[String]) -> ExitCode {
    if args.is_empty() || args.iter().any(|a| a == "--help" || a == "-h") {
        let _ = writeln!(std::io::stdout(), "{USAGE}");
        return if args.is_empty() {
            ExitCode::from(2)
        } else {
            ExitCode::SUCCESS
        };
    }
    let result = parse(args)
        .map_err(|e| (e, true))
        .and_then(|o| run(&o).map_err(|e| (e, false)));
    match result {
        Ok(msg) => {
            let _ = writeln!(std::io::stdout(), "{msg}");
            ExitCode::SUCCESS
        }
        Err((e, usage)) => {
            let _ = writeln!(std::io::stderr(), "trubal chart: {e}");
            if usage {
                let _ = writeln!(std::io::stderr(), "{USAGE}");
            }
            ExitCode::from(if usage { 2 } else { 1 })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &[&str]) -> Vec<String> {
        s.iter().map(|a| a.to_string()).collect()
    }

    const CSV: &str = "# a comment\nliquid,v,ours,thesis\ndry,1,2.5,\ndry,0.5,1,\ndry,2,,40\n\"0.1\",1,0.5,0.2\n0.1,2,1.5,\n";

    #[test]
    fn by_key_ours_solid_thesis_dashed_same_colour() {
        let o = parse(&args(&[
            "t.csv",
            "--x",
            "v",
            "--y",
            "ours",
            "--ref",
            "thesis",
            "--by",
            "liquid",
            "--keys",
            "1,0.1,dry",
            "--label",
            "ours=trubal",
            "--label",
            "thesis=Olsson",
            "--out",
            "t.png",
        ]))
        .unwrap();
        let t = read_csv(CSV, "t.csv").unwrap();
        let c = build(&o, &t).unwrap();
        let got: Vec<(&str, usize, Style, usize)> = c
            .series
            .iter()
            .map(|s| (s.label.as_str(), s.colour, s.style, s.points.len()))
            .collect();
        assert_eq!(
            got,
            [
                ("trubal 0.1", 1, Style::Line, 2),
                ("trubal dry", 2, Style::Line, 2),
                ("Olsson 0.1", 1, Style::Dashed, 1),
                ("Olsson dry", 2, Style::Dashed, 1),
            ]
        );
        // Sorted by x; the empty cells are no points.
        assert_eq!(c.series[1].points, [(0.5, 1.0), (1.0, 2.5)]);
        assert_eq!(c.series[3].points, [(2.0, 40.0)]);
    }

    #[test]
    fn bad_names_and_cells_are_clear_errors() {
        let t = read_csv(CSV, "t.csv").unwrap();
        let o = parse(&args(&[
            "t.csv", "--x", "speed", "--y", "ours", "--out", "a.png",
        ]))
        .unwrap();
        let e = build(&o, &t).unwrap_err();
        assert!(
            e.contains("no column `speed`") && e.contains("liquid, v, ours, thesis"),
            "{e}"
        );
        let bad = read_csv("v,y\n1,2\n2,abc\n", "b.csv").unwrap();
        let o = parse(&args(&["b.csv", "--x", "v", "--y", "y", "--out", "a.png"])).unwrap();
        let e = build(&o, &bad).unwrap_err();
        assert_eq!(e, "b.csv line 3: column `y` holds `abc`, not a number");
        assert!(
            read_csv("# only\n\n", "e.csv")
                .unwrap_err()
                .contains("no header")
        );
        assert!(
            read_csv("a,b\n1,2,3\n", "c.csv")
                .unwrap_err()
                .contains("line 2: 3 cells")
        );
        for (a, want) in [
            (
                vec!["t.csv", "--y", "a", "--out", "o.png"],
                "--x COL is required",
            ),
            (vec!["t.csv", "--x", "a", "--y", "b"], "--out"),
            (vec!["t.csv", "--x"], "--x needs a value"),
            (
                vec!["t.csv", "--x", "a", "--y", "b", "--out", "o", "--ymin", "z"],
                "number",
            ),
            (vec!["--x", "a", "--y", "b", "--out", "o"], "no CSV file"),
            (vec!["t.csv", "--bogus", "1"], "unknown option --bogus"),
        ] {
            let e = parse(&args(&a)).unwrap_err();
            assert!(e.contains(want), "{a:?}: {e}");
        }
    }

    #[test]
    fn quoted_cells_and_scales() {
        assert_eq!(cells("\"a, b\",\"c\"\"d\", 3 "), ["a, b", "c\"d", "3"]);
        let t = read_csv("h,F\n0.001,2\n0.002,4\n", "f.csv").unwrap();
        let o = parse(&args(&[
            "f.csv", "--x", "h", "--y", "F", "--xscale", "1e3", "--yscale", "0.5", "--out", "o",
        ]))
        .unwrap();
        let c = build(&o, &t).unwrap();
        assert_eq!(c.series[0].points, [(1.0, 1.0), (2.0, 2.0)]);
        assert_eq!(c.series[0].label, "F");
        assert_eq!((c.x.label.as_str(), c.y.label.as_str()), ("h", "F"));
    }
}
