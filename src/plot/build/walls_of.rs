//! Walls in a picture: plane walls as lines clipped to the view, spheres as rings, a
//! cylinder as a ring (seen along its axis) or its two sides (axis in the view's plane).

use super::*;

/// A plane wall waiting for the final bounds: `n·(u, v) = d` in view coordinates (`n` unit,
/// pointing to the particles' side).
pub(super) struct PlaneLine {
    pub(super) wall: usize,
    pub(super) n: [f64; 2],
    pub(super) d: f64,
}

pub(super) fn walls_of(
    scene: &Scene,
    proj: &Projection,
    pic: &mut Picture,
    planes: &mut Vec<PlaneLine>,
) {
    if scene.walls().is_empty() {
        pic.notes.push("no walls".into());
        return;
    }
    let p = &scene.particles();
    // The plane walls are cut at mid-depth of the particles (or of the work-space).
    let c0 = if p.is_empty() {
        0.5 * scene.size()[proj.depth_axis]
    } else {
        let (lo, hi) = p
            .pos
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x[proj.depth_axis]), hi.max(x[proj.depth_axis]))
            });
        0.5 * (lo + hi)
    };
    for (k, w) in scene.walls().iter().enumerate() {
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
            WallGeom::Cylinder {
                point,
                axis,
                radius,
            } => {
                let c = proj.project(&Vec3::from(point));
                let a = Vec3::from(axis);
                let len = a.norm();
                if !(len > 0.0 && len.is_finite() && radius.is_finite()) {
                    continue;
                }
                let (ar, au) = (axis[proj.right] / len, axis[proj.up] / len);
                let h = ar.hypot(au);
                if h < 1e-9 {
                    // Seen along its axis: a circle.
                    pic.rings.push(Ring {
                        centre: c,
                        radius,
                        colour: colour::BLACK,
                        fill: None,
                        tag: Tag::Wall(k),
                    });
                    pic.bounds.add(c, radius);
                } else if h > 1.0 - 1e-9 {
                    // The axis in the view's plane: its two sides, hatched outside.
                    let m = [-au / h, ar / h];
                    let mc = m[0] * c[0] + m[1] * c[1];
                    for (sign, n) in [(1.0, m), (-1.0, [-m[0], -m[1]])] {
                        planes.push(PlaneLine {
                            wall: k,
                            n,
                            d: sign * mc - radius,
                        });
                    }
                } else {
                    pic.notes.push(format!(
                        "wall {}: cylinder oblique to the view, not drawn",
                        k + 1
                    ));
                }
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
pub(super) fn plane_wall(pl: &PlaneLine, pic: &mut Picture) {
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
pub(super) fn clip_line(p: [f64; 2], t: [f64; 2], b: &Bounds) -> Option<([f64; 2], [f64; 2])> {
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
