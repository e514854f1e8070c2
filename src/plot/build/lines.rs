//! Lines between particles: contact forces (per set, scaled by the largest) and the
//! contact network (CND/LCNd) against the reference state.

use super::*;

/// Pushes the line between two particle centres: one segment, or two halves when the pair
/// is joined across a periodic side.
pub(super) fn pair_line(
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
pub(super) struct ForceLine {
    pub(super) f: f64,
    pub(super) tag: Tag,
    pub(super) i: usize,
    pub(super) end: Option<Vec3>,
    pub(super) j: Option<usize>,
}

pub(super) fn force_list(
    scene: &Scene,
    index: &HashMap<u32, usize>,
    set: ForceSet,
) -> Vec<ForceLine> {
    let p = &scene.particles();
    let mut list = Vec::new();
    for c in scene.contacts().iter() {
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
    for c in scene.contacts().wall_pairs() {
        let (Some(&i), Some(w)) = (index.get(&c.id), scene.walls().get(c.wall as usize)) else {
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
pub(super) fn force_sets(items: &[PlotItem]) -> Vec<ForceSet> {
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
pub(super) fn forces(
    scene: &Scene,
    proj: &Projection,
    index: &HashMap<u32, usize>,
    r_mean: f64,
    sets: &[ForceSet],
    pic: &mut Picture,
) {
    let p = &scene.particles();
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

pub(super) fn cnd(
    scene: &Scene,
    proj: &Projection,
    index: &HashMap<u32, usize>,
    r_mean: f64,
    set: BondSet,
    pic: &mut Picture,
) {
    let Some(r) = &scene.reference() else { return };
    let p = &scene.particles();
    let bridges = set == BondSet::Bridges;
    let now = scene.bonded_pairs(bridges);
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
