//! Liquid bookkeeping outside the time step: re-issuing `LIQuid` updates the volume and the
//! rupture distance of every live bridge (Lian §5.7.1).

use super::scene::Scene;
use crate::physics::bridge::{self, Bridge};

/// Bridge volume for a pair: pvol % of the mean volume of the two spheres (a wall pair uses
/// the particle's volume) (DECISIONS.md).
pub fn bridge_volume(pvol: f64, r1: f64, r2: f64) -> f64 {
    let v = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let v2 = if r2.is_finite() { v(r2) } else { v(r1) };
    pvol / 100.0 * 0.5 * (v(r1) + v2)
}

/// Applies new liquid parameters to the existing bridges.
pub fn reissue(scene: &mut Scene) {
    let Some(l) = scene.liquid else { return };
    let p = &scene.particles;
    for c in scene.contacts.pairs.iter_mut() {
        if let Some(b) = c.s.bridge.as_deref_mut() {
            let (r1, r2) = (p.radius[c.i as usize], p.radius[c.j as usize]);
            b.volume = bridge_volume(l.pvol, r1, r2);
            b.s_c = bridge::rupture_distance(&Bridge {
                r1,
                r2,
                volume: b.volume,
                gamma: l.gamma,
                theta: l.theta,
            });
        }
    }
    for c in scene.contacts.wall_pairs.iter_mut() {
        if let Some(b) = c.s.bridge.as_deref_mut() {
            let r1 = p.radius[c.i as usize];
            b.volume = bridge_volume(l.pvol, r1, f64::INFINITY);
            b.s_c = bridge::rupture_distance(&Bridge {
                r1,
                r2: f64::INFINITY,
                volume: b.volume,
                gamma: l.gamma,
                theta: l.theta,
            });
        }
    }
}
