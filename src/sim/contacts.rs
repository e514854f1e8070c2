//! Contact history: a flat store of candidate pairs (particle–particle and particle–wall),
//! each with the state of its solid contact and, in wet scenes, its liquid bridge. Pairs are
//! keyed by stable particle ids, so that history survives re-mapping and re-ordering.

use serde::{Deserialize, Serialize};

use super::scene::{Particles, Vec3};
use crate::physics::tangential::TangentialState;

/// State of a liquid bridge (Lian §5.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BridgeState {
    /// Liquid volume (m³).
    pub volume: f64,
    /// Rupture distance S_c (m).
    pub s_c: f64,
    /// Static (capillary) force of the last step, attractive positive (N).
    pub f_static: f64,
    /// Viscous normal force of the last step (N, positive = resisting approach).
    pub f_visc: f64,
    /// Half-filling angle on the first sphere (rad).
    pub phi: f64,
    /// Gap of the last step (m).
    pub gap: f64,
    /// Work done against the static force since formation (J).
    pub work: f64,
}

/// State of one contact (solid part).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// A solid contact is active (Hertz: overlap > 0; JKR: made and not yet detached).
    pub touching: bool,
    /// Overlap α (positive = compression) of the last step.
    pub overlap: f64,
    /// Elastic normal force P (compressive positive).
    pub normal_force: f64,
    /// Dashpot normal force of the last step.
    pub damp_force: f64,
    /// Stored normal energy (Hertz strain, or JKR elastic + surface energy from first touch).
    pub strain: f64,
    /// Stored tangential elastic energy.
    pub tang_energy: f64,
    /// Contact radius a.
    pub a: f64,
    /// Surface energy of this contact (J/m²).
    pub gamma: f64,
    /// Accumulated tangential displacement vector δ (of B relative to A).
    pub delta: Vec3,
    /// Tangential force on B.
    pub tforce: Vec3,
    /// Tangential dashpot force on B (Rayleigh contact damping).
    pub tdamp: Vec3,
    /// Signed resultant tangential displacement (Lian (5.23)).
    pub tdelta: f64,
    /// Signed resultant tangential law state.
    pub tang: TangentialState,
    /// Unit normal of the last step (A → B).
    pub normal: Vec3,
    /// Liquid bridge, if any.
    pub bridge: Option<Box<BridgeState>>,
    /// Whether the pair ever carried a bridge since the liquid was issued (for `LIQuid`).
    pub wetted: bool,
}

/// A candidate particle–particle pair: gap < TOL at the last rebuild, or a live bond.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pair {
    /// Particle indices (valid until the next re-ordering; refreshed at rebuilds).
    pub i: u32,
    pub j: u32,
    /// Stable ids, `ida < idb`.
    pub ida: u32,
    pub idb: u32,
    pub s: ContactState,
}

/// A candidate particle–wall pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WallPair {
    pub i: u32,
    pub id: u32,
    pub wall: u32,
    pub s: ContactState,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ContactStore {
    pub pairs: Vec<Pair>,
    pub wall_pairs: Vec<WallPair>,
    /// A command changed the scene: rebuild the candidate list and re-evaluate the contact
    /// states at the current positions (`cycle::prime`) before the next step.
    pub stale: bool,
    /// Particles moved more than XRES (or TOL changed) since the last rebuild: rebuild the
    /// candidate list before the next force evaluation. The contact states are those of the
    /// last step and must not be re-evaluated (that would advance history-dependent laws twice
    /// and break exact continuation across `Cycle` commands and `SAve`/`RESTart`).
    pub remap: bool,
    /// Search distance used at the last rebuild.
    pub tol: f64,
    /// Number of rebuilds so far (for PRint Entries).
    pub rebuilds: u64,
}

impl ContactStore {
    /// Replaces the pair lists by new candidates (sorted by ids), carrying over the state of
    /// pairs present in both. Pairs that disappear lose their history (they were farther apart
    /// than TOL and carried no bond).
    pub fn merge(&mut self, mut new_pairs: Vec<Pair>, mut new_walls: Vec<WallPair>) {
        new_pairs.sort_unstable_by_key(|p| (p.ida, p.idb));
        let mut old = std::mem::take(&mut self.pairs).into_iter().peekable();
        for p in new_pairs.iter_mut() {
            while let Some(o) = old.peek() {
                if (o.ida, o.idb) < (p.ida, p.idb) {
                    old.next();
                } else {
                    break;
                }
            }
            if let Some(o) = old.peek() {
                if (o.ida, o.idb) == (p.ida, p.idb) {
                    p.s = old.next().expect("peeked").s;
                }
            }
        }
        self.pairs = new_pairs;

        new_walls.sort_unstable_by_key(|p| (p.id, p.wall));
        let mut old = std::mem::take(&mut self.wall_pairs).into_iter().peekable();
        for p in new_walls.iter_mut() {
            while let Some(o) = old.peek() {
                if (o.id, o.wall) < (p.id, p.wall) {
                    old.next();
                } else {
                    break;
                }
            }
            if let Some(o) = old.peek() {
                if (o.id, o.wall) == (p.id, p.wall) {
                    p.s = old.next().expect("peeked").s;
                }
            }
        }
        self.wall_pairs = new_walls;
        self.stale = false;
        self.remap = false;
        self.rebuilds += 1;
    }

    /// Bonds now: solid contacts that are active (`bridges` false) or live liquid bridges
    /// (`bridges` true), as sorted id pairs.
    pub fn bonded_pairs(&self, _p: &Particles, bridges: bool) -> Vec<(u32, u32)> {
        let mut v: Vec<(u32, u32)> = self
            .pairs
            .iter()
            .filter(|p| {
                if bridges {
                    p.s.bridge.is_some()
                } else {
                    p.s.touching
                }
            })
            .map(|p| (p.ida, p.idb))
            .collect();
        v.sort_unstable();
        v
    }

    /// Active solid contacts (particle–particle) and particle–wall.
    pub fn active_counts(&self) -> (usize, usize) {
        (
            self.pairs.iter().filter(|p| p.s.touching).count(),
            self.wall_pairs.iter().filter(|p| p.s.touching).count(),
        )
    }

    /// Live liquid bridges (particle–particle, particle–wall).
    pub fn bridge_counts(&self) -> (usize, usize) {
        (
            self.pairs.iter().filter(|p| p.s.bridge.is_some()).count(),
            self.wall_pairs
                .iter()
                .filter(|p| p.s.bridge.is_some())
                .count(),
        )
    }
}
