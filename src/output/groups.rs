//! `PRint GROup name|ALL` and `PRint RANge range`: the sums and averages over a group's or a
//! range's particles now (`sim::aggregate`), as a table and as JSON (doc/groups.md).

use serde_json::{Value, json};

use crate::sim::Scene;
use crate::sim::aggregate::{self, Aggregate};
use crate::sim::range::Range;

/// One `PRint GROup`/`RANge` item: `None` every group (in the order they were defined).
/// An error (a group not defined) before anything is formatted.
pub fn item(scene: &Scene, range: Option<&Range>) -> Result<(String, Value), String> {
    match range {
        Some(r) => {
            let a = aggregate::of_range(scene, r)?;
            let (name, kind) = match single_group(r).and_then(|n| scene.groups().get(n)) {
                Some(g) => (Some(g.name.as_str()), Some(kind(g.ids.is_none()))),
                None => (None, None),
            };
            let definition = match single_group(r).and_then(|n| scene.groups().get(n)) {
                Some(g) => g.range.text(),
                None => r.text(),
            };
            let head = match name {
                Some(n) => format!("group {n} ({}): {definition}", kind.unwrap_or("")),
                None => format!("range {definition}"),
            };
            let mut j = fields(&a);
            j["print"] = json!(if name.is_some() { "group" } else { "range" });
            j["name"] = json!(name);
            j["kind"] = json!(kind);
            j["range"] = json!(definition);
            j["cycle"] = json!(scene.cycle());
            Ok((format!("{head}\n{}", table(&a)), j))
        }
        None => {
            let mut s = String::new();
            let mut list = Vec::new();
            if scene.groups().list.is_empty() {
                s.push_str("no groups (GROup name range defines one)\n");
            }
            for g in &scene.groups().list {
                let a = aggregate::of_group(scene, &g.name)?;
                let k = kind(g.ids.is_none());
                s.push_str(&format!(
                    "group {} ({k}): {}\n{}",
                    g.name,
                    g.range.text(),
                    table(&a)
                ));
                let mut j = fields(&a);
                j["name"] = json!(g.name);
                j["kind"] = json!(k);
                j["range"] = json!(g.range.text());
                list.push(j);
            }
            Ok((
                s,
                json!({"print": "groups", "cycle": scene.cycle(), "groups": list}),
            ))
        }
    }
}

/// The history's columns of the recorded groups (`NAME.QUANTITY`, the groups in the order
/// they were defined) and, for each history row, their values at its cycle (`None`: not
/// recorded then).
pub fn history_columns(scene: &Scene) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let recorded: Vec<_> = scene
        .groups()
        .list
        .iter()
        .filter(|g| g.record || !g.rows.is_empty())
        .collect();
    let mut cols = Vec::new();
    for g in &recorded {
        cols.extend(
            aggregate::QUANTITIES
                .iter()
                .map(|q| format!("{}.{q}", g.name)),
        );
    }
    let rows = scene
        .history()
        .rows
        .iter()
        .map(|r| {
            let mut out = Vec::with_capacity(cols.len());
            for g in &recorded {
                let at = g.rows.binary_search_by(|x| x[0].total_cmp(&r[0]));
                match at {
                    Ok(k) => out.extend(g.rows[k][1..].iter().map(|&x| Some(x))),
                    Err(_) => out.extend(aggregate::QUANTITIES.iter().map(|_| None)),
                }
            }
            out
        })
        .collect();
    (cols, rows)
}

fn kind(dynamic: bool) -> &'static str {
    if dynamic { "dynamic" } else { "static" }
}

/// The group's name when the range is exactly one group (`PRint GROup name`).
fn single_group(r: &Range) -> Option<&str> {
    match r.any.as_slice() {
        [all] => match all.as_slice() {
            [t] if !t.not => match &t.cond {
                crate::sim::range::Condition::Group(n) => Some(n),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

fn table(a: &Aggregate) -> String {
    let v3 = |v: [f64; 3]| format!("({:.6e}, {:.6e}, {:.6e})", v[0], v[1], v[2]);
    format!(
        "  particles {}  mass {:.6e} kg  kinetic energy {:.6e} J  mean coordination {:.4}\n  \
         centre of mass {} m\n  velocity of the centre of mass {} m/s\n  force sum {} N\n",
        a.count,
        a.mass,
        a.kinetic,
        a.coordination,
        v3(a.centre),
        v3(a.velocity),
        v3(a.force)
    )
}

/// The JSON fields of an aggregate (NaN, the means of an empty range, as null).
fn fields(a: &Aggregate) -> Value {
    let n = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    let v = |x: [f64; 3]| json!([n(x[0]), n(x[1]), n(x[2])]);
    json!({
        "count": a.count, "mass": a.mass, "centre": v(a.centre), "velocity": v(a.velocity),
        "kinetic": a.kinetic, "force": v(a.force), "coordination": n(a.coordination),
    })
}
