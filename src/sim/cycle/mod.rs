//! `Cycle n`: the time step. Forces from the current positions (contacts, bridges, walls),
//! then the leap-frog central-difference update with global mass-proportional damping,
//! Lian (5.9)–(5.14):
//!
//! v_new = ((m/Δt − β/2) v_old + F + m g) / (m/Δt + β/2), β = α_R m;  x += v_new Δt,
//!
//! and the same for rotations with I = 2/5 m R². The energy ledger is updated exactly for the
//! scheme: the damping loss is β |v̄|² Δt and the work of gravity m g·v̄ Δt with
//! v̄ = (v_old + v_new)/2, so that ½ m v_new² − ½ m v_old² = (F + m g − β v̄)·v̄ Δt.
//!
//! The step along its seams (a function here calls down, never up):
//! - this file: the driver — `run_watched` (the Cycle: snapshots, energy audit, interrupts),
//!   `one_step` (forces, then update), priming contacts after a command changed the scene;
//! - `checks`: is the scene complete (`check`), what to warn about (`warnings`), tunnelling;
//! - `distances`: TOL/XRES, candidate-list rebuilds, per-group reach margins;
//! - `forces`: orchestration of the contact forces (serial, tasks, chunk sums);
//! - `pairs`: the pair loop over blocks of contact states (uniform particles, SIMD lanes);
//! - `wall_loop`: particle–wall contacts and the walls' motion;
//! - `update`: the leap-frog update, fixed components, removal of lost particles;
//! - `fused`: one parallel region per step (forces and update of a chunk together);
//! - `reach`: which pairs can touch within the step.

use rayon::prelude::*;

use super::contacts::{
    self, BLOCK, Balance, ContactState, HotPair, Incidence, NO_STATE, Pair, PairForce, PairRange,
    StateBlock, StepParts, WALL_BLOCK, WallForce, WallOut, WallPair, WallPiece,
};
use super::interact::{Acc, Kin, Laws, interact, interact_rows};
use super::lanes;
use super::leapfrog;
use super::params::{self, Model};
use super::scene::{Scene, Speeds, TunnelAction, Vec3, Wall};
use super::search;
use super::walls::{self, WallShape, surface_speed, surface_velocity, wall_gap, wall_r_star};
use crate::sim::model::{TangentialChoice, WallGeom};

mod checks;
mod clearance;
mod distances;
mod forces;
mod fused;
mod pairs;
mod reach;
mod update;
mod wall_loop;
pub use checks::*;
pub use distances::*;
use forces::*;
use fused::View;
use pairs::*;
pub use update::delete_marked;
use update::*;
use wall_loop::*;

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
    run_until(scene, n, watch, None)
}

/// [`run_watched`] with a condition read after every step (`Cycle n UNTIL cond`): the
/// first step after which `until` holds is the last. With a condition every step keeps its
/// forces in the particle arrays, for the condition to read (the same bits: the last step
/// of every Cycle keeps them).
pub fn run_until(
    scene: &mut Scene,
    n: u64,
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
    until: Option<&mut (dyn FnMut(&Scene) -> bool + Send)>,
) -> Result<(Model, u64), Blowup> {
    if scene.derived.servo.is_none() {
        // A Cycle without the stress servo: the next servo Cycle starts its own.
        scene.carried.servo = None;
    }
    let r = super::parallel::awake::while_running(|pacer| {
        run_steps(&mut *scene, n, watch, until, pacer)
    });
    // (Derived per step; not kept between commands.)
    scene.derived.reach_ext = Vec::new();
    scene.derived.speeds = Speeds::default();
    scene.contacts.step.margins = [0.0; 2];
    r
}

/// The body of [`run`].
fn run_steps(
    scene: &mut Scene,
    n: u64,
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
    mut until: Option<&mut (dyn FnMut(&Scene) -> bool + Send)>,
    pacer: &mut super::parallel::awake::Pacer,
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
    if let Some(m) = crate::sim::cell::shrink_refusal(scene, n, model.dt) {
        return Err(Blowup {
            cycle: scene.cycle,
            message: m,
        });
    }
    let (tol, xres) = prepare(scene, &mut model);
    // (A step too long for the fastest contact at the start is the session's pre-Cycle
    // warning, `warnings`.)
    let mut warned_step = scene.settings.auto_step.is_some()
        || super::contact_time::warning(scene, &model, model.fraction).is_some();
    let mut key_bound = None;
    // Energy runaway: no energy may appear that the ledger did not put in. What commands
    // left unbooked is the reference; the energy cycling created since the scene was made
    // is checked against the energy the scene had or was given (`Audit`).
    let audit = Audit::of(scene);
    let mut snapshot = snapshot_of(scene);
    let every = scene.settings.snapshot_every.max(1);
    // A snapshot is taken before step `s` (of this Cycle) when this holds.
    let snapshot_before = |s: u64| s > 0 && s.is_multiple_of(every);
    let mut ran = n;
    // (`after_step`: the smallest radius, and the relative travel since the last check.)
    let rmin = scene.min_radius();
    let mut step_watch = StepWatch::default();
    let threads = model.plan.threads;
    for step in 0..n {
        // An interrupt makes this step the last, as if the Cycle had been this long.
        let last = watch(scene, step);
        if snapshot_before(step) {
            if let Some(e) = audit.check(scene, &model) {
                return Err(stop(scene, snapshot, e));
            }
            // The old snapshot goes before the new one is made (never three copies at once).
            snapshot.particles = Default::default();
            snapshot.contacts = Default::default();
            snapshot = snapshot_of(scene);
        }
        let (lost_before, commands_before) = (scene.lost, scene.ledger.commands);
        let rebuilds_before = scene.contacts.rebuilds();
        let allowed = 1e3 * audit.scale(scene);
        // The forces of the last step are kept for what reads them after the Cycle (PRint,
        // plots, checkpoints), and those of the step before a snapshot for the snapshot.
        // So are those of a step whose history row records a group (its force sum,
        // `GROup name HIStory`).
        let keep = last
            || step + 1 == n
            || snapshot_before(step + 1)
            || records_a_group(scene)
            || until.is_some();
        // With the pollers asleep the step runs on this thread alone: the one-thread plan
        // (the same bits; `Pacer::asleep`).
        model.plan.threads = if pacer.asleep() { 1 } else { threads };
        let mut result = one_step(scene, &mut model, (tol, xres), (keep, step == 0));
        if result.is_ok() && scene.contacts.rebuilds() != rebuilds_before && !warned_step {
            warned_step = warn_step(scene, &model, &mut key_bound);
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
        if result.is_ok() {
            result = after_step(scene, model.dt, rmin, &mut step_watch);
        }
        if let Err(e) = result {
            return Err(stop(scene, snapshot, e));
        }
        if scene.settings.history_every > 0
            && scene.cycle.is_multiple_of(scene.settings.history_every)
        {
            record_history(scene);
        }
        pacer.step_done();
        if let Some(u) = until.as_mut()
            && u(scene)
        {
            ran = step + 1;
            break;
        }
        if last {
            ran = step + 1;
            break;
        }
    }
    model.plan.threads = threads;
    // The end of the Cycle is audited too (a Cycle shorter than the snapshot interval).
    if let Some(e) = audit.check(scene, &model) {
        return Err(stop(scene, snapshot, e));
    }
    Ok((model, ran))
}

/// Whether the next step's history row records a group (`GROup name HIStory`), whose force
/// sum needs the step's forces kept.
fn records_a_group(scene: &Scene) -> bool {
    let every = scene.settings.history_every;
    every > 0
        && (scene.cycle + 1).is_multiple_of(every)
        && scene.groups.list.iter().any(|g| g.record)
}

/// The start of a Cycle with particles: plane walls open the periodic axes they cross, the
/// search distances, the contact states primed if a command changed the scene (else a
/// re-mapping if only TOL changed), and the step of `FRAction AUTO`. Returns TOL and XRES.
fn prepare(scene: &mut Scene, model: &mut Model) -> (f64, f64) {
    // A plane wall across a periodic axis makes the axis open (doc/limits.md; a checkpoint
    // of an earlier version, or walls turned since, may hold one).
    let opened = walls::open_crossed(&scene.walls, &mut scene.settings.periodic);
    if opened != [false; 3] {
        scene.derived.notes.push(format!(
            "the {} axis is now open: a plane wall crosses it, and a particle leaving through one side would re-enter behind the wall",
            walls::axis_names(&opened)
        ));
    }
    let (tol, xres) = search_distances(scene, model);
    // Commands may have changed contact states between Cycles: derive the pair liveness anew.
    scene.contacts.clear_derived();
    scene.derived.maybe_outside = true;
    let commanded = scene.contacts.is_stale();
    if scene.contacts.is_stale() {
        prime(scene, model, tol);
    } else if !tol_serves(scene, scene.contacts.tol(), tol) {
        // Only the search distance changed: re-map, keep the states of the last step.
        scene.contacts.request_remap();
    }
    // FRAction AUTO: the step of the last rebuild goes on (the same bits after SAve and
    // RESTart, or across Cycle commands) unless a command changed the scene.
    if let Some(kept) = scene.settings.auto_step {
        let dt = if kept > 0.0 && !commanded {
            kept.min(model.dt_base)
        } else {
            super::contact_time::auto_step(scene, model, model.dt_base)
        };
        scene.settings.auto_step = Some(dt);
        model.dt = dt;
    }
    (tol, xres)
}

/// The step the next `Cycle` would start with (0 when it cannot run): the FRAction step, or
/// under `FRAction AUTO` the step `prepare` keeps or derives.
pub fn next_step(scene: &Scene) -> f64 {
    let Ok(model) = params::build(scene) else {
        return 0.0;
    };
    match scene.settings.auto_step {
        Some(kept) if kept > 0.0 && !scene.contacts.is_stale() => kept.min(model.dt_base),
        Some(_) if !scene.particles.is_empty() => {
            super::contact_time::auto_step(scene, &model, model.dt_base)
        }
        _ => model.dt,
    }
}

/// A `Cycle` that failed: the scene goes back to the last good snapshot, and the message
/// says so.
fn stop(scene: &mut Scene, snapshot: Scene, mut e: Blowup) -> Blowup {
    e.message.push_str(&format!(
        "\nthe state of cycle {} (the last good snapshot) is kept: SAve it or change the scene",
        snapshot.cycle
    ));
    restore(scene, snapshot);
    // (The audit of the next Cycle measures from the restored books.)
    scene.carried.audit_end = super::energy::residual(scene);
    e
}

/// The energy the audit lets cycling create, as a fraction of the scene's energy scale
/// ([`Audit::scale`]): a run whose books' residual grows beyond it since the scene was made
/// stops (doc/limits.md, "No silent energy creation").
pub const AUDIT_TOLERANCE: f64 = 0.05;

/// The energy audit of a `Cycle`: the energy that cycling created since the scene was made —
/// the growth of the books' residual (stored + dissipated − put in) beyond what commands
/// left unbooked (`Ledger::unbooked`) — may not exceed [`AUDIT_TOLERANCE`] of the energy the
/// scene had or was given, however it is split into Cycles. The books of a healthy run close
/// to ~1e-3 of the input (doc/timestep.md).
struct Audit {
    /// The least energy scale: every particle pressed against its like to an overlap of
    /// 1 % of its radius (Hertz, 8/15 E* √R* α^{5/2}), so that a scene at rest is not
    /// stopped for the round-off of its books.
    floor: f64,
}

impl Audit {
    /// The audit of a Cycle about to start: what the residual moved by since the last
    /// Cycle ended, commands moved; it joins `Ledger::unbooked`.
    fn of(scene: &mut Scene) -> Audit {
        let p = &scene.particles;
        let floor = (0..p.len())
            .map(|i| {
                let m = &scene.materials[p.material[i] as usize - 1];
                let e_star = m.young / (2.0 * (1.0 - m.poisson * m.poisson));
                let r_star = 0.5 * p.radius[i];
                8.0 / 15.0 * e_star * r_star.sqrt() * (0.01 * p.radius[i]).powf(2.5)
            })
            .sum::<f64>();
        let r = super::energy::residual(scene);
        let l = &mut scene.ledger;
        if l.unbooked.is_nan() {
            l.unbooked = r;
        } else if r != scene.carried.audit_end {
            l.unbooked += r - scene.carried.audit_end;
        }
        scene.carried.audit_end = r;
        Audit { floor }
    }

    /// The energy scale of the scene: the largest of the energy put in so far (the
    /// periodic cell's work included, as in the books' residual), the energy commands left
    /// unbooked (a scene read from an old checkpoint) and the floor — what the scene had or
    /// was given, the same however its run is split into Cycles.
    fn scale(&self, scene: &Scene) -> f64 {
        (scene.ledger.input() + scene.cell.work)
            .abs()
            .max(scene.ledger.unbooked.abs())
            .max(self.floor)
            .max(1e-300)
    }

    /// A runaway, if the energy cycling created exceeds the tolerance (or the stored energy
    /// is not finite). Keeps the residual for the next Cycle's start.
    fn check(&self, scene: &mut Scene, model: &Model) -> Option<Blowup> {
        let stored = super::energy::stored(scene).total();
        let r = super::energy::residual(scene);
        let created = r - scene.ledger.unbooked;
        let scale = self.scale(scene);
        if !stored.is_finite()
            || !created.is_finite()
            || created - in_flight(scene, model.dt) > AUDIT_TOLERANCE * scale
        {
            return Some(runaway(scene, model, created, scale));
        }
        scene.carried.audit_end = r;
        scene.carried.in_flight_end = in_flight(scene, model.dt);
        None
    }
}

/// The part of the residual that contacts in progress show at any instant: the second half
/// of the last step's force work — the leap-frog books a force's work about its instant,
/// while the strain energy is that of the positions the forces were computed at. For the
/// particles ½ Δt Σ (F·v + M·ω) with the last step's forces (kept at every point the audit
/// runs); for a moving wall, less half of the work it did in the last step (its force times
/// the displacement it goes on with). A Hertz impact of 17 steps shows up to 12 % of its
/// energy so, which this takes out to within 1 %; a wall pressing particles at 10 m/s shows
/// a residual of first order in Δt (2 % at FRAction 0.2), which this makes second order
/// (1.4e-3, 3e-4, 8e-5 at FRAction 0.2, 0.1, 0.05; doc/limits.md).
fn in_flight(scene: &Scene, dt: f64) -> f64 {
    0.5 * dt * scene.force_power() - 0.5 * scene.carried.wall_step_work
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
    scene.carried.in_flight_end = 0.0;
    let n = scene.particles.len();
    scene.particles.disp = vec![Vec3::zeros(); n];
}

/// Describes an energy runaway: how much energy appeared, against what, which particle
/// carries the most kinetic energy, and the step against the scene's fastest contact.
fn runaway(scene: &Scene, model: &Model, created: f64, scale: f64) -> Blowup {
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
    let cause = match super::contact_time::shortest(scene, model) {
        Some(f) => {
            let steps = f.tc / model.dt;
            format!(
                "the fastest contact (particle {} at {:.3e} m/s) lasts {:.3e} s, {:.1} steps of {:.3e} s{}",
                p.id[f.particle],
                f.speed,
                f.tc,
                steps,
                model.dt,
                if steps < super::contact_time::AUTO_STEPS {
                    format!(
                        ": too few; FRAction {:.3} would give {} (FRAction AUTO follows the fastest contact)",
                        model.fraction * steps / super::contact_time::AUTO_STEPS,
                        super::contact_time::AUTO_STEPS
                    )
                } else {
                    String::new()
                }
            )
        }
        None => "nothing moves".into(),
    };
    let mut servo = scene
        .walls
        .iter()
        .position(|w| w.servo.is_some())
        .map_or(String::new(), |w| {
            format!(
                "; wall {} is servo-controlled: a gain that makes it hunt does work the books cannot follow (see the warnings before the Cycle)",
                w + 1
            )
        });
    if scene.derived.servo.is_some() {
        servo.push_str(
            "; the periodic cell's stress servo drives the strain rates: a GAIN that makes it hunt does work the books cannot follow (doc/cell.md, \"Choosing the servo gain\")",
        );
    }
    Blowup {
        cycle: scene.cycle,
        message: format!(
            "energy runaway at cycle {}: cycling created {:.3e} J that the energy ledger did not put in since the scene was made, \
             more than {}% of the energy the scene holds or was given ({:.3e} J); \
             particle {} at ({:.4e}, {:.4e}, {:.4e}) moves at {:.3e} m/s; {cause}{servo}. \
             Hint: a smaller FRAction (or FRAction AUTO); check deep overlaps, servo gains and contact damping (istiff)",
            scene.cycle,
            created,
            AUDIT_TOLERANCE * 100.0,
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
/// update clears them as it goes, which saves the next step a pass over them); `first`: the
/// first step of a Cycle. A Fix standing on a dynamic group is applied first (its members
/// now fixed, doc/groups.md).
pub fn one_step(
    scene: &mut Scene,
    model: &mut Model,
    (tol, xres): (f64, f64),
    (keep, first): (bool, bool),
) -> Result<(), Blowup> {
    scene.apply_standing_fixes();
    let mut dt = model.dt;
    if !set_margins(scene, model, dt) {
        scene.contacts.request_remap();
    }
    let rebuilt = scene.contacts.is_stale() || scene.contacts.needs_remap();
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
    // Particles behind a wall's surface at a Cycle's first step (commands may have put them
    // there; a crossing in a step is found after that step, every particle when the list is
    // due for a re-mapping, `after_step`); before those that left the work-space are
    // removed (one may have left through the wall first).
    if !scene.walls.is_empty() && first {
        let behind = behind_walls(scene);
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
    let cell = scene.cell.needs_stress() || scene.derived.servo.is_some();
    // (Rolling friction is a pass between the force step and the update: two regions.)
    let rolling = model.rolling.is_some();
    if model.plan.threads > 1 && model.plan.one_region && !conserve && !cell && !rolling {
        // Both steps in one parallel region (`fused`): the same bits. (With more threads
        // than cores two regions are faster: a task that waits for another holds a core;
        // 3 threads on 2 cores took 6 × the time of two regions, 1.3 × without the wait.)
        let mv = Mover::of(scene, model);
        let (acc, parts) = forces_fused(scene, model, &mv, keep);
        let wall_work = move_walls(scene, dt);
        return finish_move(scene, (xres, keep), acc, wall_work, &parts, dt);
    }
    let mut acc = forces(scene, model, dt);
    if rolling {
        let [friction, damping] = crate::sim::rolling::moments(scene, model, dt);
        acc.friction += friction;
        acc.damping_contact += damping;
    }
    if conserve {
        super::liquid::settle(scene);
    }
    move_all(scene, model, xres, acc, keep)
}

/// At a rebuild: a step too long for the fastest contact (noted once a Cycle; not under
/// `FRAction AUTO`, which follows it). `bound`: the Cycle's [`contact_time::KeyBound`], made
/// at the first rebuild. Whether it warned.
///
/// [`contact_time::KeyBound`]: super::contact_time::KeyBound
fn warn_step(
    scene: &mut Scene,
    model: &Model,
    bound: &mut Option<super::contact_time::KeyBound>,
) -> bool {
    if scene.settings.auto_step.is_some() {
        return false;
    }
    let bound = bound.get_or_insert_with(|| super::contact_time::key_bound(scene, model));
    let v1 = largest_norm_squared(&scene.particles.vel).sqrt();
    match super::contact_time::warning_bounded(scene, model, model.fraction, bound, v1) {
        Some(w) => {
            scene.derived.notes.push(w);
            true
        }
        None => false,
    }
}

/// Primes the contact states if commands changed the scene (no-op otherwise, or when the
/// scene cannot cycle yet).
pub fn prime_if_stale(scene: &mut Scene) {
    if !scene.contacts.is_stale() || scene.particles.is_empty() {
        return;
    }
    if let Ok(model) = check(scene) {
        let (tol, _) = search_distances(scene, &model);
        prime(scene, &model, tol);
        scene.contacts.set_tol(tol);
    }
}

/// Re-evaluates the contact states at the current positions without moving anything (after
/// commands changed the scene): initial overlaps get their strain energy, which is booked as
/// energy put in by the commands.
///
/// After a `Cycle` the states are those of the last step's forces, a step behind the
/// positions: re-evaluated, they would hold a step's work less (`−2 ×` the work in flight,
/// [`in_flight`], to first order) without any command. That part is the scheme's, not the
/// command's: it is left out of what the command put in, so that a command that changes
/// nothing (an `AWAll ... V` between two Cycles) leaves the books as one longer Cycle would,
/// to second order in the step (doc/limits.md, "Issue 49, item by item").
pub fn prime(scene: &mut Scene, model: &Model, tol: f64) {
    let before = super::energy::stored(scene).total();
    rebuild(scene, tol);
    let _ = forces(scene, model, 0.0);
    finish_deferred(scene, model);
    let after = super::energy::stored(scene).total();
    let behind = std::mem::take(&mut scene.carried.in_flight_end);
    scene.ledger.commands += after - before + 2.0 * behind;
}

/// Appends one row to the history (columns of [`super::history::COLUMNS`]).
pub fn record_history(scene: &mut Scene) {
    let st = super::energy::stored(scene);
    let (c, cw) = scene.touching_counts();
    let (b, bw) = scene.contacts.bridge_counts();
    let wf: f64 = scene.walls.iter().map(|w| w.normal_force).sum();
    let mut row = vec![
        scene.cycle as f64,
        scene.time,
        st.kinetic_translation + st.kinetic_rotation,
        st.strain_normal + st.strain_tangential + st.bridge,
        scene.ledger.input() + scene.cell.work,
        scene.ledger.dissipated(),
        super::energy::residual(scene),
        (c + cw) as f64,
        (b + bw) as f64,
        wf,
    ];
    // The average stress (`stress`: total, compression positive, Pa; rows recorded before
    // checkpoint format 4 hold 0) and the granular temperature ⟨C·C⟩/3.
    let s = super::stress::of(scene).total();
    row.extend([s[0][0], s[1][1], s[2][2], s[0][1], s[1][2], s[2][0]]);
    row.push(super::stress::temperature(scene));
    // The periodic cell's accumulated strains (`sim::cell`).
    let e = scene.cell.strain;
    row.extend([e[0], e[1], e[2], e[3]]);
    scene.history.rows.push(row);
    // The groups recorded with the history (`GROup name HIStory`).
    super::aggregate::record(scene);
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

    /// The audit's energy scale counts the periodic cell's work as an input, as the books'
    /// residual does (doc/limits.md, "No silent energy creation"): a scene given its energy
    /// by the cell alone is held to 5 % of that energy, not of the 1 %-overlap floor.
    #[test]
    fn the_audit_scale_includes_the_cell_work() {
        let mut sc = Scene::new([1e-3; 3], 10, 200, 0);
        sc.cell.work = 1e-6;
        let audit = Audit { floor: 1e-8 };
        assert_eq!(sc.ledger.input(), 0.0);
        assert_eq!(audit.scale(&sc), 1e-6);
        sc.cell.work = -1e-6;
        assert_eq!(audit.scale(&sc), 1e-6);
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
