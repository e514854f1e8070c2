//! `Cycle n`: the time step. Forces from the current positions (contacts, bridges, walls),
//! then the leap-frog central-difference update with global mass-proportional damping,
//! Lian (5.9)–(5.14):
//!
//! v_new = ((m/Δt − β/2) v_old + F + m g) / (m/Δt + β/2), β = α_R m;  x += v_new Δt,
//!
//! and the same for rotations with I = 2/5 m R². The energy ledger is updated exactly for the
//! scheme: the damping loss is β |v̄|² Δt and the work of gravity m g·v̄ Δt with
//! v̄ = (v_old + v_new)/2, so that ½ m v_new² − ½ m v_old² = (F + m g − β v̄)·v̄ Δt.

use rayon::prelude::*;

use super::contacts::{
    self, BLOCK, Balance, ContactState, HotPair, Incidence, NO_STATE, Pair, PairForce, PairRange,
    WALL_BLOCK, WallForce, WallOut, WallPair, WallPiece,
};
use super::interact::{Acc, Kin, Laws, interact};
use super::lanes;
use super::leapfrog;
use super::params::{self, Model};
use super::scene::{Scene, TunnelAction, Vec3, Wall};
use super::search;
use super::walls::{self, WallShape, surface_velocity, wall_gap, wall_r_star};
use crate::sim::model::{TangentialChoice, WallGeom};

mod fused;
mod reach;
use fused::View;

/// Fixed chunk size of the parallel loops: partial sums are formed per chunk and added in
/// chunk order, so results are bitwise independent of the number of threads.
pub const CHUNK: usize = 1024;

/// Why a `Cycle` stopped early.
#[derive(Debug, Clone, PartialEq)]
pub struct Blowup {
    /// Cycle number (1-based count of the scene) of the step that failed.
    pub cycle: u64,
    pub message: String,
}

/// Search distances in use: TOL (gap below which pairs are candidates) and XRES.
pub fn search_distances(scene: &Scene, model: &Model) -> (f64, f64) {
    let p = &scene.particles;
    let rmean = if p.is_empty() {
        0.0
    } else {
        p.radius.iter().sum::<f64>() / p.len() as f64
    };
    let mut need: f64 = 0.0;
    // Live bonds must stay in the candidate list: JKR down to α_s, bridges up to S_c.
    if model.adhesion {
        for i in 0..model.nmat {
            for j in 0..model.nmat {
                let pc = &model.table[i * model.nmat + j];
                let g = pc.gamma.max(pc.gamma_base);
                if g > 0.0 {
                    let rmax = scene.max_radius();
                    let jk = crate::physics::jkr::Jkr {
                        e_star: pc.e_star,
                        r_star: rmax,
                        gamma: g,
                    };
                    need = need.max(-jk.alpha_s());
                }
            }
        }
    }
    if let Some(l) = &scene.liquid
        && l.pvol > 0.0
    {
        for c in scene.contacts.iter() {
            if let Some(b) = &c.s.bridge {
                need = need.max(b.s_c);
            }
        }
        // Bridges not formed yet: the largest possible volume (two largest spheres).
        let rmax = scene.max_radius();
        let v = l.pvol / 100.0 * 4.0 / 3.0 * std::f64::consts::PI * rmax.powi(3);
        let b = crate::physics::bridge::Bridge {
            r1: rmax,
            r2: rmax,
            volume: v,
            gamma: l.gamma,
            theta: l.theta,
        };
        need = need.max(crate::physics::bridge::rupture_distance(&b));
    }
    let auto = (0.35 * rmean).max(1.5 * need);
    let tol = scene.settings.tol.unwrap_or(auto).max(1.5 * need);
    let xres = scene
        .settings
        .xres
        .map(|x| x.min(xres_of(tol)))
        .unwrap_or(xres_of(tol));
    (tol, xres)
}

/// The candidate list of a fast scene is made with up to this many times the automatic
/// TOL ([`rebuild_tol`]).
const TOL_GROWTH: f64 = 2.0;

/// The number of steps the candidate list of a fast scene should last at least, at the
/// speed of its fastest particle ([`rebuild_tol`]).
const LIST_STEPS: f64 = 50.0;

/// XRES for a TOL: just below TOL/(2√3) (Lian 1994 §5: no two particles can then have
/// closed a gap of TOL since the last rebuild without some displacement component
/// exceeding XRES).
pub fn xres_of(tol: f64) -> f64 {
    tol / (2.0 * 3f64.sqrt()) * 0.999
}

/// Whether TOL and XRES are both automatic, so that the rebuilds may use a larger TOL
/// ([`rebuild_tol`]).
fn auto_search(scene: &Scene) -> bool {
    scene.settings.tol.is_none() && scene.settings.xres.is_none()
}

/// The TOL of a rebuild when TOL and XRES are automatic: large enough that the list lasts
/// [`LIST_STEPS`] steps at the fastest particle's largest velocity component v (XRES ≥
/// LIST_STEPS · v Δt), between the automatic `base` and [`TOL_GROWTH`] × `base`. A falling
/// or flowing scene then rebuilds its list up to half as often, for more candidate pairs
/// to test in each step; a settled one keeps `base`. The candidate list may be any list
/// that holds every pair with a gap below its TOL: the forces and positions are the same
/// bits for any TOL. The TOL used is kept with the list (`ContactStore::tol`, saved in
/// checkpoints) and the re-mapping test uses its XRES, so a restarted run rebuilds at the
/// same steps with the same TOL. Measured (doc/performance.md, sixth session of
/// 2026-12-03), S1 one thread side by side: the 50k bed (falling through its 5000 steps)
/// 0.92 × the time with LIST_STEPS 50 (0.97 × with 20; 0.86 × with twice the TOL
/// throughout), the 10k bed (settled after ~2000 steps) 1.03 × (0.98 × with 20).
fn rebuild_tol(scene: &Scene, base: f64, dt: f64) -> f64 {
    if !auto_search(scene) {
        return base;
    }
    let vmax = scene
        .particles
        .vel
        .iter()
        .fold(0.0f64, |m, v| m.max(v.amax()));
    let want = 2.0 * 3f64.sqrt() * LIST_STEPS * vmax * dt / 0.999;
    // (NaN or a step of zero: the base.)
    if want > base {
        want.min(TOL_GROWTH * base)
    } else {
        base
    }
}

/// XRES of the re-mapping test: that of the TOL the list was made with when the search
/// distances are automatic (see [`rebuild_tol`]), else the user's (`xres`).
fn xres_in_use(scene: &Scene, xres: f64) -> f64 {
    if auto_search(scene) {
        xres_of(scene.contacts.tol)
    } else {
        xres
    }
}

/// Whether the list made with TOL `made` serves a scene whose automatic TOL is `base`.
fn tol_serves(scene: &Scene, made: f64, base: f64) -> bool {
    made == base || (auto_search(scene) && made >= base && made <= TOL_GROWTH * base)
}

/// Rebuilds the candidate lists.
pub fn rebuild(scene: &mut Scene, tol: f64) -> search::GridInfo {
    let parts = rayon::current_num_threads();
    // The hot list is derived from the list being replaced (`merge` makes it anew): freed
    // before the search, whose key lists made the rebuild's peak of memory with it (valgrind
    // massif, S1 50k, two threads: peak RSS 68.3-68.8 -> 66.9-67.2 MB).
    scene.contacts.hot = Vec::new();
    let (pairs, walls, info) = search::candidates_in_parts(scene, tol, parts);
    scene.contacts.merge(pairs, walls);
    scene.contacts.tol = tol;
    scene
        .particles
        .disp
        .par_chunks_mut(CHUNK)
        .for_each(|d| d.fill(Vec3::zeros()));
    for w in scene.walls.iter_mut() {
        w.travel = 0.0;
    }
    scene.contacts.max_disp = Some(0.0);
    info
}

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
    Ok(model)
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
        && let Some(w) = super::contact_time::warning(scene, &model, model.fraction)
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
                    .map_or("R*/100".to_string(), |s| format!("{s:.3e} m")),
                scene.damping_pp.beta.max(scene.damping_pw.beta)
            ));
        }
    }
    if let Ok(model) = params::build(scene) {
        for (w, wall) in scene.walls.iter().enumerate() {
            if let Some(s) = wall.servo {
                // Loop gain of the servo per step: g × (stiffness of the wall contacts) × Δt,
                // with a contact stiffness 2E*a at an overlap of 1e-3 R for every particle near
                // the wall; above 1 the wall overshoots every step.
                let m = &scene.materials[wall.material - 1];
                let r = scene.max_radius();
                let k =
                    2.0 * m.young / (2.0 * (1.0 - m.poisson * m.poisson)) * (r * 1e-3 * r).sqrt();
                let n = scene
                    .contacts
                    .wall_pairs
                    .iter()
                    .filter(|c| c.wall as usize == w)
                    .count()
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
                    let c = pc.dash * (mi * mi * ri * 1e-3 * ri).sqrt().sqrt()
                        + scene.damping_pw.beta * k;
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

/// Runs `n` cycles. On a blow-up the scene is restored to the last good snapshot and the
/// error says where it happened.
pub fn run(scene: &mut Scene, n: u64) -> Result<Model, Blowup> {
    run_watched(scene, n, &mut |_, _| false).map(|(model, _)| model)
}

/// [`run`] with a watcher, called before each step with the scene and the number of steps
/// done so far. When it answers `true` (an interrupt was asked for), the step about to run
/// is the Cycle's last: the scene is left exactly as a `Cycle` of `done + 1` would have left
/// it (the same bits, continuable). Returns the model and the number of steps run. The
/// watcher is where the session draws its progress line; the core itself does no I/O.
pub fn run_watched(
    scene: &mut Scene,
    n: u64,
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
) -> Result<(Model, u64), Blowup> {
    // With several threads the pool's other workers poll for the length of the Cycle
    // instead of falling asleep between the step's parallel regions (`awake`).
    let r = super::awake::while_running(|| run_steps(scene, n, watch));
    // (Derived per step; not kept between commands.)
    scene.reach_ext = Vec::new();
    scene.contacts.margins = [0.0; 2];
    r
}

/// The body of [`run`].
fn run_steps(
    scene: &mut Scene,
    n: u64,
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
) -> Result<(Model, u64), Blowup> {
    let mut model = check(scene).map_err(|m| Blowup {
        cycle: scene.cycle,
        message: m,
    })?;
    if scene.particles.is_empty() {
        // Step by step, as with particles, so that Cycle N; Cycle M == Cycle N+M exactly.
        for _ in 0..n {
            scene.cycle += 1;
            scene.time += model.dt;
        }
        return Ok((model, n));
    }
    // A plane wall across a periodic axis makes the axis open (doc/limits.md; a checkpoint
    // of an earlier version, or walls turned since, may hold one).
    let opened = walls::open_crossed(&scene.walls, &mut scene.settings.periodic);
    if opened != [false; 3] {
        scene.notes.push(format!(
            "the {} axis is now open: a plane wall crosses it, and a particle leaving through one side would re-enter behind the wall",
            walls::axis_names(&opened)
        ));
    }
    let (tol, xres) = search_distances(scene, &model);
    // Commands may have changed contact states between Cycles: derive the pair liveness anew.
    scene.contacts.clear_derived();
    scene.maybe_outside = true;
    let commanded = scene.contacts.stale;
    if scene.contacts.stale {
        prime(scene, &model, tol);
    } else if !tol_serves(scene, scene.contacts.tol, tol) {
        // Only the search distance changed: re-map, keep the states of the last step.
        scene.contacts.remap = true;
    }
    // FRAction AUTO: the step of the last rebuild goes on (the same bits after SAve and
    // RESTart, or across Cycle commands) unless a command changed the scene.
    if let Some(kept) = scene.settings.auto_step {
        let dt = if kept > 0.0 && !commanded {
            kept.min(model.dt_base)
        } else {
            super::contact_time::auto_step(scene, &model, model.dt_base)
        };
        scene.settings.auto_step = Some(dt);
        model.dt = dt;
    }
    // (A step too long for the fastest contact at the start is the session's pre-Cycle
    // warning, `warnings`.)
    let mut warned_step = scene.settings.auto_step.is_some()
        || super::contact_time::warning(scene, &model, model.fraction).is_some();
    let mut snapshot = snapshot_of(scene);
    let every = scene.settings.snapshot_every.max(1);
    // Energy runaway: no energy may appear that the ledger did not put in. The books'
    // residual at the start (what commands left unbooked) is the reference; the energy
    // created since is checked against the energy the scene had or was given (`Audit`).
    let audit = Audit::of(scene);
    // A snapshot is taken before step `s` (of this Cycle) when this holds.
    let snapshot_before = |s: u64| s > 0 && s.is_multiple_of(every);
    let mut ran = n;
    for step in 0..n {
        // An interrupt makes this step the last, as if the Cycle had been this long.
        let last = watch(scene, step);
        if snapshot_before(step) {
            if let Some(e) = audit.check(scene) {
                return Err(stop(scene, snapshot, e));
            }
            // The old snapshot goes before the new one is made (never three copies at once).
            snapshot.particles = Default::default();
            snapshot.contacts = Default::default();
            snapshot = snapshot_of(scene);
        }
        let (lost_before, commands_before) = (scene.lost, scene.ledger.commands);
        let rebuilds_before = scene.contacts.rebuilds;
        let allowed = 1e3 * audit.scale(scene);
        // The forces of the last step are kept for what reads them after the Cycle (PRint,
        // plots, checkpoints), and those of the step before a snapshot for the snapshot.
        let keep = last || step + 1 == n || snapshot_before(step + 1);
        let mut result = one_step(scene, &mut model, (tol, xres), keep);
        if result.is_ok() && scene.contacts.rebuilds != rebuilds_before && !warned_step {
            // At each rebuild: a step too long for the fastest contact (once a Cycle).
            if scene.settings.auto_step.is_none()
                && let Some(w) = super::contact_time::warning(scene, &model, model.fraction)
            {
                scene.notes.push(w);
                warned_step = true;
            }
        }
        // A particle that leaves through an open side carrying far more energy than was
        // ever put in is a blow-up, not an exit.
        let carried = commands_before - scene.ledger.commands;
        if result.is_ok() && scene.lost > lost_before && carried > allowed {
            result = Err(Blowup {
                cycle: scene.cycle,
                message: format!(
                    "energy runaway at cycle {}: {} particle(s) left the work-space carrying {carried:.3e} J, \
                     more than 1000 times the energy put in ({:.3e} J). Hint: reduce FRAction, check \
                     contact damping (istiff), servo gains and deep overlaps",
                    scene.cycle,
                    scene.lost - lost_before,
                    allowed / 1e3
                ),
            });
        }
        if let Err(e) = result {
            return Err(stop(scene, snapshot, e));
        }
        if scene.settings.history_every > 0
            && scene.cycle.is_multiple_of(scene.settings.history_every)
        {
            super::record_history(scene);
        }
        if last {
            ran = step + 1;
            break;
        }
    }
    // The end of the Cycle is audited too (a Cycle shorter than the snapshot interval).
    if let Some(e) = audit.check(scene) {
        return Err(stop(scene, snapshot, e));
    }
    Ok((model, ran))
}

/// A `Cycle` that failed: the scene goes back to the last good snapshot, and the message
/// says so.
fn stop(scene: &mut Scene, snapshot: Scene, mut e: Blowup) -> Blowup {
    e.message.push_str(&format!(
        "\nthe state of cycle {} (the last good snapshot) is kept: SAve it or change the scene",
        snapshot.cycle
    ));
    restore(scene, snapshot);
    e
}

/// The energy audit of a `Cycle`: stored energy plus what was dissipated may not exceed the
/// energy put in (the ledger's input) by more than the energy the scene had or was given —
/// however slowly it grows (the residual at the start, what commands left unbooked, is
/// subtracted). The books of a healthy run close to ~1e-3 of the input (doc/timestep.md);
/// energy created on the scale of all the energy there is, is a blow-up.
struct Audit {
    /// Residual of the books at the start.
    residual: f64,
    /// Stored energy at the start.
    stored: f64,
    /// The least energy scale: every particle pressed against its like to an overlap of
    /// 1 % of its radius (Hertz, 8/15 E* √R* α^{5/2}), so that a scene at rest is not
    /// stopped for the round-off of its books.
    floor: f64,
}

impl Audit {
    fn of(scene: &Scene) -> Audit {
        let p = &scene.particles;
        let floor = (0..p.len())
            .map(|i| {
                let m = &scene.materials[p.material[i] as usize - 1];
                let e_star = m.young / (2.0 * (1.0 - m.poisson * m.poisson));
                let r_star = 0.5 * p.radius[i];
                8.0 / 15.0 * e_star * r_star.sqrt() * (0.01 * p.radius[i]).powf(2.5)
            })
            .sum::<f64>();
        Audit {
            residual: super::energy::residual(scene),
            stored: super::energy::stored(scene).total(),
            floor,
        }
    }

    /// The energy scale of the scene: the largest of the energy put in so far, the energy
    /// stored at the start and the floor.
    fn scale(&self, scene: &Scene) -> f64 {
        scene
            .ledger
            .input()
            .abs()
            .max(self.stored.abs())
            .max(self.floor)
            .max(1e-300)
    }

    /// A runaway, if the energy created since the start exceeds the scene's scale (or the
    /// stored energy is not finite).
    fn check(&self, scene: &Scene) -> Option<Blowup> {
        let stored = super::energy::stored(scene).total();
        let created = super::energy::residual(scene) - self.residual;
        let scale = self.scale(scene);
        (!stored.is_finite() || !created.is_finite() || created > scale)
            .then(|| runaway(scene, created, scale))
    }
}

/// The blow-up snapshot: the scene without what a restore can make anew, the particles'
/// displacements since the last rebuild and the candidate pairs without a state
/// ([`ContactStore::lean_clone`]; the list is marked for re-mapping). At S1 50k this is
/// 11.9 MB instead of 17.7 MB, held through the whole `Cycle`.
pub fn snapshot_of(scene: &mut Scene) -> Scene {
    let contacts = std::mem::take(&mut scene.contacts);
    let disp = std::mem::take(&mut scene.particles.disp);
    let mut s = scene.clone();
    scene.contacts = contacts;
    scene.particles.disp = disp;
    s.contacts = scene.contacts.lean_clone();
    s
}

/// Puts the snapshot back: the displacements since the last rebuild are zero, as the
/// re-mapping that the restored list is marked for leaves them.
pub fn restore(scene: &mut Scene, snapshot: Scene) {
    *scene = snapshot;
    let n = scene.particles.len();
    scene.particles.disp = vec![Vec3::zeros(); n];
}

/// Describes an energy runaway: how much energy appeared, which particle carries the most
/// kinetic energy, and what it may be.
fn runaway(scene: &Scene, created: f64, scale: f64) -> Blowup {
    let p = &scene.particles;
    let mut worst = 0;
    let mut kmax = 0.0;
    for i in 0..p.len() {
        let k = 0.5 * p.mass[i] * p.vel[i].norm_squared();
        if k > kmax {
            kmax = k;
            worst = i;
        }
    }
    Blowup {
        cycle: scene.cycle,
        message: format!(
            "energy runaway at cycle {}: {:.3e} J appeared that the energy ledger did not put in, more than the energy the scene holds or was given ({:.3e} J); \
             particle {} at ({:.4e}, {:.4e}, {:.4e}) moves at {:.3e} m/s. \
             Hint: check deep overlaps, servo gains and contact damping (istiff); a step too long for the fastest contacts shows as a warning (FRAction AUTO follows it)",
            scene.cycle,
            created,
            scale,
            p.id.get(worst).copied().unwrap_or(0),
            p.pos.get(worst).map_or(0.0, |x| x.x),
            p.pos.get(worst).map_or(0.0, |x| x.y),
            p.pos.get(worst).map_or(0.0, |x| x.z),
            p.vel.get(worst).map_or(0.0, |v| v.norm()),
        ),
    }
}

/// One time step; `keep`: leave the forces and moments in the particle arrays (otherwise the
/// update clears them as it goes, which saves the next step a pass over them).
pub fn one_step(
    scene: &mut Scene,
    model: &mut Model,
    (tol, xres): (f64, f64),
    keep: bool,
) -> Result<(), Blowup> {
    let mut dt = model.dt;
    if !set_margins(scene, model, dt) {
        scene.contacts.remap = true;
    }
    let rebuilt = scene.contacts.stale || scene.contacts.remap;
    if rebuilt {
        let tol = rebuild_tol(scene, tol, dt);
        rebuild(scene, tol);
        // FRAction AUTO: the step follows the fastest contact at every rebuild.
        if scene.settings.auto_step.is_some() {
            dt = super::contact_time::auto_step(scene, model, model.dt_base);
            scene.settings.auto_step = Some(dt);
            model.dt = dt;
        }
        set_margins(scene, model, dt);
    }
    let model = &*model;
    let xres = xres_in_use(scene, xres);
    let mut renumbered = false;
    // Particles behind a wall's surface: every particle at a rebuild (one that crossed in a
    // step moved far enough to trigger it, as does a wall that jumped), the wall pairs at
    // every step; before those that left the work-space are removed (one may have left
    // through the wall first).
    if !scene.walls.is_empty() {
        let behind = behind_walls(scene, rebuilt);
        if !behind.is_empty() {
            match scene.settings.tunnel {
                TunnelAction::Stop => return Err(tunnelled(scene, &behind, dt)),
                TunnelAction::Delete => {
                    delete_tunnelled(scene, &behind, dt);
                    renumbered = true;
                }
            }
        }
    }
    renumbered |= remove_lost(scene);
    if renumbered {
        // (The particles' numbering changed: their margins again.)
        set_margins(scene, model, dt);
    }
    let conserve = scene.liquid.is_some()
        && scene.settings.liquid_mode == crate::sim::model::LiquidMode::Conserve;
    let threads = rayon::current_num_threads();
    let one_region = match step_regions() {
        Some(n) => n == 1,
        None => threads <= super::awake::cores(),
    };
    if threads > 1 && one_region && !conserve {
        // Both steps in one parallel region (`fused`): the same bits. (With more threads
        // than cores two regions are faster: a task that waits for another holds a core;
        // 3 threads on 2 cores took 6 × the time of two regions, 1.3 × without the wait.)
        let mv = Mover::of(scene, model);
        let (acc, parts) = forces_fused(scene, model, &mv, keep);
        let wall_work = move_walls(scene, dt);
        return finish_move(scene, (xres, keep), acc, wall_work, &parts, dt);
    }
    let acc = forces(scene, model, dt);
    if conserve {
        super::liquid::settle(scene);
    }
    move_all(scene, model, xres, acc, keep)
}

/// `TRUBAL_STEP_REGIONS` = 1 or 2: the step with several threads in one parallel region or
/// in two (the force step, then the update), whatever the number of cores; otherwise
/// (`None`) one region unless there are more threads than cores. For measurements and
/// tests: both give the same bits.
fn step_regions() -> Option<u8> {
    static REGIONS: std::sync::OnceLock<Option<u8>> = std::sync::OnceLock::new();
    *REGIONS.get_or_init(|| match std::env::var("TRUBAL_STEP_REGIONS").as_deref() {
        Ok("1") => Some(1),
        Ok("2") => Some(2),
        _ => None,
    })
}

/// Step 1 of a cycle: all contact forces at the current positions (dt = 0: states only).
fn forces(scene: &mut Scene, model: &Model, dt: f64) -> Acc {
    forces_or_fused(scene, model, dt, None).0
}

/// Steps 1 and 2 of a cycle in one parallel region (several threads, see `fused`): the
/// energy increments and the update's chunk sums.
fn forces_fused(scene: &mut Scene, model: &Model, mv: &Mover, keep: bool) -> (Acc, Vec<ChunkSums>) {
    let (acc, parts) = forces_or_fused(scene, model, model.dt, Some((mv, keep)));
    (acc, parts.unwrap_or_default())
}

fn forces_or_fused(
    scene: &mut Scene,
    model: &Model,
    dt: f64,
    fuse: Option<(&Mover, bool)>,
) -> (Acc, Option<Vec<ChunkSums>>) {
    // The kernel for what the scene has: adhesion, liquid (see `interact`).
    match (model.adhesion, scene.liquid.is_some()) {
        (false, false) => forces_with::<false, false>(scene, model, dt, fuse),
        (false, true) => forces_with::<false, true>(scene, model, dt, fuse),
        (true, false) => forces_with::<true, false>(scene, model, dt, fuse),
        (true, true) => forces_with::<true, true>(scene, model, dt, fuse),
    }
}

/// The contact forces (`fuse`: with the update, in one region, see `fused`).
fn forces_with<const ADH: bool, const LIQ: bool>(
    scene: &mut Scene,
    model: &Model,
    dt: f64,
    fuse: Option<(&Mover, bool)>,
) -> (Acc, Option<Vec<ChunkSums>>) {
    let liquid = scene.liquid;
    let laws_pp = Laws {
        dt,
        tangential: scene.settings.tangential,
        rotation: model.rotation,
        beta: scene.damping_pp.beta,
        liquid: liquid.as_ref(),
        bridge: scene.settings.bridge,
        smin: scene.settings.smin,
        impact: scene.impact,
        liquid_share: (scene.settings.liquid_mode == crate::sim::model::LiquidMode::Conserve)
            .then_some(super::liquid::OLSSON_SHARE),
        goldman: scene.settings.goldman,
        // (Only in a step, with the margins of its particles: not while priming.)
        margin: if dt > 0.0 && scene.reach_ext.len() == scene.particles.len().div_ceil(EXT_GROUP) {
            scene.contacts.margins[0]
        } else {
            0.0
        },
    };

    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    // The same laws for particle–wall contacts; Rayleigh contact damping has its own
    // particle–wall set.
    let laws_pw = Laws {
        beta: scene.damping_pw.beta,
        margin: if laws_pp.margin > 0.0 {
            scene.contacts.margins[1]
        } else {
            0.0
        },
        ..laws_pp
    };
    let (pair_acc, wall_acc, parts) = if let Some((mv, keep)) = fuse {
        let (pair_acc, wall_acc, parts) = fused::forces_and_moves::<ADH, LIQ>(
            scene,
            (model, &laws_pp, &laws_pw, &shapes),
            mv,
            keep,
        );
        (pair_acc, wall_acc, Some(parts))
    } else {
        let (pair_acc, wall_acc) =
            contact_forces::<ADH, LIQ>(scene, model, (&laws_pp, &laws_pw), &shapes);
        (pair_acc, wall_acc, None)
    };
    let mut acc = Acc::default();
    acc.add(&pair_acc);
    for a in &wall_acc {
        acc.add(a);
    }
    // ---- particle–wall contacts -------------------------------------------------------
    // The tasks have made the walls' forces (summed per block of wall pairs, then in block
    // order) and the energy increments (per block). The particles get theirs in the update
    // (`move_all` or, in one region, `fused`, chunk by chunk), after their moments are
    // scaled by the radius and, with several threads, after the shared particles' sums.
    scene.contacts.wall_out.sum_walls(scene.walls.len());
    for (w, f) in scene.walls.iter_mut().zip(&scene.contacts.wall_out.on_wall) {
        w.force = *f;
    }
    scene.contacts.deferred = parts.is_none();
    (acc, parts)
}

/// Particles per entry of [`Scene::reach_ext`]: the margin of reach is kept per group of
/// consecutive particles (neighbours in space, the numbering follows it), so that the reach
/// tests read it from a table that stays in the cache.
pub const EXT_GROUP: usize = 64;

/// Each group's margin of reach `Δt × its particles' largest velocity component` into `ext`
/// ([`EXT_GROUP`]); the largest velocity component (any thread count: the same value).
fn reach_margins(vel: &[Vec3], dt: f64, ext: &mut Vec<f64>) -> f64 {
    ext.resize(vel.len().div_ceil(EXT_GROUP), 0.0);
    vel.par_chunks(CHUNK)
        .zip(ext.par_chunks_mut(CHUNK / EXT_GROUP))
        .map(|(v, e)| {
            let mut vmax = 0.0f64;
            for (v, e) in v.chunks(EXT_GROUP).zip(e.iter_mut()) {
                let a = v.iter().fold(0.0f64, |m, v| m.max(v.amax()));
                *e = a * dt;
                vmax = if a > vmax { a } else { vmax };
            }
            vmax
        })
        .reduce(|| 0.0, f64::max)
}

/// The largest displacement component since the last rebuild (kept by the update; worked
/// out when not known).
fn max_disp(scene: &mut Scene) -> f64 {
    if let Some(d) = scene.contacts.max_disp {
        return d;
    }
    let d = scene
        .particles
        .disp
        .par_chunks(CHUNK)
        .map(|d| d.iter().fold(0.0f64, |m, d| m.max(d.amax())))
        .reduce(|| 0.0, f64::max);
    scene.contacts.max_disp = Some(d);
    d
}

/// The margins of this step ([`ContactStore::margins`], [`Scene::reach_ext`]): pairs
/// approaching within half a step's travel get their share of the restitution dashpot
/// (physics::dashpot), so they are evaluated within Δt × (a bound of their relative speed)
/// of touching: |v_B − v_A|/2 ≤ (|v_A| + |v_B|)/2 < the sum of the two particles' largest
/// velocity components (the reach tests keep of those only the ones that may approach); a
/// particle–wall pair within its particle's margin plus the fastest wall's travel in a step
/// (`margins[1]`). Zero without a dashpot. Returns whether the candidate
/// list still holds every pair within those margins (gap at the last rebuild below TOL:
/// closed since by at most 2√3 × the largest displacement component, and a wall by its
/// travel).
fn set_margins(scene: &mut Scene, model: &Model, dt: f64) -> bool {
    if !(dt > 0.0) || !model.table.iter().any(|p| p.zeta > 0.0) || scene.particles.is_empty() {
        scene.contacts.margins = [0.0; 2];
        scene.reach_ext = Vec::new();
        return true;
    }
    let v = reach_margins(&scene.particles.vel, dt, &mut scene.reach_ext);
    let d = max_disp(scene);
    if std::env::var("EXP").as_deref() == Ok("2") {
        scene.contacts.margins = [0.0; 2];
        return true;
    }
    let walls = scene
        .walls
        .iter()
        .fold(0.0f64, |m, w| m.max(Vec3::from(w.vel).norm() + w.vr.abs()));
    let travel = scene.walls.iter().fold(0.0f64, |m, w| m.max(w.travel));
    // (Positive with a dashpot even when nothing moves: it also says "evaluate within the
    // margins", e.g. a wall that approaches particles at rest.)
    let m = [(2.0 * v * dt).max(f64::MIN_POSITIVE), walls * dt];
    scene.contacts.margins = m;
    let tol = scene.contacts.tol;
    let s3 = 3f64.sqrt();
    2.0 * s3 * d + m[0] < tol && s3 * d + travel + v * dt + m[1] < tol
}

/// The contact forces of the two-region step ([`pair_forces`]): the pairs' energy
/// increments (per block in block order) and the wall pairs' (per block).
fn contact_forces<const ADH: bool, const LIQ: bool>(
    scene: &mut Scene,
    model: &Model,
    (laws_pp, laws_pw): (&Laws, &Laws),
    shapes: &[WallShape],
) -> (Acc, Vec<Acc>) {
    // ---- particle–particle contacts ---------------------------------------------------
    // Each pair's force goes onto its two particles in pair order. With one thread that is
    // done in the pair loop; with several, each task (a range of whole blocks) does it for
    // the particles whose pairs all lie in its range, and the few others are summed from
    // the pairs' slots afterwards, also in pair order. Either way every particle sums its
    // pairs in the same order, and the energy partial sums are added per block in block
    // order (then the wall contacts' per chunk): the result does not depend on the number
    // of threads.
    let ctx = PairCtx {
        pos: View::of(&scene.particles.pos),
        vel: View::of(&scene.particles.vel),
        spin: View::of(&scene.particles.spin),
        radius: &scene.particles.radius,
        mass: &scene.particles.mass,
        material: &scene.particles.material,
        model,
        laws: laws_pp,
        size: scene.size,
        periodic: scene.settings.periodic,
        uni: UniPair::of(model),
        ext: (laws_pp.margin > 0.0).then_some(&scene.reach_ext[..]),
    };
    let wall_ctx = PairCtx {
        laws: laws_pw,
        ..ctx
    };
    let zeroed = std::mem::take(&mut scene.contacts.zeroed);
    let (hot, pairs, blocks, out, scatter, wall_pairs, wall_out) = scene.contacts.step_parts();
    let force = &mut scene.particles.force;
    let moment = &mut scene.particles.moment;
    let walls = (&scene.walls[..], shapes);
    pair_forces::<ADH, LIQ>(
        (hot, pairs, blocks, out, scatter),
        (force, moment, zeroed),
        &ctx,
        (wall_pairs, wall_out, walls, &wall_ctx),
    )
}

/// What the force step left to the update (see [`ContactStore::deferred`]), for the
/// particles of chunk `c` (`force`, `moment`: the chunk's): with several threads the shared
/// particles' sums from their pairs' slots, in pair order; the moments (summed per unit
/// radius) times the radius; then each particle's wall forces in pair order. The same sums
/// in the same order for any number of threads, done where the update reads the chunk
/// anyway (one pass over the moments less per step).
fn finish_chunk(
    left: Left<'_>,
    c: usize,
    (force, moment): (&mut [Vec3], &mut [Vec3]),
    radius: &[f64],
    rotation: bool,
) {
    let lo = c * CHUNK;
    let hi = lo + force.len();
    if let Some((inc, hot, out)) = left.scatter {
        let list = &inc.shared_list;
        let first = list.partition_point(|&q| (q as usize) < lo);
        let last = list.partition_point(|&q| (q as usize) < hi);
        for (s, &q) in list.iter().enumerate().take(last).skip(first) {
            let q = q as usize;
            let (mut f, mut m) = (Vec3::zeros(), Vec3::zeros());
            for &k in inc.of_shared(s) {
                let h = &hot[k as usize];
                // (A pair not evaluated in this step left its slot at zero, which adds
                // nothing: the sum starts at +0 and never becomes −0.)
                let o = &out[inc.slot[k as usize] as usize];
                // Force −f on the pair's first particle (A), +f on B.
                if h.i as usize == q {
                    f -= o.f;
                } else {
                    f += o.f;
                }
                if rotation {
                    m += o.m;
                }
            }
            force[q - lo] = f;
            moment[q - lo] = m;
        }
    }
    if rotation {
        for (m, r) in moment.iter_mut().zip(&radius[lo..hi]) {
            *m *= *r;
        }
    }
    for o in WallOut::of_chunk(left.walls, c) {
        let i = o.i as usize - lo;
        force[i] -= o.f;
        if rotation {
            moment[i] += o.m;
        }
    }
}

/// The deferred part of the force step without the update (after `prime`).
fn finish_deferred(scene: &mut Scene, rotation: bool) {
    if !std::mem::take(&mut scene.contacts.deferred) {
        return;
    }
    let contacts = &scene.contacts;
    let left = Left {
        scatter: Some((&contacts.scatter, &contacts.hot, &contacts.out)),
        walls: &contacts.wall_out.pieces,
    };
    let p = &mut scene.particles;
    let radius = &p.radius;
    p.force
        .par_chunks_mut(CHUNK)
        .zip(p.moment.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (f, m))| finish_chunk(left, c, (f, m), radius, rotation));
}

/// The particle–particle forces (see [`forces_with`]): each pair's force goes onto its two
/// particles in pair order; the moments are summed per unit radius (the update scales them,
/// `finish_chunk`). The wall contacts are evaluated alongside: with several threads each task
/// takes the stretch of wall pairs (whole blocks of [`WALL_BLOCK`]) that begins about where
/// its particles do, before its pairs ([`wall_forces`], one piece of `wall_out` per task), so
/// that the core that updates a particle has its wall forces in its cache.
/// Returns the energy increments, the pairs' summed per block in block order, and the wall
/// pairs' per block, in block order.
#[allow(clippy::type_complexity)]
fn pair_forces<const ADH: bool, const LIQ: bool>(
    (hot, pairs, blocks, out, scatter): (
        &mut [HotPair],
        &mut [Pair],
        &mut [Vec<ContactState>],
        &mut Vec<PairForce>,
        &mut Incidence,
    ),
    (force, moment, zeroed): (&mut Vec<Vec3>, &mut Vec<Vec3>, bool),
    ctx: &PairCtx,
    (wall_pairs, wall_out, walls, wall_ctx): (
        &mut [WallPair],
        &mut WallOut,
        (&[Wall], &[WallShape]),
        &PairCtx,
    ),
) -> (Acc, Vec<Acc>) {
    let ctx = *ctx;
    let rotation = ctx.model.rotation;
    let np = force.len();
    let acc;
    let wall_acc;
    {
        if rayon::current_num_threads() == 1 {
            wall_out.pieces.resize_with(1, WallPiece::default);
            wall_acc =
                wall_forces::<ADH, LIQ>(wall_pairs, &mut wall_out.pieces[0], walls, wall_ctx, np);
            if !zeroed {
                force.fill(Vec3::zeros());
                moment.fill(Vec3::zeros());
            }
            // (The blocks' increments are the whole of `acc` on one thread.)
            let parts = (hot, pairs, blocks);
            acc = if ctx.uni.is_some() {
                serial_pairs::<ADH, LIQ, true>(parts, (force, moment), &ctx, rotation)
            } else {
                serial_pairs::<ADH, LIQ, false>(parts, (force, moment), &ctx, rotation)
            };
        } else {
            split_if_needed(scatter, hot, np);
            out.resize(scatter.slots, PairForce::default());
            let inc = &*scatter;
            let ranges = &inc.ranges;
            let wall_cut = wall_cuts(ranges, wall_pairs);
            wall_out
                .pieces
                .resize_with(ranges.len(), WallPiece::default);
            // Each task takes a range of whole blocks and the particles it owns: those of
            // its particle interval whose pairs all lie in its blocks. Their forces are summed
            // in the pair loop, in pair order, as with one thread; every other particle's
            // share is left in the pair's slot and summed below, also in pair order.
            let mut tasks = Vec::with_capacity(ranges.len());
            {
                let (mut hot, mut pairs, mut blocks, mut out) =
                    (&mut hot[..], &mut pairs[..], &mut blocks[..], &mut out[..]);
                let (mut force, mut moment) = (&mut force[..], &mut moment[..]);
                let mut wall_rest = &mut wall_pairs[..];
                let mut pieces = &mut wall_out.pieces[..];
                for (t, (r, slots)) in ranges.iter().zip(&inc.task_slots).enumerate() {
                    let (h, rest) = hot.split_at_mut(r.pairs.len());
                    hot = rest;
                    let (p, rest) = pairs.split_at_mut(r.pairs.len());
                    pairs = rest;
                    let (b, rest) = blocks.split_at_mut(r.pairs.len().div_ceil(BLOCK));
                    blocks = rest;
                    let (o, rest) = out.split_at_mut(slots.len());
                    out = rest;
                    let (f, rest) = force.split_at_mut(r.parts.len());
                    force = rest;
                    let (m, rest) = moment.split_at_mut(r.parts.len());
                    moment = rest;
                    let (w, rest) = wall_rest.split_at_mut(wall_cut[t + 1] - wall_cut[t]);
                    wall_rest = rest;
                    let (piece, rest) = pieces.split_at_mut(1);
                    pieces = rest;
                    let walls_of = (w, &mut piece[0]);
                    tasks.push((r.clone(), slots.start, h, p, b, o, f, m, walls_of));
                }
            }
            let task_acc: Vec<(Vec<Acc>, Vec<Acc>, f64)> = tasks
                .into_par_iter()
                .with_max_len(1)
                .map(
                    |(r, slot0, hots, pairs, blocks, outs, force, moment, (wp, piece))| {
                        let t0 = std::time::Instant::now();
                        let wall_accs = wall_forces::<ADH, LIQ>(wp, piece, walls, wall_ctx, np);
                        let accs = task_pairs::<ADH, LIQ>(
                            (&r, slot0, inc),
                            (hots, pairs, blocks, outs),
                            (force, moment, zeroed),
                            &ctx,
                        );
                        (accs, wall_accs, t0.elapsed().as_secs_f64())
                    },
                )
                .collect();
            (acc, wall_acc) = task_sums(&task_acc, &mut scatter.balance);
            // The particles no task owned are summed from their pairs' slots by the
            // update (`finish_chunk`).
        }
    }

    (acc, wall_acc)
}

/// The pair loop on one thread: each pair's force onto its two particles in pair order; the
/// energy increments per block, added in block order. `UNI`: the particles are all alike
/// (chosen here, once, so that the loop and its force closure are compiled once per choice
/// and stay inlined).
fn serial_pairs<const ADH: bool, const LIQ: bool, const UNI: bool>(
    (hot, pairs, blocks): (&mut [HotPair], &mut [Pair], &mut [Vec<ContactState>]),
    (force, moment): (&mut [Vec3], &mut [Vec3]),
    ctx: &PairCtx,
    rotation: bool,
) -> Acc {
    let mut acc = Acc::default();
    let mut sc = Scratch::new();
    for ((hots, pairs), block) in hot
        .chunks_mut(BLOCK)
        .zip(pairs.chunks_mut(BLOCK))
        .zip(blocks.iter_mut())
    {
        let mut a = Acc::default();
        block_forces::<ADH, LIQ, UNI>(hots, pairs, block, ctx, &mut a, &mut sc, |_, h, o| {
            let (i, j) = (h.i as usize, h.j as usize);
            force[i] -= o.f;
            force[j] += o.f;
            if rotation {
                moment[i] += o.m;
                moment[j] += o.m;
            }
        });
        acc.add(&a);
    }
    acc
}

/// The tasks' results (per task: the energy increments of its pair blocks, of its wall
/// blocks, and its time) as one sum of the pair blocks in block order and the wall blocks'
/// list in block order; each task's time is added to its share of `balance`.
fn task_sums(results: &[(Vec<Acc>, Vec<Acc>, f64)], balance: &mut Balance) -> (Acc, Vec<Acc>) {
    let mut acc = Acc::default();
    let mut wall_acc = Vec::new();
    for (accs, wall_accs, _) in results {
        for a in accs {
            acc.add(a);
        }
        wall_acc.extend_from_slice(wall_accs);
    }
    for (t, (_, _, secs)) in balance.tasks.iter_mut().zip(results) {
        t.2 += secs;
    }
    (acc, wall_acc)
}

/// With several threads, once per rebuild: one task per thread (measured: more tasks make
/// more particles shared), balanced on the contacts of this step and on what the tasks took
/// since the last split.
fn split_if_needed(scatter: &mut Incidence, hot: &mut [HotPair], np: usize) {
    let threads = rayon::current_num_threads();
    if scatter.needs_split(np, threads) {
        let rates = scatter.balance.rates().unwrap_or_default();
        let (ranges, costs) = pair_ranges(hot, np, threads, &rates);
        let n = hot.len().max(1) as f64;
        scatter.balance = Balance {
            tasks: (ranges.iter().zip(costs))
                .map(|(r, c)| (r.pairs.end as f64 / n, c, 0.0))
                .collect(),
        };
        scatter.split(hot, np, ranges, threads);
    }
}

/// Where each task's stretch of wall pairs begins (and, last, their number): whole blocks,
/// from the block boundary nearest to the first wall pair of its particle interval (wall
/// pairs are in id order, which is mostly index order). Where the cut falls changes no sum.
fn wall_cuts(ranges: &[PairRange], wall_pairs: &[WallPair]) -> Vec<usize> {
    let mut wall_cut = vec![0; ranges.len() + 1];
    for (t, r) in ranges.iter().enumerate().skip(1) {
        let k = wall_pairs.partition_point(|w| (w.i as usize) < r.parts.start);
        let k = (k + WALL_BLOCK / 2) / WALL_BLOCK * WALL_BLOCK;
        wall_cut[t] = k.clamp(wall_cut[t - 1], wall_pairs.len());
    }
    wall_cut[ranges.len()] = wall_pairs.len();
    wall_cut
}

/// One task's pairs with several threads (task range `r`, its first force slot `slot0`):
/// the forces of the particles it owns (those of its interval `force`, `moment` that no
/// other task's pairs touch) summed in pair order, as with one thread; every other
/// particle's share left in the pair's slot (`outs`; the slots of pairs not evaluated in this
/// step stay zero: they are cleared here, on the core that writes them). Returns the energy
/// increments per block.
fn task_pairs<const ADH: bool, const LIQ: bool>(
    task: (&PairRange, usize, &Incidence),
    lists: (
        &mut [HotPair],
        &mut [Pair],
        &mut [Vec<ContactState>],
        &mut [PairForce],
    ),
    sums: (&mut [Vec3], &mut [Vec3], bool),
    ctx: &PairCtx,
) -> Vec<Acc> {
    // The choice for uniform scenes once per task (not per block: two copies of the block
    // loop in one function left its force closure out of line, a call per pair, 15 % slower
    // on two threads).
    if ctx.uni.is_some() {
        task_pairs_of::<ADH, LIQ, true>(task, lists, sums, ctx)
    } else {
        task_pairs_of::<ADH, LIQ, false>(task, lists, sums, ctx)
    }
}

fn task_pairs_of<const ADH: bool, const LIQ: bool, const UNI: bool>(
    (r, slot0, inc): (&PairRange, usize, &Incidence),
    (hots, pairs, blocks, outs): (
        &mut [HotPair],
        &mut [Pair],
        &mut [Vec<ContactState>],
        &mut [PairForce],
    ),
    (force, moment, zeroed): (&mut [Vec3], &mut [Vec3], bool),
    ctx: &PairCtx,
) -> Vec<Acc> {
    let rotation = ctx.model.rotation;
    let lo = r.parts.start;
    outs.fill(PairForce::default());
    if !zeroed {
        force.fill(Vec3::zeros());
        moment.fill(Vec3::zeros());
    }
    let mut accs = Vec::with_capacity(blocks.len());
    let mut sc = Scratch::new();
    for (b, ((hots, pairs), block)) in hots
        .chunks_mut(BLOCK)
        .zip(pairs.chunks_mut(BLOCK))
        .zip(blocks.iter_mut())
        .enumerate()
    {
        let base = r.pairs.start + b * BLOCK;
        let mut a = Acc::default();
        block_forces::<ADH, LIQ, UNI>(hots, pairs, block, ctx, &mut a, &mut sc, |k, h, o| {
            let (i, j) = (h.i as usize, h.j as usize);
            // A particle this task's pairs touch is its own unless shared.
            let (oi, oj) = (h.shared & 1 == 0, h.shared & 2 == 0);
            if oi {
                force[i - lo] -= o.f;
                if rotation {
                    moment[i - lo] += o.m;
                }
            }
            if oj {
                force[j - lo] += o.f;
                if rotation {
                    moment[j - lo] += o.m;
                }
            }
            if !(oi && oj) {
                outs[inc.slot[base + k] as usize - slot0] = o;
            }
        });
        accs.push(a);
    }
    accs
}

/// The particle–wall contacts of a stretch of wall pairs (whole blocks of [`WALL_BLOCK`]):
/// each evaluated pair's force and moment into `out`, in pair order, with the force on each
/// wall summed per block in pair order, and the entries grouped by the update's chunk of
/// their particle (`np` particles); returns the energy increments per block. The steady
/// no-slip contacts go through [`lanes::hertz_noslip`] in sub-batches of [`lanes::SUB`]
/// pairs (S1 10k, one thread: 5.5 % → 3.7 % of the samples in this function, same bits).
fn wall_forces<const ADH: bool, const LIQ: bool>(
    wall_pairs: &mut [WallPair],
    out: &mut WallPiece,
    walls: (&[Wall], &[WallShape]),
    c: &PairCtx,
    np: usize,
) -> Vec<Acc> {
    use lanes::SUB;
    let nw = walls.0.len();
    out.forces.clear();
    out.sums.clear();
    // The steady Hertz contacts with the no-slip law go through the vectorised kernel, as
    // in the pair loop (`block_forces`): the same arithmetic, so the same bits.
    let laws = c.laws;
    let batched = batches_steady::<ADH, LIQ>(c);
    let mut batch = lanes::Batch::new();
    let mut kins = [Kin::ZERO; SUB];
    let mut idx = [0u8; SUB];
    let mut lane = [u8::MAX; SUB];
    let accs = wall_pairs
        .chunks_mut(WALL_BLOCK)
        .map(|pairs| {
            let mut acc = Acc::default();
            let base = out.sums.len();
            out.sums.resize(base + nw, [0.0; 3]);
            for sub in pairs.chunks_mut(SUB) {
                // The pairs evaluated, their geometry, and the steady ones into the batch.
                let mut m = 0;
                batch.len = 0;
                for (k, c2) in sub.iter().enumerate() {
                    let Some((kin, pc)) = wall_kin(c2, walls, c) else {
                        continue;
                    };
                    idx[m] = k as u8;
                    lane[m] = if batched && lanes::Batch::takes(&kin, pc, &c2.s) {
                        batch.push(&kin, pc, &c2.s) as u8
                    } else {
                        u8::MAX
                    };
                    // (Only the general kernel reads it back.)
                    if lane[m] == u8::MAX {
                        kins[m] = kin;
                    }
                    m += 1;
                }
                if batch.len > 0 {
                    lanes::hertz_noslip(&mut batch, laws.dt);
                }
                // In pair order: each force and the ledger's terms.
                for q in 0..m {
                    let c2 = &mut sub[idx[q] as usize];
                    let kin = &kins[q];
                    let i = c2.i as usize;
                    let ri = c.radius[i];
                    let (f, ft_moment) = if lane[q] != u8::MAX {
                        let l = lane[q] as usize;
                        let (f, m) = batch.store(l, &mut c2.s);
                        acc.damping_contact += batch.e_damp_n[l];
                        acc.friction += batch.e_friction[l];
                        acc.damping_contact += batch.e_damp_t[l];
                        (f, m * ri)
                    } else {
                        let w = &walls.0[c2.wall as usize];
                        let pc = c.model.pair(c.material[i] as usize, w.material);
                        let o = interact::<ADH, LIQ>(kin, pc, laws, &mut c2.s, &mut acc);
                        let m = if c.model.rotation {
                            -kin.n.cross(&o.ft) * ri
                        } else {
                            Vec3::zeros()
                        };
                        (o.f, m)
                    };
                    let o = WallForce {
                        f,
                        m: ft_moment,
                        i: c2.i,
                    };
                    let w = &mut out.sums[base + c2.wall as usize];
                    for (wk, fk) in w.iter_mut().zip(o.f.iter()) {
                        *wk += fk;
                    }
                    out.forces.push(o);
                }
            }
            acc
        })
        .collect();
    // A counting sort of the entries by chunk (stable: pair order within a chunk).
    let nchunks = np.div_ceil(CHUNK);
    out.start.clear();
    out.start.resize(nchunks + 2, 0);
    for o in &out.forces {
        out.start[o.i as usize / CHUNK + 2] += 1;
    }
    for c in 2..out.start.len() {
        out.start[c] += out.start[c - 1];
    }
    out.order.clear();
    out.order.resize(out.forces.len(), 0);
    for (e, o) in out.forces.iter().enumerate() {
        let at = &mut out.start[o.i as usize / CHUNK + 1];
        out.order[*at as usize] = e as u32;
        *at += 1;
    }
    out.start.pop();
    accs
}

/// The geometry of one particle–wall pair and the pair's constants (`None`: skipped, the
/// particle is out of reach with nothing to remember).
#[inline(always)]
fn wall_kin<'m>(
    c: &WallPair,
    (walls, shapes): (&[Wall], &[WallShape]),
    ctx: &PairCtx<'m>,
) -> Option<(Kin, &'m super::params::PairConst)> {
    let i = c.i as usize;
    let w = &walls[c.wall as usize];
    let ri = ctx.radius[i];
    let (gap, n) = shapes[c.wall as usize].gap(&ctx.pos[i], ri);
    let far = gap > 1e-6 * ri && !c.s.live();
    // Beyond the dashpot's margin (the particle's and the fastest wall's travel in a step,
    // `ContactStore::margins`), or without a dashpot: not evaluated.
    let reach = match ctx.ext {
        Some(e) => 1e-6 * ri + e[i / EXT_GROUP] + ctx.laws.margin,
        None => 1e-6 * ri,
    };
    if far && !(gap <= reach) {
        return None;
    }
    let vw = surface_velocity(w, &n);
    let v_rel = vw - ctx.vel[i] - (ctx.spin[i] * ri).cross(&n);
    if far {
        // Only a pair approaching within half a step's travel gets the dashpot's share
        // (the kernel's own test, `interact`).
        let v_n = v_rel.dot(&n);
        if !(v_n < 0.0 && -gap - v_n * (0.5 * ctx.laws.dt) > 0.0) {
            return None;
        }
    }
    let r2 = match w.geom {
        WallGeom::Plane { .. } => f64::INFINITY,
        WallGeom::Sphere { radius, .. } => -radius,
        WallGeom::Obstacle { radius, .. } => radius,
    };
    let k = Kin {
        n,
        gap,
        v_rel,
        r_star: wall_r_star(&w.geom, ri),
        m_star: ctx.mass[i],
        r1: ri,
        r2: if r2 < 0.0 { f64::INFINITY } else { r2 },
    };
    Some((k, ctx.model.pair(ctx.material[i] as usize, w.material)))
}

/// Splits the pairs into about `n` ranges of whole blocks of similar cost (pairs evaluated in
/// the last step count 8, the others 1, times the relative rate measured at their place in
/// the list, `rates` as from [`Balance::rates`]), each with
/// the particle interval that starts at its first pair's first particle; and each range's
/// pair cost (unweighted). Where the split falls changes which particles are summed in the
/// pair loop and which from the slots, not the result.
fn pair_ranges(
    hot: &[HotPair],
    np: usize,
    n: usize,
    rates: &[(f64, f64)],
) -> (Vec<PairRange>, Vec<usize>) {
    let cost: Vec<usize> = hot
        .par_chunks(BLOCK)
        .map(|c| c.len() + 7 * c.iter().filter(|h| h.live).count())
        .collect();
    let nb = cost.len().max(1) as f64;
    let rate = |b: usize| {
        let x = (b as f64 + 0.5) / nb;
        rates.iter().find(|r| x < r.0).map_or(1.0, |r| r.1)
    };
    let weight: Vec<f64> = cost
        .iter()
        .enumerate()
        .map(|(b, &c)| c as f64 * rate(b))
        .collect();
    let total = weight.iter().sum::<f64>();
    let n = n.clamp(1, cost.len().max(1));
    let mut ranges = Vec::with_capacity(n);
    let mut costs = Vec::with_capacity(n);
    let (mut b0, mut acc, mut p0) = (0, 0.0, 0);
    for (b, w) in weight.iter().enumerate() {
        acc += w;
        let last = b + 1 == cost.len();
        if last || acc * n as f64 >= total * (ranges.len() + 1) as f64 {
            let end = ((b + 1) * BLOCK).min(hot.len());
            let p1 = if last {
                np
            } else {
                (hot[end].i as usize).clamp(p0, np)
            };
            ranges.push(PairRange {
                pairs: b0 * BLOCK..end,
                parts: p0..p1,
            });
            costs.push(cost[b0..=b].iter().sum());
            (b0, p0) = (b + 1, p1);
        }
    }
    if ranges.is_empty() {
        ranges.push(PairRange {
            pairs: 0..0,
            parts: 0..np,
        });
        costs.push(0);
    }
    (ranges, costs)
}

/// What the pair loop reads of the particles and the scene.
#[derive(Clone, Copy)]
struct PairCtx<'a> {
    pos: View<'a>,
    vel: View<'a>,
    spin: View<'a>,
    radius: &'a [f64],
    mass: &'a [f64],
    material: &'a [u16],
    model: &'a Model,
    laws: &'a Laws<'a>,
    size: [f64; 3],
    periodic: [bool; 3],
    /// The particles are all alike: their radius, mass and pair constants.
    uni: Option<UniPair>,
    /// Per particle, the dashpot's margin of reach (`Scene::reach_ext`; `None`: none).
    ext: Option<&'a [f64]>,
}

/// The constants of a scene whose particles all have the same radius, mass and material
/// ([`params::Uniform`]), for the pair loop: R* and m* computed once, as the pair loop
/// computes them (`r r / (r + r)`), so they have the same bits.
#[derive(Clone, Copy, Default)]
struct UniPair {
    r: f64,
    r_star: f64,
    m_star: f64,
    pc: params::PairConst,
}

impl UniPair {
    fn of(model: &Model) -> Option<UniPair> {
        let u = model.uniform?;
        let (r, m, k) = (u.radius, u.mass, u.material as usize);
        Some(UniPair {
            r,
            r_star: r * r / (r + r),
            m_star: m * m / (m + m),
            pc: *model.pair(k, k),
        })
    }
}

/// The pair loop over one block, in sub-batches of [`lanes::SUB`] pairs and four passes:
/// which pairs are evaluated (near, or with something to remember), decided without a
/// branch per pair; their geometry (steady Hertz contacts with the no-slip law are gathered
/// into a [`lanes::Batch`]); the batch's contact law on arrays (vectorised); then, in pair
/// order, the ledger terms and forces of the batch and the general kernel for every other
/// evaluated pair. The arithmetic and its order are those of one pass
/// with the general kernel, and `emit` gets each force (with the pair's index in the block)
/// in pair order.
#[inline(always)]
fn block_forces<const ADH: bool, const LIQ: bool, const UNI: bool>(
    hots: &mut [HotPair],
    pairs: &mut [Pair],
    block: &mut Vec<ContactState>,
    c: &PairCtx,
    acc: &mut Acc,
    sc: &mut Scratch,
    mut emit: impl FnMut(usize, &HotPair, PairForce),
) {
    use lanes::SUB;
    let laws = c.laws;
    // (Read only when `UNI`.)
    let u = c.uni.unwrap_or_default();
    let batched = batches_steady::<ADH, LIQ>(c);
    let vector_reach = vector_reach(c);
    let Scratch {
        batch,
        kins,
        idx,
        ds,
        dists,
        lane,
    } = sc;
    let mut start = 0;
    while start < hots.len() {
        let end = (start + SUB).min(hots.len());
        // Which pairs are evaluated, without a branch per pair (whether a pair is near is
        // as good as random along the list).
        let m = reach::evaluated::<ADH, LIQ, UNI>(&hots[start..end], start, c, vector_reach, idx);
        prefetch_states(hots, block, &idx[..m]);
        // The distances and normals of the evaluated pairs in a loop of their own: its
        // square roots and divisions overlap, where inside the loop below each pair's
        // waited for the one before.
        for q in 0..m {
            let d = reach::separation(&hots[idx[q] as usize], c);
            let dist = d.norm_squared().sqrt();
            dists[q] = dist;
            ds[q] = d / dist;
        }

        batch.len = 0;
        for q in 0..m {
            let k = idx[q] as usize;
            let h = &mut hots[k];
            {
                let kin = pair_kin::<UNI>(h, &mut pairs[k].slot, block, c, &u, (ds[q], dists[q]));
                lane[q] = u8::MAX;
                if batched {
                    let s = &block[h.slot as usize];
                    let pc = if UNI {
                        &u.pc
                    } else {
                        c.model.pair(
                            c.material[h.i as usize] as usize,
                            c.material[h.j as usize] as usize,
                        )
                    };
                    if lanes::Batch::takes(&kin, pc, s) {
                        lane[q] = batch.push(&kin, pc, s) as u8;
                    }
                }
                // (Only the general kernel reads it back.)
                if lane[q] == u8::MAX {
                    kins[q] = kin;
                }
            }
        }
        if batch.len > 0 {
            lanes::hertz_noslip(batch, laws.dt);
        }
        for q in 0..m {
            let k = idx[q] as usize;
            let h = &mut hots[k];
            let s = &mut block[h.slot as usize];
            let f = if lane[q] != u8::MAX {
                let l = lane[q] as usize;
                let (f, m) = batch.store(l, s);
                acc.damping_contact += batch.e_damp_n[l];
                acc.friction += batch.e_friction[l];
                acc.damping_contact += batch.e_damp_t[l];
                // (`h.live` stays true: the contact was touching, `Batch::takes`, and it
                // still overlaps.)
                PairForce { f, m }
            } else {
                let kin = &kins[q];
                let (i, j) = (h.i as usize, h.j as usize);
                let pc = c.model.pair(c.material[i] as usize, c.material[j] as usize);
                let out = interact::<ADH, LIQ>(kin, pc, laws, s, acc);
                let live = s.live();
                if h.live != live {
                    h.live = live;
                }
                PairForce {
                    f: out.f,
                    m: if c.model.rotation {
                        -kin.n.cross(&out.ft)
                    } else {
                        Vec3::zeros()
                    },
                }
            };
            emit(k, h, f);
        }
        start = end;
    }
}

/// Velocity of B's contact point relative to A's (the pair's `Kin::v_rel`).
#[inline(always)]
fn rel_velocity(c: &PairCtx, (i, j): (usize, usize), (ri, rj): (f64, f64), n: &Vec3) -> Vec3 {
    c.vel[j] - c.vel[i] - (c.spin[i] * ri + c.spin[j] * rj).cross(n)
}

/// Asks the processor to fetch the contact states of a sub-batch's evaluated pairs (`idx`)
/// before their geometry is worked out: the loads of the states then overlap with each
/// other and with the geometry instead of each waiting in turn (all three cache lines a
/// 120-byte state can span). Measured on the AMD EPYC host of the fifth session of
/// 2026-12-03: S1 10k one thread 0.914 × the time (side by side, 8 pairs; doc/performance.md);
/// prefetching the next sub-batch's states instead (found one sub-batch ahead) was 1.04 ×
/// slower, prefetching the particles' velocities and spins too no gain.
#[inline(always)]
fn prefetch_states(hots: &[HotPair], block: &[ContactState], idx: &[u32]) {
    #[cfg(target_arch = "x86_64")]
    for &k in idx {
        let s = hots[k as usize].slot as usize;
        if s < block.len() {
            let p = (&block[s]) as *const ContactState as *const i8;
            // SAFETY: `p`, `p + 64` and `p + 111` lie inside the state `block[s]`; and a
            // prefetch reads no value and never faults, whatever the address.
            unsafe {
                use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
                _mm_prefetch::<_MM_HINT_T0>(p);
                _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64));
                _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(size_of::<ContactState>() - 1));
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (hots, block, idx);
}

/// Whether the reach tests run four candidates at a time (`reach::mask_avx2`): the
/// processor has AVX2 and the scene no periodic axis.
#[inline(always)]
fn vector_reach(c: &PairCtx) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        c.periodic == [false; 3] && std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = c;
        false
    }
}

/// Whether the steady contacts of this step go through the vectorised kernel
/// ([`lanes::hertz_noslip`]): a dry scene without adhesion, the no-slip law with rotation,
/// no Rayleigh tangential dashpot, a time step (not the states-only pass).
#[inline(always)]
fn batches_steady<const ADH: bool, const LIQ: bool>(c: &PairCtx) -> bool {
    let laws = c.laws;
    !ADH && !LIQ
        && laws.tangential == TangentialChoice::NoSlip
        && !(laws.beta > 0.0)
        && laws.rotation
        && c.model.rotation
        && laws.dt > 0.0
}

/// Work arrays of the pair loop's sub-batches, made once per task and step and reused by
/// every block (every entry is written before it is read; made per block, their 12 KB of
/// initial zeros cost a noticeable part of the step).
struct Scratch {
    batch: lanes::Batch,
    kins: [Kin; lanes::SUB],
    idx: [u32; lanes::SUB],
    /// The evaluated pairs' normals and distances.
    ds: [Vec3; lanes::SUB],
    dists: [f64; lanes::SUB],
    /// Lane of each evaluated pair in the batch (u8::MAX: general kernel).
    lane: [u8; lanes::SUB],
}

impl Scratch {
    fn new() -> Scratch {
        Scratch {
            batch: lanes::Batch::new(),
            kins: [Kin::ZERO; lanes::SUB],
            idx: [0; lanes::SUB],
            ds: [Vec3::zeros(); lanes::SUB],
            dists: [0.0; lanes::SUB],
            lane: [u8::MAX; lanes::SUB],
        }
    }
}

/// The geometry of an evaluated pair. A pair that comes within reach for the first time
/// gets its state appended to its block. `UNI`: the particles are all alike (`u`).
#[inline(always)]
fn pair_kin<const UNI: bool>(
    h: &mut HotPair,
    slot: &mut u32,
    block: &mut Vec<ContactState>,
    c: &PairCtx,
    u: &UniPair,
    (n, dist): (Vec3, f64),
) -> Kin {
    let (i, j) = (h.i as usize, h.j as usize);
    if h.slot == NO_STATE {
        h.slot = block.len() as u32;
        *slot = h.slot;
        contacts::grow_block(block);
        block.push(ContactState::default());
    }
    let (ri, rj) = if UNI {
        (u.r, u.r)
    } else {
        (c.radius[i], c.radius[j])
    };
    let v_rel = rel_velocity(c, (i, j), (ri, rj), &n);
    let (r_star, m_star) = if UNI {
        (u.r_star, u.m_star)
    } else {
        let (mi, mj) = (c.mass[i], c.mass[j]);
        (ri * rj / (ri + rj), mi * mj / (mi + mj))
    };
    Kin {
        n,
        gap: dist - ri - rj,
        v_rel,
        r_star,
        m_star,
        r1: ri,
        r2: rj,
    }
}

/// Primes the contact states if commands changed the scene (no-op otherwise, or when the
/// scene cannot cycle yet).
pub fn prime_if_stale(scene: &mut Scene) {
    if !scene.contacts.stale || scene.particles.is_empty() {
        return;
    }
    if let Ok(model) = check(scene) {
        let (tol, _) = search_distances(scene, &model);
        prime(scene, &model, tol);
        scene.contacts.tol = tol;
    }
}

/// Re-evaluates the contact states at the current positions without moving anything (after
/// commands changed the scene): initial overlaps get their strain energy, which is booked as
/// energy put in by the commands.
pub fn prime(scene: &mut Scene, model: &Model, tol: f64) {
    let before = super::energy::stored(scene).total();
    rebuild(scene, tol);
    let _ = forces(scene, model, 0.0);
    finish_deferred(scene, model.rotation);
    let after = super::energy::stored(scene).total();
    scene.ledger.commands += after - before;
}

/// Step 2 of a cycle: wall forces and motion, then the particle update.
fn move_all(
    scene: &mut Scene,
    model: &Model,
    xres: f64,
    acc: Acc,
    keep: bool,
) -> Result<(), Blowup> {
    let wall_work = move_walls(scene, model.dt);
    let mv = Mover::of(scene, model);
    let deferred = std::mem::take(&mut scene.contacts.deferred);
    let contacts = &scene.contacts;
    let left = deferred.then_some(Left {
        scatter: Some((&contacts.scatter, &contacts.hot, &contacts.out)),
        walls: &contacts.wall_out.pieces,
    });
    let p = &mut scene.particles;
    let fixed_arrays = (&p.mass[..], &p.agg[..], &p.fixed[..], &p.radius[..]);
    // Parallel over fixed chunks of particles; the partial sums are added in chunk order,
    // so the ledger does not depend on the number of threads.
    let parts: Vec<ChunkSums> = p
        .vel
        .par_chunks_mut(CHUNK)
        .zip(p.pos.par_chunks_mut(CHUNK))
        .zip(p.disp.par_chunks_mut(CHUNK))
        .zip(p.spin.par_chunks_mut(CHUNK))
        .zip(p.rot.par_chunks_mut(CHUNK))
        .zip(p.force.par_chunks_mut(CHUNK))
        .zip(p.moment.par_chunks_mut(CHUNK))
        .enumerate()
        .map(
            |(chunk, ((((((vel, pos), disp), spin), rot), force), moment))| {
                let sums = mv.chunk(
                    chunk,
                    ChunkArrays {
                        vel,
                        pos,
                        disp,
                        spin,
                        rot,
                        force: &mut *force,
                        moment: &mut *moment,
                    },
                    fixed_arrays,
                    left,
                );
                // Cleared while the chunk is in the cache, for the next step's sums (a
                // particle with a non-finite state keeps its force for the message).
                if !keep && sums.3.is_none() {
                    force.fill(Vec3::zeros());
                    moment.fill(Vec3::zeros());
                }
                sums
            },
        )
        .collect();
    finish_move(scene, (xres, keep), acc, wall_work, &parts, model.dt)
}

/// The walls' measured forces and the work they put in; then their motion (servo,
/// advance). Returns the work of the walls on the particles in this step.
fn move_walls(scene: &mut Scene, dt: f64) -> f64 {
    // The walls' measured forces: a plane's normal force, a sphere's radial one.
    let mut radial = vec![0.0; scene.walls.len()];
    for w in scene.walls.iter_mut() {
        let f = Vec3::from(w.force);
        w.normal_force = match w.geom {
            WallGeom::Plane { normal, .. } => -f.dot(&Vec3::from(normal).normalize()),
            _ => 0.0,
        };
    }
    let round = |w: &Wall| matches!(w.geom, WallGeom::Sphere { .. } | WallGeom::Obstacle { .. });
    let wall_pairs: &[WallPair] = if scene.walls.iter().any(round) {
        &scene.contacts.wall_pairs
    } else {
        &[]
    };
    for c in wall_pairs {
        let w = &mut scene.walls[c.wall as usize];
        if let WallGeom::Sphere { .. } | WallGeom::Obstacle { .. } = w.geom {
            let fn_ = c.s.normal_force
                + c.s.damp_force
                + c.s.bridge.as_ref().map_or(0.0, |b| b.f_visc - b.f_static);
            if c.s.touching || c.s.bridge.is_some() {
                w.normal_force += fn_;
                radial[c.wall as usize] += fn_;
            }
        }
    }
    // The servos set the velocities the walls move with until the next step; a wall's work
    // on the particles is its force times its displacement about this instant, the mean of
    // the velocity it came with and the one it goes on with (central in time, as the
    // particles' booking: exact for the scheme when a servo changes the speed every step).
    let mut wall_work = 0.0;
    for (w, fr) in scene.walls.iter_mut().zip(&radial) {
        let (vel_old, vr_old) = (Vec3::from(w.vel), w.vr);
        walls::servo(w);
        let vel = (vel_old + Vec3::from(w.vel)) * 0.5;
        let vr = 0.5 * (vr_old + w.vr);
        // Work done by a moving wall on the particles: −(force on wall)·v_w Δt.
        wall_work -= Vec3::from(w.force).dot(&vel) * dt;
        let sign = match w.geom {
            WallGeom::Sphere { .. } => 1.0,
            WallGeom::Obstacle { .. } => -1.0,
            WallGeom::Plane { .. } => 0.0,
        };
        if sign != 0.0 {
            wall_work -= sign * fr * vr * dt;
        }
        walls::advance(w, dt);
    }
    wall_work
}

/// One chunk's sums of the update: work of gravity, mass-damping loss, largest displacement
/// component since the last rebuild, the first particle with a non-finite state, whether a
/// particle is beyond an open side, the work of the velocity constraints (`Fix`, 2-D).
type ChunkSums = (f64, f64, f64, Option<usize>, bool, f64);

/// A chunk's particle arrays.
struct ChunkArrays<'a> {
    vel: &'a mut [Vec3],
    pos: &'a mut [Vec3],
    disp: &'a mut [Vec3],
    spin: &'a mut [Vec3],
    rot: &'a mut [Vec3],
    force: &'a mut [Vec3],
    moment: &'a mut [Vec3],
}

/// What the force step left to the update (see [`finish_chunk`]): the shared particles'
/// pairs and slots (none with one thread), the wall forces.
#[derive(Clone, Copy)]
struct Left<'a> {
    scatter: Option<(&'a Incidence, &'a [HotPair], &'a [PairForce])>,
    walls: &'a [WallPiece],
}

/// The constants of the particle update of a step, Lian (5.9)–(5.14).
#[derive(Clone, Copy)]
struct Mover {
    dt: f64,
    g: Vec3,
    two_d: bool,
    alpha: f64,
    damp: f64,
    inv: f64,
    cg: [f64; 2],
    centres: [Option<Vec3>; 2],
    fmm: f64,
    rotation: bool,
    size: [f64; 3],
    periodic: [bool; 3],
    plain: Option<leapfrog::Plain>,
}

impl Mover {
    fn of(scene: &Scene, model: &Model) -> Mover {
        let dt = model.dt;
        let g = Vec3::from(scene.gravity);
        let two_d = scene.settings.two_d;
        let alpha = scene.damping_pp.alpha;
        let damp = (1.0 - 0.5 * alpha * dt) / (1.0 + 0.5 * alpha * dt);
        let inv = 1.0 / (1.0 + 0.5 * alpha * dt);
        let cg = scene.cgravity;
        let centres = scene.regions.map(|r| r.map(|r| Vec3::from(r.centre)));
        let fmm = scene.fmm;
        let rotation = model.rotation;
        let (size, periodic) = (scene.size, scene.settings.periodic);
        let plain = (!two_d && alpha == 0.0).then(|| {
            let mut c = leapfrog::Plain {
                g: scene.gravity,
                fmm,
                damp,
                dt,
                rotation,
                lo: [f64::NEG_INFINITY; 3],
                hi: [f64::INFINITY; 3],
                uniform: model.uniform.map(|u| {
                    let (mut sv, mut sw) = ([0.0], [0.0]);
                    step_factors(&[u.mass], &[u.radius], dt, inv, &mut sv, &mut sw);
                    leapfrog::UniformSteps {
                        mass: u.mass,
                        step_v: sv[0],
                        step_w: sw[0],
                    }
                }),
            };
            for k in 0..3 {
                if !periodic[k] {
                    (c.lo[k], c.hi[k]) = (0.0, size[k]);
                }
            }
            c
        });
        Mover {
            dt,
            g,
            two_d,
            alpha,
            damp,
            inv,
            cg,
            centres,
            fmm,
            rotation,
            size,
            periodic,
            plain,
        }
    }

    /// Moves the particles of chunk `chunk` (after adding what the force step `left`).
    fn chunk(
        &self,
        chunk: usize,
        a: ChunkArrays<'_>,
        (mass, agg, fixed, radius): (&[f64], &[u8], &[u8], &[f64]),
        left: Option<Left<'_>>,
    ) -> ChunkSums {
        let Mover {
            dt,
            g,
            two_d,
            alpha,
            damp,
            inv,
            cg,
            centres,
            fmm,
            rotation,
            size,
            periodic,
            plain,
        } = *self;
        let ChunkArrays {
            vel,
            pos,
            disp,
            spin,
            rot,
            force,
            moment,
        } = a;
        // First what the force step left (`finish_chunk`): with several threads the shared
        // particles' sums; the moments times the radius; the wall forces.
        if let Some(left) = left {
            finish_chunk(left, chunk, (&mut *force, &mut *moment), radius, rotation);
        }
        let (force, moment) = (&*force, &*moment);
        let mut w_grav = 0.0;
        let mut d_mass = 0.0;
        let mut w_fix = 0.0;
        let mut max_disp = 0.0f64;
        let mut bad: Option<usize> = None;
        let mut outside = false;
        let lo = chunk * CHUNK;
        let hi = lo + vel.len();
        let n = vel.len();
        // Plain particles (no aggregate gravity, nothing fixed, no 2-D constraint, no
        // mass damping): the component update, bitwise the same as the loop below.
        let plain_chunk = plain.is_some()
            && agg[lo..hi].iter().zip(&fixed[lo..hi]).all(|(&a, &fx)| {
                fx & 0x3f == 0 && (a == 0 || cg.get(a as usize - 1).is_none_or(|&g| !(g > 0.0)))
            });
        // The step factors Δt/m and Δt/I of the chunk first, in a loop of their own that
        // the compiler vectorises (the divisions then do not stall the update below); not
        // needed by the plain update of alike particles (`Plain::uniform`).
        let mut step_v = [0.0; CHUNK];
        let mut step_w = [0.0; CHUNK];
        let alike = plain_chunk && plain.is_some_and(|c| c.uniform.is_some());
        if !alike {
            step_factors(
                &mass[lo..hi],
                &radius[lo..hi],
                dt,
                inv,
                &mut step_v,
                &mut step_w,
            );
        }
        if let (Some(c), true) = (&plain, plain_chunk) {
            let (mass, step_v, step_w) = if alike {
                (&[][..], &[][..], &[][..])
            } else {
                (&mass[lo..hi], &step_v[..n], &step_w[..n])
            };
            let s = leapfrog::update(
                c,
                leapfrog::Run {
                    mass,
                    step_v,
                    step_w,
                    force,
                    moment,
                    vel: &mut *vel,
                    pos: &mut *pos,
                    disp: &mut *disp,
                    spin: &mut *spin,
                    rot: &mut *rot,
                },
            );
            if !s.finite {
                bad = (0..n)
                    .find(|&l| !all_finite(&pos[l], &vel[l]))
                    .map(|l| lo + l);
            }
            return (s.w_grav, 0.0, s.max_disp, bad, s.outside, 0.0);
        }
        for l in 0..vel.len() {
            let i = chunk * CHUNK + l;
            let m = mass[i];
            let mut body = g;
            let a = agg[i] as usize;
            if a > 0
                && cg[a - 1] > 0.0
                && let Some(c) = centres[a - 1]
            {
                let e = c - pos[l];
                let len = e.norm();
                if len > 0.0 {
                    body += e * (cg[a - 1] / len);
                }
            }
            let fb = body * (m * fmm);
            let f = force[l] + fb;
            let v_old = vel[l];
            let mut v = v_old * damp + f * step_v[l];
            let fx = fixed[i];
            keep_fixed(&mut v, &v_old, fx);
            if two_d {
                v.z = 0.0;
            }
            if fx & 7 != 0 || two_d {
                w_fix += constraint_work(m, &v_old, &v, &f, alpha, dt, fx & 7, two_d);
            }
            let vbar = (v + v_old) * 0.5;
            w_grav += fb.dot(&vbar) * dt;
            if alpha != 0.0 {
                // (With α = 0 the term is +0 and adding it changes nothing.)
                d_mass += alpha * m * vbar.norm_squared() * dt;
            }
            vel[l] = v;
            let dx = v * dt;
            pos[l] += dx;
            disp[l] += dx;
            let x = pos[l];
            outside |= outside_open_side(&x, &size, &periodic);
            max_disp = max_disp.max(disp[l].amax());
            if rotation {
                let inertia = 0.4 * m * radius[i] * radius[i];
                let w_old = spin[l];
                let mut w = w_old * damp + moment[l] * step_w[l];
                keep_fixed(&mut w, &w_old, fx >> 3);
                if two_d {
                    w.x = 0.0;
                    w.y = 0.0;
                }
                if (fx >> 3) & 7 != 0 || two_d {
                    // (In 2-D the spin keeps only its z component: x and y are held.)
                    let held = ((fx >> 3) & 7) | if two_d { 0b011 } else { 0 };
                    w_fix +=
                        constraint_work(inertia, &w_old, &w, &moment[l], alpha, dt, held, false);
                }
                if alpha != 0.0 {
                    let wbar = (w + w_old) * 0.5;
                    d_mass += alpha * inertia * wbar.norm_squared() * dt;
                }
                spin[l] = w;
                rot[l] += w * dt;
            }
            if !all_finite(&pos[l], &v) && bad.is_none() {
                bad = Some(i);
            }
        }
        (w_grav, d_mass, max_disp, bad, outside, w_fix)
    }
}

/// The work a velocity constraint did in one step on the components it held (bit k of
/// `held`: component k; `flat`: the z component, held at 0 in 2-D): the change of their
/// kinetic energy less the work booked for them (the force `f` with v̄ Δt, the mass damping
/// α m v̄² Δt), so that the ledger closes when a user drives particles with `Fix`.
#[allow(clippy::too_many_arguments)]
fn constraint_work(
    m: f64,
    v_old: &Vec3,
    v: &Vec3,
    f: &Vec3,
    alpha: f64,
    dt: f64,
    held: u8,
    flat: bool,
) -> f64 {
    let mut w = 0.0;
    for k in 0..3 {
        if held & (1 << k) != 0 || (flat && k == 2) {
            let vbar = 0.5 * (v[k] + v_old[k]);
            let kinetic = 0.5 * m * (v[k] * v[k] - v_old[k] * v_old[k]);
            w += kinetic - (f[k] * vbar * dt - alpha * m * vbar * vbar * dt);
        }
    }
    w
}

/// The end of a step: the chunks' sums (in chunk order), whether the update cleared the
/// forces (not with `keep`), blow-up check, periodic wrap, the rebuild flag and the ledger.
fn finish_move(
    scene: &mut Scene,
    (xres, keep): (f64, bool),
    acc: Acc,
    wall_work: f64,
    parts: &[ChunkSums],
    dt: f64,
) -> Result<(), Blowup> {
    scene.contacts.zeroed = !keep && parts.iter().all(|s| s.3.is_none());
    let mut w_grav = 0.0;
    let mut d_mass = 0.0;
    let mut max_disp = 0.0f64;
    let mut bad: Option<usize> = None;
    let mut outside = false;
    let mut w_fix = 0.0;
    for &(wg, dm, md, b, o, wf) in parts {
        outside |= o;
        w_grav += wg;
        d_mass += dm;
        max_disp = max_disp.max(md);
        bad = bad.or(b);
        w_fix += wf;
    }
    scene.maybe_outside = outside;
    let p = &mut scene.particles;
    if let Some(i) = bad {
        return Err(Blowup {
            cycle: scene.cycle + 1,
            message: format!(
                "numerical blow-up at cycle {}: particle {} has a non-finite position or velocity (force {:?}). \
                 Hint: reduce FRAction, check for deep initial overlaps, very stiff dashpots or servo gains",
                scene.cycle + 1,
                p.id[i],
                [p.force[i].x, p.force[i].y, p.force[i].z]
            ),
        });
    }
    // Wrap periodic coordinates.
    for k in 0..3 {
        if scene.settings.periodic[k] {
            let l = scene.size[k];
            for x in p.pos.iter_mut() {
                if x[k] < 0.0 || x[k] >= l {
                    x[k] = x[k].rem_euclid(l);
                }
            }
        }
    }
    if scene.zero_always {
        // The kinetic energy taken out leaves the books as a command's change.
        let mut taken = 0.0;
        for i in 0..p.len() {
            taken += 0.5 * p.mass[i] * p.vel[i].norm_squared()
                + 0.5 * p.inertia(i) * p.spin[i].norm_squared();
            p.vel[i] = Vec3::zeros();
            p.spin[i] = Vec3::zeros();
        }
        scene.ledger.commands -= taken;
    }
    // A wall that moved more than XRES since the last rebuild is re-mapped like a particle
    // (its travel closes a gap as much as a particle's displacement).
    scene.contacts.max_disp = Some(max_disp);
    if max_disp > xres || scene.walls.iter().any(|w| w.travel > xres) {
        scene.contacts.remap = true;
    }

    let l = &mut scene.ledger;
    // The work of velocity constraints (Fix, 2-D) is put in by a command, as its kinetic
    // energy is.
    l.commands += w_fix;
    l.gravity += w_grav;
    l.walls += wall_work;
    l.damping_mass += d_mass;
    l.friction += acc.friction;
    l.damping_contact += acc.damping_contact;
    l.viscous += acc.viscous;
    l.adhesion += acc.adhesion;
    l.rupture += acc.rupture;
    scene.cycle += 1;
    scene.time += dt;
    Ok(())
}

/// Δt/m·inv and Δt/I·inv (I = 0.4 m R², a solid sphere) for a chunk of particles, as the
/// update computes them (Lian (5.9)–(5.10) with the mass-damping factor `inv`).
fn step_factors(mass: &[f64], radius: &[f64], dt: f64, inv: f64, sv: &mut [f64], sw: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above); same arithmetic, no FMA.
            return unsafe { step_factors_avx2(mass, radius, dt, inv, sv, sw) };
        }
    }
    step_factors_impl(mass, radius, dt, inv, sv, sw)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn step_factors_avx2(
    mass: &[f64],
    radius: &[f64],
    dt: f64,
    inv: f64,
    sv: &mut [f64],
    sw: &mut [f64],
) {
    step_factors_impl(mass, radius, dt, inv, sv, sw)
}

#[inline(always)]
fn step_factors_impl(
    mass: &[f64],
    radius: &[f64],
    dt: f64,
    inv: f64,
    sv: &mut [f64],
    sw: &mut [f64],
) {
    for (((&m, &r), v), w) in mass
        .iter()
        .zip(radius)
        .zip(sv.iter_mut())
        .zip(sw.iter_mut())
    {
        *v = dt / m * inv;
        let inertia = 0.4 * m * r * r;
        *w = dt / inertia * inv;
    }
}

/// Every component of the two vectors is finite (without a branch per component: x·0 is
/// ±0 for finite x and NaN otherwise, and a sum of zeros is zero).
#[inline(always)]
fn all_finite(a: &Vec3, b: &Vec3) -> bool {
    (a.x * 0.0 + a.y * 0.0 + a.z * 0.0 + b.x * 0.0 + b.y * 0.0 + b.z * 0.0) == 0.0
}

/// Fixed degrees of freedom (`Fix`): components whose bit is set in `mask` (bit k for
/// component k) keep their old velocity.
#[inline]
fn keep_fixed(v: &mut Vec3, old: &Vec3, mask: u8) {
    if mask & 7 != 0 {
        for k in 0..3 {
            if mask & (1 << k) != 0 {
                v[k] = old[k];
            }
        }
    }
}

/// The position is beyond a non-periodic side of the work-space.
#[inline]
fn outside_open_side(x: &Vec3, size: &[f64; 3], periodic: &[bool; 3]) -> bool {
    (0..3).any(|k| !periodic[k] && (x[k] < 0.0 || x[k] > size[k]))
}

/// Removes particles that left through an open side (counted in `lost`); returns whether
/// any was.
fn remove_lost(scene: &mut Scene) -> bool {
    if !scene.maybe_outside {
        return false;
    }
    let (size, periodic) = (scene.size, scene.settings.periodic);
    let out: Vec<bool> = scene
        .particles
        .pos
        .iter()
        .map(|x| outside_open_side(x, &size, &periodic))
        .collect();
    if !out.contains(&true) {
        return false;
    }
    // Their kinetic energy leaves the books with them.
    for (i, _) in out.iter().enumerate().filter(|(_, o)| **o) {
        let p = &scene.particles;
        let e = 0.5 * p.mass[i] * p.vel[i].norm_squared()
            + 0.5 * p.inertia(i) * p.spin[i].norm_squared();
        scene.ledger.commands -= e;
        scene.lost += 1;
    }
    remove_where(scene, &out);
    true
}

/// Removes the particles marked in `gone`, with their pairs and wall pairs (the indices of
/// the others re-mapped).
fn remove_where(scene: &mut Scene, gone: &[bool]) {
    let mut i = 0;
    let mut k = 0;
    while i < scene.particles.len() {
        if gone[k] {
            scene.particles.remove(i);
        } else {
            i += 1;
        }
        k += 1;
    }
    // Indices changed: drop pairs of removed particles and re-index.
    let ids = &scene.particles.id;
    let mut index = std::collections::HashMap::new();
    for (k, &id) in ids.iter().enumerate() {
        index.insert(id, k as u32);
    }
    scene
        .contacts
        .retain_pairs(|c| match (index.get(&c.ida), index.get(&c.idb)) {
            (Some(&a), Some(&b)) => {
                c.i = a;
                c.j = b;
                true
            }
            _ => false,
        });
    scene
        .contacts
        .wall_pairs
        .retain_mut(|c| match index.get(&c.id) {
            Some(&a) => {
                c.i = a;
                true
            }
            None => false,
        });
    scene.contacts.clear_derived();
}

/// Particles whose centre lies behind a wall's surface (gap < −R: behind a plane, outside a
/// container, inside an obstacle), as (particle, wall) in particle order: every particle
/// against every wall when `all`, else the wall pairs (candidates) only.
fn behind_walls(scene: &Scene, all: bool) -> Vec<(usize, usize)> {
    let p = &scene.particles;
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    let behind = |i: usize, w: usize| {
        let (gap, _) = shapes[w].gap(&p.pos[i], p.radius[i]);
        // (NaN is not "behind": a non-finite state is the blow-up check's.)
        gap < -p.radius[i]
    };
    if all {
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
    } else {
        let mut out: Vec<(usize, usize)> = scene
            .contacts
            .wall_pairs
            .iter()
            .filter(|c| behind(c.i as usize, c.wall as usize))
            .map(|c| (c.i as usize, c.wall as usize))
            .collect();
        out.sort_unstable();
        out
    }
}

/// What a crossing looks like: the particle, the wall, how far behind, the speeds against
/// the step.
fn crossing(scene: &Scene, (i, w): (usize, usize), dt: f64) -> String {
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
fn tunnelled(scene: &Scene, behind: &[(usize, usize)], dt: f64) -> Blowup {
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
fn delete_tunnelled(scene: &mut Scene, behind: &[(usize, usize)], dt: f64) {
    let mut gone = vec![false; scene.particles.len()];
    for &(i, w) in behind {
        if !gone[i] {
            gone[i] = true;
            let note = format!(
                "{}; deleted (SET TUNnel DELETE)",
                crossing(scene, (i, w), dt)
            );
            scene.notes.push(note);
        }
    }
    let before = super::energy::stored(scene).total();
    let n = gone.iter().filter(|g| **g).count() as u64;
    remove_where(scene, &gone);
    let after = super::energy::stored(scene).total();
    scene.ledger.commands += after - before;
    scene.lost += n;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `blocks` blocks of pairs over `np` particles, pair k's first particle k·np/len.
    fn hot_list(blocks: usize, np: usize) -> Vec<HotPair> {
        let n = blocks * BLOCK;
        (0..n)
            .map(|k| HotPair {
                i: (k * np / n) as u32,
                j: ((k * np / n + 1) % np) as u32,
                ..Default::default()
            })
            .collect()
    }

    fn check_cover(ranges: &[PairRange], n: usize, np: usize) {
        assert_eq!(ranges[0].pairs.start, 0);
        assert_eq!(ranges[0].parts.start, 0);
        for w in ranges.windows(2) {
            assert_eq!(w[0].pairs.end, w[1].pairs.start);
            assert_eq!(w[0].parts.end, w[1].parts.start);
            assert_eq!(w[0].pairs.end % BLOCK, 0, "whole blocks");
        }
        assert_eq!(ranges.last().map(|r| r.pairs.end), Some(n));
        assert_eq!(ranges.last().map(|r| r.parts.end), Some(np));
    }

    /// Uniform cost: two ranges of 20 blocks each. Pairs measured twice as slow per unit in
    /// the first half of the list: the first range gets 15 blocks (time 2x for the cut x
    /// blocks in, against 2(20 − x) + 20 for the rest).
    #[test]
    fn the_cut_follows_the_measured_rates() {
        let np = 4000;
        let hot = hot_list(40, np);
        let (r, costs) = pair_ranges(&hot, np, 2, &[]);
        check_cover(&r, hot.len(), np);
        assert_eq!(r[0].pairs.end, 20 * BLOCK);
        assert_eq!(costs, vec![20 * BLOCK, 20 * BLOCK]);
        assert_eq!(r[1].parts.start, hot[20 * BLOCK].i as usize);

        let (r, costs) = pair_ranges(&hot, np, 2, &[(0.5, 2.0), (1.0, 1.0)]);
        check_cover(&r, hot.len(), np);
        assert_eq!(r[0].pairs.end, 15 * BLOCK);
        assert_eq!(costs, vec![15 * BLOCK, 25 * BLOCK]);
    }

    /// Rates relative to the mean time per unit of cost, clamped.
    #[test]
    fn balance_rates_are_relative_to_the_mean() {
        assert!(Balance::default().rates().is_none());
        assert!(!Balance::default().measured());
        let b = Balance {
            tasks: vec![(0.5, 100, 2.0), (1.0, 100, 1.0)],
        };
        assert!(b.measured());
        let rates = b.rates().unwrap();
        // Mean 3 s / 200 = 0.015 s per unit.
        assert!((rates[0].1 - 2.0 / 1.5).abs() < 1e-12);
        assert!((rates[1].1 - 1.0 / 1.5).abs() < 1e-12);
        let skewed = Balance {
            tasks: vec![(0.05, 10, 10.0), (1.0, 190, 0.01)],
        };
        let rates = skewed.rates().unwrap();
        assert_eq!((rates[0].1, rates[1].1), (2.0, 0.5));
    }
}
