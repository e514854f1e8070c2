//! What the names of an expression mean in a session: its variables, and the queries of the
//! scene (doc/language.md, "Queries"). Read-only: a query never changes the scene.
//!
//! A later range or group (issue 54 item 5) plugs in at [`Names::reduce`]: `avg(vz, top)`
//! reaches it with `range = Some("top")`; the particles it names replace "every particle".

use std::collections::BTreeMap;

use serde_json::Value;

use crate::lang::expr::{Reduce, Scope};
use crate::lang::keyword::match_keyword;
use crate::lang::table::PRINT_ITEMS;
use crate::sim::Scene;
use crate::sim::model::WallGeom;

/// The names of a session: variables, then queries of the scene (when there is one).
pub struct Names<'a> {
    pub vars: &'a BTreeMap<String, f64>,
    pub scene: Option<&'a Scene>,
}

/// The queries without arguments.
pub const VALUES: &[&str] = &["time", "cycle", "dt", "nball", "nwall"];
/// Particle queries `ball_Q(id)` and the quantities of `sum`/`avg`.
pub const BALL: &[&str] = &["x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "r", "m"];
/// Wall queries `wall_Q(n)`.
pub const WALL: &[&str] = &["x", "y", "z", "d", "vx", "vy", "vz", "fx", "fy", "fz", "fn"];

/// Whether a variable may have this name (no query of the scene has it).
pub fn is_query(name: &str) -> bool {
    VALUES.contains(&name)
        || name.contains('.')
        || name
            .strip_prefix("ball_")
            .is_some_and(|q| BALL.contains(&q))
        || name
            .strip_prefix("wall_")
            .is_some_and(|q| WALL.contains(&q))
}

impl Names<'_> {
    fn scene(&self, what: &str) -> Result<&Scene, String> {
        self.scene
            .ok_or_else(|| format!("`{what}` needs a scene: give STArt (or RESTart) first"))
    }

    /// A particle's quantity by index.
    fn ball(s: &Scene, i: usize, q: &str) -> f64 {
        let p = s.particles();
        match q {
            "x" => p.pos[i][0],
            "y" => p.pos[i][1],
            "z" => p.pos[i][2],
            "vx" => p.vel[i][0],
            "vy" => p.vel[i][1],
            "vz" => p.vel[i][2],
            "fx" => p.force[i][0],
            "fy" => p.force[i][1],
            "fz" => p.force[i][2],
            "r" => p.radius[i],
            _ => p.mass[i],
        }
    }

    fn wall(s: &Scene, n: f64, q: &str) -> Result<f64, String> {
        let walls = s.walls();
        if !(n >= 1.0 && n.fract() == 0.0 && n <= walls.len() as f64) {
            return Err(format!(
                "wall_{q}({n}): there is no wall {n} (walls 1 to {})",
                walls.len()
            ));
        }
        let w = &walls[n as usize - 1];
        let (point, d) = match w.geom {
            WallGeom::Plane { normal, d } => ([normal[0] * d, normal[1] * d, normal[2] * d], d),
            WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
                (centre, radius)
            }
            WallGeom::Cylinder { point, radius, .. } => (point, radius),
        };
        Ok(match q {
            "x" => point[0],
            "y" => point[1],
            "z" => point[2],
            "d" => d,
            "vx" => w.vel[0],
            "vy" => w.vel[1],
            "vz" => w.vel[2],
            "fx" => w.force[0],
            "fy" => w.force[1],
            "fz" => w.force[2],
            _ => w.normal_force,
        })
    }

    /// `item.key.key...`: a number of PRint item's JSON (indices from 1).
    fn printed(&self, path: &str) -> Result<f64, String> {
        let mut parts = path.split('.');
        let first = parts.next().unwrap_or("");
        let item = match_keyword(first, PRINT_ITEMS)
            .map_err(|e| format!("`{path}`: {}", e.describe(first, "PRint item", PRINT_ITEMS)))?;
        let s = self.scene(path)?;
        let (_, mut v) = crate::output::print::item(s, item);
        let mut at = first.to_string();
        for key in parts {
            let next = match &v {
                Value::Object(m) => m
                    .iter()
                    .find(|(k, _)| k.eq_ignore_ascii_case(key))
                    .map(|(_, x)| x.clone())
                    .ok_or_else(|| {
                        let keys: Vec<&String> = m.keys().filter(|k| *k != "print").collect();
                        format!(
                            "`{path}`: {at} has no `{key}`; it has {}",
                            keys.iter()
                                .map(|k| k.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    })?,
                Value::Array(a) => {
                    let k: usize = key.parse().map_err(|_| {
                        format!("`{path}`: {at} is a list: index it with 1 to {}", a.len())
                    })?;
                    if k == 0 || k > a.len() {
                        return Err(format!(
                            "`{path}`: {at} has {} entries, not {key} (indices from 1)",
                            a.len()
                        ));
                    }
                    a[k - 1].clone()
                }
                _ => return Err(format!("`{path}`: {at} is a number, not a table")),
            };
            v = next;
            at = format!("{at}.{key}");
        }
        match &v {
            Value::Number(n) => n
                .as_f64()
                .ok_or_else(|| format!("`{path}` is not a number")),
            Value::Bool(b) => Ok(if *b { 1.0 } else { 0.0 }),
            Value::Object(m) => Err(format!(
                "`{path}` is a table: add one of {}",
                m.keys()
                    .filter(|k| *k != "print")
                    .map(|k| k.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            Value::Array(a) => Err(format!(
                "`{path}` is a list of {}: add an index from 1",
                a.len()
            )),
            _ => Err(format!("`{path}` is not a number (it is {v})")),
        }
    }
}

impl Scope for Names<'_> {
    fn value(&self, name: &str) -> Option<Result<f64, String>> {
        if let Some(v) = self.vars.get(name) {
            return Some(Ok(*v));
        }
        if name.contains('.') {
            return Some(self.printed(name));
        }
        if !VALUES.contains(&name) {
            return None;
        }
        Some(self.scene(name).map(|s| match name {
            "time" => s.time(),
            "cycle" => s.cycle() as f64,
            "dt" => crate::output::print::current_dt(s),
            "nball" => s.particles().len() as f64,
            _ => s.walls().len() as f64,
        }))
    }

    fn call(&self, name: &str, args: &[f64]) -> Option<Result<f64, String>> {
        let (kind, q) = if let Some(q) = name.strip_prefix("ball_")
            && BALL.contains(&q)
        {
            ("ball", q)
        } else if let Some(q) = name.strip_prefix("wall_")
            && WALL.contains(&q)
        {
            ("wall", q)
        } else {
            return None;
        };
        let r = (|| {
            let s = self.scene(name)?;
            let [n] = args else {
                return Err(format!(
                    "{name} takes one argument, the {} number",
                    if kind == "ball" {
                        "particle's id"
                    } else {
                        "wall's"
                    }
                ));
            };
            if kind == "wall" {
                return Self::wall(s, *n, q);
            }
            let i = (*n >= 0.0 && n.fract() == 0.0 && *n < u32::MAX as f64)
                .then(|| s.index_of(*n as usize))
                .flatten()
                .ok_or_else(|| format!("{name}({n}): no particle has id {n}"))?;
            Ok(Self::ball(s, i, q))
        })();
        Some(r)
    }

    fn reduce(&self, op: Reduce, field: &str, range: Option<&str>) -> Option<Result<f64, String>> {
        let word = if op == Reduce::Sum { "sum" } else { "avg" };
        let r = (|| {
            if !BALL.contains(&field) {
                return Err(format!(
                    "{word}({field}): `{field}` is not a particle quantity ({})",
                    BALL.join(", ")
                ));
            }
            let s = self.scene(word)?;
            // Over a group's members (doc/groups.md; a dynamic group evaluated now), in
            // the order of the particle arrays, or over every particle.
            let members: Vec<usize> = match range {
                Some(g) => s
                    .members(&crate::sim::range::Range::group(g))
                    .map_err(|e| format!("{word}({field}, {g}): {e}"))?,
                None => (0..s.particles().len()).collect(),
            };
            let n = members.len();
            let total: f64 = members.iter().map(|&i| Self::ball(s, i, field)).sum();
            match op {
                Reduce::Sum => Ok(total),
                Reduce::Avg if n == 0 => Err(format!(
                    "{word}({field}{}): there are no particles",
                    range.map(|g| format!(", {g}")).unwrap_or_default()
                )),
                Reduce::Avg => Ok(total / n as f64),
            }
        })();
        Some(r)
    }
}
