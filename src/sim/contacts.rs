//! Contact history: a flat store of candidate pairs (particle–particle and particle–wall),
//! each with the state of its solid contact and, in wet scenes, its liquid bridge. Pairs are
//! keyed by stable particle ids, so that history survives re-mapping and re-ordering.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::scene::{Particles, Vec3};
use crate::physics::bridge::{Bridge, BridgeCoeffs, BridgeModel};
use crate::physics::tangential::TangentialState;

/// State of a liquid bridge (Lian §5.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BridgeState {
    /// Liquid volume (m³).
    pub volume: f64,
    /// Rupture distance S_c (m) of the bridge model in use.
    pub s_c: f64,
    /// Static (capillary) force of the last step, attractive magnitude (N).
    pub f_static: f64,
    /// Viscous normal force of the last step, compressive positive (N).
    pub f_visc: f64,
    /// Gap of the last step (m).
    pub gap: f64,
    /// Work done against the static force since formation (J).
    pub work: f64,
    /// Liquid drawn from particle A and B (conserving mode; zero in Lian's mode).
    pub share: [f64; 2],
    /// Not yet settled with the particles' liquid (conserving mode).
    pub fresh: bool,
    /// Tangential viscous force on B of the last step (Goldman, `SET GOLdman ON`).
    pub f_tang: Vec3,
    /// Precomputed shape coefficients of the bridge model (rebuilt on load).
    pub coeffs: BridgeCoeffs,
}

impl BridgeState {
    pub fn new(model: BridgeModel, b: Bridge, gap: f64, share: [f64; 2]) -> Self {
        let coeffs = BridgeCoeffs::new(model, &b);
        BridgeState {
            volume: b.volume,
            s_c: coeffs.rupture_distance(),
            f_static: 0.0,
            f_visc: 0.0,
            gap,
            work: 0.0,
            share,
            fresh: share != [0.0; 2],
            f_tang: Vec3::zeros(),
            coeffs,
        }
    }

    /// Recomputes the coefficients for another model or new liquid parameters.
    pub fn rebuild(&mut self, model: BridgeModel) {
        self.coeffs = BridgeCoeffs::new(model, self.coeffs.bridge());
        self.s_c = self.coeffs.rupture_distance();
    }

    /// Half-filling angle on the first sphere at the last gap (rad).
    pub fn phi(&self) -> f64 {
        crate::physics::bridge::half_filling_angle(
            self.coeffs.model(),
            self.coeffs.bridge(),
            self.gap.max(0.0),
        )
    }
}

/// State of one contact: the part every contact law reads and writes at every step, kept
/// small (the force loop streams it), with the state of the laws only some scenes use (JKR,
/// Mindlin–Deresiewicz, liquid bridges) behind pointers that stay empty otherwise ("model
/// only what a scene needs": a Hertz contact with the no-slip law is 112 bytes).
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
    /// Stored tangential elastic energy.
    pub tang_energy: f64,
    /// Contact radius a.
    pub a: f64,
    /// Tangential force on B.
    pub tforce: Vec3,
    /// Tangential dashpot force on B (Rayleigh contact damping).
    pub tdamp: Vec3,
    /// JKR and Mindlin–Deresiewicz state, and liquid to return; `None` while all of it is
    /// at its default (Hertz contacts with the no-slip law never allocate it).
    pub ext: Option<Box<ContactExt>>,
    /// Liquid bridge, if any.
    pub bridge: Option<Box<BridgeState>>,
}

/// The part of a contact's state that only some laws use.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactExt {
    /// JKR separation radius a_s (3.117), computed at snap-in.
    pub a_s: f64,
    /// Surface energy of this contact (J/m²); 0 for a Hertz contact.
    pub gamma: f64,
    /// Accumulated tangential displacement vector δ (of B relative to A); kept by the
    /// Mindlin–Deresiewicz law (the no-slip law, like LIGGGHTS' and LAMMPS' shear history,
    /// keeps only the force).
    pub delta: Vec3,
    /// Signed resultant tangential displacement (Lian (5.23)).
    pub tdelta: f64,
    /// Signed resultant tangential law state.
    pub tang: TangentialState,
    /// Liquid returned to A and B by a bridge that ruptured in this step (conserving mode).
    pub released: [f64; 2],
}

static DEFAULT_EXT: std::sync::LazyLock<ContactExt> = std::sync::LazyLock::new(ContactExt::default);

impl ContactState {
    /// The law-specific state (the default values if the contact has none).
    pub fn ext(&self) -> &ContactExt {
        self.ext.as_deref().unwrap_or(&DEFAULT_EXT)
    }
    /// The law-specific state, allocated (at its defaults) if the contact had none.
    pub fn ext_mut(&mut self) -> &mut ContactExt {
        self.ext.get_or_insert_with(Box::default)
    }
    /// Surface energy of the contact (0: Hertz).
    pub fn gamma(&self) -> f64 {
        self.ext.as_ref().map_or(0.0, |e| e.gamma)
    }
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
    pub s: StateBox,
}

/// The contact state of a candidate pair, allocated only once the pair comes within reach:
/// most candidates never touch, and an inline state for each of them made the pair
/// list, its merges and the blow-up snapshot several times larger than the contacts need.
/// Reads of a pair without a state see the default state ([`std::ops::Deref`]); writes go
/// through [`StateBox::make_mut`] (allocates) or [`StateBox::get_mut`] (does not). In a
/// checkpoint it is written exactly as an inline [`ContactState`] (format version 1).
#[derive(Clone, Debug, Default)]
pub struct StateBox(Option<Box<ContactState>>);

static DEFAULT_STATE: std::sync::LazyLock<ContactState> =
    std::sync::LazyLock::new(ContactState::default);

impl StateBox {
    pub fn new(s: ContactState) -> Self {
        StateBox(Some(Box::new(s)))
    }
    /// The state, allocated (as the default state) if the pair had none.
    pub fn make_mut(&mut self) -> &mut ContactState {
        self.0.get_or_insert_with(Box::default)
    }
    /// The state if the pair has one (no allocation).
    pub fn get_mut(&mut self) -> Option<&mut ContactState> {
        self.0.as_deref_mut()
    }
}

impl std::ops::Deref for StateBox {
    type Target = ContactState;
    fn deref(&self) -> &ContactState {
        match &self.0 {
            Some(b) => b,
            None => &DEFAULT_STATE,
        }
    }
}

impl PartialEq for StateBox {
    fn eq(&self, o: &Self) -> bool {
        **self == **o
    }
}

impl Serialize for StateBox {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        (**self).serialize(ser)
    }
}

/// The default state's encoding: a loaded state that encodes the same (bit for bit, so
/// signed zeros count) stays unallocated.
static DEFAULT_BYTES: std::sync::LazyLock<Vec<u8>> = std::sync::LazyLock::new(|| {
    bincode::serde::encode_to_vec(&*DEFAULT_STATE, bincode::config::standard()).unwrap_or_default()
});

impl<'de> Deserialize<'de> for StateBox {
    fn deserialize<D: serde::Deserializer<'de>>(de: D) -> Result<Self, D::Error> {
        let s = v1::deserialize_state(de)?;
        let pristine = !s.touching
            && s.bridge.is_none()
            && bincode::serde::encode_to_vec(&s, bincode::config::standard())
                .is_ok_and(|b| b == *DEFAULT_BYTES);
        Ok(if pristine {
            StateBox::default()
        } else {
            StateBox::new(s)
        })
    }
}

/// A candidate pair found by the search (no state yet).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct PairKey {
    pub ida: u32,
    pub idb: u32,
    pub i: u32,
    pub j: u32,
}

/// A candidate particle–wall pair found by the search.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct WallKey {
    pub id: u32,
    pub wall: u32,
    pub i: u32,
}

/// A candidate particle–wall pair.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WallPair {
    pub i: u32,
    pub id: u32,
    pub wall: u32,
    #[serde(deserialize_with = "v1::deserialize_state")]
    pub s: ContactState,
}

/// Force of a pair in the last step: force on B (`f`) and the moment per unit radius
/// (`m = −n × F_t`, the same for both particles, Lian §2.4 item 10 corrected).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairForce {
    pub f: Vec3,
    pub m: Vec3,
}

/// The part of a candidate pair the force loop reads for every pair, kept apart from the
/// [`ContactState`] so that far-apart pairs without a bond cost one small read
/// (derived from `pairs`; rebuilt after every merge).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HotPair {
    pub i: u32,
    pub j: u32,
    /// The pair had a solid contact or a bridge after its last evaluation.
    pub live: bool,
    /// The pair was evaluated in this step (its `out` slot holds its force); pairs skipped as
    /// far apart carry no force and their `out` slot is stale.
    pub evaluated: bool,
}

/// Cloning (the blow-up snapshot, command undo) copies the state, not the derived per-step
/// buffers `out` and `hot` (rebuilt when needed).
#[derive(Debug, Default, Serialize, Deserialize)]
pub struct ContactStore {
    /// Per-pair forces of the current step (derived; not saved).
    #[serde(skip)]
    pub out: Vec<PairForce>,
    /// Indices and liveness of `pairs`, in the same order. Derived: rebuilt after a merge.
    #[serde(skip)]
    pub hot: Vec<HotPair>,
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

impl Clone for ContactStore {
    fn clone(&self) -> Self {
        let mut c = ContactStore::default();
        c.clone_from(self);
        c
    }
    fn clone_from(&mut self, o: &Self) {
        self.out.clear();
        self.hot.clear();
        self.pairs.clone_from(&o.pairs);
        self.wall_pairs.clone_from(&o.wall_pairs);
        self.stale = o.stale;
        self.remap = o.remap;
        self.tol = o.tol;
        self.rebuilds = o.rebuilds;
    }
}

/// Walks the sorted new keys against the sorted old entries: each key comes with the old
/// entry of the same id (whose history it carries on), or `None` for a new candidate.
fn carry<K, T, I: Ord>(
    new: Vec<K>,
    old: Vec<T>,
    id_new: impl Fn(&K) -> I,
    id_old: impl Fn(&T) -> I,
) -> impl Iterator<Item = (K, Option<T>)> {
    let mut old = old.into_iter().peekable();
    new.into_iter().map(move |k| {
        let id = id_new(&k);
        while old.peek().is_some_and(|o| id_old(o) < id) {
            old.next();
        }
        let same = old.next_if(|o| id_old(o) == id);
        (k, same)
    })
}

impl ContactStore {
    /// Replaces the pair lists by new candidates (sorted by ids), carrying over the state of
    /// pairs present in both. Pairs that disappear lose their history (they were farther apart
    /// than TOL and carried no bond).
    pub fn merge(&mut self, mut new_pairs: Vec<PairKey>, mut new_walls: Vec<WallKey>) {
        // Sort the small keys (not the pairs with their states), then walk both sorted lists.
        // The keys are unique, so the parallel sort gives the one sorted order.
        new_pairs.par_sort_unstable();
        let mut pairs: Vec<Pair> = carry(
            new_pairs,
            std::mem::take(&mut self.pairs),
            |k| (k.ida, k.idb),
            |o| (o.ida, o.idb),
        )
        .map(|(k, old)| Pair {
            i: k.i,
            j: k.j,
            ida: k.ida,
            idb: k.idb,
            s: old.map(|o| o.s).unwrap_or_default(),
        })
        .collect();
        // Re-allocate the states in pair order (all of a block freed first), so that the
        // force loop walks the heap forward instead of in the order the contacts were made.
        // Blocks in parallel (addresses do not affect results).
        pairs.par_chunks_mut(1024).for_each(|block| {
            let moved: Vec<(usize, ContactState)> = block
                .iter_mut()
                .enumerate()
                .filter_map(|(k, p)| p.s.0.take().map(|b| (k, *b)))
                .collect();
            for (k, st) in moved {
                block[k].s = StateBox::new(st);
            }
        });
        self.pairs = pairs;

        new_walls.sort_unstable();
        self.wall_pairs = carry(
            new_walls,
            std::mem::take(&mut self.wall_pairs),
            |k| (k.id, k.wall),
            |o| (o.id, o.wall),
        )
        .map(|(k, old)| WallPair {
            i: k.i,
            id: k.id,
            wall: k.wall,
            s: old.map(|o| o.s).unwrap_or_default(),
        })
        .collect();
        self.stale = false;
        self.remap = false;
        self.rebuilds += 1;
        self.hot.clear();
    }

    /// Drops the derived per-step buffers (rebuilt when needed; not part of the state).
    pub fn clear_derived(&mut self) {
        self.out.clear();
        self.hot.clear();
    }

    /// Builds the compact [`HotPair`] list from the pairs.
    pub fn build_hot(&mut self) {
        self.hot.clear();
        self.hot.extend(self.pairs.iter().map(|c| HotPair {
            i: c.i,
            j: c.j,
            live: c.s.touching || c.s.bridge.is_some(),
            evaluated: false,
        }));
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

/// Checkpoint format version 1 stored every contact state in one flat layout (with a contact
/// normal that was written and never read); this reads it into the current state.
pub mod v1 {
    use std::cell::Cell;

    use serde::{Deserialize, Deserializer};

    use super::{BridgeState, ContactExt, TangentialState, Vec3};

    thread_local! {
        static READING_V1: Cell<bool> = const { Cell::new(false) };
    }

    /// Runs `f` (a decoding of a whole checkpoint payload) with contact states read in the
    /// version-1 layout.
    pub fn reading<R>(f: impl FnOnce() -> R) -> R {
        READING_V1.with(|r| r.set(true));
        let out = f();
        READING_V1.with(|r| r.set(false));
        out
    }

    /// The contact state as format version 1 wrote it (frozen: never change).
    #[derive(Deserialize)]
    struct ContactState {
        touching: bool,
        overlap: f64,
        normal_force: f64,
        damp_force: f64,
        a_s: f64,
        tang_energy: f64,
        a: f64,
        gamma: f64,
        delta: Vec3,
        tforce: Vec3,
        tdamp: Vec3,
        tdelta: f64,
        tang: TangentialState,
        #[allow(dead_code)]
        normal: Vec3,
        bridge: Option<Box<BridgeState>>,
        released: [f64; 2],
    }

    impl From<ContactState> for super::ContactState {
        fn from(o: ContactState) -> Self {
            let ext = ContactExt {
                a_s: o.a_s,
                gamma: o.gamma,
                delta: o.delta,
                tdelta: o.tdelta,
                tang: o.tang,
                released: o.released,
            };
            super::ContactState {
                touching: o.touching,
                overlap: o.overlap,
                normal_force: o.normal_force,
                damp_force: o.damp_force,
                tang_energy: o.tang_energy,
                a: o.a,
                tforce: o.tforce,
                tdamp: o.tdamp,
                ext: (ext != ContactExt::default()).then(|| Box::new(ext)),
                bridge: o.bridge,
            }
        }
    }

    /// Reads a contact state in the layout of the checkpoint being decoded.
    pub fn deserialize_state<'de, D: Deserializer<'de>>(
        de: D,
    ) -> Result<super::ContactState, D::Error> {
        if READING_V1.with(|r| r.get()) {
            ContactState::deserialize(de).map(Into::into)
        } else {
            super::ContactState::deserialize(de)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The state every contact reads and writes at every step stays small (the force loop
    /// streams it): law-specific state belongs in `ContactExt` or `BridgeState`.
    #[test]
    fn the_per_step_contact_state_stays_small() {
        assert!(std::mem::size_of::<ContactState>() <= 112);
        assert!(std::mem::size_of::<Pair>() <= 24);
        assert!(std::mem::size_of::<HotPair>() <= 12);
    }
}
