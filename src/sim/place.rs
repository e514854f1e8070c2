//! Particle placement: the API behind CReate, AGEnerate, RGEnerate, AGGlomerate and MOve.
//! Each function checks everything before it changes anything (a refused placement leaves
//! the scene as it was) and returns the message to print.
//!
//! Generation needs a particle's radius only, as in TRUBAL (geometry first, then the
//! materials): a material not defined yet gives a mass of 0, `Density` re-computes the
//! masses, and the first `Cycle` names what is still missing.

use super::generate::{
    Advance, CreateIndex, OverlapIndex, RateWatch, WATCH_EVERY, Watch, first_overlap, inside,
    lattice_ranges, lattice_sites, max_lattice_sites, morton_order, sphere_mass,
};
use super::model::WallGeom;
use super::scene::{LatticeRun, MAX_MATERIALS, Material, Region, Scene, Vec3, Wall};
use super::walls::WallShape;

/// `AGGlomerate`: the spherical region of agglomerate `nagg` (1 or 2).
pub fn define_region(
    scene: &mut Scene,
    nagg: usize,
    centre: [f64; 3],
    radius: f64,
) -> Result<String, String> {
    scene.regions[nagg - 1] = Some(Region { centre, radius });
    Ok(String::new())
}

/// `CReate`: one particle, refused if it lies outside the work-space or overlaps another.
pub fn create(
    scene: &mut Scene,
    pos: [f64; 3],
    vel: [f64; 3],
    spin: [f64; 3],
    size: usize,
    material: usize,
) -> Result<String, String> {
    let r = radius_for(scene, size)?;
    let rho = generation_density(scene, material)?;
    check_capacity(scene, 1)?;
    let x = Vec3::from(pos);
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
    let (mut idx, kinetic) = match scene.derived.create_index.take() {
        Some(c) if c.n == scene.particles.len() => (c.index, c.kinetic),
        _ => (OverlapIndex::new(scene, r), None),
    };
    if (!idx.decides(scene) || idx.overlaps(scene, &x, r).is_some())
        && let Some(j) = first_overlap(scene, &x, r)
    {
        let n = scene.particles.len();
        // (Nothing changed: the index and the kinetic total stay valid.)
        scene.derived.create_index = Some(CreateIndex {
            n,
            index: idx,
            kinetic,
        });
        return Err(format!(
            "the particle would overlap particle {}",
            scene.particles.id[j]
        ));
    }
    ensure_material(scene, material);
    add(
        scene,
        (x, Vec3::from(vel), Vec3::from(spin)),
        r,
        rho,
        (size, material, 0),
    );
    idx.insert(&x, r);
    let n = scene.particles.len();
    // (The session books the kinetic energy and keeps the new total.)
    scene.derived.create_index = Some(CreateIndex {
        n,
        index: idx,
        kinetic: None,
    });
    scene.contacts.mark_stale();
    Ok(String::new())
}

/// `AGEnerate`: a regular (orthorhombic) lattice, in agglomerate `nagg`'s region if it has
/// one; all or nothing.
pub fn lattice(
    scene: &mut Scene,
    size: usize,
    material: usize,
    nagg: usize,
    origin: [f64; 3],
    step: [f64; 3],
    watch: Watch,
) -> Result<String, String> {
    let r = radius_for(scene, size)?;
    let rho = generation_density(scene, material)?;
    let region = if nagg > 0 {
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
    let (range, count) = lattice_ranges(origin, step, lo, hi);
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
    let (mut seen, mut stopped) = (0u64, false);
    let total = u64::try_from(count).unwrap_or(u64::MAX);
    lattice_sites(scene, origin, step, range, |x| {
        seen += 1;
        if seen.is_multiple_of(WATCH_EVERY) {
            let a = Advance {
                command: "AGEnerate",
                what: "sites examined",
                done: seen,
                total,
                tries: 0,
                rate: 0.0,
            };
            if !watch(&a) {
                stopped = true;
                return false;
            }
        }
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
    if stopped {
        return Err(format!(
            "AGEnerate stopped after {seen} of {total} sites: nothing was placed (the scene is as before the command)"
        ));
    }
    // All or nothing: the capacity is checked before anything is added.
    if accepted.len() > free {
        return Err(format!(
            "too many particles: the lattice has more than the {free} free places \
                 ({} particles, nball = {} given to Start)",
            scene.particles.len(),
            scene.nball
        ));
    }
    ensure_material(scene, material);
    let made = accepted.len();
    let first_new = scene.particles.len();
    for x in accepted {
        add(
            scene,
            (x, Vec3::zeros(), Vec3::zeros()),
            r,
            rho,
            (size, material, nagg),
        );
    }
    layer_order(scene, first_new, nagg);
    scene.contacts.mark_stale();
    Ok(format!(
        "AGEnerate: {made} particles generated ({skipped} sites skipped for overlap); {} in all",
        scene.particles.len()
    ))
}

/// `RGEnerate`: `n` particles at random places without overlap, numbered along a Morton
/// curve; with `walls`, only where the whole particle lies on the particles' side of every
/// wall (inside a die), the draws confined to the walls' bounding box ([`walls_box`]).
///
/// The places are found first, then the particles added. When the target cannot be reached
/// (the rate of placement shows it, [`RateWatch`], or the try limit of 1000 n + 10,000 tries
/// is spent) it gives up with the particles that found room, as TRUBAL did at its try limit,
/// and says why. When `watch` says stop (Ctrl-C) nothing is placed and the random numbers
/// drawn are given back (the scene is as before the command).
pub fn random(
    scene: &mut Scene,
    (n, size, material, nagg): (usize, usize, usize, usize),
    walls: bool,
    watch: Watch,
) -> Result<String, String> {
    let r = radius_for(scene, size)?;
    let rho = generation_density(scene, material)?;
    check_capacity(scene, n)?;
    let region = if nagg > 0 {
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
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    let (lo, hi) = if walls {
        walls_room(&scene.walls, lo, hi, region.is_some())?
    } else {
        (lo, hi)
    };
    let clear_of_walls = |x: &Vec3, r: f64| !walls || shapes.iter().all(|s| s.gap(x, r).0 >= 0.0);
    let limit = (n as u64).saturating_mul(1000).saturating_add(10_000);
    let rng_before = scene.rng.clone();
    let r_big = scene.max_radius_of(size).unwrap_or(r);
    let mut idx = OverlapIndex::new(scene, r_big);
    let mut placed: Vec<(Vec3, f64)> = Vec::new();
    let mut tries: u64 = 0;
    let mut rates = RateWatch::new(scene.settings.two_d);
    let mut recent = (0u64, 0usize);
    let mut r = r;
    let mut need_radius = true;
    let mut hopeless = None;
    while placed.len() < n && tries < limit {
        if tries.is_multiple_of(WATCH_EVERY) && tries > 0 {
            let rate = (placed.len() - recent.1) as f64 / (tries - recent.0) as f64;
            recent = (tries, placed.len());
            let a = Advance {
                command: "RGEnerate",
                what: "particles placed",
                done: placed.len() as u64,
                total: n as u64,
                tries,
                rate,
            };
            if !watch(&a) {
                scene.rng = rng_before;
                return Err(format!(
                    "RGEnerate stopped after {tries} tries with {} of {n} particles placed: nothing was placed (the scene is as before the command)",
                    placed.len()
                ));
            }
        }
        tries += 1;
        if need_radius {
            r = scene.draw_radius(size).unwrap_or(r);
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
        if inside(scene, region.as_ref(), &x, r)
            && clear_of_walls(&x, r)
            && idx.overlaps(scene, &x, r).is_none()
        {
            idx.insert(&x, r);
            placed.push((x, r));
            need_radius = true;
        }
        hopeless = rates.hopeless(tries, placed.len() as u64, n as u64, limit);
        if hopeless.is_some() {
            break;
        }
    }
    let made = placed.len();
    let start = commit_random(scene, &placed, (lo, hi), rho, (size, material, nagg));
    let mut text = if made < n {
        let why = match hopeless {
            Some(h) => format!(
                "the rate of placement ({} of the last {} tries placed one, and falling) showed that at most about {} could be placed within the try limit ({limit} tries)",
                h.recent.0, h.recent.1, h.most
            ),
            None => format!("the try limit ({limit} tries) was reached"),
        };
        format!("RGEnerate: only {made} of {n} particles placed in {tries} tries: {why}")
    } else {
        format!("RGEnerate: {made} particles placed in {tries} tries (limit {limit})")
    };
    // Without WAlls, particles placed behind or across a wall (outside a die) are named.
    if !walls && !shapes.is_empty() {
        text.push_str(&against_walls(&scene.particles, start, &shapes));
    }
    Ok(text)
}

/// Adds the particles `RGEnerate` found room for, numbered along a Morton curve through the
/// box `lo`–`hi` (the random placement order would scatter neighbours over memory: 2.6 × the
/// cost per step at 10^6); returns the index of the first.
fn commit_random(
    scene: &mut Scene,
    placed: &[(Vec3, f64)],
    (lo, hi): (Vec3, Vec3),
    rho: f64,
    (size, material, nagg): (usize, usize, usize),
) -> usize {
    ensure_material(scene, material);
    let pos: Vec<Vec3> = placed.iter().map(|p| p.0).collect();
    let start = scene.particles.len();
    for k in morton_order(&pos, lo, hi) {
        let (x, r) = placed[k];
        add(
            scene,
            (x, Vec3::zeros(), Vec3::zeros()),
            r,
            rho,
            (size, material, nagg),
        );
    }
    scene.contacts.mark_stale();
    start
}

/// `RGEnerate ... WAlls`: the box `lo`–`hi` (the region's or the work-space's) narrowed to
/// what the walls leave free ([`walls_box`]); an error if they leave no room.
fn walls_room(
    walls: &[crate::sim::scene::Wall],
    lo: Vec3,
    hi: Vec3,
    in_region: bool,
) -> Result<(Vec3, Vec3), String> {
    let (lo, hi) = walls_box(walls, lo, hi);
    if (0..3).any(|k| !(lo[k] < hi[k])) {
        return Err(format!(
            "RGEnerate WAlls: the walls leave no room in the {}: the box between them is ({:e}, {:e}, {:e}) to ({:e}, {:e}, {:e})",
            if in_region {
                "region's bounding box"
            } else {
                "work-space"
            },
            lo.x,
            lo.y,
            lo.z,
            hi.x,
            hi.y,
            hi.z
        ));
    }
    Ok((lo, hi))
}

/// The warning for particles `start..` that lie behind a wall (centre behind its surface) or
/// across one, or "".
fn against_walls(p: &crate::sim::scene::Particles, start: usize, shapes: &[WallShape]) -> String {
    let mut behind = 0;
    let mut across = 0;
    for i in start..p.len() {
        let worst = shapes
            .iter()
            .map(|s| s.gap(&p.pos[i], p.radius[i]).0 / p.radius[i])
            .fold(f64::INFINITY, f64::min);
        if worst < -1.0 {
            behind += 1;
        } else if worst < 0.0 {
            across += 1;
        }
    }
    if behind + across == 0 {
        return String::new();
    }
    format!(
        "\nwarning: RGEnerate placed {behind} particle(s) with the centre behind a wall (outside a die or container, inside an indenter) and {across} across a wall's surface; RGEnerate ... WAlls places them only on the particles' side of every wall"
    )
}

/// The box `lo`–`hi` narrowed to what the walls leave free: a spherical container's
/// bounding box, the cross-section of a cylinder whose axis is parallel to a coordinate
/// axis, the half-space of a plane whose normal is along one (other walls leave it as it is:
/// the draws outside them are rejected one by one).
pub fn walls_box(walls: &[Wall], mut lo: Vec3, mut hi: Vec3) -> (Vec3, Vec3) {
    for w in walls {
        match w.geom {
            WallGeom::Sphere { centre, radius } => {
                for k in 0..3 {
                    lo[k] = lo[k].max(centre[k] - radius);
                    hi[k] = hi[k].min(centre[k] + radius);
                }
            }
            WallGeom::Cylinder {
                point,
                axis,
                radius,
            } => {
                let along: Vec<usize> = (0..3).filter(|&k| axis[k] != 0.0).collect();
                if along.len() == 1 {
                    for k in (0..3).filter(|&k| k != along[0]) {
                        lo[k] = lo[k].max(point[k] - radius);
                        hi[k] = hi[k].min(point[k] + radius);
                    }
                }
            }
            WallGeom::Plane { normal, d } => {
                let along: Vec<usize> = (0..3).filter(|&k| normal[k] != 0.0).collect();
                if let [k] = along[..] {
                    let at = d / normal[k];
                    if normal[k] > 0.0 {
                        lo[k] = lo[k].max(at);
                    } else {
                        hi[k] = hi[k].min(at);
                    }
                }
            }
            WallGeom::Obstacle { .. } => {}
        }
    }
    (lo, hi)
}

/// `MOve`: displaces agglomerate `nagg` (its particles and its region) by `d`.
pub fn move_agglomerate(scene: &mut Scene, nagg: usize, d: [f64; 3]) -> Result<String, String> {
    let dv = Vec3::from(d);
    let p = &mut scene.particles;
    let mut moved = 0;
    for i in 0..p.len() {
        if p.agg[i] as usize == nagg {
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
    scene.contacts.mark_stale();
    Ok(format!("moved {moved} particles of agglomerate {nagg}"))
}

/// `DELete x1 x2 y1 y2 z1 z2`: deletes the particles whose centres lie in the box (bounds
/// included), with their contacts; the stored energy of those leaves the ledger
/// (`cycle::delete_marked`), their kinetic energy with the session's booking of the command.
pub fn delete_in_box(scene: &mut Scene, b: [f64; 6]) -> Result<String, String> {
    let gone: Vec<bool> = scene
        .particles
        .pos
        .iter()
        .map(|x| (0..3).all(|k| x[k] >= b[2 * k] && x[k] <= b[2 * k + 1]))
        .collect();
    let n = crate::sim::cycle::delete_marked(scene, &gone);
    if n == 0 {
        return Err(format!(
            "no particle has its centre in the box x {} to {}, y {} to {}, z {} to {}: nothing deleted",
            b[0], b[1], b[2], b[3], b[4], b[5]
        ));
    }
    Ok(format!(
        "deleted {n} particles; {} remain",
        scene.particles.len()
    ))
}

/// `DELete range`: deletes the particles of index `members` (ascending, from
/// [`Scene::members`]); `what` names the range for the message.
pub fn delete_members(scene: &mut Scene, members: &[usize], what: &str) -> Result<String, String> {
    let mut gone = vec![false; scene.particles.len()];
    for &i in members {
        if let Some(g) = gone.get_mut(i) {
            *g = true;
        }
    }
    let n = crate::sim::cycle::delete_marked(scene, &gone);
    if n == 0 {
        return Err(format!(
            "no particle is in the range {what}: nothing deleted"
        ));
    }
    Ok(format!(
        "deleted {n} particles; {} remain",
        scene.particles.len()
    ))
}

/// `RGEnerate Seed n`: draws and discards `n` random numbers (all or none: `watch` saying
/// stop gives them back).
pub fn discard_random(scene: &mut Scene, n: u64, watch: Watch) -> Result<String, String> {
    let before = scene.rng.clone();
    // (Checked every 2^20 numbers: a few ms.)
    let every = WATCH_EVERY * 256;
    for k in 0..n {
        if k.is_multiple_of(every) && k > 0 {
            let a = Advance {
                command: "RGEnerate Seed",
                what: "numbers drawn",
                done: k,
                total: n,
                tries: 0,
                rate: 0.0,
            };
            if !watch(&a) {
                scene.rng = before;
                return Err(format!(
                    "RGEnerate Seed stopped after {k} of {n} numbers: the generator is as before the command"
                ));
            }
        }
        scene.rng.uniform();
    }
    Ok(String::new())
}

/// Appends one particle with the next id: position, velocity and spin, radius, density (its
/// mass is that of the sphere), size type, material type and agglomerate.
fn add(
    scene: &mut Scene,
    (x, vel, spin): (Vec3, Vec3, Vec3),
    r: f64,
    rho: f64,
    (size, material, nagg): (usize, usize, usize),
) {
    let id = scene.next_id;
    scene.next_id += 1;
    scene.particles.push(
        id,
        x,
        vel,
        spin,
        r,
        sphere_mass(rho, r),
        size,
        material,
        nagg,
    );
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
    let start = match scene.derived.lattice_run {
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
    scene.derived.lattice_run = Some(LatticeRun { start, nagg });
}
