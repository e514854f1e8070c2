//! Checks around a Cycle: the scene is complete before it starts (`check`), the warnings
//! a user should see first (`warnings`), and particles that crossed a wall in a step
//! (tunnelling: stop with a message, or delete them with `SET TUNnel DELETE`).

use super::*;

/// Checks that must pass before cycling (bad input gives a clear error, not a NaN).
pub fn check(scene: &Scene) -> Result<Model, String> {
    let model = params::build(scene)?;
    let p = &scene.particles;
    if !(model.dt > 0.0) && !p.is_empty() {
        return Err("the time step is zero: check radii, densities and moduli".into());
    }
    // Periodic axes must be wider than two interaction ranges.
    let rmax = scene.max_radius();
    for k in 0..3 {
        if scene.settings.periodic[k] && !p.is_empty() && scene.size[k] < 4.0 * rmax {
            return Err(format!(
                "the periodic work-space is too small along {}: {} < 4 × largest radius; enlarge it or `SET OPEn {}`",
                ["x", "y", "z"][k],
                scene.size[k],
                ["X", "Y", "Z"][k]
            ));
        }
    }
    check_cell(scene)?;
    check_gain(scene, &model)?;
    check_plane(scene)?;
    if !p.is_empty() {
        check_strain_steps(scene, &model)?;
    }
    Ok(model)
}

/// The most the cell may strain in one step (1 %: no contact follows more).
pub const MAX_STRAIN_STEP: f64 = 0.01;

/// Rates and gains that no packing can follow, refused before the first step (they passed
/// every other check and blew up two or three steps later): a `GRID` rate or the servo's
/// `edmax` straining the cell by more than [`MAX_STRAIN_STEP`] a step, and a servo gain far
/// beyond divergence once the packing reaches its target stress, whatever contacts it has
/// now (a gas has none): the modulus of a Hertz packing at the stress σ is about
/// (E*² σ)^(1/3), and a loop gain `g M Δt` a hundred times the divergence limit is no
/// choice of gain but a slip.
fn check_strain_steps(scene: &Scene, model: &Model) -> Result<(), String> {
    let dt = model.dt;
    let names = ["ed11", "ed22", "ed33", "ed12"];
    for (k, name) in names.iter().enumerate() {
        let ed = scene.cell.rate[k];
        if !(ed.abs() * dt <= MAX_STRAIN_STEP) {
            return Err(format!(
                "GRID {name} = {ed:e} 1/s strains the cell by {:e} per step (dt = {dt:e} s): more than {MAX_STRAIN_STEP} a step, which no contact can follow; at this step the rates must stay within ±{:e} 1/s",
                ed.abs() * dt,
                MAX_STRAIN_STEP / dt
            ));
        }
    }
    let Some(servo) = &scene.derived.servo else {
        return Ok(());
    };
    let [g, edmax] = scene.cell.gain;
    if !(edmax * dt <= MAX_STRAIN_STEP) {
        return Err(format!(
            "GAIN edmax = {edmax:e} 1/s lets the servo strain the cell by {:e} per step (dt = {dt:e} s): more than {MAX_STRAIN_STEP} a step; give edmax at most {:e} 1/s",
            edmax * dt,
            MAX_STRAIN_STEP / dt
        ));
    }
    let e_star = model.table.iter().map(|p| p.e_star).fold(0.0, f64::max);
    let limit = if scene.cell.mode == 0 { 4.0 } else { 2.0 };
    for &(t, target, _) in &servo.targets {
        if t == crate::sim::cell::StressTarget::Ring {
            continue;
        }
        let m = (e_star * e_star * target).cbrt();
        let lg = g * m * dt;
        if lg > 100.0 * limit {
            return Err(format!(
                "GAIN {g:e} would make the stress servo diverge once the packing carries its target of {target:e} Pa: its loop gain g M dt would be about {lg:.1e} (M ≈ (E*² σ)^(1/3) = {m:.3e} Pa, a Hertz packing's modulus at that stress), where mode {} diverges above {limit}; use GAIN of the order of {:.1e} or below (doc/cell.md, \"Choosing the servo gain\")",
                scene.cell.mode,
                0.5 * limit / (m * dt)
            ));
        }
    }
    Ok(())
}

/// A servo whose gain would make the cell's stress diverge at the present contacts
/// ([`servo_loop_gain`]) is refused before cycling.
fn check_gain(scene: &Scene, model: &Model) -> Result<(), String> {
    if scene.derived.servo.is_none() {
        return Ok(());
    }
    let lg = servo_loop_gain(scene, model, model.dt);
    let limit = if scene.cell.mode == 0 { 4.0 } else { 2.0 };
    if lg > limit {
        return Err(format!(
            "GAIN {:e} would make the stress servo diverge: its loop gain g (M Δt + η) is {lg:.3} at the present contacts (stiffness and dashpots) (mode {} diverges above {limit}); use GAIN below {:.3e} (doc/cell.md, \"Choosing the servo gain\")",
            scene.cell.gain[0],
            scene.cell.mode,
            scene.cell.gain[0] * 0.5 * limit / lg
        ));
    }
    Ok(())
}

/// In 2-D (motion in the x–y plane) every particle must lie in the plane of the first one,
/// and the cell must not strain along z.
fn check_plane(scene: &Scene) -> Result<(), String> {
    if !scene.settings.two_d {
        return Ok(());
    }
    let p = &scene.particles;
    if let Some(z0) = p.pos.first().map(|x| x.z) {
        let tol = 1e-9 * scene.size[2].max(scene.max_radius());
        if let Some(i) = p.pos.iter().position(|x| (x.z - z0).abs() > tol) {
            return Err(format!(
                "2-D: particle {} is off the plane of motion z = {z0:e} m (it is at z = {:e} m): in 2-D all particles move in one x-y plane",
                p.id[i], p.pos[i].z
            ));
        }
    }
    if scene.cell.rate[2] != 0.0 {
        return Err(
            "2-D: GRID ed33 would strain the cell out of the plane of motion; give 0".into(),
        );
    }
    Ok(())
}

/// A deforming cell or a stress servo needs a cell of periodic axes without walls (a wall
/// does not follow the mean field), its rates on periodic axes, and a gain for the servo.
fn check_cell(scene: &Scene) -> Result<(), String> {
    let servo = scene.derived.servo.is_some();
    if !scene.cell.in_use() && !servo {
        return Ok(());
    }
    if !scene.walls.is_empty() {
        return Err(format!(
            "the periodic cell {} but the scene has {} wall(s): walls do not follow the cell's deformation; delete them (New) or stop the cell (GRID 0 0 0 0 0 0)",
            if servo {
                "is servo-controlled"
            } else {
                "deforms (GRID)"
            },
            scene.walls.len()
        ));
    }
    if let Some(m) = crate::sim::cell::grid_refusal(&scene.cell.rate, scene.settings.periodic) {
        return Err(m);
    }
    if servo {
        let [g, edmax] = scene.cell.gain;
        if !(g > 0.0 && edmax > 0.0) {
            return Err("the stress servo needs a gain: give GAIN g edmax (g > 0 in 1/(s Pa), the largest strain rate edmax > 0 in 1/s) before Cycle n S0 σ".into());
        }
        if scene.settings.periodic != [true; 3] {
            return Err("the stress servo works on a fully periodic cell: SET PERiodic ALL".into());
        }
    }
    Ok(())
}

/// Warnings about the scene before cycling (deep overlaps, walls through particles,
/// servo gains that would make the wall hunt or diverge).
pub fn warnings(scene: &Scene) -> Vec<String> {
    let mut out = Vec::new();
    let p = &scene.particles;
    if !p.is_empty() {
        let (pairs, _, _) = search::candidates(scene, 0.0);
        // Pairs already touching in the last step (a running bed, a restarted one) are
        // contacts with a history, not overlaps a command made.
        let stored = scene.contacts.pairs();
        let touching = |ida: u32, idb: u32| {
            stored
                .binary_search_by_key(&(ida, idb), |q| (q.ida, q.idb))
                .is_ok_and(|k| scene.contacts.state(k).touching)
        };
        let deep = pairs
            .iter()
            .filter(|c| {
                let (i, j) = (c.i as usize, c.j as usize);
                let d = scene.branch(&p.pos[i], &p.pos[j]).norm();
                p.radius[i] + p.radius[j] - d > 0.05 * p.radius[i].min(p.radius[j])
                    && !touching(c.ida, c.idb)
            })
            .count();
        if deep > 0 {
            out.push(format!(
                "{deep} particle pair(s) not in contact before overlap by more than 5 % of the smaller radius: they will fly apart"
            ));
        }
    }
    if let Ok(model) = params::build(scene)
        && scene.settings.auto_step.is_none()
        && let Some(w) = crate::sim::contact_time::warning(scene, &model, model.fraction)
    {
        out.push(w);
    }
    // A step the dashpot limits shrink far below the FRAction step (a viscous bridge at a
    // tiny S_min: SET SMIN 1e-300 made Δt = 5e-302 s without a word).
    if let Ok(model) = params::build(scene) {
        let fraction_step = model.fraction * model.dt_rayleigh;
        if model.dt_base < 0.01 * fraction_step && !scene.particles.is_empty() {
            out.push(format!(
                "the step is {:.3e} s, {:.1e} times below the FRAction step {:.3e} s: the viscous force of the bridges at S_min ({}) or Rayleigh contact damping (β = {:.3e} s) limits it; a larger SET SMIN (Lian: R/1000 to R/100) or a smaller β gives a longer step",
                model.dt_base,
                fraction_step / model.dt_base,
                fraction_step,
                scene
                    .settings
                    .smin
                    .map_or(
                        if scene.settings.bridge == crate::sim::model::BridgeChoice::Rabinovich {
                            "R*/1000"
                        } else {
                            "R*/100"
                        }
                        .to_string(),
                        |s| format!("{s:.3e} m")
                    ),
                scene.damping_pp.beta.max(scene.damping_pw.beta)
            ));
        }
    }
    if let Ok(model) = params::build(scene) {
        out.extend(servo_warnings(scene, &model));
    }
    for (w, wall) in scene.walls.iter().enumerate() {
        let mut n = 0;
        for i in 0..p.len() {
            let (gap, _) = wall_gap(&wall.geom, &p.pos[i], p.radius[i]);
            if gap < -0.5 * p.radius[i] {
                n += 1;
            }
        }
        if n > 0 {
            out.push(format!(
                "wall {} cuts through {n} particle(s) (overlap > R/2): they will be pushed out violently",
                w + 1
            ));
        }
    }
    out
}

/// A servo of wall `w` that cannot reach its target force: it cannot move (vmax or g is 0)
/// while the force differs, or it asks for a pull (F < 0) from particles that cannot pull
/// (no adhesion between the wall's material and any particle's, no liquid bridges): the wall
/// would back away at vmax for ever.
fn unreachable_target(scene: &Scene, w: usize) -> Option<String> {
    let wall = &scene.walls[w];
    let s = wall.servo?;
    if (s.vmax == 0.0 || s.gain == 0.0) && s.force != wall.normal_force {
        return Some(format!(
            "servo of wall {} cannot move (vmax = {}, g = {}): its target force {} N will not be reached (the force is {:e} N now)",
            w + 1,
            s.vmax,
            s.gain,
            s.force,
            wall.normal_force
        ));
    }
    if s.force < 0.0 {
        let gw = scene
            .materials
            .get(wall.material - 1)
            .map_or(0.0, |m| m.gamma);
        let p = &scene.particles;
        // Liquid bridges pull on walls too (`LIQuid`).
        let wet = scene.liquid.is_some_and(|l| l.pvol > 0.0 && l.gamma > 0.0);
        let sticky = wet
            || (0..scene.materials.len()).any(|m| {
                scene.materials[m].gamma * gw > 0.0
                    && p.material.iter().any(|&k| k as usize == m + 1)
            });
        if !sticky {
            return Some(format!(
                "servo of wall {} targets a pull ({} N < 0) but no particle adheres to its material {} (COHesion) and there is no liquid (LIQuid): the target cannot be reached, the wall will back away at vmax = {} m/s",
                w + 1,
                s.force,
                wall.material,
                s.vmax
            ));
        }
    }
    None
}

/// Servo walls whose gain makes them hunt: through the contacts' stiffness over a step, or
/// through the contacts' dashpots at once.
fn servo_warnings(scene: &Scene, model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    for (w, wall) in scene.walls.iter().enumerate() {
        if let Some(s) = wall.servo {
            out.extend(unreachable_target(scene, w));
            // Loop gain of the servo per step: g × (stiffness of the wall contacts) × Δt,
            // with a contact stiffness 2E*a at an overlap of 1e-3 R for every particle near
            // the wall; above 1 the wall overshoots every step.
            let m = &scene.materials[wall.material - 1];
            let r = scene.max_radius();
            let k = 2.0 * m.young / (2.0 * (1.0 - m.poisson * m.poisson)) * (r * 1e-3 * r).sqrt();
            // The wall's contacts: those of the candidate list, or, if more, the particles of
            // the layer nearest to the wall (within a largest diameter of the nearest one),
            // which a wall still away from the bed (or just moved by AWAll, its candidates
            // not yet found) will press.
            let n = scene
                .contacts
                .wall_pairs
                .iter()
                .filter(|c| c.wall as usize == w)
                .count()
                .max(nearest_layer(scene, w))
                .max(1) as f64;
            let loop_gain = s.gain * k * n * model.dt;
            if loop_gain > 1.0 {
                out.push(format!(
                    "servo of wall {}: gain {} gives a loop gain of {loop_gain:.2e} per step (> 1): the wall will hunt or diverge; use g below {:.2e}",
                    w + 1,
                    s.gain,
                    s.gain / loop_gain
                ));
            }
            // The contacts' dashpots close a second loop, without the step: the wall's
            // speed g × (force error) makes a dashpot force c × speed at once, so
            // g × n × c above 1 makes the speed change sign every step (c: the
            // restitution dashpot of the largest particle at the same overlap, plus
            // Rayleigh's β k).
            let p = &scene.particles;
            if let Some(i) = (0..p.len()).max_by(|&a, &b| p.radius[a].total_cmp(&p.radius[b])) {
                let pc = model.pair(p.material[i] as usize, wall.material);
                let (mi, ri) = (p.mass[i], p.radius[i]);
                // The dashpot grows as the overlap^{1/4}: at the overlap of the target force
                // shared by the n contacts (Hertz against a plane), at least 1e-3 R.
                let f = s.force.abs() / n;
                let hertz = (3.0 * f / (4.0 * pc.e_star * ri.sqrt())).powf(2.0 / 3.0);
                let delta = hertz.max(1e-3 * ri);
                let c = pc.dash * (mi * mi * ri * delta).sqrt().sqrt() + scene.damping_pw.beta * k;
                let dash_gain = s.gain * n * c;
                if dash_gain > 1.0 {
                    out.push(format!(
                        "servo of wall {}: gain {} through the contacts' dashpots gives a loop gain of {dash_gain:.2e} (> 1): the wall's speed will change sign every step (hunting; the books then close less well); use g below {:.2e}",
                        w + 1,
                        s.gain,
                        s.gain / dash_gain
                    ));
                }
            }
        }
    }
    out
}

/// The particles of the layer nearest to wall `w`: those whose gap is within the largest
/// particle diameter of the smallest gap.
fn nearest_layer(scene: &Scene, w: usize) -> usize {
    let p = &scene.particles;
    let shape = WallShape::of(&scene.walls[w].geom);
    let gaps: Vec<f64> = (0..p.len())
        .map(|i| shape.gap(&p.pos[i], p.radius[i]).0)
        .filter(|g| g.is_finite())
        .collect();
    let least = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    let reach = least + 2.0 * scene.max_radius();
    gaps.iter().filter(|&&g| g <= reach).count()
}

/// Particles whose centre lies behind a wall's surface (gap < −R: behind a plane, outside a
/// container, inside an obstacle), as (particle, wall) in particle order: every particle
/// against every wall (the wall pairs alone: [`clearance::behind_with_clearance`]).
pub(super) fn behind_walls(scene: &Scene) -> Vec<(usize, usize)> {
    let p = &scene.particles;
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    let behind = |i: usize, w: usize| {
        let (gap, _) = shapes[w].gap(&p.pos[i], p.radius[i]);
        // (NaN is not "behind": a non-finite state is the blow-up check's.)
        gap < -p.radius[i]
    };
    let mut out: Vec<(usize, usize)> = p
        .pos
        .par_chunks(CHUNK)
        .enumerate()
        .flat_map_iter(|(c, xs)| {
            let behind = &behind;
            let nw = shapes.len();
            (0..xs.len()).flat_map(move |l| {
                let i = c * CHUNK + l;
                (0..nw).filter(move |&w| behind(i, w)).map(move |w| (i, w))
            })
        })
        .collect();
    out.sort_unstable();
    out
}

/// What a crossing looks like: the particle, the wall, how far behind, the speeds against
/// the step.
pub(super) fn crossing(scene: &Scene, (i, w): (usize, usize), dt: f64) -> String {
    let p = &scene.particles;
    let wall = &scene.walls[w];
    let (gap, n) = WallShape::of(&wall.geom).gap(&p.pos[i], p.radius[i]);
    let v = p.vel[i];
    let vw = surface_velocity(wall, &n);
    // Approach speed towards the wall (n points from the particle to the wall).
    let approach = (v - vw).dot(&n);
    format!(
        "particle {} crossed wall {} at cycle {}: its centre ({:.4e}, {:.4e}, {:.4e}) is {:.3e} m behind the wall's surface \
         (radius {:.3e} m; it moves at {:.3e} m/s, {:.3e} m/s towards the wall, which moves at {:.3e} m/s: {:.3e} m per step of {:.3e} s)",
        p.id[i],
        w + 1,
        scene.cycle,
        p.pos[i].x,
        p.pos[i].y,
        p.pos[i].z,
        -(gap + p.radius[i]),
        p.radius[i],
        v.norm(),
        approach,
        vw.norm(),
        approach.abs() * dt,
        dt
    )
}

/// The stop of a run on a crossing (`SET TUNnel STOP`).
pub(super) fn tunnelled(scene: &Scene, behind: &[(usize, usize)], dt: f64) -> Blowup {
    let more = if behind.len() > 1 {
        format!(" ({} particle-wall crossings in all)", behind.len())
    } else {
        String::new()
    };
    Blowup {
        cycle: scene.cycle,
        message: format!(
            "{}{more}. A wall's surface was passed between two steps or two re-mappings: the particle came too fast for the step, \
             the wall moved too far in one step, or it entered behind the wall. \
             Hint: a smaller FRAction (or FRAction AUTO), a slower wall (V, or the servo's vmax), walls inside the work-space; \
             SET TUNnel DELETE removes such particles instead",
            crossing(scene, behind[0], dt)
        ),
    }
}

/// Deletes the particles that crossed a wall (`SET TUNnel DELETE`), with a note each; what
/// they held (kinetic energy and their contacts' stored energy) leaves the books with them.
pub(super) fn delete_tunnelled(scene: &mut Scene, behind: &[(usize, usize)], dt: f64) {
    let mut gone = vec![false; scene.particles.len()];
    for &(i, w) in behind {
        if !gone[i] {
            gone[i] = true;
            let note = format!(
                "{}; deleted (SET TUNnel DELETE)",
                crossing(scene, (i, w), dt)
            );
            scene.derived.notes.push(note);
        }
    }
    let kinetic = crate::sim::energy::kinetic(scene);
    scene.lost += delete_marked(scene, &gone);
    scene.ledger.commands += crate::sim::energy::kinetic(scene) - kinetic;
}

/// A single step that moves a pair by more than this fraction of the smaller radius
/// relative to each other can carry one particle through another without a contact state
/// ever seeing it: such a step is checked along the particles' paths ([`after_step`]).
pub const JUMP_FRACTION: f64 = 0.5;

/// The overlaps of the stored contacts are checked whenever the particles may have moved by
/// this fraction of the smallest radius relative to each other since the last check.
const WATCH_FRACTION: f64 = 0.25;

/// The checks after a step, when every particle has moved by v Δt and the walls by theirs
/// (a crossing is found in the step in which it happens, so that no Cycle ends, and no
/// `SAve` writes, a state with a particle through a wall or through another particle):
///
/// - a particle whose centre is behind a wall's surface (every particle when the list of
///   candidates is due for a re-mapping, the wall pairs otherwise), or whose path went
///   through an obstacle (`DWAll OB`) that moves by more than [`JUMP_FRACTION`] of the
///   smallest radius in a step;
/// - a pair whose overlap exceeds the smaller radius (one centre inside the other sphere:
///   beyond anything a contact law holds), checked on the stored contacts whenever the
///   particles may have moved by [`WATCH_FRACTION`] of the smallest radius since the last
///   check (`watch` keeps that count between steps), and along the paths of the step for
///   every pair within reach when a step moves particles by more than [`JUMP_FRACTION`] of
///   it relative to each other.
///
/// - a servo wall that hunts ([`watch_servos`]).
///
/// `rmin`: the smallest radius of the Cycle's start (deletions only make it larger).
pub(super) fn after_step(
    scene: &mut Scene,
    dt: f64,
    rmin: f64,
    watch: &mut StepWatch,
) -> Result<(), Blowup> {
    let p = &scene.particles;
    if p.is_empty() {
        return Ok(());
    }
    // The largest distance a particle moved in this step.
    let vmax = scene
        .derived
        .speeds
        .fastest()
        .unwrap_or_else(|| largest_norm_squared(&p.vel))
        .sqrt();
    let step = vmax * dt;
    if !scene.walls.is_empty() {
        // Every particle when the candidates are due for a re-mapping or a wall jumped by
        // more than JUMP_FRACTION of the smallest radius (a wall within that of a particle's
        // centre is one of its candidates).
        let jumped = scene
            .walls
            .iter()
            .any(|w| surface_speed(w) * dt > JUMP_FRACTION * rmin);
        let all = jumped || scene.contacts.is_stale() || scene.contacts.needs_remap();
        // The wall pairs only while they may have reached their walls (`clearance`).
        let behind = if all {
            watch.clearance = None;
            behind_walls(scene)
        } else if clearance::wall_pairs_clear(scene, &mut watch.clearance, step, dt, rmin) {
            Vec::new()
        } else {
            let (behind, c) = clearance::behind_with_clearance(scene);
            watch.clearance = c;
            behind
        };
        let through = through_obstacles(scene, dt, step, rmin);
        if let Some(&(i, w)) = through.first() {
            return Err(passed_obstacle(scene, (i, w), dt));
        }
        if !behind.is_empty() {
            match scene.settings.tunnel {
                TunnelAction::Stop => return Err(tunnelled(scene, &behind, dt)),
                TunnelAction::Delete => delete_tunnelled(scene, &behind, dt),
            }
        }
    }
    watch.moved += 2.0 * step;
    if 2.0 * step > JUMP_FRACTION * rmin {
        watch.moved = 0.0;
        if let Some(e) = pairs_through(scene, dt, 2.0 * step) {
            return Err(e);
        }
    } else if watch.moved >= WATCH_FRACTION * rmin {
        watch.moved = 0.0;
        if let Some(e) = deep_contacts(scene, dt, rmin) {
            return Err(e);
        }
    }
    watch_servos(scene, watch)
}

/// The closest approach of the relative path `d0 → d1` (a straight segment over the step)
/// to the origin.
fn closest_approach(d0: Vec3, d1: Vec3) -> f64 {
    let s = d1 - d0;
    let ss = s.norm_squared();
    let t = if ss > 0.0 {
        (-d0.dot(&s) / ss).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (d0 + s * t).norm()
}

/// Particles whose path in this step went through an obstacle that moved, relative to
/// them, by more than [`JUMP_FRACTION`] of the smallest radius (its centre passed within the
/// obstacle's radius of theirs): (particle, wall).
fn through_obstacles(scene: &Scene, dt: f64, step: f64, rmin: f64) -> Vec<(usize, usize)> {
    let p = &scene.particles;
    let mut out = Vec::new();
    for (w, wall) in scene.walls.iter().enumerate() {
        let WallGeom::Obstacle { centre, radius } = wall.geom else {
            continue;
        };
        let vw = Vec3::from(wall.vel);
        if !(vw.norm() * dt + step > JUMP_FRACTION * rmin) {
            continue;
        }
        let c = Vec3::from(centre);
        for i in 0..p.len() {
            let d1 = p.pos[i] - c;
            let d0 = d1 - (p.vel[i] - vw) * dt;
            if closest_approach(d0, d1) < radius {
                out.push((i, w));
            }
        }
    }
    out
}

/// The stop of a run whose particle passed through an obstacle within one step.
fn passed_obstacle(scene: &Scene, (i, w): (usize, usize), dt: f64) -> Blowup {
    let p = &scene.particles;
    let wall = &scene.walls[w];
    let rel = (p.vel[i] - Vec3::from(wall.vel)).norm();
    Blowup {
        cycle: scene.cycle,
        message: format!(
            "particle {} passed through wall {} (an obstacle) in the step of cycle {}: relative to each other they moved {:.3e} m in a step of {:.3e} s \
             (the particle at {:.3e} m/s, the wall at {:.3e} m/s; particle radius {:.3e} m), and its centre went through the obstacle. \
             Hint: a smaller FRAction (or FRAction AUTO), a slower wall",
            p.id[i],
            w + 1,
            scene.cycle,
            rel * dt,
            dt,
            p.vel[i].norm(),
            Vec3::from(wall.vel).norm(),
            p.radius[i],
        ),
    }
}

/// A pair of particles one of which went into or through the other (index order), with the
/// depth reached: the closest approach of their centres.
fn pair_through(scene: &Scene, (i, j): (usize, usize), closest: f64, dt: f64) -> Blowup {
    let p = &scene.particles;
    let rel = (p.vel[j] - p.vel[i]).norm();
    let (ri, rj) = (p.radius[i], p.radius[j]);
    Blowup {
        cycle: scene.cycle,
        message: format!(
            "particles {} and {} passed into each other at cycle {}: their centres came within {:.3e} m, an overlap of {:.3e} m, more than the smaller radius {:.3e} m \
             (beyond what a contact law can hold); they move at {:.3e} and {:.3e} m/s, {:.3e} m/s relative to each other: {:.3e} m per step of {:.3e} s. \
             Hint: a smaller FRAction (or FRAction AUTO, which limits the relative travel to a fifth of a radius a step), stiffer particles (YMD), slower ones",
            p.id[i],
            p.id[j],
            scene.cycle,
            closest,
            ri + rj - closest,
            ri.min(rj),
            p.vel[i].norm(),
            p.vel[j].norm(),
            rel,
            rel * dt,
            dt,
        ),
    }
}

/// Stored contacts whose overlap exceeds the smaller radius. Such an overlap exceeds
/// `rmin` (no larger than any radius: `ri.min(rj) ≥ rmin`, and `min` passes a NaN over),
/// so the pairs are looked at only when a state's overlap does.
fn deep_contacts(scene: &Scene, dt: f64, rmin: f64) -> Option<Blowup> {
    if !scene.contacts.any_overlap_above(rmin) {
        return None;
    }
    let p = &scene.particles;
    scene.contacts.iter().find_map(|c| {
        let (i, j) = (c.i as usize, c.j as usize);
        let (ri, rj) = (p.radius[i], p.radius[j]);
        (c.s.overlap > ri.min(rj)).then(|| {
            let d = scene.branch(&p.pos[i], &p.pos[j]).norm();
            pair_through(scene, (i, j), d.min(ri + rj - c.s.overlap), dt)
        })
    })
}

/// Every pair within `reach` of touching now (so every pair whose paths came within
/// touching in this step), its centres' relative path over the step tested against the
/// larger radius.
fn pairs_through(scene: &Scene, dt: f64, reach: f64) -> Option<Blowup> {
    let p = &scene.particles;
    let (pairs, _, _) = search::candidates(scene, reach);
    // In a deforming cell the velocities are relative to the mean field: the end state only.
    let paths = !scene.cell.in_use();
    pairs.iter().find_map(|c| {
        let (i, j) = (c.i as usize, c.j as usize);
        let d1 = scene.branch(&p.pos[i], &p.pos[j]);
        let closest = if paths {
            closest_approach(d1 - (p.vel[j] - p.vel[i]) * dt, d1)
        } else {
            d1.norm()
        };
        (closest < p.radius[i].max(p.radius[j])).then(|| pair_through(scene, (i, j), closest, dt))
    })
}

/// A particle whose centre lies behind a wall's surface (made so by commands: a Cycle never
/// ends with one), described; `SAve` refuses such a state.
pub fn behind_a_wall(scene: &Scene) -> Option<String> {
    let (i, w) = *behind_walls(scene).first()?;
    let p = &scene.particles;
    let (gap, _) = WallShape::of(&scene.walls[w].geom).gap(&p.pos[i], p.radius[i]);
    Some(format!(
        "particle {} at ({:.4e}, {:.4e}, {:.4e}) is behind wall {}: its centre is {:.3e} m behind the wall's surface",
        p.id[i],
        p.pos[i].x,
        p.pos[i].y,
        p.pos[i].z,
        w + 1,
        -(gap + p.radius[i])
    ))
}

/// A servo wall whose speed has changed sign at this many consecutive steps without its
/// amplitude decaying hunts: the run stops ([`watch_servos`]).
pub const HUNT_STEPS: u32 = 200;

/// A servo's force error below this fraction of its target (or force) is a dither about
/// the target, not hunting ([`watch_servos`]).
pub const HUNT_ERROR: f64 = 0.01;

/// What the checks after a step keep from one step to the next within a Cycle.
#[derive(Default)]
pub(super) struct StepWatch {
    /// The particles' relative travel since the last check of the contacts' overlaps.
    moved: f64,
    /// Per wall: the servo's speed of the last two steps and how many consecutive steps it
    /// changed sign without decaying.
    servo: Vec<([f64; 2], u32)>,
    /// The wall pairs' clearance at their last check ([`clearance`]).
    clearance: Option<clearance::Clearance>,
}

/// A servo wall that hunts — its speed g (F − F_target), clipped to ±vmax, changing sign at
/// every step for [`HUNT_STEPS`] steps without decaying, the force more than [`HUNT_ERROR`]
/// off its target (a loop gain above 2, or a limit cycle at ±vmax) — stops the run: the scheme cannot book the work of a wall that reverses
/// at every step (the books drift by several % of the input), so its results are not to be
/// trusted. The message gives the gain that holds.
fn watch_servos(scene: &Scene, watch: &mut StepWatch) -> Result<(), Blowup> {
    if watch.servo.len() != scene.walls.len() {
        watch.servo = vec![([0.0; 2], 0); scene.walls.len()];
    }
    for (w, wall) in scene.walls.iter().enumerate() {
        let Some(s) = wall.servo else { continue };
        let err = wall.normal_force - s.force;
        let speed = (s.gain * err).clamp(-s.vmax, s.vmax);
        let ([last, before], flips) = &mut watch.servo[w];
        // (A dither about the target, the force within 1 % of it, is no hunting.)
        let large = err.abs() > HUNT_ERROR * s.force.abs().max(wall.normal_force.abs());
        let hunting = large && speed * *last < 0.0 && speed.abs() >= 0.9 * before.abs();
        *flips = if hunting { *flips + 1 } else { 0 };
        (*before, *last) = (*last, speed);
        if *flips >= HUNT_STEPS {
            return Err(Blowup {
                cycle: scene.cycle,
                message: format!(
                    "servo of wall {} hunts: its speed changed sign at each of the last {HUNT_STEPS} steps without decaying (now {speed:.3e} m/s; gain {}, vmax {}, target {} N, force {:.3e} N): \
                     the work of a wall that reverses at every step cannot be booked, and the run's energy books would drift. \
                     Hint: a smaller gain (the warning before the Cycle gives one that holds), a smaller vmax, or a smaller FRAction",
                    w + 1,
                    s.gain,
                    s.vmax,
                    s.force,
                    wall.normal_force
                ),
            });
        }
    }
    Ok(())
}

/// The servo's loop gain per step, `g (M Δt + η)`, with `M = Σ_c k_n l² / V` (k_n = 2 E* a
/// the Hertz stiffness of each touching contact, l its branch length), an upper bound of the
/// assembly's modulus dσ/dε under an affine strain, and `η = Σ_c c_n l² / V` (c_n the
/// restitution dashpot's coefficient `dash (m*² R* α)^{1/4}`, `physics::dashpot`), the
/// stress the dashpots add per unit strain rate at once: a strain rate set from the stress
/// (mode 1) feeds back through them in the same step. Mode 1 relaxes the error by about
/// `(1 − gain)` per step (it overshoots above 1 and diverges above 2); mode 0 oscillates
/// about the target and diverges above 4 (doc/cell.md, "Choosing the servo gain").
fn servo_loop_gain(scene: &Scene, model: &Model, dt: f64) -> f64 {
    let p = &scene.particles;
    let (mut m, mut eta) = (0.0, 0.0);
    for c in scene.contacts.iter() {
        if !c.s.touching {
            continue;
        }
        let (i, j) = (c.i as usize, c.j as usize);
        let (ka, kb) = (p.material[i] as usize, p.material[j] as usize);
        let (a, b) = (&scene.materials[ka - 1], &scene.materials[kb - 1]);
        let es = crate::physics::hertz::e_star(a.young, a.poisson, b.young, b.poisson);
        let l2 = scene.branch(&p.pos[i], &p.pos[j]).norm_squared();
        m += 2.0 * es * c.s.a * l2;
        let dash = model.pair(ka, kb).dash;
        if dash > 0.0 && c.s.overlap > 0.0 {
            let r_star = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
            let m_star = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
            eta += dash * (m_star * m_star * r_star * c.s.overlap).powf(0.25) * l2;
        }
    }
    scene.cell.gain[0] * (m * dt + eta) / crate::sim::stress::volume(scene)
}
