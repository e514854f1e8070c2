//! The time step against the scene's fastest contact: the duration of a Hertz impact at the
//! largest approach speed, `t_c = 2.868 (m*²/(R* E*² v))^{1/5}` (Hertz theory on Lian 1994
//! (3.14)–(3.15), `physics::hertz::impact_duration`), compared with Δt. The Rayleigh step
//! (doc/spec/DECISIONS.md) depends on the materials and sizes only; a contact at 100 m/s lasts about
//! 2.5 times less than one at 1 m/s, so a step chosen for a settling bed can leave a fast
//! impact with a handful of steps. Fewer than [`WARN_STEPS`] steps per contact gives a
//! warning; `FRAction AUTO` takes Δt = min(FRAction × Δt_R, t_c/[`AUTO_STEPS`]) at every
//! rebuild of the candidate list (doc/timestep.md).

use super::params::Model;
use super::scene::Scene;
use super::walls::surface_speed;
use crate::physics::hertz::HERTZ_DURATION_FACTOR;

/// Below this many steps per contact a `Cycle` warns (restitution, peak force and contact
/// time are then several per cent off, doc/timestep.md).
pub const WARN_STEPS: f64 = 10.0;

/// `FRAction AUTO` gives the fastest contact this many steps.
pub const AUTO_STEPS: f64 = 15.0;

/// The shortest contact the scene's motion can make now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fastest {
    /// Its duration (s).
    pub tc: f64,
    /// The particle (index) and its speed (m/s).
    pub particle: usize,
    pub speed: f64,
    /// The approach speed (m/s): the particle's speed plus the fastest other particle's, or
    /// plus the fastest wall's surface speed.
    pub approach: f64,
    /// With a wall (its index) rather than a particle like itself.
    pub wall: Option<usize>,
}

/// The shortest Hertz contact among each particle's fastest possible approaches: head-on
/// with the fastest other particle (reduced mass and radius of a pair of its own kind), or
/// against the fastest wall surface (its own mass and radius; a sphere wall's curvature is
/// left out). `None` when nothing moves or there are no particles.
pub fn shortest(scene: &Scene, model: &Model) -> Option<Fastest> {
    let p = &scene.particles;
    if p.is_empty() {
        return None;
    }
    let (v1, i1, v2) = two_fastest(&p.vel);
    let walls: Vec<(usize, f64)> = scene
        .walls
        .iter()
        .enumerate()
        .map(|(w, wall)| (w, surface_speed(wall)))
        .collect();
    // (1.25 m*/K)² / v: t_c = factor · that^{1/5}; the smallest wins.
    let key = |m_star: f64, r_star: f64, e_star: f64, v: f64| key(m_star, r_star, e_star) / v;
    let mut best: Option<(f64, Fastest)> = None;
    let mut consider = |q: f64, f: Fastest| {
        if q > 0.0 && q.is_finite() && best.is_none_or(|(b, _)| q < b) {
            best = Some((q, f));
        }
    };
    for i in 0..p.len() {
        let s = p.vel[i].norm();
        let mat = p.material[i] as usize;
        let (m, r) = (p.mass[i], p.radius[i]);
        if p.len() > 1 {
            let other = if i == i1 { v2 } else { v1 };
            let v = s + other;
            let e = model.pair(mat, mat).e_star;
            let f = Fastest {
                tc: 0.0,
                particle: i,
                speed: s,
                approach: v,
                wall: None,
            };
            consider(key(0.5 * m, 0.5 * r, e, v), f);
        }
        for &(w, sw) in &walls {
            let v = s + sw;
            let e = model.pair(mat, scene.walls[w].material).e_star;
            let f = Fastest {
                tc: 0.0,
                particle: i,
                speed: s,
                approach: v,
                wall: Some(w),
            };
            consider(key(m, r, e, v), f);
        }
    }
    best.map(|(q, f)| Fastest {
        tc: HERTZ_DURATION_FACTOR * q.powf(0.2),
        ..f
    })
}

/// `(1.25 m*/K)²`, `K = 4/3 E* √R*`: [`shortest`]'s key before its division by the approach
/// speed.
fn key(m_star: f64, r_star: f64, e_star: f64) -> f64 {
    let k = 4.0 / 3.0 * e_star * r_star.sqrt();
    let q = 1.25 * m_star / k;
    q * q
}

/// The largest speed, its particle, and the second largest (the fastest other particle of
/// every particle but the fastest).
fn two_fastest(vel: &[super::scene::Vec3]) -> (f64, usize, f64) {
    let (mut v1, mut i1, mut v2) = (0.0f64, usize::MAX, 0.0f64);
    for (i, v) in vel.iter().enumerate() {
        let s = v.norm();
        if s > v1 {
            (v2, v1, i1) = (v1, s, i);
        } else if s > v2 {
            v2 = s;
        }
    }
    (v1, i1, v2)
}

/// The least [`key`] of the scene's particles, with a particle of their own kind and with any
/// wall: fixed within a
/// `Cycle` (no command runs; lost particles only raise it), so the rebuilds' check of the
/// step ([`warning_bounded`]) needs only the fastest speeds.
#[derive(Clone, Copy, Debug)]
pub struct KeyBound {
    pair: f64,
    wall: f64,
}

/// The [`KeyBound`] of the scene now.
pub fn key_bound(scene: &Scene, model: &Model) -> KeyBound {
    let p = &scene.particles;
    let (mut pair, mut wall) = (f64::INFINITY, f64::INFINITY);
    for i in 0..p.len() {
        let mat = p.material[i] as usize;
        let (m, r) = (p.mass[i], p.radius[i]);
        pair = pair.min(key(0.5 * m, 0.5 * r, model.pair(mat, mat).e_star));
        for w in &scene.walls {
            wall = wall.min(key(m, r, model.pair(mat, w.material).e_star));
        }
    }
    KeyBound { pair, wall }
}

/// [`warning`], with the per-particle pass only when a lower bound of the shortest contact
/// (the least key of [`KeyBound`] over the largest approach speeds: twice the fastest
/// particle's speed, or it plus the fastest wall surface's) gives fewer than [`WARN_STEPS`]
/// steps: the same warnings (the bound is one-sided, kept 1e-9 below), without a square root
/// and two divisions per particle and wall at every rebuild (2.3 % of the S1 bed's
/// instructions, doc/performance.md "Where the time went since b0b4c42"). `v1`: the
/// largest particle speed.
pub fn warning_bounded(
    scene: &Scene,
    model: &Model,
    fraction: f64,
    bound: &KeyBound,
    v1: f64,
) -> Option<String> {
    let sw = scene.walls.iter().map(surface_speed).fold(0.0f64, f64::max);
    let q = (bound.pair / (2.0 * v1)).min(bound.wall / (v1 + sw));
    let tc_low = HERTZ_DURATION_FACTOR * q.powf(0.2) * (1.0 - 1e-9);
    if tc_low / model.dt >= WARN_STEPS {
        return None;
    }
    warning(scene, model, fraction)
}

/// The warning for a step that gives the fastest contact fewer than [`WARN_STEPS`] steps:
/// the particle, its speed, the steps per contact and the FRAction that would give
/// [`AUTO_STEPS`] (`fraction`: the one in use).
pub fn warning(scene: &Scene, model: &Model, fraction: f64) -> Option<String> {
    let f = shortest(scene, model)?;
    let steps = f.tc / model.dt;
    if !(steps < WARN_STEPS) {
        return None;
    }
    let with = match f.wall {
        Some(w) => format!("wall {}", w + 1),
        None => "a particle like it".into(),
    };
    Some(format!(
        "cycle {}: particle {} moves at {:.3e} m/s: a Hertz contact with {with} at {:.3e} m/s lasts {:.3e} s, {:.1} steps of {:.3e} s \
         (fewer than {WARN_STEPS}: restitution, peak force and contact time are several % off, doc/timestep.md); \
         FRAction {:.3} would give {AUTO_STEPS} (FRAction AUTO follows the fastest contact)",
        scene.cycle,
        scene.particles.id[f.particle],
        f.speed,
        f.approach,
        f.tc,
        steps,
        model.dt,
        fraction * steps / AUTO_STEPS,
    ))
}

/// `FRAction AUTO` lets no particle move by more than this fraction of its radius relative
/// to another particle or a wall in one step.
pub const AUTO_TRAVEL: f64 = 0.2;

/// The step of `FRAction AUTO`: the scene's FRAction step `base` (with its limits for
/// viscous and Rayleigh dashpots), or t_c/[`AUTO_STEPS`] of the fastest contact if shorter,
/// or the step in which a particle travels [`AUTO_TRAVEL`] of its radius relative to the
/// fastest other particle or wall surface if shorter still (a soft particle fast enough to
/// pass through another within a Hertz contact time is then met by the contact law, and
/// stopped by the overlap check, instead of jumping it).
pub fn auto_step(scene: &Scene, model: &Model, base: f64) -> f64 {
    let dt = match shortest(scene, model) {
        Some(f) if f.tc / AUTO_STEPS < base => f.tc / AUTO_STEPS,
        _ => base,
    };
    dt.min(travel_step(scene))
}

/// The step in which no particle travels more than [`AUTO_TRAVEL`] of its radius relative to
/// the fastest other particle or wall surface (∞ when nothing moves).
fn travel_step(scene: &Scene) -> f64 {
    let p = &scene.particles;
    let (v1, i1, v2) = two_fastest(&p.vel);
    let walls = scene.walls.iter().map(surface_speed).fold(0.0f64, f64::max);
    let mut dt = f64::INFINITY;
    for i in 0..p.len() {
        let other = if i == i1 { v2 } else { v1 };
        let v = p.vel[i].norm() + other.max(walls);
        if v > 0.0 {
            dt = dt.min(AUTO_TRAVEL * p.radius[i] / v);
        }
    }
    dt
}

#[cfg(test)]
mod tests {
    use crate::physics::hertz::impact_duration;

    /// The key form gives `impact_duration`.
    #[test]
    fn the_key_is_the_impact_duration() {
        let (m, r, e, v) = (3e-10, 1.5e-5, 3.8e10, 200.0);
        let k = 4.0 / 3.0 * e * f64::sqrt(r);
        let q = 1.25 * m / k;
        let tc = super::HERTZ_DURATION_FACTOR * (q * q / v).powf(0.2);
        assert!((tc / impact_duration(m, r, e, v) - 1.0).abs() < 1e-12);
    }
}
