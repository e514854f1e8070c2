//! Walls: DWAll and AWAll (geometry, velocity, material, servo).

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Dwall(opts) => {
            if scene.walls.len() >= scene.nwall {
                return Err(format!(
                    "too many walls: nwall = {} given to Start",
                    scene.nwall
                ));
            }
            let geom = opts.geom.expect("DWAll parser requires a geometry");
            check_geom(&geom)?;
            let material = opts.material.unwrap_or(1);
            existing_material(scene, material)?;
            let (vel, vr) = opts.vel.unwrap_or(([0.0; 3], 0.0));
            scene.walls.push(Wall {
                geom,
                vel,
                vr,
                material,
                servo: opts.servo,
                force: [0.0; 3],
                normal_force: 0.0,
                disp: [0.0; 3],
                travel: 0.0,
            });
            scene.contacts.mark_stale();
            let opened = open_crossed_axes(scene);
            Ok(format!("wall {} defined{opened}", scene.walls.len()))
        }
        Command::Awall { n, opts } => {
            if *n == 0 || *n > scene.walls.len() {
                return Err(format!(
                    "wall {n} does not exist ({} walls)",
                    scene.walls.len()
                ));
            }
            if let Some(m) = opts.material {
                existing_material(scene, m)?;
            }
            if let Some(g) = &opts.geom {
                check_geom(g)?;
            }
            let w = &mut scene.walls[n - 1];
            if let Some(g) = opts.geom {
                w.geom = g;
            }
            if let Some((v, vr)) = opts.vel {
                w.vel = v;
                w.vr = vr;
            }
            if let Some(m) = opts.material {
                w.material = m;
            }
            if opts.servo.is_some() {
                w.servo = opts.servo;
            }
            scene.contacts.mark_stale();
            let opened = open_crossed_axes(scene);
            Ok(opened.trim_start_matches("; ").to_string())
        }
        other => Err(not_here(other)),
    }
}

/// Makes open every periodic axis that a plane wall crosses (doc/limits.md, "Walls and
/// periodic axes"); returns what it did, as "; the z axis is now open (...)" or "".
fn open_crossed_axes(scene: &mut Scene) -> String {
    let opened = walls::open_crossed(&scene.walls, &mut scene.settings.periodic);
    if opened == [false; 3] {
        return String::new();
    }
    format!(
        "; the {} axis is now open: a plane wall across a periodic axis would let a particle that leaves through one side re-enter behind the wall (a particle leaving through an open side is removed and counted)",
        walls::axis_names(&opened)
    )
}

fn check_geom(g: &WallGeom) -> Result<(), String> {
    if let WallGeom::Plane { normal, .. } = g
        && normal.iter().all(|&x| x == 0.0)
    {
        return Err("a plane wall needs a non-zero normal (a, b, c)".into());
    }
    Ok(())
}
