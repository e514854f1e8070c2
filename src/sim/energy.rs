//! The energy ledger: what went in (initial energy, work of gravity, walls and commands),
//! what is stored (kinetic, contact strain, adhesive and bridge stretch) and what was
//! dissipated (friction, global and contact damping, viscosity, adhesion hysteresis, bridge
//! rupture). The residual `stored − (input − dissipated)` shows how well the books close.

use serde::{Deserialize, Serialize};

use super::contacts::ContactState;
pub use super::scene::Ledger;
use super::scene::Scene;
use super::walls::wall_r_star;
use crate::physics::hertz;
use crate::physics::jkr::Jkr;

/// Energies that are functions of the current state (J).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stored {
    pub kinetic_translation: f64,
    pub kinetic_rotation: f64,
    /// Normal elastic strain (Hertz) or elastic + surface energy (JKR), zero at first touch.
    pub strain_normal: f64,
    pub strain_tangential: f64,
    /// Work done against static liquid-bridge forces since each live bridge formed.
    pub bridge: f64,
}

impl Stored {
    pub fn total(&self) -> f64 {
        self.kinetic_translation
            + self.kinetic_rotation
            + self.strain_normal
            + self.strain_tangential
            + self.bridge
    }
}

/// Kinetic energy (translation + rotation) with the half-step velocities.
pub fn kinetic(scene: &Scene) -> f64 {
    (0..scene.particles.len())
        .map(|i| kinetic_of(scene, i))
        .sum()
}

/// Particle `i`'s term of [`kinetic`] (summed in particle order, so the total with one more
/// particle at the end is the total before plus its term, to the bit).
#[inline]
pub fn kinetic_of(scene: &Scene, i: usize) -> f64 {
    let p = &scene.particles;
    0.5 * p.mass[i] * p.vel[i].norm_squared() + 0.5 * p.inertia(i) * p.spin[i].norm_squared()
}

/// Kinetic energy with the half-step velocities of the leap-frog scheme.
pub fn stored(scene: &Scene) -> Stored {
    let p = &scene.particles;
    let (kinetic_translation, kinetic_rotation) = p.kinetic_parts();
    let mut s = Stored {
        kinetic_translation,
        kinetic_rotation,
        ..Stored::default()
    };
    let e_star = |m1: usize, m2: usize| {
        let (a, b) = (&scene.materials[m1 - 1], &scene.materials[m2 - 1]);
        hertz::e_star(a.young, a.poisson, b.young, b.poisson)
    };
    for c in scene.contacts.iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        if c.s.touching {
            let r_star = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
            let es = e_star(p.material[i] as usize, p.material[j] as usize);
            s.strain_normal += normal_strain(c.s, es, r_star);
            s.strain_tangential += c.s.tang_energy;
            if let Some(l) = c.s.ext.as_deref().and_then(|e| e.laws.as_deref()) {
                // The rolling spring (`sim::rolling`).
                s.strain_tangential += l.roll_energy;
            }
        }
        if let Some(b) = &c.s.bridge {
            s.bridge += b.work;
        }
    }
    for c in &scene.contacts.wall_pairs {
        let i = c.i as usize;
        let w = &scene.walls[c.wall as usize];
        if c.s.touching {
            let r_star = wall_r_star(&w.geom, p.radius[i]);
            let es = e_star(p.material[i] as usize, w.material);
            s.strain_normal += normal_strain(&c.s, es, r_star);
            s.strain_tangential += c.s.tang_energy;
            if let Some(l) = c.s.ext.as_deref().and_then(|e| e.laws.as_deref()) {
                s.strain_tangential += l.roll_energy;
            }
        }
        if let Some(b) = &c.s.bridge {
            s.bridge += b.work;
        }
    }
    s
}

/// Residual of the books: stored − (input − dissipated); the input includes the work of the
/// periodic cell's deformation (`Cell::work`).
pub fn residual(scene: &Scene) -> f64 {
    stored(scene).total() - (scene.ledger.input() + scene.cell.work - scene.ledger.dissipated())
}

/// Energy stored in the normal direction of a touching contact: Hertz strain energy
/// 8/15 E* √R* α^{5/2}, or for JKR the elastic + surface energy since snap-in,
/// U(a) − U(a0) (so that it equals the peeling work W_p (3.119) at separation).
pub fn normal_strain(s: &ContactState, e_star: f64, r_star: f64) -> f64 {
    if !s.touching {
        return 0.0;
    }
    if let Some(l) = s.ext.as_deref().and_then(|e| e.laws.as_deref())
        && !l.normal.is_none()
    {
        // The laws of `SET NORmal`: the energy on their reversible branch (sim::elastoplastic).
        return l.normal.stored();
    }
    let gamma = s.gamma();
    if gamma > 0.0 {
        let j = Jkr {
            e_star,
            r_star,
            gamma,
        };
        j.energy_of_a(s.a) + j.peel_work()
    } else {
        hertz::energy(e_star, r_star, s.overlap)
    }
}
