//! The reference state stored by `PLot SAve`: positions, rotations and the bonds (solid
//! contacts and liquid bridges) at that moment, keyed by stable particle ids.

use serde::{Deserialize, Serialize};

use super::Scene;

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Reference {
    pub cycle: u64,
    /// (id, position, rotation) of every particle.
    pub ids: Vec<u32>,
    pub pos: Vec<[f64; 3]>,
    pub rot: Vec<[f64; 3]>,
    /// Touching pairs (a < b, by id; `Scene::touching_pairs`).
    pub contacts: Vec<(u32, u32)>,
    /// Liquid bridges (a < b, by id).
    pub bridges: Vec<(u32, u32)>,
    /// Kinetic energy at the reference (J): the incident energy of an impact.
    pub kinetic: f64,
    /// Energy needed to break every bond of the reference (J): the JKR peeling work (3.119)
    /// of each adhesive contact, or the bond energy ∫F dS to rupture of each liquid bridge.
    pub bond_energy: f64,
}

impl Reference {
    pub fn take(scene: &Scene) -> Self {
        let p = &scene.particles;
        let (translation, rotation) = p.kinetic_parts();
        let mut bond_energy = 0.0;
        for c in scene.contacts.iter() {
            let (i, j) = (c.i as usize, c.j as usize);
            if let Some(b) = &c.s.bridge {
                bond_energy += b.coeffs.bond_energy(b.gap.max(0.0));
            } else if c.s.touching && c.s.gamma() > 0.0 {
                let (ma, mb) = (
                    &scene.materials[p.material[i] as usize - 1],
                    &scene.materials[p.material[j] as usize - 1],
                );
                let jk = crate::physics::jkr::Jkr {
                    e_star: crate::physics::hertz::e_star(
                        ma.young, ma.poisson, mb.young, mb.poisson,
                    ),
                    r_star: p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]),
                    gamma: c.s.gamma(),
                };
                bond_energy += jk.peel_work();
            }
        }
        Reference {
            cycle: scene.cycle,
            ids: p.id.clone(),
            pos: p.pos.iter().map(|v| [v.x, v.y, v.z]).collect(),
            rot: p.rot.iter().map(|v| [v.x, v.y, v.z]).collect(),
            contacts: scene.bonded_pairs(false),
            bridges: scene.bonded_pairs(true),
            kinetic: translation + rotation,
            bond_energy,
        }
    }
}
