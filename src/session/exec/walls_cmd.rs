//! Walls: DWAll and AWAll (geometry, velocity, material, servo).

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Dwall(opts) => {
            // (Invariant: the parser refuses a DWAll without a geometry.)
            let geom = unit_axis(opts.geom.expect("DWAll parser requires a geometry"));
            check_geom(&geom)?;
            let material = opts.material.unwrap_or(1);
            existing_material(scene, material)?;
            if scene.walls().len() >= scene.nwall() {
                return Err(format!(
                    "too many walls: nwall = {} given to Start",
                    scene.nwall()
                ));
            }
            let overlap = particles_against(scene, &geom, scene.walls().len() + 1)?;
            let (vel, vr) = opts.vel.unwrap_or(([0.0; 3], 0.0));
            let opened = scene.add_wall(Wall {
                geom,
                vel,
                vr,
                material,
                servo: opts.servo,
                force: [0.0; 3],
                normal_force: 0.0,
                disp: [0.0; 3],
                travel: 0.0,
            })?;
            Ok(format!(
                "wall {} defined{}{overlap}",
                scene.walls().len(),
                opened_message(opened)
            ))
        }
        Command::Awall { n, opts } => {
            if *n == 0 || *n > scene.walls().len() {
                return Err(format!(
                    "wall {n} does not exist ({} walls)",
                    scene.walls().len()
                ));
            }
            if let Some(m) = opts.material {
                existing_material(scene, m)?;
            }
            let geom = opts.geom.map(unit_axis);
            if let Some(g) = &geom {
                check_geom(g)?;
            }
            let overlap = match &geom {
                Some(g) => particles_against(scene, g, *n)?,
                None => String::new(),
            };
            let opened = scene.edit_wall(*n, |w| {
                if let Some(g) = geom {
                    w.geom = g;
                }
                if let Some((v, vr)) = opts.vel {
                    w.vel = v;
                    w.vr = vr;
                }
                if let Some(m) = opts.material {
                    w.material = m;
                }
                // A velocity without SE takes the servo off (the servo would set the
                // velocity again at the next step); SE alone keeps the velocity until the
                // servo sets it.
                if opts.servo.is_some() || opts.vel.is_some() {
                    w.servo = opts.servo;
                }
            });
            Ok(format!(
                "{}{overlap}",
                opened_message(opened).trim_start_matches("; ")
            ))
        }
        other => Err(not_here(other)),
    }
}

/// What opening the periodic axes a plane wall crosses did (doc/limits.md, "Walls and
/// periodic axes"), as "; the z axis is now open (...)" or "".
fn opened_message(opened: [bool; 3]) -> String {
    if opened == [false; 3] {
        return String::new();
    }
    format!(
        "; the {} axis is now open: a plane wall across a periodic axis would let a particle that leaves through one side re-enter behind the wall (a particle leaving through an open side is removed and counted)",
        walls::axis_names(&opened)
    )
}

fn check_geom(g: &WallGeom) -> Result<(), String> {
    match *g {
        WallGeom::Plane { normal, .. } if normal.iter().all(|&x| x == 0.0) => {
            Err("a plane wall needs a non-zero normal (a, b, c)".into())
        }
        WallGeom::Cylinder { axis, .. } if !axis.iter().all(|x| x.is_finite()) => {
            Err("a cylinder needs a finite, non-zero axis (ax, ay, az)".into())
        }
        WallGeom::Cylinder { radius, .. } if !(radius > 0.0 && radius.is_finite()) => {
            Err(format!("a cylinder needs a positive radius (r = {radius})"))
        }
        _ => Ok(()),
    }
}

/// A cylinder's axis made a unit vector (the parser refused a zero one); other walls as
/// they are.
fn unit_axis(g: WallGeom) -> WallGeom {
    match g {
        WallGeom::Cylinder {
            point,
            axis,
            radius,
        } => {
            let a = Vec3::from(axis);
            let a = a / a.norm();
            WallGeom::Cylinder {
                point,
                axis: [a.x, a.y, a.z],
                radius,
            }
        }
        g => g,
    }
}

/// The particles a new wall geometry (wall number `number`) would hold on its wrong side:
/// a particle's centre behind the surface (outside a die or container, inside an indenter)
/// is an error with `SET TUNnel STOP` (the first step would stop on it); particles cut by the
/// surface give a warning (returned as "\nwarning: ..." or "").
fn particles_against(scene: &Scene, geom: &WallGeom, number: usize) -> Result<String, String> {
    let shape = walls::WallShape::of(geom);
    let p = scene.particles();
    let mut behind = None;
    let mut nbehind = 0;
    let mut cut = 0;
    let mut deepest = 0.0f64;
    for i in 0..p.len() {
        let (gap, _) = shape.gap(&p.pos[i], p.radius[i]);
        if gap < -p.radius[i] {
            nbehind += 1;
            behind.get_or_insert(i);
        } else if gap < -0.05 * p.radius[i] {
            cut += 1;
            deepest = deepest.max(-gap / p.radius[i]);
        }
    }
    let tunnel_stop = scene.settings().tunnel == crate::sim::scene::TunnelAction::Stop;
    // Where the particles belong, said for the wall's kind.
    let (side, hint) = match geom {
        WallGeom::Plane { .. } => ("behind the plane", "on the side its normal points to"),
        WallGeom::Sphere { .. } => ("outside the container", "inside the container"),
        WallGeom::Cylinder { .. } => ("outside the die", "inside the die"),
        WallGeom::Obstacle { .. } => (
            "inside the obstacle",
            "outside it (an indenter starts above the bed)",
        ),
    };
    if let Some(i) = behind
        && tunnel_stop
    {
        return Err(format!(
            "wall {number} would leave {nbehind} particle(s) with the centre {side}, the first particle {} at ({:e}, {:e}, {:e}): move or resize the wall so that the particles lie {hint}, or SET TUNnel DELETE to have them deleted at the next Cycle",
            p.id[i], p.pos[i].x, p.pos[i].y, p.pos[i].z
        ));
    }
    let mut out = String::new();
    if nbehind > 0 {
        out.push_str(&format!(
            "\nwarning: wall {number} leaves {nbehind} particle(s) with the centre behind its surface: the next Cycle deletes them (SET TUNnel DELETE)"
        ));
    }
    if cut > 0 {
        out.push_str(&format!(
            "\nwarning: wall {number} cuts {cut} particle(s), the deepest by {:.3} of its radius: they will be pushed out at the next Cycle (particles belong {hint})",
            deepest
        ));
    }
    Ok(out)
}
