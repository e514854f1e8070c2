//! Scene → [`Picture`]: projection, depth order, colours and scales. Pure; no pixels.

use std::collections::HashMap;
use std::f64::consts::PI;

use super::picture::{
    Arc, ArcKind, Arrow, BondSet, Bounds, CLUSTER_CLASSES, Disc, ForceSet, Layer, LegendEntry,
    Mark, Picture, Ring, ScaleBar, Segment, Shade, Swatch, Tag, VectorKind, cluster_class, colour,
};
use crate::lang::command::{PlotItem, View, WallGeom};
use crate::sim::{Scene, Vec3, walls};

/// Sweep of the arc of the largest rotation or moment (300°).
pub const MAX_SWEEP: f64 = 5.0 * PI / 3.0;
/// The longest vector is drawn this many mean particle radii long.
pub const VECTOR_RADII: f64 = 4.0;
/// Radius of rotation/couple arcs as a fraction of the particle radius.
pub const ARC_RADIUS: f64 = 0.6;
/// Width of a CND line, in mean particle radii (the renderer draws at least 2 pixels).
pub const CND_WIDTH: f64 = 0.05;
/// Width of the line of the largest force, in mean particle radii.
pub const FORCE_WIDTH: f64 = 0.25;
/// Margin around the drawn things, as a fraction of the larger span.
pub const MARGIN: f64 = 0.04;

/// An orthographic projection: looking along one axis, no mirror image (right × up points
/// toward the viewer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// World axes shown to the right and up, and the axis looked along.
    pub right: usize,
    pub up: usize,
    pub depth_axis: usize,
    /// Depth (distance from the viewer, larger = farther) is `depth_sign` × that coordinate.
    pub depth_sign: f64,
    pub name: &'static str,
    pub description: &'static str,
}

const AXIS_NAMES: [&str; 3] = ["x", "y", "z"];

impl Projection {
    /// The projection of `SET VIEw`; 2-D mode always shows the x–y plane.
    pub fn of(view: View, two_d: bool) -> Self {
        let view = if two_d { View::Xy } else { view };
        match view {
            View::Xz => Projection {
                right: 0,
                up: 2,
                depth_axis: 1,
                depth_sign: 1.0,
                name: "XZ",
                description: "side view: x to the right, z up, looking along +y",
            },
            View::Yz => Projection {
                right: 1,
                up: 2,
                depth_axis: 0,
                depth_sign: -1.0,
                name: "YZ",
                description: "side view: y to the right, z up, looking along -x",
            },
            View::Xy => Projection {
                right: 0,
                up: 1,
                depth_axis: 2,
                depth_sign: -1.0,
                name: "XY",
                description: "top view: x to the right, y up, looking along -z",
            },
        }
    }

    pub fn project(&self, x: &Vec3) -> [f64; 2] {
        [x[self.right], x[self.up]]
    }

    pub fn depth(&self, x: &Vec3) -> f64 {
        self.depth_sign * x[self.depth_axis]
    }

    /// Unit vector pointing from the scene toward the viewer.
    pub fn toward(&self) -> Vec3 {
        let mut t = Vec3::zeros();
        t[self.depth_axis] = -self.depth_sign;
        t
    }

    pub fn axes(&self) -> [&'static str; 2] {
        [AXIS_NAMES[self.right], AXIS_NAMES[self.up]]
    }
}

/// Lower-case name of an item, as used in file names.
pub fn item_name(it: PlotItem) -> &'static str {
    match it {
        PlotItem::Ball => "ball",
        PlotItem::Disks => "disks",
        PlotItem::Bou => "bou",
        PlotItem::Grid => "grid",
        PlotItem::Cluster => "cluster",
        PlotItem::LCluster => "lcluster",
        PlotItem::Cnd => "cnd",
        PlotItem::LCnd => "lcnd",
        PlotItem::Couple => "couple",
        PlotItem::Forces => "forces",
        PlotItem::LForces => "lforces",
        PlotItem::MForces => "mforces",
        PlotItem::RDisp => "rdisp",
        PlotItem::Rotation => "rotation",
        PlotItem::Save => "save",
        PlotItem::Velocity => "velocity",
        PlotItem::Wall => "wall",
        PlotItem::History => "history",
    }
}

/// The items in the order given, without repeats and without `SAVe`.
pub fn drawn_items(items: &[PlotItem]) -> Vec<PlotItem> {
    let mut v: Vec<PlotItem> = Vec::new();
    for &it in items {
        if it != PlotItem::Save && !v.contains(&it) {
            v.push(it);
        }
    }
    v
}

/// Checks a list of items against the scene: what needs a reference state, what cannot be
/// combined. The error text is for the user.
pub fn check_items(scene: &Scene, items: &[PlotItem]) -> Result<(), String> {
    if items.is_empty() {
        return Err("PLot needs at least one item to draw".into());
    }
    if items.contains(&PlotItem::History) && items.len() > 1 {
        return Err(
            "PLot HIStory draws a chart of its own: give it alone (`plot history`), and the scene items in another PLot"
                .into(),
        );
    }
    if items.contains(&PlotItem::Cluster) && items.contains(&PlotItem::LCluster) {
        return Err(
            "CLUster and LCLuster both colour the particles: give one of them per PLot".into(),
        );
    }
    if scene.reference.is_none() {
        let need: Vec<&str> = items
            .iter()
            .filter(|it| {
                matches!(
                    it,
                    PlotItem::RDisp | PlotItem::Rotation | PlotItem::Cnd | PlotItem::LCnd
                )
            })
            .map(|it| item_name(*it))
            .collect();
        if !need.is_empty() {
            return Err(format!(
                "PLot {} compares with a reference state, and none was saved: give `PLot SAVe` first (e.g. `plot save`, `cycle 200`, `plot bou rdisp`)",
                need.join(" ").to_uppercase()
            ));
        }
    }
    Ok(())
}

/// The state of a bond against the reference: kept, new or broken. Both lists sorted.
pub fn classify_bonds(reference: &[(u32, u32)], now: &[(u32, u32)]) -> Vec<((u32, u32), Mark)> {
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::with_capacity(reference.len().max(now.len()));
    while i < reference.len() || j < now.len() {
        match (reference.get(i), now.get(j)) {
            (Some(a), Some(b)) if a == b => {
                out.push((*a, Mark::Kept));
                i += 1;
                j += 1;
            }
            (Some(a), Some(b)) if a < b => {
                out.push((*a, Mark::Broken));
                i += 1;
            }
            (Some(a), None) => {
                out.push((*a, Mark::Broken));
                i += 1;
            }
            (_, Some(b)) => {
                out.push((*b, Mark::New));
                j += 1;
            }
            (None, None) => break,
        }
    }
    out
}

/// A round length (1, 2 or 5 × 10^k) not longer than `x`.
pub fn round_length(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return 0.0;
    }
    let p = 10f64.powf(x.log10().floor());
    for m in [5.0, 2.0, 1.0] {
        if m * p <= x * (1.0 + 1e-12) {
            return m * p;
        }
    }
    p
}

/// A length with a unit chosen so that the number is between 1 and 1000.
pub fn format_length(x: f64) -> String {
    let (u, name) = if x >= 1.0 {
        (1.0, "m")
    } else if x >= 1e-3 {
        (1e-3, "mm")
    } else if x >= 1e-6 {
        (1e-6, "µm")
    } else {
        (1e-9, "nm")
    };
    let v = x / u;
    if (v - v.round()).abs() < 1e-9 * v.max(1.0) {
        format!("{} {name}", v.round())
    } else {
        format!("{v:.3} {name}")
    }
}

/// Builds the picture of the given items (already checked with [`check_items`]; `HIStory` is
/// not a scene item).
pub fn picture(scene: &Scene, items: &[PlotItem]) -> Result<Picture, String> {
    check_items(scene, items)?;
    let proj = Projection::of(scene.settings.view, scene.settings.two_d);
    let p = &scene.particles;
    let n = p.len();
    let index: HashMap<u32, usize> = p.id.iter().enumerate().map(|(k, &id)| (id, k)).collect();
    let r_mean = if n > 0 {
        p.radius.iter().sum::<f64>() / n as f64
    } else {
        0.0
    };
    let names: Vec<&str> = items.iter().map(|it| item_name(*it)).collect();
    let mut pic = Picture {
        title: format!(
            "trubal   cycle {}   t = {:.4e} s   view {}   plot {}",
            scene.cycle,
            scene.time,
            proj.name,
            names.join(" ")
        ),
        axes: proj.axes(),
        bounds: Bounds::empty(),
        discs: Vec::new(),
        rings: Vec::new(),
        segments: Vec::new(),
        arcs: Vec::new(),
        arrows: Vec::new(),
        legend: Vec::new(),
        notes: vec![format!("view {}: {}", proj.name, proj.description)],
        scale_bar: None,
    };
    if scene.settings.two_d {
        pic.notes.push("2-D mode: the x-y plane".into());
    }
    let has = |it: PlotItem| items.contains(&it);
    let needs_particles = items
        .iter()
        .any(|it| !matches!(it, PlotItem::Bou | PlotItem::Grid | PlotItem::Wall));
    if n == 0 && needs_particles {
        pic.notes
            .push("no particles: nothing to draw but the boundary and the walls".into());
    }
    for k in 0..n {
        pic.bounds.add(proj.project(&p.pos[k]), p.radius[k]);
    }
    let mut planes = Vec::new();
    for &it in items {
        match it {
            PlotItem::Ball | PlotItem::Disks | PlotItem::Cluster | PlotItem::LCluster => {}
            PlotItem::Bou | PlotItem::Grid => boundary(scene, &proj, &mut pic),
            PlotItem::Wall => walls_of(scene, &proj, &mut pic, &mut planes),
            PlotItem::Forces | PlotItem::MForces | PlotItem::LForces => {}
            PlotItem::Cnd => cnd(scene, &proj, &index, r_mean, BondSet::Contacts, &mut pic),
            PlotItem::LCnd => cnd(scene, &proj, &index, r_mean, BondSet::Bridges, &mut pic),
            PlotItem::Velocity => vectors(scene, &proj, r_mean, VectorKind::Velocity, &mut pic),
            PlotItem::RDisp => vectors(scene, &proj, r_mean, VectorKind::Displacement, &mut pic),
            PlotItem::Rotation => arcs(scene, &proj, ArcKind::Rotation, &mut pic),
            PlotItem::Couple => arcs(scene, &proj, ArcKind::Couple, &mut pic),
            PlotItem::Save | PlotItem::History => {}
        }
    }
    let sets = force_sets(items);
    if !sets.is_empty() {
        forces(scene, &proj, &index, r_mean, &sets, &mut pic);
    }
    if has(PlotItem::Ball)
        || has(PlotItem::Disks)
        || has(PlotItem::Cluster)
        || has(PlotItem::LCluster)
    {
        discs(scene, &proj, items, &mut pic);
    }
    // Bounds: what is drawn, or the work-space when nothing is.
    if pic.bounds.is_empty() {
        pic.bounds.add([0.0, 0.0], 0.0);
        pic.bounds
            .add([scene.size[proj.right], scene.size[proj.up]], 0.0);
    }
    add_margin(&mut pic.bounds);
    for pl in planes {
        plane_wall(&pl, &mut pic);
    }
    let bar = round_length(pic.bounds.width() / 5.0);
    if bar > 0.0 {
        pic.scale_bar = Some(ScaleBar {
            length: bar,
            label: format_length(bar),
        });
    }
    if !pic.bounds.width().is_finite() || !pic.bounds.height().is_finite() {
        return Err("the scene has non-finite coordinates: nothing sensible to draw".into());
    }
    Ok(pic)
}

fn add_margin(b: &mut Bounds) {
    let span = b.width().max(b.height());
    let m = if span > 0.0 {
        MARGIN * span
    } else if b.umax.abs().max(b.vmax.abs()) > 0.0 {
        0.05 * b.umax.abs().max(b.vmax.abs())
    } else {
        1.0
    };
    b.umin -= m;
    b.umax += m;
    b.vmin -= m;
    b.vmax += m;
}

/// Particles as discs, far first.
fn discs(scene: &Scene, proj: &Projection, items: &[PlotItem], pic: &mut Picture) {
    let p = &scene.particles;
    let shade = if items.contains(&PlotItem::Ball) || !items.contains(&PlotItem::Disks) {
        Shade::Sphere
    } else {
        Shade::Flat
    };
    let cluster = if items.contains(&PlotItem::Cluster) {
        Some(false)
    } else if items.contains(&PlotItem::LCluster) {
        Some(true)
    } else {
        None
    };
    let fills: Vec<_> = match cluster {
        Some(bridges) => {
            let bonds = scene.contacts.bonded_pairs(p, bridges);
            // Label = a particle index of the cluster; size per label.
            let labels = crate::analysis::cluster_labels(&p.id, &bonds);
            let mut sizes = vec![0usize; labels.len()];
            for &l in &labels {
                sizes[l] += 1;
            }
            let mut clusters = [0usize; 6];
            let mut members = [0usize; 6];
            for &s in sizes.iter().filter(|&&s| s > 0) {
                clusters[cluster_class(s)] += 1;
                members[cluster_class(s)] += s;
            }
            let by = if bridges {
                "liquid bridges"
            } else {
                "solid contacts"
            };
            pic.legend.push(LegendEntry {
                swatch: Swatch::None,
                text: format!("clusters by {by} (size: clusters, particles)"),
            });
            for (c, &(_, _, label)) in CLUSTER_CLASSES.iter().enumerate() {
                if clusters[c] > 0 {
                    pic.legend.push(LegendEntry {
                        swatch: Swatch::Disc(colour::CLUSTER[c]),
                        text: format!("{label}: {}, {}", clusters[c], members[c]),
                    });
                }
            }
            labels
                .iter()
                .map(|&l| colour::CLUSTER[cluster_class(sizes[l])])
                .collect()
        }
        None => {
            let mut seen: Vec<u16> = p.material.clone();
            seen.sort_unstable();
            seen.dedup();
            for m in seen {
                pic.legend.push(LegendEntry {
                    swatch: Swatch::Disc(material_colour(m)),
                    text: format!("particles of material {m}"),
                });
            }
            p.material.iter().map(|&m| material_colour(m)).collect()
        }
    };
    let mut d: Vec<Disc> = (0..p.len())
        .filter(|&k| p.pos[k].iter().all(|x| x.is_finite()))
        .map(|k| Disc {
            id: p.id[k],
            centre: proj.project(&p.pos[k]),
            radius: p.radius[k],
            depth: proj.depth(&p.pos[k]),
            fill: fills[k],
            shade,
        })
        .collect();
    d.sort_by(|a, b| b.depth.total_cmp(&a.depth).then(a.id.cmp(&b.id)));
    pic.discs = d;
}

fn material_colour(m: u16) -> super::picture::Rgb {
    colour::MATERIAL[(m as usize).saturating_sub(1) % colour::MATERIAL.len()]
}

/// The work-space outline; periodic sides dashed.
fn boundary(scene: &Scene, proj: &Projection, pic: &mut Picture) {
    if pic.segments.iter().any(|s| s.layer == Layer::Boundary) {
        return; // BOU and GRId together: once.
    }
    let (lu, lv) = (scene.size[proj.right], scene.size[proj.up]);
    let per = scene.settings.periodic;
    let mark = |periodic: bool| if periodic { Mark::Dashed } else { Mark::Plain };
    let sides = [
        ([0.0, 0.0], [lu, 0.0], mark(per[proj.up])),
        ([0.0, lv], [lu, lv], mark(per[proj.up])),
        ([0.0, 0.0], [0.0, lv], mark(per[proj.right])),
        ([lu, 0.0], [lu, lv], mark(per[proj.right])),
    ];
    for (a, b, m) in sides {
        pic.segments.push(Segment {
            a,
            b,
            width: 0.0,
            colour: colour::BLACK,
            layer: Layer::Boundary,
            mark: m,
            tag: Tag::None,
            value: 0.0,
        });
    }
    pic.bounds.add([0.0, 0.0], 0.0);
    pic.bounds.add([lu, lv], 0.0);
    pic.legend.push(LegendEntry {
        swatch: Swatch::Line(colour::BLACK),
        text: "work-space boundary (dashed: periodic)".into(),
    });
}

/// A plane wall waiting for the final bounds: `n·(u, v) = d` in view coordinates (`n` unit,
/// pointing to the particles' side).
struct PlaneLine {
    wall: usize,
    n: [f64; 2],
    d: f64,
}

fn walls_of(scene: &Scene, proj: &Projection, pic: &mut Picture, planes: &mut Vec<PlaneLine>) {
    if scene.walls.is_empty() {
        pic.notes.push("no walls".into());
        return;
    }
    let p = &scene.particles;
    // The plane walls are cut at mid-depth of the particles (or of the work-space).
    let c0 = if p.is_empty() {
        0.5 * scene.size[proj.depth_axis]
    } else {
        let (lo, hi) = p
            .pos
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x[proj.depth_axis]), hi.max(x[proj.depth_axis]))
            });
        0.5 * (lo + hi)
    };
    for (k, w) in scene.walls.iter().enumerate() {
        match w.geom {
            WallGeom::Plane { normal, d } => {
                let nv = Vec3::from(normal);
                let len = nv.norm();
                if !(len > 0.0 && len.is_finite() && d.is_finite()) {
                    continue;
                }
                let (nr, nu, nd) = (
                    normal[proj.right] / len,
                    normal[proj.up] / len,
                    normal[proj.depth_axis] / len,
                );
                let h = nr.hypot(nu);
                if h < 1e-9 {
                    pic.notes.push(format!(
                        "wall {}: plane parallel to the view, not drawn",
                        k + 1
                    ));
                    continue;
                }
                planes.push(PlaneLine {
                    wall: k,
                    n: [nr / h, nu / h],
                    d: (d / len - nd * c0) / h,
                });
            }
            WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
                let c = proj.project(&Vec3::from(centre));
                let obstacle = matches!(w.geom, WallGeom::Obstacle { .. });
                pic.rings.push(Ring {
                    centre: c,
                    radius,
                    colour: colour::BLACK,
                    fill: obstacle.then_some(colour::GREY),
                    tag: Tag::Wall(k),
                });
                pic.bounds.add(c, radius);
            }
        }
    }
    pic.legend.push(LegendEntry {
        swatch: Swatch::Line(colour::BLACK),
        text: "walls (planes hatched on the far side)".into(),
    });
}

/// Clips the line of a plane wall to the bounds (extending them if the line misses), with
/// hatch marks on the side away from the particles.
fn plane_wall(pl: &PlaneLine, pic: &mut Picture) {
    let b = &mut pic.bounds;
    let centre = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
    let dist = pl.n[0] * centre[0] + pl.n[1] * centre[1] - pl.d;
    let foot = [centre[0] - pl.n[0] * dist, centre[1] - pl.n[1] * dist];
    if !b.contains(foot) {
        let span = b.width().max(b.height());
        b.add(foot, MARGIN * span);
    }
    let t = [-pl.n[1], pl.n[0]];
    let Some((a, e)) = clip_line(foot, t, b) else {
        return;
    };
    let span = b.width().max(b.height());
    pic.segments.push(Segment {
        a,
        b: e,
        width: 0.0,
        colour: colour::BLACK,
        layer: Layer::Wall,
        mark: Mark::Plain,
        tag: Tag::Wall(pl.wall),
        value: 0.0,
    });
    let len = ((e[0] - a[0]).powi(2) + (e[1] - a[1]).powi(2)).sqrt();
    let step = span / 40.0;
    let h = span / 60.0;
    if step > 0.0 && len > 0.0 {
        let count = (len / step).floor().min(200.0) as usize;
        for i in 0..=count {
            let s = i as f64 * step;
            let q = [a[0] + t[0] * s, a[1] + t[1] * s];
            // Away from the particles, slanted along the line.
            let r = [
                q[0] - pl.n[0] * h - t[0] * h * 0.6,
                q[1] - pl.n[1] * h - t[1] * h * 0.6,
            ];
            pic.segments.push(Segment {
                a: q,
                b: r,
                width: 0.0,
                colour: colour::BLACK,
                layer: Layer::Wall,
                mark: Mark::Hatch,
                tag: Tag::Wall(pl.wall),
                value: 0.0,
            });
        }
    }
}

/// The part of the line `p + s t` inside the bounds (Liang–Barsky).
fn clip_line(p: [f64; 2], t: [f64; 2], b: &Bounds) -> Option<([f64; 2], [f64; 2])> {
    let (mut s0, mut s1) = (f64::NEG_INFINITY, f64::INFINITY);
    for (k, (lo, hi)) in [(b.umin, b.umax), (b.vmin, b.vmax)].into_iter().enumerate() {
        if t[k].abs() < 1e-300 {
            if p[k] < lo || p[k] > hi {
                return None;
            }
        } else {
            let (a, c) = ((lo - p[k]) / t[k], (hi - p[k]) / t[k]);
            s0 = s0.max(a.min(c));
            s1 = s1.min(a.max(c));
        }
    }
    if s0 > s1 || !s0.is_finite() || !s1.is_finite() {
        return None;
    }
    Some((
        [p[0] + t[0] * s0, p[1] + t[1] * s0],
        [p[0] + t[0] * s1, p[1] + t[1] * s1],
    ))
}

/// Pushes the line between two particle centres: one segment, or two halves when the pair
/// is joined across a periodic side.
fn pair_line(
    scene: &Scene,
    proj: &Projection,
    xa: &Vec3,
    xb: &Vec3,
    mut seg: Segment,
    out: &mut Vec<Segment>,
) {
    let br = scene.branch(xa, xb);
    let direct = xb - xa;
    if (direct - br).norm() <= 1e-9 * direct.norm().max(br.norm()) {
        seg.a = proj.project(xa);
        seg.b = proj.project(xb);
        out.push(seg);
    } else {
        let mut s2 = seg.clone();
        seg.a = proj.project(xa);
        seg.b = proj.project(&(xa + br * 0.5));
        s2.a = proj.project(xb);
        s2.b = proj.project(&(xb - br * 0.5));
        out.push(seg);
        out.push(s2);
    }
}

/// Normal force of a contact, compressive positive: the solid part (elastic + dashpot, when
/// touching) and the bridge part (viscous − static, when a bridge exists), following the
/// conventions documented on `ContactState` and `BridgeState` (static: attractive positive;
/// viscous: positive = resisting approach, as `physics::bridge::viscous_normal` returns it).
pub fn contact_force(s: &crate::sim::contacts::ContactState, set: ForceSet) -> Option<f64> {
    let solid = s.touching.then_some(s.normal_force + s.damp_force);
    let bridge = s.bridge.as_ref().map(|b| b.f_visc - b.f_static);
    match set {
        ForceSet::Solid => solid,
        ForceSet::Bridge => bridge,
        ForceSet::Total => match (solid, bridge) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(0.0) + b.unwrap_or(0.0)),
        },
    }
}

/// One contact of a force network: force (compressive positive), tag, particle index, and
/// the other end (a wall point or another particle index).
struct ForceLine {
    f: f64,
    tag: Tag,
    i: usize,
    end: Option<Vec3>,
    j: Option<usize>,
}

fn force_list(scene: &Scene, index: &HashMap<u32, usize>, set: ForceSet) -> Vec<ForceLine> {
    let p = &scene.particles;
    let mut list = Vec::new();
    for c in scene.contacts.iter() {
        let (Some(&i), Some(&j)) = (index.get(&c.ida), index.get(&c.idb)) else {
            continue;
        };
        if let Some(f) = contact_force(c.s, set) {
            list.push(ForceLine {
                f,
                tag: Tag::Pair(c.ida, c.idb),
                i,
                end: None,
                j: Some(j),
            });
        }
    }
    for c in &scene.contacts.wall_pairs {
        let (Some(&i), Some(w)) = (index.get(&c.id), scene.walls.get(c.wall as usize)) else {
            continue;
        };
        if let Some(f) = contact_force(&c.s, set) {
            let (gap, nrm) = walls::wall_gap(&w.geom, &p.pos[i], p.radius[i]);
            list.push(ForceLine {
                f,
                tag: Tag::WallContact(c.id, c.wall as usize),
                i,
                end: Some(p.pos[i] + nrm * (p.radius[i] + gap)),
                j: None,
            });
        }
    }
    list
}

/// The force sets asked for, in order.
fn force_sets(items: &[PlotItem]) -> Vec<ForceSet> {
    items
        .iter()
        .filter_map(|it| match it {
            PlotItem::Forces => Some(ForceSet::Total),
            PlotItem::MForces => Some(ForceSet::Solid),
            PlotItem::LForces => Some(ForceSet::Bridge),
            _ => None,
        })
        .collect()
}

/// The force networks of all force items, with widths scaled to one maximum over all of
/// them, drawn widest first so that thin lines stay visible on top of thick ones.
fn forces(
    scene: &Scene,
    proj: &Projection,
    index: &HashMap<u32, usize>,
    r_mean: f64,
    sets: &[ForceSet],
    pic: &mut Picture,
) {
    let p = &scene.particles;
    let lists: Vec<(ForceSet, Vec<ForceLine>)> = sets
        .iter()
        .map(|&s| (s, force_list(scene, index, s)))
        .collect();
    let fmax = lists
        .iter()
        .flat_map(|(_, l)| l.iter())
        .map(|l| l.f.abs())
        .fold(0.0, f64::max);
    let mut segs = Vec::new();
    for (set, list) in lists {
        let what = match set {
            ForceSet::Total => "contact forces, solid + bridge (FORces)",
            ForceSet::Solid => "solid contact forces (MFOrces)",
            ForceSet::Bridge => "liquid-bridge forces (LFOrces)",
        };
        if list.is_empty() {
            pic.notes.push(format!("no {what} to draw"));
            continue;
        }
        let (mut nc, mut nt) = (0, 0);
        for l in list {
            let tensile = l.f < 0.0;
            if tensile {
                nt += 1;
            } else {
                nc += 1;
            }
            let mut seg = Segment {
                a: [0.0; 2],
                b: [0.0; 2],
                width: if fmax > 0.0 {
                    l.f.abs() / fmax * FORCE_WIDTH * r_mean
                } else {
                    0.0
                },
                colour: if tensile {
                    colour::TENSILE
                } else {
                    colour::COMPRESSIVE
                },
                layer: Layer::Force(set),
                mark: if tensile {
                    Mark::Tensile
                } else {
                    Mark::Compressive
                },
                tag: l.tag,
                value: l.f,
            };
            match (l.end, l.j) {
                (Some(e), _) => {
                    seg.a = proj.project(&p.pos[l.i]);
                    seg.b = proj.project(&e);
                    pic.bounds.add(seg.b, 0.0);
                    segs.push(seg);
                }
                (None, Some(j)) => pair_line(scene, proj, &p.pos[l.i], &p.pos[j], seg, &mut segs),
                (None, None) => {}
            }
        }
        pic.legend.push(LegendEntry {
            swatch: Swatch::None,
            text: what.into(),
        });
        pic.legend.push(LegendEntry {
            swatch: Swatch::Line(colour::COMPRESSIVE),
            text: format!("compressive: {nc}"),
        });
        pic.legend.push(LegendEntry {
            swatch: Swatch::Line(colour::TENSILE),
            text: format!("tensile: {nt}"),
        });
    }
    if !segs.is_empty() {
        pic.notes.push(format!(
            "force lines: width proportional to |F|, the widest = {fmax:.3e} N"
        ));
    }
    segs.sort_by(|a, b| b.value.abs().total_cmp(&a.value.abs()));
    pic.segments.extend(segs);
}

fn cnd(
    scene: &Scene,
    proj: &Projection,
    index: &HashMap<u32, usize>,
    r_mean: f64,
    set: BondSet,
    pic: &mut Picture,
) {
    let Some(r) = &scene.reference else { return };
    let p = &scene.particles;
    let bridges = set == BondSet::Bridges;
    let now = scene.contacts.bonded_pairs(p, bridges);
    let reference = if bridges { &r.bridges } else { &r.contacts };
    let classes = classify_bonds(reference, &now);
    let mut counts = [0usize; 3];
    let mut lost = 0;
    // Broken underneath, then the survivors, new ones on top.
    for order in [Mark::Broken, Mark::Kept, Mark::New] {
        for &((a, b), m) in classes.iter().filter(|c| c.1 == order) {
            let (Some(&i), Some(&j)) = (index.get(&a), index.get(&b)) else {
                lost += 1;
                continue;
            };
            let (col, k) = match m {
                Mark::Kept => (colour::KEPT, 0),
                Mark::Broken => (colour::BROKEN, 2),
                _ => (colour::NEW, 1),
            };
            counts[k] += 1;
            let seg = Segment {
                a: [0.0; 2],
                b: [0.0; 2],
                width: CND_WIDTH * r_mean,
                colour: col,
                layer: Layer::Cnd(set),
                mark: m,
                tag: Tag::Pair(a, b),
                value: 0.0,
            };
            pair_line(scene, proj, &p.pos[i], &p.pos[j], seg, &mut pic.segments);
        }
    }
    let what = if bridges {
        "liquid bridges"
    } else {
        "solid contacts"
    };
    pic.legend.push(LegendEntry {
        swatch: Swatch::None,
        text: format!("{what} since cycle {}", r.cycle),
    });
    for (k, (col, name)) in [
        (colour::KEPT, "existing"),
        (colour::NEW, "new"),
        (colour::BROKEN, "broken"),
    ]
    .into_iter()
    .enumerate()
    {
        pic.legend.push(LegendEntry {
            swatch: Swatch::Line(col),
            text: format!("{name}: {}", counts[k]),
        });
    }
    if lost > 0 {
        pic.notes.push(format!(
            "{lost} {what} with a particle no longer present are not drawn"
        ));
    }
}

fn vectors(scene: &Scene, proj: &Projection, r_mean: f64, kind: VectorKind, pic: &mut Picture) {
    let p = &scene.particles;
    let mut v: Vec<(usize, Vec3)> = Vec::new();
    let mut missing = 0;
    match kind {
        VectorKind::Velocity => v.extend(p.vel.iter().copied().enumerate()),
        VectorKind::Displacement => {
            let Some(r) = &scene.reference else { return };
            let at: HashMap<u32, usize> =
                r.ids.iter().enumerate().map(|(k, &id)| (id, k)).collect();
            for k in 0..p.len() {
                match at.get(&p.id[k]).and_then(|&m| r.pos.get(m)) {
                    Some(x0) => v.push((k, scene.branch(&Vec3::from(*x0), &p.pos[k]))),
                    None => missing += 1,
                }
            }
        }
    }
    let inplane = |x: &Vec3| {
        let q = proj.project(x);
        q[0].hypot(q[1])
    };
    let vmax = v.iter().map(|(_, x)| inplane(x)).fold(0.0, f64::max);
    let (what, unit) = match kind {
        VectorKind::Velocity => ("velocity", "m/s"),
        VectorKind::Displacement => ("displacement", "m"),
    };
    if missing > 0 {
        pic.notes.push(format!(
            "{missing} particles created after the reference state have no displacement"
        ));
    }
    if !(vmax > 0.0 && vmax.is_finite()) {
        pic.notes.push(format!(
            "every {what} is zero in the view plane: no vectors"
        ));
        return;
    }
    let scale = VECTOR_RADII * r_mean / vmax;
    for (k, x) in v {
        let m = inplane(&x);
        if !(m > 0.0) {
            continue;
        }
        let from = proj.project(&p.pos[k]);
        let d = proj.project(&x);
        let to = [from[0] + d[0] * scale, from[1] + d[1] * scale];
        pic.bounds.add(to, 0.0);
        pic.arrows.push(Arrow {
            id: p.id[k],
            from,
            to,
            kind,
            value: m,
        });
    }
    let since = match (&scene.reference, kind) {
        (Some(r), VectorKind::Displacement) => format!(" since cycle {}", r.cycle),
        _ => String::new(),
    };
    pic.legend.push(LegendEntry {
        swatch: Swatch::Vector,
        text: format!("{what}{since} (dot = forward end)"),
    });
    pic.notes.push(format!(
        "{what}: longest vector = {vmax:.3e} {unit} (drawn {} mean radii long)",
        VECTOR_RADII
    ));
}

fn arcs(scene: &Scene, proj: &Projection, kind: ArcKind, pic: &mut Picture) {
    let p = &scene.particles;
    let toward = proj.toward();
    let mut vals: Vec<(usize, f64)> = Vec::new();
    match kind {
        ArcKind::Couple => vals.extend(p.moment.iter().map(|m| m.dot(&toward)).enumerate()),
        ArcKind::Rotation => {
            let Some(r) = &scene.reference else { return };
            let at: HashMap<u32, usize> =
                r.ids.iter().enumerate().map(|(k, &id)| (id, k)).collect();
            for k in 0..p.len() {
                if let Some(r0) = at.get(&p.id[k]).and_then(|&m| r.rot.get(m)) {
                    vals.push((k, (p.rot[k] - Vec3::from(*r0)).dot(&toward)));
                }
            }
        }
    }
    let vmax = vals.iter().map(|v| v.1.abs()).fold(0.0, f64::max);
    let (what, unit) = match kind {
        ArcKind::Rotation => ("rotation", "rad"),
        ArcKind::Couple => ("out-of-balance moment", "N m"),
    };
    if !(vmax > 0.0 && vmax.is_finite()) {
        pic.notes.push(format!(
            "every {what} about the viewing axis is zero: no arcs"
        ));
        return;
    }
    for (k, val) in vals {
        if val == 0.0 || !val.is_finite() {
            continue;
        }
        pic.arcs.push(Arc {
            id: p.id[k],
            centre: proj.project(&p.pos[k]),
            radius: ARC_RADIUS * p.radius[k],
            start: 0.5 * PI,
            sweep: val / vmax * MAX_SWEEP,
            colour: if val > 0.0 {
                colour::ANTICLOCKWISE
            } else {
                colour::CLOCKWISE
            },
            kind,
            depth: proj.depth(&p.pos[k]),
            value: val,
        });
    }
    let since = match (&scene.reference, kind) {
        (Some(r), ArcKind::Rotation) => format!(" since cycle {}", r.cycle),
        _ => String::new(),
    };
    pic.legend.push(LegendEntry {
        swatch: Swatch::Arc(colour::ANTICLOCKWISE),
        text: format!("{what}{since}, anticlockwise"),
    });
    pic.legend.push(LegendEntry {
        swatch: Swatch::Arc(colour::CLOCKWISE),
        text: format!("{what}{since}, clockwise"),
    });
    pic.notes.push(format!(
        "{what} about the viewing axis: largest {vmax:.3e} {unit} = 300° arc"
    ));
}
