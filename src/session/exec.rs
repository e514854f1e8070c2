//! Applies a command to the scene. Every function here either succeeds or returns an error
//! and leaves the scene as it was (the caller works on a copy for multi-step changes).

#[allow(unused_imports)]
use crate::lang::command::SizeDist;
use crate::lang::command::*;
use crate::sim::generate::{
    CreateIndex, OverlapIndex, first_overlap, inside, lattice_ranges, lattice_sites,
    max_lattice_sites, morton_order, sphere_mass,
};
use crate::sim::scene::{
    LatticeRun, MAX_MATERIALS, MAX_SIZES, Material, Rayleigh, Region, Scene, Vec3, Wall,
};
use crate::sim::walls;

fn material_mut(scene: &mut Scene, m: usize) -> Result<&mut Material, String> {
    if m > MAX_MATERIALS {
        return Err(format!(
            "material type {m} is beyond the limit of {MAX_MATERIALS}"
        ));
    }
    if m > scene.materials.len() {
        scene.materials.resize(m, Material::default());
    }
    Ok(&mut scene.materials[m - 1])
}

fn existing_material(scene: &Scene, m: usize) -> Result<(), String> {
    if m == 0 || m > scene.materials.len() || scene.materials[m - 1] == Material::default() {
        return Err(format!(
            "material type {m} is not defined: give it YMD, PRA and Density first"
        ));
    }
    Ok(())
}

fn radius_for(scene: &Scene, size: usize) -> Result<f64, String> {
    scene
        .radius_of(size)
        .ok_or_else(|| format!("size type {size} has no radius: give `RAdius r {size}` first"))
}

/// The density new particles of material `m` get. Generation needs their radius only, as in
/// TRUBAL (geometry first, then materials): a material not given yet is 0 here, `Density`
/// later re-computes the masses, and the first `Cycle` names what is still missing.
fn generation_density(scene: &Scene, m: usize) -> Result<f64, String> {
    if m == 0 || m > MAX_MATERIALS {
        return Err(format!("material type {m} is outside 1..{MAX_MATERIALS}"));
    }
    Ok(scene.materials.get(m - 1).map_or(0.0, |x| x.density))
}

/// Makes room for material `m` (its properties come later), once a generation command
/// has passed its checks.
fn ensure_material(scene: &mut Scene, m: usize) {
    if m > scene.materials.len() {
        scene.materials.resize(m, Material::default());
    }
}

fn check_capacity(scene: &Scene, more: usize) -> Result<(), String> {
    if scene.particles.len() + more > scene.nball {
        return Err(format!(
            "too many particles: {} + {more} would exceed nball = {} given to Start",
            scene.particles.len(),
            scene.nball
        ));
    }
    Ok(())
}

/// Re-computes particle masses of a material after a density change.
fn refresh_masses(scene: &mut Scene, m: usize) {
    let rho = scene.materials[m - 1].density;
    let p = &mut scene.particles;
    for i in 0..p.len() {
        if p.material[i] as usize == m {
            p.mass[i] = sphere_mass(rho, p.radius[i]);
        }
    }
}

/// Applies a scene command. Returns a message to print (possibly empty).
pub fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Radius { r, size, dist } => {
            if *size > MAX_SIZES {
                return Err(format!(
                    "size type {size} is beyond the limit of {MAX_SIZES}"
                ));
            }
            if *size > scene.sizes.len() {
                scene.sizes.resize(*size, 0.0);
                scene.size_dist.resize(*size, Default::default());
            }
            scene.sizes[size - 1] = *r;
            scene.size_dist[size - 1] = *dist;
            // Particles of a fixed size type change radius (and mass).
            let p = &mut scene.particles;
            for i in 0..p.len() {
                if *dist == SizeDist::Fixed && p.size[i] as usize == *size {
                    let rho = p.mass[i] / sphere_mass(1.0, p.radius[i]);
                    p.radius[i] = *r;
                    p.mass[i] = sphere_mass(rho, *r);
                }
            }
            scene.contacts.stale = true;
            Ok(String::new())
        }
        Command::Density { rho, material } => {
            material_mut(scene, *material)?.density = *rho;
            refresh_masses(scene, *material);
            Ok(String::new())
        }
        Command::Ymd { e, material } => {
            material_mut(scene, *material)?.young = *e;
            Ok(String::new())
        }
        Command::Pra { nu, material } => {
            material_mut(scene, *material)?.poisson = *nu;
            Ok(String::new())
        }
        Command::Friction { mu, material } => {
            material_mut(scene, *material)?.friction = *mu;
            Ok(String::new())
        }
        Command::Cohesion {
            gamma,
            material,
            base,
        } => {
            existing_material(scene, *material)?;
            let m = material_mut(scene, *material)?;
            m.gamma = *gamma;
            m.gamma_base = base.unwrap_or(*gamma);
            scene.contacts.stale = true;
            Ok(String::new())
        }
        Command::Agglomerate {
            nagg,
            centre,
            radius,
        } => {
            scene.regions[nagg - 1] = Some(Region {
                centre: *centre,
                radius: *radius,
            });
            Ok(String::new())
        }
        Command::Create {
            pos,
            vel,
            spin,
            size,
            material,
        } => {
            let r = radius_for(scene, *size)?;
            let rho = generation_density(scene, *material)?;
            check_capacity(scene, 1)?;
            let x = Vec3::from(*pos);
            if !inside(scene, None, &x, r) {
                return Err(format!(
                    "the particle at ({}, {}, {}) is outside the work-space",
                    pos[0], pos[1], pos[2]
                ));
            }
            // A run of CReate commands (a command file of an assembly) keeps one overlap
            // index of the scene's particles instead of scanning them all for each new one
            // (N CReate lines were O(N²): 16 s for 50,000). The index decides only "no
            // overlap", and only while it can (`OverlapIndex::decides`); an overlap is
            // confirmed and named by the plain scan, so the message is the scan's.
            let (mut idx, kinetic) = match scene.create_index.take() {
                Some(c) if c.n == scene.particles.len() => (c.index, c.kinetic),
                _ => (OverlapIndex::new(scene, r), None),
            };
            if (!idx.decides(scene) || idx.overlaps(scene, &x, r).is_some())
                && let Some(j) = first_overlap(scene, &x, r)
            {
                let n = scene.particles.len();
                // (Nothing changed: the index and the kinetic total stay valid.)
                scene.create_index = Some(CreateIndex {
                    n,
                    index: idx,
                    kinetic,
                });
                return Err(format!(
                    "the particle would overlap particle {}",
                    scene.particles.id[j]
                ));
            }
            ensure_material(scene, *material);
            let id = scene.next_id;
            scene.next_id += 1;
            scene.particles.push(
                id,
                x,
                Vec3::from(*vel),
                Vec3::from(*spin),
                r,
                sphere_mass(rho, r),
                *size,
                *material,
                0,
            );
            idx.insert(&x, r);
            let n = scene.particles.len();
            // (The session books the kinetic energy and keeps the new total.)
            scene.create_index = Some(CreateIndex {
                n,
                index: idx,
                kinetic: None,
            });
            scene.contacts.stale = true;
            Ok(String::new())
        }
        Command::Agenerate {
            size,
            material,
            nagg,
            origin,
            step,
        } => {
            let r = radius_for(scene, *size)?;
            let rho = generation_density(scene, *material)?;
            let region = if *nagg > 0 {
                scene.regions[nagg - 1]
            } else {
                None
            };
            // The sites that can lie in the region (its bounding box) or the work-space.
            let (lo, hi) = match region {
                Some(g) => (
                    std::array::from_fn(|k| (g.centre[k] - g.radius).max(0.0)),
                    std::array::from_fn(|k| (g.centre[k] + g.radius).min(scene.size[k])),
                ),
                None => ([0.0; 3], scene.size),
            };
            let (range, count) = lattice_ranges(*origin, *step, lo, hi);
            let most = max_lattice_sites(scene.nball);
            if count > most {
                return Err(format!(
                    "the lattice has {count:.3e} sites in the {} (at most {most} are examined): \
                     is the step (dx, dy, dz) far below the particle size?",
                    if region.is_some() {
                        "region's bounding box"
                    } else {
                        "work-space"
                    }
                ));
            }
            let free = scene.nball.saturating_sub(scene.particles.len());
            let mut idx = OverlapIndex::new(scene, r);
            let mut accepted = Vec::new();
            let mut skipped = 0;
            lattice_sites(scene, *origin, *step, range, |x| {
                if !inside(scene, region.as_ref(), &x, r) {
                    return true;
                }
                if idx.overlaps(scene, &x, r).is_some() {
                    skipped += 1;
                    return true;
                }
                idx.insert(&x, r);
                accepted.push(x);
                // One more than fits is enough to refuse (below).
                accepted.len() <= free
            });
            // All or nothing: the capacity is checked before anything is added.
            if accepted.len() > free {
                return Err(format!(
                    "too many particles: the lattice has more than the {free} free places \
                     ({} particles, nball = {} given to Start)",
                    scene.particles.len(),
                    scene.nball
                ));
            }
            ensure_material(scene, *material);
            let made = accepted.len();
            let first_new = scene.particles.len();
            for x in accepted {
                let id = scene.next_id;
                scene.next_id += 1;
                scene.particles.push(
                    id,
                    x,
                    Vec3::zeros(),
                    Vec3::zeros(),
                    r,
                    sphere_mass(rho, r),
                    *size,
                    *material,
                    *nagg,
                );
            }
            layer_order(scene, first_new, *nagg);
            scene.contacts.stale = true;
            Ok(format!(
                "AGEnerate: {made} particles generated ({skipped} sites skipped for overlap); {} in all",
                scene.particles.len()
            ))
        }
        Command::Rgenerate {
            n,
            size,
            material,
            nagg,
        } => {
            let r = radius_for(scene, *size)?;
            let rho = generation_density(scene, *material)?;
            check_capacity(scene, *n)?;
            let region = if *nagg > 0 {
                Some(scene.regions[nagg - 1].ok_or_else(|| {
                    format!("agglomerate region {nagg} is not defined: give AGGlomerate first")
                })?)
            } else {
                None
            };
            let (lo, hi) = match region {
                Some(g) => (
                    Vec3::from(g.centre).map(|c| c - g.radius),
                    Vec3::from(g.centre).map(|c| c + g.radius),
                ),
                None => (Vec3::zeros(), Vec3::from(scene.size)),
            };
            ensure_material(scene, *material);
            let limit = 1000 * n + 10_000;
            let (start, first_id) = (scene.particles.len(), scene.next_id);
            let r_big = scene.max_radius_of(*size).unwrap_or(r);
            let mut idx = OverlapIndex::new(scene, r_big);
            let mut made = 0;
            let mut tries = 0;
            let mut r = r;
            let mut need_radius = true;
            while made < *n && tries < limit {
                tries += 1;
                if need_radius {
                    r = scene.draw_radius(*size).unwrap_or(r);
                    need_radius = false;
                }
                let x = Vec3::new(
                    lo.x + (hi.x - lo.x) * scene.rng.uniform(),
                    lo.y + (hi.y - lo.y) * scene.rng.uniform(),
                    lo.z + (hi.z - lo.z) * scene.rng.uniform(),
                );
                let x = if scene.settings.two_d {
                    Vec3::new(x.x, x.y, 0.5 * scene.size[2])
                } else {
                    x
                };
                if !inside(scene, region.as_ref(), &x, r) || idx.overlaps(scene, &x, r).is_some() {
                    continue;
                }
                let id = scene.next_id;
                scene.next_id += 1;
                scene.particles.push(
                    id,
                    x,
                    Vec3::zeros(),
                    Vec3::zeros(),
                    r,
                    sphere_mass(rho, r),
                    *size,
                    *material,
                    *nagg,
                );
                idx.insert(&x, r);
                made += 1;
                need_radius = true;
            }
            // Number the new particles along a Morton curve (the random placement order
            // would scatter neighbours over memory: 2.6 × the cost per step at 10^6).
            let order = morton_order(&scene.particles.pos[start..], lo, hi);
            scene.particles.permute_tail(start, &order);
            for (k, id) in scene.particles.id[start..].iter_mut().enumerate() {
                *id = first_id + k as u32;
            }
            scene.contacts.stale = true;
            if made < *n {
                Ok(format!(
                    "RGEnerate: only {made} of {n} particles placed: the try limit ({limit} tries) was reached"
                ))
            } else {
                Ok(format!(
                    "RGEnerate: {made} particles placed in {tries} tries (limit {limit})"
                ))
            }
        }
        Command::Move { nagg, d } => {
            let dv = Vec3::from(*d);
            let p = &mut scene.particles;
            let mut moved = 0;
            for i in 0..p.len() {
                if p.agg[i] as usize == *nagg {
                    p.pos[i] += dv;
                    moved += 1;
                }
            }
            if moved == 0 {
                return Err(format!("agglomerate {nagg} has no particles"));
            }
            if let Some(r) = scene.regions[nagg - 1].as_mut() {
                for k in 0..3 {
                    r.centre[k] += d[k];
                }
            }
            // Bonds inside the agglomerate keep their geometry; pairs with others are re-made.
            scene.contacts.stale = true;
            Ok(format!("moved {moved} particles of agglomerate {nagg}"))
        }
        Command::RgenerateSeed { n } => {
            for _ in 0..*n {
                scene.rng.uniform();
            }
            Ok(String::new())
        }
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
            scene.contacts.stale = true;
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
            scene.contacts.stale = true;
            let opened = open_crossed_axes(scene);
            Ok(opened.trim_start_matches("; ").to_string())
        }
        Command::Damping(DampingSpec::Rayleigh {
            frac,
            freq,
            mass_off,
            stiff_off,
            ball_ball,
        }) => {
            let w = 2.0 * std::f64::consts::PI * freq;
            let r = Rayleigh {
                alpha: if *mass_off { 0.0 } else { frac * w },
                beta: if *stiff_off { 0.0 } else { frac / w },
            };
            if *ball_ball {
                scene.damping_pp = r;
            } else {
                scene.damping_pw = r;
            }
            Ok(String::new())
        }
        Command::Damping(DampingSpec::Restitution { e, material }) => {
            match material {
                Some(m) => {
                    existing_material(scene, *m)?;
                    scene.materials[m - 1].restitution = Some(*e);
                }
                None => {
                    for m in scene.materials.iter_mut() {
                        m.restitution = Some(*e);
                    }
                }
            }
            Ok(String::new())
        }
        Command::Fix { flags, target } => {
            let bits = flags
                .iter()
                .enumerate()
                .fold(0u8, |b, (k, &f)| if f { b | (1 << k) } else { b });
            match target {
                FixTarget::All => scene.particles.fixed.iter_mut().for_each(|f| *f = bits),
                FixTarget::Particle(id) => {
                    let i = index_of(scene, *id)?;
                    scene.particles.fixed[i] = bits;
                }
            }
            Ok(String::new())
        }
        Command::Fmm { r } => {
            scene.fmm *= r;
            Ok(String::new())
        }
        Command::Fro => {
            scene
                .particles
                .spin
                .iter_mut()
                .for_each(|w| *w = Vec3::zeros());
            Ok(String::new())
        }
        Command::Fraction { f } => {
            match f {
                Some(f) => {
                    scene.settings.fraction = Some(*f);
                    scene.settings.auto_step = None;
                }
                // (0: worked out at the next Cycle.)
                None => scene.settings.auto_step = Some(0.0),
            }
            Ok(String::new())
        }
        Command::Gravity { g } => {
            scene.gravity = *g;
            Ok(String::new())
        }
        Command::Cgravity { nagg, g } => {
            if scene.regions[nagg - 1].is_none() {
                return Err(format!("agglomerate region {nagg} is not defined"));
            }
            scene.cgravity[nagg - 1] = *g;
            Ok(String::new())
        }
        Command::Liquid {
            pvol,
            gsurf,
            theta_deg,
            eta,
        } => {
            if *pvol == 0.0 {
                scene.liquid = None;
                scene.contacts.for_each_state_mut(|_, s| s.bridge = None);
                for c in scene.contacts.wall_pairs.iter_mut() {
                    c.s.bridge = None;
                }
                return Ok("all liquid bridges removed".into());
            }
            let l = crate::sim::scene::Liquid {
                pvol: *pvol,
                gamma: *gsurf,
                theta: theta_deg.to_radians(),
                eta: *eta,
            };
            // Check the bridges of the smallest and largest sizes in use (equal and unequal
            // pairs; a unit sphere if there are no particles yet) against the chosen
            // model's validity range.
            let model = crate::sim::interact::bridge_model(scene.settings.bridge);
            let mut radii: Vec<f64> = scene.particles.radius.clone();
            radii.sort_by(f64::total_cmp);
            let (rmin, rmax) = (
                radii.first().copied().unwrap_or(1.0),
                radii.last().copied().unwrap_or(1.0),
            );
            let mut warn = Vec::new();
            for (r1, r2) in [(rmin, rmin), (rmin, rmax)] {
                let b = crate::physics::bridge::Bridge {
                    r1,
                    r2,
                    volume: crate::sim::liquid::bridge_volume(*pvol, r1, r2),
                    gamma: *gsurf,
                    theta: l.theta,
                };
                match crate::physics::bridge::validate(model, &b) {
                    Ok(w) => warn.extend(w),
                    Err(e) => return Err(format!("LIQuid: {e}")),
                }
            }
            let mut seen = std::collections::HashSet::new();
            warn.retain(|w| seen.insert(w.clone()));
            let warn: String = warn.iter().map(|w| format!("warning: {w}\n")).collect();
            scene.liquid = Some(l);
            // Existing bridges take the new parameters (rupture distance recomputed).
            crate::sim::liquid::reissue(scene);
            scene.contacts.stale = true;
            Ok(warn)
        }
        Command::Velocity { v1, v2, ivd } => {
            let p = &mut scene.particles;
            let n1 = p.agg.iter().filter(|&&a| a == 1).count();
            if n1 == 0 {
                return Err("agglomerate 1 has no particles".into());
            }
            if v2.is_some() && p.agg.iter().all(|&a| a != 2) {
                return Err("agglomerate 2 has no particles".into());
            }
            for i in 0..p.len() {
                match p.agg[i] {
                    1 => p.vel[i] = Vec3::from(*v1),
                    2 => {
                        if let Some(v) = v2 {
                            p.vel[i] = Vec3::from(*v)
                        }
                    }
                    _ => {}
                }
            }
            scene.impact = *ivd;
            Ok(String::new())
        }
        Command::Vmu { r } => {
            let p = &mut scene.particles;
            for i in 0..p.len() {
                for k in 0..3 {
                    if p.fixed[i] & (1 << k) != 0 {
                        p.vel[i][k] *= r;
                    }
                    if p.fixed[i] & (8 << k) != 0 {
                        p.spin[i][k] *= r;
                    }
                }
            }
            Ok(String::new())
        }
        Command::Window { bounds } => {
            if bounds[0] > bounds[1] || bounds[2] > bounds[3] || bounds[4] > bounds[5] {
                return Err("Window needs x1 <= x2, y1 <= y2, z1 <= z2".into());
            }
            scene.settings.window = Some(*bounds);
            Ok(String::new())
        }
        Command::Zero { always } => {
            scene
                .particles
                .vel
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            scene
                .particles
                .spin
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            scene.zero_always = *always;
            Ok(String::new())
        }
        Command::Reset => {
            scene
                .particles
                .rot
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            Ok(String::new())
        }
        Command::TwoD => {
            scene.settings.two_d = true;
            Ok(String::new())
        }
        Command::Set(s) => {
            if let Setting::Boundary { axes, periodic } = s {
                let mut want = scene.settings.periodic;
                for k in 0..3 {
                    if axes[k] {
                        want[k] = *periodic;
                    }
                }
                for (w, wall) in scene.walls.iter().enumerate() {
                    let crossed = walls::crossed_axes(&wall.geom, &want);
                    if crossed != [false; 3] {
                        return Err(format!(
                            "plane wall {} crosses the {} axis, which must stay open (a particle leaving through one side would re-enter behind the wall); turn the wall parallel to the axis first (AWAll n P ...)",
                            w + 1,
                            walls::axis_names(&crossed)
                        ));
                    }
                }
            }
            let st = &mut scene.settings;
            match s {
                Setting::Tol(v) => st.tol = *v,
                Setting::Xres(v) => st.xres = *v,
                Setting::Smin(v) => st.smin = *v,
                Setting::Bridge(b) => st.bridge = *b,
                Setting::Tangential(t) => st.tangential = *t,
                Setting::Liquid(m) => st.liquid_mode = *m,
                Setting::Boundary { axes, periodic } => {
                    for k in 0..3 {
                        if axes[k] {
                            st.periodic[k] = *periodic;
                        }
                    }
                }
                Setting::OutDir(d) => st.out_dir = d.clone(),
                Setting::View(v) => st.view = *v,
                Setting::Snapshot(n) => st.snapshot_every = *n,
                Setting::History(n) => st.history_every = *n,
                Setting::GenOverlap(f) => st.gen_overlap = *f,
                Setting::Fragment(e) => st.fragment_eps = *e,
                Setting::Goldman(on) => st.goldman = *on,
                Setting::Tunnel(t) => st.tunnel = *t,
            }
            scene.contacts.stale = true;
            Ok(String::new())
        }
        other => Err(format!(
            "internal: {} is not a scene command",
            crate::lang::parse::command_name(other)
        )),
    }
}

/// Orders the lattice particles an AGEnerate just placed (from `first_new` on), together
/// with those of the command before if it was an AGEnerate into the same agglomerate `nagg`
/// (`Session::execute` forgets the run at any other command), layer by layer (z, then y,
/// then x), and gives them their ids in that order (the smallest first); then remembers
/// them for the next AGEnerate. A BCC lattice is two AGEnerate commands: without this its
/// two simple cubic halves would each be a contiguous run of the particle list, every
/// nearest-neighbour pair would join the first half to the second, and with several threads
/// nearly every particle would be shared between the tasks (`contacts::Incidence`): the Lian
/// 1994 agglomerates ran 1.2–1.5 × slower on two threads. Each lattice alone is already in
/// this order.
fn layer_order(scene: &mut Scene, first_new: usize, nagg: usize) {
    let p = &scene.particles;
    let start = match scene.lattice_run {
        Some(run)
            if run.nagg == nagg
                && run.start < first_new
                && p.agg[run.start..first_new]
                    .iter()
                    .all(|&a| a as usize == nagg) =>
        {
            run.start
        }
        _ => first_new,
    };
    if start < first_new {
        let pos = &p.pos[start..];
        let mut order: Vec<usize> = (0..pos.len()).collect();
        order.sort_by(|&a, &b| {
            let (x, y) = (&pos[a], &pos[b]);
            (x.z.total_cmp(&y.z))
                .then(x.y.total_cmp(&y.y))
                .then(x.x.total_cmp(&y.x))
        });
        let mut ids = p.id[start..].to_vec();
        ids.sort_unstable();
        scene.particles.permute_tail(start, &order);
        scene.particles.id[start..].copy_from_slice(&ids);
    }
    scene.lattice_run = Some(LatticeRun { start, nagg });
}

fn index_of(scene: &Scene, id: usize) -> Result<usize, String> {
    scene
        .particles
        .id
        .iter()
        .position(|&x| x as usize == id)
        .ok_or_else(|| format!("particle {id} does not exist"))
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
