//! Contact history: a flat store of candidate pairs (particle–particle and particle–wall),
//! each with the state of its solid contact and, in wet scenes, its liquid bridge. Pairs are
//! keyed by stable particle ids, so that history survives re-mapping and re-ordering.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::physics::bridge::{Bridge, BridgeCoeffs, BridgeModel};
use crate::physics::mdr::MdrRow;
use crate::physics::tangential::TangentialState;
use crate::physics::walton::WaltonState;

/// The vector of the simulation (`scene::Vec3`, the same type: the store sits below the
/// scene and names it itself).
type Vec3 = nalgebra::Vector3<f64>;

mod keys;
pub mod old;
mod rows;
mod serial;
mod split;
mod state;
mod walls;
pub use keys::*;
pub use rows::*;
pub use split::*;
pub use state::*;
pub use walls::*;

/// Pairs per block of contact states (and per chunk of the parallel force loop).
pub const BLOCK: usize = 1024;

/// The merge works through the new pairs in this many stretches, freeing the old states
/// behind each ([`ContactStore::merge`]).
const MERGE_STRETCHES: usize = 16;

/// No contact state allocated for a pair.
pub const NO_STATE: u32 = u32::MAX;

/// [`Incidence::shared`] of a particle that is not shared.
pub const NOT_SHARED: u32 = u32::MAX;

/// A candidate particle–particle pair: gap < TOL at the last rebuild, or a live bond. Its
/// contact state lives in the store's block of the pair (see [`ContactStore`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    /// Particle indices (valid until the next re-ordering; refreshed at rebuilds).
    pub i: u32,
    pub j: u32,
    /// Stable ids, `ida < idb`.
    pub ida: u32,
    pub idb: u32,
    /// Index of the state in the pair's block, or `NO_STATE`.
    pub(super) slot: u32,
}

/// A pair with its contact state, as checkpoints hold it and as pairs are given to
/// [`ContactStore::set_pairs`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairWithState {
    pub i: u32,
    pub j: u32,
    pub ida: u32,
    pub idb: u32,
    #[serde(deserialize_with = "old::deserialize_state")]
    pub s: ContactState,
}

/// A pair and its contact state (the default state if none is allocated), read-only, with
/// its MDR spring row or JKR row if its block keeps one for it ([`StateBlock`]; a pair's
/// MDR row is never in `s.ext`, nor is its JKR row's path end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairView<'a> {
    pub i: u32,
    pub j: u32,
    pub ida: u32,
    pub idb: u32,
    pub s: &'a ContactState,
    pub row: Option<&'a MdrRow>,
    pub jkr: Option<&'a JkrRow>,
}

static DEFAULT_STATE: std::sync::LazyLock<ContactState> =
    std::sync::LazyLock::new(ContactState::default);

/// The default state's encoding: a loaded state that encodes the same (bit for bit, so
/// signed zeros count) stays unallocated.
static DEFAULT_BYTES: std::sync::LazyLock<Vec<u8>> = std::sync::LazyLock::new(|| {
    bincode::serde::encode_to_vec(&*DEFAULT_STATE, bincode::config::standard()).unwrap_or_default()
});

/// The state is the default state of a pair that never came within reach (it needs no
/// allocation).
fn pristine(s: &ContactState) -> bool {
    !s.touching
        && s.bridge.is_none()
        && bincode::serde::encode_to_vec(s, bincode::config::standard())
            .is_ok_and(|b| b == *DEFAULT_BYTES)
}

/// A candidate pair found by the search (no state yet).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct PairKey {
    pub ida: u32,
    pub idb: u32,
    pub i: u32,
    pub j: u32,
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
    /// Index of the pair's state in its block (`u32::MAX`: none yet).
    pub slot: u32,
    /// The pair had a solid contact, a bridge or a dashpot's history after its last
    /// evaluation (`ContactState::live`).
    pub live: bool,
    /// Set by [`Incidence::split`]: bit 0 if the first particle is shared between tasks,
    /// bit 1 if the second is (the multi-thread loop's ownership test, without a lookup).
    pub shared: u8,
}

/// What the force loop works on (see [`ContactStore::step_parts`]): the store's parts,
/// borrowed each on its own.
pub struct StepParts<'a> {
    /// The hot list (indices, state slots, liveness), in pair order.
    pub hot: &'a mut [HotPair],
    pub pairs: &'a mut [Pair],
    /// The contact states (and MDR rows) in blocks of `BLOCK` pairs.
    pub blocks: &'a mut [StateBlock],
    /// Per-pair force slots of the shared particles (several threads).
    pub out: &'a mut Vec<PairForce>,
    /// Which particles are shared between tasks, and their pairs.
    pub scatter: &'a mut Incidence,
    pub wall_pairs: &'a mut [WallPair],
    pub wall_out: &'a mut WallOut,
}

/// The contact history of all candidate pairs.
///
/// Pairs are sorted by ids. Their contact states are stored in blocks: block `b` holds the
/// states of pairs `b·BLOCK .. (b+1)·BLOCK`, in pair order after each merge, so the force loop
/// reads them as a forward stream, each chunk of the parallel loop owns its block, and a pair
/// that comes within reach between rebuilds gets its state appended to its own block. Pairs
/// that never come within reach have no state (they read as the default state).
///
/// Cloning (the blow-up snapshot, command undo) copies the state, not the derived per-step
/// buffers `out` and `hot` (rebuilt when needed). In a checkpoint every pair is written with
/// its state inline ([`PairWithState`]), as format versions 1 and 2 always did.
///
/// # The flags, as a state machine
///
/// | flag | set by | cleared by | meaning while set |
/// |---|---|---|---|
/// | `stale` | any command that changes the scene (placement, radii, materials, walls, SET, LIQuid, MOve) | `cycle::prime` at the start of the next `Cycle` | the candidate list and the contact states do not match the particles: rebuild, then evaluate every state at the current positions (Δt = 0) |
/// | `remap` | the update, when a displacement component since the last rebuild exceeds XRES or a wall travelled that far; the start of a `Cycle` when TOL grew | the rebuild before the next force step | the candidate list may miss pairs; the states are the last step's and are carried by id, never re-evaluated |
/// | `step.deferred` | the force step with several threads (or walls) | the update of each chunk (`finish_chunk`) | the particles' sums are partial: shared particles, wall forces and moment scaling are still to be added |
/// | `step.zeroed` | the update, when it cleared a chunk's forces after use | a step whose forces are kept (the last of a `Cycle`, the one before a snapshot) | the force and moment arrays are zero, the next force step need not clear them |
///
/// `stale` and `remap` are never both acted on: `stale` wins (a full re-evaluation includes the
/// rebuild). Saved (`serial.rs`): the pairs with their states, the wall pairs, `stale`,
/// `remap`, `tol` and `rebuilds`; the other flags and buffers are derived and start afresh
/// after `RESTart` (the first `Cycle` re-derives them without changing a state, so a
/// continued run is bitwise the uninterrupted one).
#[derive(Default)]
pub struct ContactStore {
    pairs: Vec<Pair>,
    blocks: Vec<StateBlock>,
    pub(in crate::sim) wall_pairs: Vec<WallPair>,
    /// A command changed the scene: rebuild the candidate list and re-evaluate the contact
    /// states at the current positions (`cycle::prime`) before the next step.
    stale: bool,
    /// Particles moved more than XRES (or TOL changed) since the last rebuild: rebuild the
    /// candidate list before the next force evaluation. The contact states are those of the
    /// last step and must not be re-evaluated (that would advance history-dependent laws twice
    /// and break exact continuation across `Cycle` commands and `SAve`/`RESTart`).
    remap: bool,
    /// Search distance used at the last rebuild.
    tol: f64,
    /// Number of rebuilds so far (for PRint Entries).
    rebuilds: u64,
    /// Per-step working buffers (derived, never saved; see [`StepBuffers`]).
    pub(in crate::sim) step: StepBuffers,
}

/// The contact store's per-step working buffers: derived from the pairs and the particles,
/// never saved, rebuilt when needed (`ContactStore::clear_derived` drops them). Kept apart
/// from the saved state so that what a checkpoint holds is plain.
#[derive(Default)]
pub struct StepBuffers {
    /// Per-pair forces of the current step (derived; not saved; used with several threads).
    pub out: Vec<PairForce>,
    /// Forces of the wall pairs evaluated in the current step (derived; not saved).
    pub wall_out: WallOut,
    /// The force step leaves to the particle update, chunk by chunk before it moves the
    /// particles: with several threads the shared particles' sums (from the pairs' slots),
    /// the moments' scaling by the radius, the wall forces (`cycle::finish_chunk`; derived,
    /// not saved).
    pub deferred: bool,
    /// The particles' force and moment arrays are zero: the update cleared each chunk's
    /// after using them, so the next force step need not (derived, not saved; a step
    /// whose forces are kept, the last of a `Cycle` or one before a blow-up snapshot,
    /// leaves it false).
    pub zeroed: bool,
    /// Indices, state slots and liveness of `pairs`, in the same order. Derived: rebuilt
    /// after a merge.
    pub hot: Vec<HotPair>,
    /// Derived with `hot` (several threads): the pairs of each particle, in pair order
    /// (empty: not built yet).
    pub scatter: Incidence,
    /// How far beyond touching particle pairs and particle–wall pairs are evaluated in the
    /// current step (`interact::Laws::margin`; derived, set by `cycle::one_step`).
    pub margins: [f64; 2],
    /// The rolling moments of the current step per particle (`sim::rolling`; empty
    /// without rolling friction; derived, not saved).
    pub roll: Vec<Vec3>,
    /// The largest displacement component of a particle since the last rebuild, as the last
    /// update left it (derived; `None`: not known, worked out from the displacements).
    pub max_disp: Option<f64>,
}

impl Clone for ContactStore {
    fn clone(&self) -> Self {
        let mut c = ContactStore::default();
        c.clone_from(self);
        c
    }
    fn clone_from(&mut self, o: &Self) {
        self.clear_derived();
        self.pairs.clone_from(&o.pairs);
        self.blocks.clone_from(&o.blocks);
        self.wall_pairs.clone_from(&o.wall_pairs);
        self.stale = o.stale;
        self.remap = o.remap;
        self.tol = o.tol;
        self.rebuilds = o.rebuilds;
    }
}

/// The state of the store: pairs with their states (not where the states are kept, nor the
/// derived buffers).
impl std::fmt::Debug for ContactStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactStore")
            .field("pairs", &self.iter().collect::<Vec<_>>())
            .field("wall_pairs", &self.wall_pairs)
            .field("stale", &self.stale)
            .field("remap", &self.remap)
            .field("tol", &self.tol)
            .field("rebuilds", &self.rebuilds)
            .finish()
    }
}

impl PartialEq for ContactStore {
    fn eq(&self, o: &Self) -> bool {
        self.pairs.len() == o.pairs.len()
            && self.iter().eq(o.iter())
            && self.wall_pairs == o.wall_pairs
            && (self.stale, self.remap, self.rebuilds) == (o.stale, o.remap, o.rebuilds)
            && self.tol.to_bits() == o.tol.to_bits()
    }
}

/// Free state slots a block keeps for contacts that form before the next rebuild: a few
/// per step in a settling bed, so 1/16 of its states plus 4 (a `Vec` that doubled when full
/// would hold up to twice the live states: 4.8 of the 20 MB heap peak of the S1 10k bed).
fn headroom(n: usize) -> usize {
    n / 16 + 4
}

/// Makes room for one more state in a block: by [`headroom`] when full, not by doubling.
#[inline]
pub fn grow_block(block: &mut Vec<ContactState>) {
    if block.len() == block.capacity() {
        block.reserve_exact(headroom(block.len()));
    }
}

/// Walks sorted keys over the sorted old pairs from index `start`: for each key, the old pair
/// of the same ids if it has a state (its index and slot).
fn old_states(old: &[Pair], start: usize) -> impl FnMut(&PairKey) -> Option<(usize, u32)> + '_ {
    let mut k = start;
    move |key| {
        let id = (key.ida, key.idb);
        while k < old.len() && (old[k].ida, old[k].idb) < id {
            k += 1;
        }
        old.get(k)
            .filter(|o| (o.ida, o.idb) == id && o.slot != NO_STATE)
            .map(|o| (k, o.slot))
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
    /// A command changed the scene: the next `Cycle` rebuilds and re-evaluates (the flags'
    /// table above).
    pub fn mark_stale(&mut self) {
        self.stale = true;
    }

    /// Whether a command changed the scene since the contacts were last evaluated.
    pub fn is_stale(&self) -> bool {
        self.stale
    }

    /// The candidate list must be rebuilt before the next force step (the states are kept).
    pub fn request_remap(&mut self) {
        self.remap = true;
    }

    /// Whether a rebuild is due before the next force step.
    pub fn needs_remap(&self) -> bool {
        self.remap
    }

    /// The search distance TOL of the last rebuild.
    pub fn tol(&self) -> f64 {
        self.tol
    }

    /// Records the search distance of a rebuild.
    pub fn set_tol(&mut self, tol: f64) {
        self.tol = tol;
    }

    /// Rebuilds of the candidate list so far (PRint Entries).
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Number of candidate pairs.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
    /// The candidate pairs, sorted by ids.
    pub fn pairs(&self) -> &[Pair] {
        &self.pairs
    }
    /// The particle–wall pairs within reach, in particle then wall order.
    pub fn wall_pairs(&self) -> &[WallPair] {
        &self.wall_pairs
    }
    /// The particle–wall pairs, mutable, for tests and tools that build states no command
    /// can (the pairs must stay in particle then wall order, one per particle and wall).
    pub fn wall_pairs_mut(&mut self) -> &mut Vec<WallPair> {
        &mut self.wall_pairs
    }
    /// The per-step working buffers (read by tests of the scheduling).
    pub fn step_buffers(&self) -> &StepBuffers {
        &self.step
    }
    /// The candidate pairs, to change their indices (not their number or order).
    pub fn pairs_mut(&mut self) -> &mut [Pair] {
        &mut self.pairs
    }
    /// The contact state of pair `k` (the default state if it has none).
    pub fn state(&self, k: usize) -> &ContactState {
        let slot = self.pairs[k].slot;
        if slot == NO_STATE {
            &DEFAULT_STATE
        } else {
            &self.blocks[k / BLOCK][slot as usize]
        }
    }
    /// The contact state of pair `k`, allocated (as the default state) if it had none (the
    /// force loop allocates in place, `cycle::pair_force`; this is for tests).
    pub fn state_mut(&mut self, k: usize) -> &mut ContactState {
        let b = &mut self.blocks[k / BLOCK];
        let p = &mut self.pairs[k];
        if p.slot == NO_STATE {
            p.slot = b.len() as u32;
            b.push(ContactState::default());
            if let Some(h) = self.step.hot.get_mut(k) {
                h.slot = p.slot;
            }
        }
        &mut b[p.slot as usize]
    }
    /// Pair `k` with its state.
    pub fn pair(&self, k: usize) -> PairView<'_> {
        let p = &self.pairs[k];
        PairView {
            i: p.i,
            j: p.j,
            ida: p.ida,
            idb: p.idb,
            s: self.state(k),
            row: (p.slot != NO_STATE)
                .then(|| self.blocks[k / BLOCK].row(p.slot as usize))
                .flatten(),
            jkr: (p.slot != NO_STATE)
                .then(|| self.blocks[k / BLOCK].jkr_row(p.slot as usize))
                .flatten(),
        }
    }
    /// The state of pair `k` in the checkpoint's shape (its MDR row in `ext.mdr`, its JKR
    /// row's path end in `ext.end`).
    pub fn saved_state(&self, k: usize) -> std::borrow::Cow<'_, ContactState> {
        let slot = self.pairs[k].slot;
        if slot == NO_STATE {
            std::borrow::Cow::Borrowed(&DEFAULT_STATE)
        } else {
            self.blocks[k / BLOCK].saved(slot as usize)
        }
    }
    /// All pairs with their states, in pair order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = PairView<'_>> + '_ {
        (0..self.pairs.len()).map(|k| self.pair(k))
    }
    /// Whether a stored state's overlap exceeds `limit`: every state of every block (a
    /// superset of the pairs' states), read without a pair, radius or row lookup.
    pub fn any_overlap_above(&self, limit: f64) -> bool {
        self.blocks
            .iter()
            .any(|b| b.iter().any(|s| s.overlap > limit))
    }
    /// Calls `f` on every pair that has a state, in pair order, with the state to change.
    pub fn for_each_state_mut(&mut self, mut f: impl FnMut(&Pair, &mut ContactState)) {
        for (k, p) in self.pairs.iter().enumerate() {
            if p.slot != NO_STATE {
                f(p, &mut self.blocks[k / BLOCK][p.slot as usize]);
            }
        }
    }
    /// The parts the force loop works on: hot pairs, pairs, blocks of states (one per
    /// `BLOCK` pairs) and the per-pair force slots.
    pub fn step_parts(&mut self) -> StepParts<'_> {
        if self.step.hot.len() != self.pairs.len() {
            self.build_hot();
        }
        StepParts {
            hot: &mut self.step.hot,
            pairs: &mut self.pairs,
            blocks: &mut self.blocks,
            out: &mut self.step.out,
            scatter: &mut self.step.scatter,
            wall_pairs: &mut self.wall_pairs,
            wall_out: &mut self.step.wall_out,
        }
    }

    /// Replaces all pairs (sorted by ids) and their states.
    pub fn set_pairs(&mut self, pairs: Vec<PairWithState>) {
        self.pairs.clear();
        self.blocks.clear();
        for p in pairs {
            self.push(p);
        }
        self.trim_last_block();
        self.clear_hot();
    }
    /// Appends a pair with its state (the caller keeps the pairs sorted by ids).
    pub fn push(&mut self, p: PairWithState) {
        let k = self.pairs.len();
        if k.is_multiple_of(BLOCK) {
            self.trim_last_block();
            self.blocks.push(StateBlock::default());
        }
        let b = &mut self.blocks[k / BLOCK];
        let slot = if pristine(&p.s) {
            NO_STATE
        } else {
            b.push_saved(p.s)
        };
        self.pairs.push(Pair {
            i: p.i,
            j: p.j,
            ida: p.ida,
            idb: p.idb,
            slot,
        });
        self.clear_hot();
    }
    /// The store as the blow-up snapshot keeps it: only the pairs and wall pairs whose state
    /// is not the default one (the others read as the default state and are found again by
    /// the search), their states in blocks of the exact size, and the list marked for
    /// re-mapping, so the first step after a restore searches anew and keeps these states.
    /// At S1 50k this is a quarter of the pairs and wall pairs (those touching): 4 MB less
    /// held through the whole `Cycle`.
    pub fn lean_clone(&self) -> ContactStore {
        let mut c = ContactStore::default();
        for (k, p) in self.pairs.iter().enumerate() {
            if p.slot == NO_STATE {
                continue;
            }
            let from = &self.blocks[k / BLOCK];
            if pristine(&from[p.slot as usize]) {
                continue;
            }
            let n = c.pairs.len();
            if n.is_multiple_of(BLOCK) {
                if let Some(b) = c.blocks.last_mut() {
                    b.shrink_to_fit();
                }
                c.blocks.push(StateBlock::of(Vec::with_capacity(BLOCK)));
            }
            let slot = c.blocks[n / BLOCK].push_copy(from, p.slot as usize);
            c.pairs.push(Pair {
                i: p.i,
                j: p.j,
                ida: p.ida,
                idb: p.idb,
                slot,
            });
        }
        if let Some(b) = c.blocks.last_mut() {
            b.shrink_to_fit();
        }
        c.pairs.shrink_to_fit();
        c.wall_pairs = self
            .wall_pairs
            .iter()
            .filter(|w| !pristine(&w.s))
            .cloned()
            .collect();
        c.stale = self.stale;
        c.remap = !self.stale;
        c.tol = self.tol;
        c.rebuilds = self.rebuilds;
        c
    }
    /// Gives the last block the room a merge gives it ([`headroom`]) instead of what
    /// doubling by [`ContactStore::push`] left (up to twice its states).
    fn trim_last_block(&mut self) {
        if let Some(b) = self.blocks.last_mut() {
            b.trim();
        }
    }
    /// Removes all particle–particle pairs.
    pub fn clear_pairs(&mut self) {
        self.pairs.clear();
        self.blocks.clear();
        self.clear_hot();
    }
    /// Keeps the pairs for which `f` returns true (it may change their indices), with their
    /// states; the others lose their history.
    pub fn retain_pairs(&mut self, mut f: impl FnMut(&mut Pair) -> bool) {
        let pairs = std::mem::take(&mut self.pairs);
        let mut blocks = std::mem::take(&mut self.blocks);
        for (k, mut p) in pairs.into_iter().enumerate() {
            if f(&mut p) {
                let s = if p.slot == NO_STATE {
                    ContactState::default()
                } else {
                    blocks[k / BLOCK].take_saved(p.slot as usize)
                };
                self.push(PairWithState {
                    i: p.i,
                    j: p.j,
                    ida: p.ida,
                    idb: p.idb,
                    s,
                });
            }
        }
        self.trim_last_block();
        self.clear_hot();
    }

    /// Replaces the pair lists by new candidates (sorted by ids), carrying over the state of
    /// pairs present in both. Pairs that disappear lose their history (they were farther apart
    /// than TOL and carried no bond). The states are laid out anew in pair order.
    pub fn merge(&mut self, new_pairs: impl Into<KeyParts>, mut new_walls: Vec<WallKey>) {
        // Sort the small keys (not the pairs with their states), then walk both sorted lists.
        let new_pairs = new_pairs.into().into_sorted();
        // The hot list goes first: a rebuild holds the old and the new lists at once.
        self.step.hot = Vec::new();
        self.step.scatter.clear();
        let old_pairs = std::mem::take(&mut self.pairs);
        // The old states are cloned, not moved: a clone allocates the boxes of the
        // Mindlin–Deresiewicz, JKR and bridge states anew, in pair order, so the force loop
        // reads them in order too (moving them, which keeps the boxes where the contacts
        // formed, made the merge 30 % cheaper and the JKR agglomerate 8–14 % slower); the
        // MDR and JKR rows are copied into their new block's lists in pair order
        // (`StateBlock`).
        let old_blocks = std::mem::take(&mut self.blocks);
        let old_walls = std::mem::take(&mut self.wall_pairs);
        // The wall pairs are carried over beside the particle pairs (nothing shared).
        let walls = || {
            new_walls.sort_unstable();
            carry(new_walls, old_walls, |k| (k.id, k.wall), |o| (o.id, o.wall))
                .map(|(k, old)| WallPair {
                    i: k.i,
                    id: k.id,
                    wall: k.wall,
                    s: old.map(|o| o.s).unwrap_or_default(),
                })
                .collect()
        };
        // Each block of new pairs finds its first old pair by bisection and walks on from
        // there (blocks in parallel; the same pairs and states as one walk), writing its pairs
        // in place and its states into a block of the exact size.
        let mut pairs = vec![
            Pair {
                i: 0,
                j: 0,
                ida: 0,
                idb: 0,
                slot: NO_STATE
            };
            new_pairs.len()
        ];
        let particle_pairs = || {
            let mut old_blocks = old_blocks;
            let mut blocks: Vec<StateBlock> = Vec::with_capacity(pairs.len().div_ceil(BLOCK));
            // In stretches of whole blocks, in order; after each, the old blocks that no later
            // key can reach (all their pairs sort before the next key) are freed, so the old
            // and the new states are held at once only around the stretch being merged
            // (S1 50k: ~6 MB less at the rebuild's peak than all old and all new states).
            let stretch = BLOCK * pairs.len().div_ceil(BLOCK).div_ceil(MERGE_STRETCHES).max(1);
            let mut freed = 0;
            for (keys, out) in new_pairs.chunks(stretch).zip(pairs.chunks_mut(stretch)) {
                let olds = &old_blocks;
                let done: Vec<StateBlock> = keys
                    .par_chunks(BLOCK)
                    .zip(out.par_chunks_mut(BLOCK))
                    .map(|(keys, out)| {
                        let first = (keys[0].ida, keys[0].idb);
                        let start = old_pairs.partition_point(|o| (o.ida, o.idb) < first);
                        // One walk: each key's old pair with a state (u32::MAX: none), then the
                        // states copied in pair order into a block of the exact size.
                        let mut matched = old_states(&old_pairs, start);
                        let mut old_of = [u32::MAX; BLOCK];
                        let (mut n, mut n_rows, mut n_jkr) = (0, 0, 0);
                        for (key, m) in keys.iter().zip(old_of.iter_mut()) {
                            if let Some((k_old, s_old)) = matched(key) {
                                *m = k_old as u32;
                                n += 1;
                                let row = olds[k_old / BLOCK][s_old as usize].row;
                                n_rows += row.mdr().is_some() as usize;
                                n_jkr += row.jkr().is_some() as usize;
                            }
                        }
                        let mut states = StateBlock::with_room(n, n_rows, n_jkr);
                        for ((key, p), &m) in keys.iter().zip(out.iter_mut()).zip(old_of.iter()) {
                            let slot = if m == u32::MAX {
                                NO_STATE
                            } else {
                                let k_old = m as usize;
                                let s_old = old_pairs[k_old].slot as usize;
                                states.push_copy(&olds[k_old / BLOCK], s_old)
                            };
                            *p = Pair {
                                i: key.i,
                                j: key.j,
                                ida: key.ida,
                                idb: key.idb,
                                slot,
                            };
                        }
                        states
                    })
                    .collect();
                blocks.extend(done);
                // The old blocks below the first old pair that a later key can match.
                let last = keys[keys.len() - 1];
                let reach = old_pairs.partition_point(|o| (o.ida, o.idb) <= (last.ida, last.idb));
                let upto = (reach / BLOCK).min(old_blocks.len());
                if upto > freed {
                    // (Each old block is freed by a worker: the drop visits every state's boxes.)
                    old_blocks[freed..upto]
                        .par_iter_mut()
                        .for_each(|b| drop(std::mem::take(b)));
                    freed = upto;
                }
            }
            old_blocks.into_par_iter().for_each(drop);
            drop(old_pairs);
            drop(new_pairs);
            (pairs, blocks)
        };
        let ((pairs, blocks), wall_pairs) = rayon::join(particle_pairs, walls);
        self.pairs = pairs;
        self.blocks = blocks;
        self.wall_pairs = wall_pairs;
        self.stale = false;
        self.remap = false;
        self.rebuilds += 1;
        self.clear_hot();
    }

    /// Drops the derived per-step buffers (rebuilt when needed; not part of the state).
    pub fn clear_derived(&mut self) {
        self.step.max_disp = None;
        self.step.margins = [0.0; 2];
        self.step.out.clear();
        self.step.wall_out = WallOut::default();
        self.step.deferred = false;
        self.step.zeroed = false;
        self.clear_hot();
    }

    /// Drops the hot list and what is derived from it.
    fn clear_hot(&mut self) {
        self.step.hot.clear();
        self.step.scatter.clear();
    }

    /// Builds the compact [`HotPair`] list from the pairs (blocks in parallel: once per
    /// rebuild, one random read of a state per pair that has one).
    pub fn build_hot(&mut self) {
        let mut hot = std::mem::take(&mut self.step.hot);
        hot.clear();
        hot.resize(self.pairs.len(), HotPair::default());
        hot.par_chunks_mut(BLOCK)
            .zip(self.pairs.par_chunks(BLOCK))
            .zip(self.blocks.par_iter())
            .for_each(|((hot, pairs), states)| {
                for (h, p) in hot.iter_mut().zip(pairs) {
                    let live = p.slot != NO_STATE && states[p.slot as usize].live();
                    *h = HotPair {
                        i: p.i,
                        j: p.j,
                        slot: p.slot,
                        live,
                        shared: 0,
                    };
                }
            });
        self.step.hot = hot;
    }

    /// Active solid contacts (particle–particle) and particle–wall.
    pub fn active_counts(&self) -> (usize, usize) {
        (
            self.iter().filter(|p| p.s.touching).count(),
            self.wall_pairs.iter().filter(|p| p.s.touching).count(),
        )
    }

    /// Live liquid bridges (particle–particle, particle–wall).
    pub fn bridge_counts(&self) -> (usize, usize) {
        (
            self.iter().filter(|p| p.s.bridge.is_some()).count(),
            self.wall_pairs
                .iter()
                .filter(|p| p.s.bridge.is_some())
                .count(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs in the order of a list sorted by ids, where ids need not follow the particle
    /// indices: the incidence lists every pair of a particle once, in pair order, and a
    /// particle not marked shared has all its pairs in the task of its interval.
    #[test]
    fn incidence_lists_pairs_in_order_and_shared_particles_are_the_others() {
        let np = 200;
        let mut rng = crate::sim::rng::Rng::new(3);
        let mut hot = Vec::new();
        for _ in 0..3000 {
            let i = (rng.uniform() * np as f64) as u32 % np as u32;
            let mut j = (i + 1 + (rng.uniform() * 12.0) as u32) % np as u32;
            if j == i {
                j = (i + 1) % np as u32;
            }
            hot.push(HotPair {
                i,
                j,
                ..Default::default()
            });
        }
        // Mostly in index order, as in a bed sorted by ids that follow the indices.
        hot.sort_by_key(|h| (h.i.min(h.j) / 8, h.i, h.j));
        let mut inc = Incidence::default();
        let all = hot.clone();
        let mine = |q: usize| -> Vec<u32> {
            (0..all.len() as u32)
                .filter(|&k| all[k as usize].i as usize == q || all[k as usize].j as usize == q)
                .collect()
        };
        let cut = [0, 1024, 2048, hot.len()];
        let parts = [
            0,
            hot[1024].i as usize,
            hot[2048].i.max(hot[1024].i) as usize,
            np,
        ];
        let ranges: Vec<PairRange> = (0..3)
            .map(|r| PairRange {
                pairs: cut[r]..cut[r + 1],
                parts: parts[r]..parts[r + 1],
            })
            .collect();
        inc.split(&mut hot, np, ranges.clone(), 3);
        // Each pair carries its particles' shared flags.
        for h in &hot {
            let want = u8::from(inc.shared[h.i as usize] != NOT_SHARED)
                | (u8::from(inc.shared[h.j as usize] != NOT_SHARED) << 1);
            assert_eq!(h.shared, want);
        }
        let mut owned = 0;
        for (r, rg) in ranges.iter().enumerate() {
            for q in rg.parts.clone() {
                let inside = mine(q).iter().all(|&k| rg.pairs.contains(&(k as usize)));
                assert_eq!(
                    inc.shared[q] != NOT_SHARED,
                    !inside,
                    "particle {q} of task {r}"
                );
                owned += inside as usize;
            }
        }
        assert_eq!(inc.shared_list.len(), np - owned);
        // Each shared particle's list: all its pairs, in pair order.
        for (s, &q) in inc.shared_list.iter().enumerate() {
            assert_eq!(
                inc.of_shared(s),
                &mine(q as usize)[..],
                "shared particle {q}"
            );
        }
        // Slots: exactly the pairs of shared particles, numbered in pair order, each task's
        // contiguous.
        let mut next = 0;
        for (k, h) in hot.iter().enumerate() {
            if inc.shared[h.i as usize] != NOT_SHARED || inc.shared[h.j as usize] != NOT_SHARED {
                assert_eq!(inc.slot[k], next, "pair {k}");
                next += 1;
            } else {
                assert_eq!(inc.slot[k], u32::MAX, "pair {k}");
            }
        }
        assert_eq!(inc.slots, next as usize);
        for (r, s) in ranges.iter().zip(&inc.task_slots) {
            let mine: Vec<u32> = inc.slot[r.pairs.clone()]
                .iter()
                .copied()
                .filter(|&x| x != u32::MAX)
                .collect();
            assert_eq!(mine, (s.start as u32..s.end as u32).collect::<Vec<_>>());
        }
        assert!(owned > np / 2 && owned < np, "{owned} of {np} owned");
    }

    /// The state every contact reads and writes at every step stays small (the force loop
    /// streams it): law-specific state belongs in `ContactExt` or `BridgeState`. (120 bytes
    /// since the separation rate of the last step, `v_prev`, that the second-order dashpot
    /// needs; 112 before.)
    #[test]
    fn the_per_step_contact_state_stays_small() {
        assert!(std::mem::size_of::<ContactState>() <= 120);
        assert!(std::mem::size_of::<Pair>() <= 20);
        assert!(std::mem::size_of::<HotPair>() <= 16);
    }

    /// A block grows by its headroom, not by doubling: 300 states appended one by one to an
    /// empty block never leave more than 1/16 + 4 of them unused (a doubling `Vec` would
    /// have left 212 free slots at 300).
    #[test]
    fn state_blocks_grow_by_their_headroom() {
        let mut b: Vec<ContactState> = Vec::new();
        for n in 1..=300 {
            grow_block(&mut b);
            b.push(ContactState::default());
            assert!(
                b.capacity() <= n + headroom(n),
                "{} states, capacity {}",
                n,
                b.capacity()
            );
        }
        // The merge sizes a block for its states plus the headroom.
        let mut store = ContactStore::default();
        let keys: Vec<PairKey> = (0..600u32)
            .map(|k| PairKey {
                i: k,
                j: k + 1,
                ida: k + 1,
                idb: k + 2,
            })
            .collect();
        store.merge(keys.clone(), Vec::new());
        for k in 0..300 {
            store.state_mut(2 * k);
        }
        store.merge(keys, Vec::new());
        assert_eq!(store.blocks[0].len(), 300);
        assert!(store.blocks[0].capacity() <= 300 + headroom(300));
    }

    /// The walls' forces are the pieces' block sums added in block order, whatever the
    /// pieces (a split of the same blocks into two pieces gives the same bits), and a chunk's
    /// wall forces come piece after piece, each in pair order.
    #[test]
    fn wall_output_in_pieces_sums_blocks_in_order() {
        let force = |i: u32, x: f64| WallForce {
            f: Vec3::new(x, -x, 0.5 * x),
            m: Vec3::zeros(),
            i,
        };
        // Three blocks of sums for two walls, with magnitudes that make the order matter.
        // (Wall 0's x: 1, 1e16, −1e16 — in block order 0; the second piece summed on its
        // own first would give 1.)
        let sums = vec![
            [1.0, 1.0, 0.0],
            [0.3, 0.0, 0.0],
            [1e16, 1e-16, 0.0],
            [0.7, 0.0, 0.0],
            [-1e16, 3.0, 0.0],
            [0.1, 0.0, 0.0],
        ];
        let piece = |forces: Vec<WallForce>, sums: &[[f64; 3]]| {
            let mut p = WallPiece {
                forces,
                sums: sums.to_vec(),
                ..Default::default()
            };
            // Chunk of each entry (two chunks), stable.
            p.start = vec![0, 0, 0];
            for o in &p.forces {
                p.start[o.i as usize / CHUNK_FOR_TEST + 1] += 1;
            }
            p.start[2] += p.start[1];
            let mut fill = p.start.clone();
            p.order = vec![0; p.forces.len()];
            for (e, o) in p.forces.iter().enumerate() {
                let c = o.i as usize / CHUNK_FOR_TEST;
                p.order[fill[c] as usize] = e as u32;
                fill[c] += 1;
            }
            p
        };
        let one = WallOut {
            pieces: vec![piece(
                vec![force(0, 1.0), force(5, 2.0), force(1, 3.0), force(6, 4.0)],
                &sums,
            )],
            on_wall: Vec::new(),
        };
        let two = WallOut {
            pieces: vec![
                piece(vec![force(0, 1.0), force(5, 2.0)], &sums[..2]),
                piece(vec![force(1, 3.0), force(6, 4.0)], &sums[2..]),
            ],
            on_wall: Vec::new(),
        };
        let (mut one, mut two) = (one, two);
        one.sum_walls(2);
        two.sum_walls(2);
        let want_0: f64 = ((0.0 + 1.0) + 1e16) + -1e16;
        assert_eq!(want_0, 0.0);
        assert_eq!(one.on_wall[0][0].to_bits(), want_0.to_bits());
        assert_eq!(one.on_wall, two.on_wall);
        for c in 0..2 {
            let xs = |w: &WallOut| {
                WallOut::of_chunk(&w.pieces, c)
                    .map(|o| o.f.x)
                    .collect::<Vec<_>>()
            };
            assert_eq!(xs(&one), xs(&two), "chunk {c}");
        }
        assert_eq!(
            WallOut::of_chunk(&two.pieces, 0)
                .map(|o| o.i)
                .collect::<Vec<_>>(),
            vec![0, 1],
            "piece after piece"
        );
    }

    /// Particles per chunk in [`wall_output_in_pieces_sums_blocks_in_order`].
    const CHUNK_FOR_TEST: usize = 4;

    #[test]
    fn keys_sort_by_ids() {
        // Ids spread over many digits, in a scrambled order; the sort equals a comparison sort.
        let mut rng = crate::sim::rng::Rng::new(7);
        // (Up to 3000 the counting sort by the lower id runs, cut into 1, 2, 3 or 7 ranges
        // of ids; beyond it the radix sort.)
        for max in [1u32, 5, 300, 3000, 1 << 20, u32::MAX] {
            let mut keys: Vec<PairKey> = (0..5000u32)
                .map(|k| {
                    let a = (rng.next_u64() % (max as u64 + 1)) as u32;
                    let b = (rng.next_u64() % (max as u64 + 1)) as u32;
                    PairKey {
                        ida: a.min(b),
                        idb: a.max(b).max(1),
                        i: k,
                        j: k,
                    }
                })
                .collect();
            keys.sort_unstable_by_key(|k| (k.ida, k.idb));
            keys.dedup_by_key(|k| (k.ida, k.idb));
            let mut want = keys.clone();
            want.sort_unstable();
            keys.reverse();
            for parts in [1, 2, 3, 7] {
                let k = KeyParts::split(keys.clone(), parts);
                assert_eq!(k.parts.len(), parts);
                for (t, p) in k.parts.iter().enumerate() {
                    let (a, b) = (k.bounds[t], k.bounds[t + 1]);
                    assert!(
                        p.iter()
                            .flatten()
                            .all(|q| a <= q.ida && (t + 1 == parts || q.ida < b))
                    );
                }
                // The same keys in several lists per part (as the search's blocks).
                let mut lists = k.clone();
                for p in &mut lists.parts {
                    let all: Vec<PairKey> = std::mem::take(p).into_iter().flatten().collect();
                    *p = all.chunks(333).map(<[PairKey]>::to_vec).collect();
                    p.insert(1.min(p.len()), Vec::new());
                }
                assert_eq!(
                    lists.into_sorted(),
                    want,
                    "ids up to {max}, {parts} parts, lists"
                );
                assert_eq!(k.into_sorted(), want, "ids up to {max}, {parts} parts");
            }
            let keys = KeyParts::from(keys).into_sorted();
            assert_eq!(keys, want, "ids up to {max}");
        }
    }

    fn marked(x: f64) -> ContactState {
        ContactState {
            touching: true,
            overlap: x,
            ..Default::default()
        }
    }

    /// 2500 pairs over three blocks; every third has a state whose overlap names the pair.
    fn store() -> ContactStore {
        let mut c = ContactStore::default();
        c.set_pairs(
            (0..2500u32)
                .map(|k| PairWithState {
                    i: k,
                    j: k + 1,
                    ida: k,
                    idb: k + 1,
                    s: if k % 3 == 0 {
                        marked(k as f64)
                    } else {
                        ContactState::default()
                    },
                })
                .collect(),
        );
        c
    }

    fn allocated(c: &ContactStore) -> usize {
        c.blocks.iter().map(|b| b.len()).sum()
    }

    #[test]
    fn states_live_in_the_block_of_their_pair_and_only_when_needed() {
        let mut c = store();
        assert_eq!(c.blocks.len(), 3);
        assert_eq!(allocated(&c), 834);
        for k in 0..2500 {
            let want = if k % 3 == 0 {
                marked(k as f64)
            } else {
                ContactState::default()
            };
            assert_eq!(*c.state(k), want);
        }
        // A pair of block 1 comes within reach: its state is appended to block 1.
        c.state_mut(1501).overlap = -1.0;
        assert_eq!(c.blocks[1].len(), 342); // 341 multiples of 3 in 1024..2048, and 1501
        assert_eq!(c.state(1501).overlap, -1.0);
        assert_eq!(*c.state(1500), marked(1500.0));
        // The checkpoint layout has no slots: a round trip gives the same pairs and states.
        let bytes = bincode::serde::encode_to_vec(&c, bincode::config::standard()).unwrap();
        let (back, _): (ContactStore, usize) =
            bincode::serde::decode_from_slice(&bytes, bincode::config::standard()).unwrap();
        assert_eq!(back, c);
        assert!(back.iter().eq(c.iter()));
    }

    #[test]
    fn a_merge_carries_states_by_id_and_lays_them_out_in_pair_order() {
        let mut c = store();
        c.state_mut(1).overlap = 7.0;
        // New candidates: every pair with an even id, plus new pairs, in scrambled order.
        let mut keys: Vec<PairKey> = (0..3000u32)
            .filter(|k| k % 2 == 0)
            .map(|k| PairKey {
                ida: k,
                idb: k + 1,
                i: k + 10,
                j: k + 11,
            })
            .collect();
        keys.reverse();
        keys.push(PairKey {
            ida: 1,
            idb: 2,
            i: 1,
            j: 2,
        });
        c.merge(keys, Vec::new());
        assert_eq!(c.len(), 1501);
        for (k, v) in c.iter().enumerate() {
            let id = v.ida;
            assert!(k == 0 || (c.pairs[k - 1].ida, c.pairs[k - 1].idb) < (v.ida, v.idb));
            let want = if id == 1 {
                ContactState {
                    overlap: 7.0,
                    ..Default::default()
                }
            } else if id < 2500 && id % 3 == 0 {
                marked(id as f64)
            } else {
                ContactState::default()
            };
            assert_eq!(*v.s, want, "pair {id}");
            if id >= 2 {
                assert_eq!((v.i, v.j), (id + 10, id + 11), "indices from the new keys");
            }
        }
        // Each block holds its own pairs' states, in pair order.
        for (b, block) in c.blocks.iter().enumerate() {
            let slots: Vec<u32> = c.pairs[b * BLOCK..((b + 1) * BLOCK).min(c.len())]
                .iter()
                .map(|p| p.slot)
                .filter(|&s| s != NO_STATE)
                .collect();
            assert_eq!(slots, (0..block.len() as u32).collect::<Vec<_>>());
        }
    }

    #[test]
    fn retained_pairs_keep_their_states() {
        let mut c = store();
        c.retain_pairs(|p| {
            p.i += 1;
            p.ida % 2 == 1
        });
        assert_eq!(c.len(), 1250);
        for v in c.iter() {
            assert_eq!(v.i, v.ida + 1);
            let want = if v.ida % 3 == 0 {
                marked(v.ida as f64)
            } else {
                ContactState::default()
            };
            assert_eq!(*v.s, want);
        }
        assert_eq!(allocated(&c), c.iter().filter(|v| v.s.touching).count());
    }
}
