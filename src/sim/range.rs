//! Ranges and groups (doc/groups.md): a range selects particles by where their centres are
//! (a box, a sphere, a cylinder), by id, material or size type, or by membership of a named
//! group; conditions joined (all must hold), negated (`NOT`) and alternatives (`OR`). A group
//! is a named range: *static* (the ids of the particles in the range when it was defined) or
//! *dynamic* (the range itself, evaluated on the particles as they are whenever the group is
//! used). Plain data here; which particles of a scene are in a range is `Scene::members`
//! (`scene/groups.rs`), their sums and averages `sim::aggregate`.

use serde::{Deserialize, Serialize};

/// One condition of a range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Condition {
    /// `BOX x1 x2 y1 y2 z1 z2`: the centre in the closed box.
    Box([f64; 6]),
    /// `SPHere xc yc zc r`: the centre within distance r of (xc, yc, zc).
    Sphere { centre: [f64; 3], radius: f64 },
    /// `CYLinder x y z ax ay az r`: the centre within distance r of the line through (x, y, z)
    /// along (ax, ay, az) (infinitely long, as the die of `DWAll CYlinder`; cut it with a box).
    Cylinder {
        point: [f64; 3],
        axis: [f64; 3],
        radius: f64,
    },
    /// `ID i [TO j] ...`: ids in any of the closed intervals.
    Ids(Vec<(u32, u32)>),
    /// `MATerial m ...`: material type in the list.
    Material(Vec<u16>),
    /// `SIZe s ...`: size type in the list.
    Size(Vec<u16>),
    /// `GROup name`: a member of the named group.
    Group(String),
}

/// A condition, or its negation (`NOT`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Term {
    pub not: bool,
    pub cond: Condition,
}

/// A range: alternatives (`OR`), each a list of terms that must all hold. Never empty; an
/// alternative is never empty.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Range {
    pub any: Vec<Vec<Term>>,
}

/// What a range tests of one particle.
#[derive(Clone, Copy, Debug)]
pub struct Candidate {
    pub id: u32,
    pub pos: [f64; 3],
    pub material: u16,
    pub size: u16,
    /// The periodic cell the centre's images are in (none: the centre alone is tested).
    pub periods: Periods,
}

/// The periodic axes of the work-space, for the images of a centre: a box, sphere or
/// cylinder holds a particle when its centre or one of the centre's images in the
/// neighbouring cells lies in it (doc/groups.md, "A range"). `shift` is the
/// Lees–Edwards offset of a sheared cell: the image one cell up in y is `shift` further
/// along x (`sim::cell::nearest_image`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Periods {
    pub size: [f64; 3],
    pub periodic: [bool; 3],
    pub shift: f64,
}

impl Periods {
    /// The centre `x` and its images in the neighbouring cells (along x two cells each way
    /// when the cell is sheared: the shift moves the images above and below by up to one
    /// cell).
    fn images(&self, x: [f64; 3]) -> impl Iterator<Item = [f64; 3]> + '_ {
        let reach = |k: usize| -> i32 {
            match (self.periodic[k], k == 0 && self.shift != 0.0) {
                (false, _) => 0,
                (true, false) => 1,
                (true, true) => 2,
            }
        };
        let (rx, ry, rz) = (reach(0), reach(1), reach(2));
        (-rz..=rz).flat_map(move |nz| {
            (-ry..=ry).flat_map(move |ny| {
                (-rx..=rx).map(move |nx| {
                    let (nx, ny, nz) = (f64::from(nx), f64::from(ny), f64::from(nz));
                    [
                        x[0] + nx * self.size[0] + ny * self.shift,
                        x[1] + ny * self.size[1],
                        x[2] + nz * self.size[2],
                    ]
                })
            })
        })
    }
}

impl Condition {
    /// Whether the particle meets the condition, `in_group` deciding `GROup` conditions.
    pub fn holds(&self, p: &Candidate, in_group: &mut dyn FnMut(&str) -> bool) -> bool {
        match self {
            Condition::Box(_) | Condition::Sphere { .. } | Condition::Cylinder { .. } => {
                p.periods.images(p.pos).any(|x| self.contains_point(x))
            }
            Condition::Ids(spans) => spans.iter().any(|&(a, b)| p.id >= a && p.id <= b),
            Condition::Material(ms) => ms.contains(&p.material),
            Condition::Size(ss) => ss.contains(&p.size),
            Condition::Group(name) => in_group(name),
        }
    }

    /// Whether the point `x` lies in a geometric condition (false for the others).
    fn contains_point(&self, x: [f64; 3]) -> bool {
        match self {
            Condition::Box(b) => (0..3).all(|k| x[k] >= b[2 * k] && x[k] <= b[2 * k + 1]),
            Condition::Sphere { centre, radius } => {
                let d2: f64 = (0..3).map(|k| (x[k] - centre[k]).powi(2)).sum();
                d2 <= radius * radius
            }
            Condition::Cylinder {
                point,
                axis,
                radius,
            } => {
                let n2: f64 = axis.iter().map(|a| a * a).sum();
                let d: Vec<f64> = (0..3).map(|k| x[k] - point[k]).collect();
                let along: f64 = (0..3).map(|k| d[k] * axis[k]).sum::<f64>();
                let d2: f64 = d.iter().map(|v| v * v).sum::<f64>() - along * along / n2;
                d2 <= radius * radius
            }
            _ => false,
        }
    }

    /// The condition as the command language writes it.
    pub fn text(&self) -> String {
        let nums = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let ints = |v: &[u16]| {
            v.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        };
        match self {
            Condition::Box(b) => format!("BOX {}", nums(b)),
            Condition::Sphere { centre, radius } => {
                format!("SPHere {} {radius}", nums(centre))
            }
            Condition::Cylinder {
                point,
                axis,
                radius,
            } => format!("CYLinder {} {} {radius}", nums(point), nums(axis)),
            Condition::Ids(spans) => {
                let s: Vec<String> = spans
                    .iter()
                    .map(|&(a, b)| {
                        if a == b {
                            a.to_string()
                        } else {
                            format!("{a} TO {b}")
                        }
                    })
                    .collect();
                format!("ID {}", s.join(" "))
            }
            Condition::Material(m) => format!("MATerial {}", ints(m)),
            Condition::Size(s) => format!("SIZe {}", ints(s)),
            Condition::Group(n) => format!("GROup {n}"),
        }
    }
}

impl Range {
    /// The group's name when the range is exactly `GROup name`.
    pub fn single_group(&self) -> Option<&str> {
        match self.any.as_slice() {
            [all] => match all.as_slice() {
                [
                    Term {
                        not: false,
                        cond: Condition::Group(n),
                    },
                ] => Some(n),
                _ => None,
            },
            _ => None,
        }
    }

    /// The range of one group's members.
    pub fn group(name: &str) -> Range {
        Range {
            any: vec![vec![Term {
                not: false,
                cond: Condition::Group(name.to_string()),
            }]],
        }
    }

    /// Whether the particle is in the range.
    pub fn contains(&self, p: &Candidate, in_group: &mut dyn FnMut(&str) -> bool) -> bool {
        self.any
            .iter()
            .any(|all| all.iter().all(|t| t.cond.holds(p, in_group) != t.not))
    }

    /// The names of the groups the range refers to (in order, each once).
    pub fn groups_named(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for t in self.any.iter().flatten() {
            if let Condition::Group(n) = &t.cond
                && !out.contains(&n.as_str())
            {
                out.push(n);
            }
        }
        out
    }

    /// The range as the command language writes it.
    pub fn text(&self) -> String {
        self.any
            .iter()
            .map(|all| {
                all.iter()
                    .map(|t| {
                        let c = t.cond.text();
                        if t.not { format!("NOT {c}") } else { c }
                    })
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect::<Vec<_>>()
            .join(" OR ")
    }
}

/// A named group: a static one keeps the ids its range selected when it was defined (sorted,
/// each once); a dynamic one keeps only its range.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Group {
    pub name: String,
    pub range: Range,
    /// `Some(ids)`: static; `None`: dynamic (`GROup name DYNamic ...`).
    pub ids: Option<Vec<u32>>,
    /// `GROup name HIStory`: each history record (`SET HIStory n`) appends a row to `rows`.
    pub record: bool,
    /// The recorded rows: the cycle, then the quantities of `sim::aggregate::QUANTITIES`.
    pub rows: Vec<Vec<f64>>,
    /// `Fix ... GROup name` over this dynamic group: re-applied before every step of a
    /// Cycle (doc/groups.md, "A Fix over a dynamic group"). None for a static group.
    pub fix: Option<StandingFix>,
}

/// A `Fix` given over a dynamic group, which stands: before every step of a Cycle the
/// particles in the group then get its degrees of freedom, and those that have left the
/// group since the last application are freed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StandingFix {
    /// The fixed degrees of freedom (bit k for x y z rx ry rz), as `Fix` gives them.
    pub bits: u8,
    /// The ids of the particles it fixed at its last application (sorted, each once).
    pub ids: Vec<u32>,
}

/// The scene's groups, in the order they were first defined (a redefinition keeps its place).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Groups {
    pub list: Vec<Group>,
}

/// The names of the quantities of a range (`sim::aggregate::Aggregate::values`, in this
/// order): the columns of a group in the history, the names an expression reads.
pub const QUANTITIES: &[&str] = &[
    "count",
    "mass",
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "kinetic",
    "fx",
    "fy",
    "fz",
    "coordination",
];

/// The most groups a scene holds (a bound for typos and runaway scripts, not a cost).
pub const MAX_GROUPS: usize = 1000;

impl Groups {
    pub fn get(&self, name: &str) -> Option<&Group> {
        self.list.iter().find(|g| g.name == name)
    }

    /// Whether `name`, defined by `range`, would reach itself through the groups it names
    /// (a dynamic group's range naming a dynamic group that names it back): the chain, if so.
    pub fn circle(&self, name: &str, range: &Range) -> Option<Vec<String>> {
        fn walk<'a>(
            gs: &'a Groups,
            name: &str,
            range: &'a Range,
            path: &mut Vec<String>,
        ) -> Option<Vec<String>> {
            for n in range.groups_named() {
                if n == name {
                    let mut p = path.clone();
                    p.push(n.to_string());
                    return Some(p);
                }
                if path.iter().any(|p| p == n) || path.len() > MAX_GROUPS {
                    continue;
                }
                // A static group's members are fixed ids: the chain stops there.
                if let Some(g) = gs.get(n).filter(|g| g.ids.is_none()) {
                    path.push(n.to_string());
                    if let Some(c) = walk(gs, name, &g.range, path) {
                        return Some(c);
                    }
                    path.pop();
                }
            }
            None
        }
        walk(self, name, range, &mut vec![name.to_string()])
    }

    /// The dynamic groups whose range names `name` (a static group's members are fixed).
    pub fn users_of(&self, name: &str) -> Vec<&str> {
        self.list
            .iter()
            .filter(|g| g.ids.is_none() && g.name != name && g.range.groups_named().contains(&name))
            .map(|g| g.name.as_str())
            .collect()
    }

    /// Defines or redefines a group (a redefinition keeps its place in the list, and its
    /// recording and rows: the history's columns continue with the new definition; a
    /// dynamic group keeps its standing Fix, which then follows the new range).
    pub fn put(&mut self, mut g: Group) {
        match self.list.iter_mut().find(|x| x.name == g.name) {
            Some(x) => {
                g.record = x.record;
                g.rows = std::mem::take(&mut x.rows);
                if g.ids.is_none() {
                    g.fix = x.fix.take();
                }
                *x = g;
            }
            None => self.list.push(g),
        }
    }

    /// Removes a group; whether it existed.
    pub fn remove(&mut self, name: &str) -> bool {
        let n = self.list.len();
        self.list.retain(|g| g.name != name);
        self.list.len() < n
    }
}
