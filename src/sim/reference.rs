//! The reference state stored by `PLot SAve`: positions, rotations and the bonds (solid
//! contacts and liquid bridges) at that moment, keyed by stable particle ids.

use serde::{Deserialize, Serialize};

use super::scene::Scene;

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Reference {
    pub cycle: u64,
    /// (id, position, rotation) of every particle.
    pub ids: Vec<u32>,
    pub pos: Vec<[f64; 3]>,
    pub rot: Vec<[f64; 3]>,
    /// Solid contacts (a < b, by id) bearing load or adhesive.
    pub contacts: Vec<(u32, u32)>,
    /// Liquid bridges (a < b, by id).
    pub bridges: Vec<(u32, u32)>,
}

impl Reference {
    pub fn take(scene: &Scene) -> Self {
        let p = &scene.particles;
        Reference {
            cycle: scene.cycle,
            ids: p.id.clone(),
            pos: p.pos.iter().map(|v| [v.x, v.y, v.z]).collect(),
            rot: p.rot.iter().map(|v| [v.x, v.y, v.z]).collect(),
            contacts: scene.contacts.bonded_pairs(&scene.particles, false),
            bridges: scene.contacts.bonded_pairs(&scene.particles, true),
        }
    }
}
