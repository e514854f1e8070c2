//! Arrows and arcs: velocities, incremental displacements and rotations.

use super::*;

pub(super) fn vectors(
    scene: &Scene,
    proj: &Projection,
    r_mean: f64,
    kind: VectorKind,
    pic: &mut Picture,
) {
    let p = &scene.particles();
    let mut v: Vec<(usize, Vec3)> = Vec::new();
    let mut missing = 0;
    match kind {
        VectorKind::Velocity => v.extend(p.vel.iter().copied().enumerate()),
        VectorKind::Displacement => {
            let Some(r) = &scene.reference() else { return };
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
    let since = match (&scene.reference(), kind) {
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

pub(super) fn arcs(scene: &Scene, proj: &Projection, kind: ArcKind, pic: &mut Picture) {
    let p = &scene.particles();
    let toward = proj.toward();
    let mut vals: Vec<(usize, f64)> = Vec::new();
    match kind {
        ArcKind::Couple => vals.extend(p.moment.iter().map(|m| m.dot(&toward)).enumerate()),
        ArcKind::Rotation => {
            let Some(r) = &scene.reference() else { return };
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
    let since = match (&scene.reference(), kind) {
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
