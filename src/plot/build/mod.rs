//! Scene → [`Picture`]: projection, depth order, colours and scales. Pure; no pixels.

use std::collections::HashMap;
use std::f64::consts::PI;

use super::picture::{
    Arc, ArcKind, Arrow, BondSet, Bounds, CLUSTER_CLASSES, Disc, ForceSet, Layer, LegendEntry,
    Mark, Picture, Ring, ScaleBar, Segment, Shade, Swatch, Tag, VectorKind, cluster_class, colour,
};
use crate::lang::command::{PlotItem, View, WallGeom};
use crate::sim::{Scene, Vec3, walls};

mod lines;
mod vectors;
mod walls_of;
pub use lines::contact_force;
use lines::*;
use vectors::*;
use walls_of::*;

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
    if scene.reference().is_none() {
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
    let proj = Projection::of(scene.settings().view, scene.settings().two_d);
    let p = &scene.particles();
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
            scene.cycle(),
            scene.time(),
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
    if scene.settings().two_d {
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
            .add([scene.size()[proj.right], scene.size()[proj.up]], 0.0);
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
    let p = &scene.particles();
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
            let bonds = scene.bonded_pairs(bridges);
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
    let (lu, lv) = (scene.size()[proj.right], scene.size()[proj.up]);
    let per = scene.settings().periodic;
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
