//! Liquid bookkeeping outside the time step: re-issuing `LIQuid` updates the volume and the
//! rupture distance of every live bridge (Lian §5.7.1).

use super::contacts::BridgeState;
use super::scene::Scene;
use crate::physics::bridge::Bridge;
use crate::sim::model::LiquidMode;

/// Bridge volume for a pair: pvol % of the mean volume of the two spheres (a wall pair uses
/// the particle's volume) (doc/spec/DECISIONS.md).
pub fn bridge_volume(pvol: f64, r1: f64, r2: f64) -> f64 {
    let v = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let v2 = if r2.is_finite() { v(r2) } else { v(r1) };
    pvol / 100.0 * 0.5 * (v(r1) + v2)
}

/// Share of a particle's initial liquid that a new bridge draws in the liquid-conserving
/// mode (Olsson 2017 §3.3.2: 16 %, reproducing her Appendix A.3).
pub const OLSSON_SHARE: f64 = 0.16;

/// Liquid a new bridge asks of its two particles in the conserving mode: the share of each
/// particle's initial content (pvol % of its volume); a wall gives none.
pub fn share_request(share: f64, pvol: f64, r1: f64, r2: f64) -> [f64; 2] {
    let v = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let d2 = if r2.is_finite() {
        share * pvol / 100.0 * v(r2)
    } else {
        0.0
    };
    [share * pvol / 100.0 * v(r1), d2]
}

/// Conserving mode, after each step: new bridges take their liquid from the particles (no more
/// than each particle has left; the bridge is rebuilt if it got less), ruptured bridges give
/// it back as it was drawn (Olsson 2017 §2.2.5). Sequential, in pair order: deterministic.
pub fn settle(scene: &mut Scene) {
    let model = crate::sim::model::bridge_model(scene.settings.bridge);
    let p = &mut scene.particles;
    scene.contacts.for_each_state_mut(|c, s| {
        let (i, j) = (c.i as usize, c.j as usize);
        if let Some(e) = s.ext.as_deref_mut()
            && e.released != [0.0; 2]
        {
            p.liquid[i] += e.released[0];
            p.liquid[j] += e.released[1];
            e.released = [0.0; 2];
        }
        if let Some(b) = s.bridge.as_deref_mut()
            && b.fresh
        {
            let d = [b.share[0].min(p.liquid[i]), b.share[1].min(p.liquid[j])];
            p.liquid[i] -= d[0];
            p.liquid[j] -= d[1];
            b.fresh = false;
            if d != b.share {
                b.share = d;
                let mut br = *b.coeffs.bridge();
                br.volume = d[0] + d[1];
                *b = BridgeState {
                    work: b.work,
                    ..BridgeState::new(model, br, b.gap, d)
                };
                b.fresh = false;
            }
        }
    });
    for c in scene.contacts.wall_pairs.iter_mut() {
        let i = c.i as usize;
        if let Some(e) = c.s.ext.as_deref_mut()
            && e.released != [0.0; 2]
        {
            p.liquid[i] += e.released[0];
            e.released = [0.0; 2];
        }
        if let Some(b) = c.s.bridge.as_deref_mut()
            && b.fresh
        {
            let d = [b.share[0].min(p.liquid[i]), 0.0];
            p.liquid[i] -= d[0];
            b.fresh = false;
            if d != b.share {
                let mut br = *b.coeffs.bridge();
                br.volume = d[0];
                *b = BridgeState {
                    work: b.work,
                    ..BridgeState::new(model, br, b.gap, d)
                };
                b.fresh = false;
            }
        }
    }
}

/// Total liquid: free liquid on the particles plus the liquid in bridges (m³).
pub fn total_liquid(scene: &Scene) -> (f64, f64) {
    let free: f64 = scene.particles.liquid.iter().fold(0.0, |a, b| a + b);
    let in_bridges: f64 = scene
        .contacts
        .iter()
        .filter_map(|c| c.s.bridge.as_ref().map(|b| b.volume))
        .chain(
            scene
                .contacts
                .wall_pairs
                .iter()
                .filter_map(|c| c.s.bridge.as_ref().map(|b| b.volume)),
        )
        .fold(0.0, |a, b| a + b);
    (free, in_bridges)
}

/// Applies new liquid parameters to the existing bridges (Lian's mode: new nominal volume;
/// conserving mode: bridges keep their liquid) and, in the conserving mode, gives every
/// particle its liquid content pvol % of its volume, less what its live bridges hold of it
/// (so re-issuing `LIQuid` to change the viscosity or surface tension adds no liquid).
pub fn reissue(scene: &mut Scene) {
    let Some(l) = scene.liquid else { return };
    let model = crate::sim::model::bridge_model(scene.settings.bridge);
    let conserve = scene.settings.liquid_mode == LiquidMode::Conserve;
    let p = &mut scene.particles;
    if conserve {
        for i in 0..p.len() {
            p.liquid[i] = l.pvol / 100.0 * 4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3);
        }
        for c in scene.contacts.iter() {
            if let Some(b) = &c.s.bridge {
                p.liquid[c.i as usize] -= b.share[0];
                p.liquid[c.j as usize] -= b.share[1];
            }
        }
        for c in &scene.contacts.wall_pairs {
            if let Some(b) = &c.s.bridge {
                p.liquid[c.i as usize] -= b.share[0];
            }
        }
        for x in p.liquid.iter_mut() {
            *x = x.max(0.0);
        }
    }
    let update = |b: &mut BridgeState, r1: f64, r2: f64| {
        let volume = if conserve {
            b.volume
        } else {
            bridge_volume(l.pvol, r1, r2)
        };
        let br = Bridge {
            r1,
            r2,
            volume,
            gamma: l.gamma,
            theta: l.theta,
        };
        *b = BridgeState {
            work: b.work,
            f_static: b.f_static,
            f_visc: b.f_visc,
            ..BridgeState::new(model, br, b.gap, b.share)
        };
        b.fresh = false;
    };
    scene.contacts.for_each_state_mut(|c, s| {
        let (ri, rj) = (p.radius[c.i as usize], p.radius[c.j as usize]);
        if let Some(b) = s.bridge.as_deref_mut() {
            update(b, ri, rj);
        }
    });
    for c in scene.contacts.wall_pairs.iter_mut() {
        if let Some(b) = c.s.bridge.as_deref_mut() {
            update(b, p.radius[c.i as usize], f64::INFINITY);
        }
    }
}
