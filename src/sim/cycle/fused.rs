//! The force step and the particle update of a step in one parallel region (several
//! threads; Lian (5.9)–(5.14) as in [`super::move_all`]).
//!
//! With two regions (`forces_with`, then `move_all`) every step pays for the second region's
//! start (the workers take the update's chunks from the pool) and each core updates the
//! particles of half the list, whatever part of it its force task covered. Here each task
//! evaluates its wall pairs and pairs, then updates the chunks of particles whose sums it
//! alone has made ([`chunk_owners`]): chunks inside its particle interval with no shared
//! particle and no wall contact in another task's stretch — no other task reads or writes
//! those particles in this step, so they can move while the other tasks still read
//! positions elsewhere. The chunks left (at each cut, the shared particles', the wall
//! contacts') are taken, once every task's pairs are done, by the tasks still in the
//! region. Each chunk is updated by the same function with the same inputs as in
//! `move_all` and its sums kept in its place, so the result is the same bits as the
//! two-region step, for any number of threads.
//!
//! The tasks share the particle arrays: a task writes the chunks it updates through raw
//! pointers while the others read other elements of the same arrays through [`View`]s,
//! which make a reference to one element at a time (safe Rust would give a task no write
//! access to part of an array another task reads). Measured (the reason for the `unsafe`):
//! 0.963 (S1 10k) and 0.952–0.971 (S1 50k) of the two-region step's time on two threads, paired
//! alternating runs; doc/performance.md, "Threads".

use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::{
    Acc, CHUNK, ChunkArrays, ChunkSums, HotPair, Incidence, Laws, Left, Model, Mover, PairCtx,
    PairForce, Scene, UniPair, Vec3, WallPair, WallPiece, WallShape, reach, split_if_needed,
    task_pairs, task_sums, wall_cuts, wall_forces,
};
use crate::sim::contacts::{ChunkPlan, Pair, StateBlock, StepParts};
use crate::sim::scene::{Particles, Wall};
use rayon::prelude::*;

/// A read-only view of a particle array (positions, velocities, spins) for the pair loop:
/// indexing makes a reference to the one element read. Made from a slice it is that
/// slice; made from a raw pointer ([`View::raw`], the one-region step) the array's other
/// elements may be written by another task while it is read.
#[derive(Clone, Copy)]
pub(super) struct View<'a> {
    ptr: *const Vec3,
    len: usize,
    _life: PhantomData<&'a [Vec3]>,
}

// SAFETY: a `View` reads like a `&[Vec3]`, which is `Send` and `Sync`; a `View` made by
// `View::raw` is used only while no task writes the elements it reads (see `raw`).
unsafe impl Send for View<'_> {}
unsafe impl Sync for View<'_> {}

impl<'a> View<'a> {
    pub(super) fn of(s: &'a [Vec3]) -> View<'a> {
        View {
            ptr: s.as_ptr(),
            len: s.len(),
            _life: PhantomData,
        }
    }

    /// The first element and the number of elements, for the vector reach tests
    /// (`reach::mask_avx2`, which loads only elements below `len`, under the view's
    /// contract).
    pub(super) fn parts(&self) -> (*const Vec3, usize) {
        (self.ptr, self.len)
    }

    /// # Safety
    /// `ptr` points to `len` initialised elements that live for `'a`, and no element is
    /// written while the view reads it.
    unsafe fn raw(ptr: *const Vec3, len: usize) -> View<'a> {
        View {
            ptr,
            len,
            _life: PhantomData,
        }
    }
}

impl std::ops::Index<usize> for View<'_> {
    type Output = Vec3;
    #[inline(always)]
    fn index(&self, i: usize) -> &Vec3 {
        assert!(i < self.len, "particle index {i} out of range {}", self.len);
        // SAFETY: in bounds (just checked); not written while read (the view's contract).
        unsafe { &*self.ptr.add(i) }
    }
}

/// How long at most a task that has updated its own chunks waits for the other tasks'
/// pairs, to share the late chunks with them: a fraction of its own time (`WAIT_SHARE`,
/// the tasks are balanced to end together), at least `MIN_WAIT` and at most `MAX_WAIT`. It
/// waits only while every task has started: a task not started yet runs after this one on
/// the same thread (no other worker took it), and one that is slow to end has lost its core
/// to another program — waiting for it would only hold this core.
const MAX_WAIT: std::time::Duration = std::time::Duration::from_millis(2);
const MIN_WAIT: std::time::Duration = std::time::Duration::from_micros(20);
const WAIT_SHARE: u32 = 8;

/// A chunk no task updates before every task's pairs are done.
const LATE: u32 = u32::MAX;

/// The task that updates each chunk as soon as its own pairs and wall pairs are done
/// ([`LATE`]: after every task's): a chunk inside the task's particle interval (so no
/// other task writes its forces) with no shared particle (so no other task's pair reads or
/// adds to it) and whose wall pairs all lie in the task's stretch (`wall_cut`, so no
/// other task's wall pairs read it). Then the late chunks, in order.
fn chunk_owners(
    inc: &Incidence,
    np: usize,
    wall_pairs: &[WallPair],
    wall_cut: &[usize],
) -> (Vec<u32>, Vec<u32>) {
    let n = np.div_ceil(CHUNK);
    let mut owner = vec![LATE; n];
    for (t, r) in inc.ranges.iter().enumerate() {
        for (c, o) in owner
            .iter_mut()
            .enumerate()
            .skip(r.parts.start.div_ceil(CHUNK))
        {
            if ((c + 1) * CHUNK).min(np) > r.parts.end {
                break;
            }
            *o = t as u32;
        }
    }
    for &q in &inc.shared_list {
        owner[q as usize / CHUNK] = LATE;
    }
    for (t, w) in wall_cut.windows(2).enumerate() {
        for p in &wall_pairs[w[0]..w[1]] {
            let o = &mut owner[p.i as usize / CHUNK];
            if *o != t as u32 {
                *o = LATE;
            }
        }
    }
    let late = (0..n as u32)
        .filter(|&c| owner[c as usize] == LATE)
        .collect();
    (owner, late)
}

/// The split's [`ChunkPlan`]: the one kept in the incidence if it was made for these wall
/// pairs, otherwise made anew. Made once per split, not at every step: it reads every wall
/// pair (~1.5 % of the step on two threads at S1 10k when it was made at every step; the
/// plan is the same either way, so only the time changes).
fn plan(inc: &mut Incidence, np: usize, wall_pairs: &[WallPair]) -> ChunkPlan {
    match inc.plan.take() {
        Some(plan) if plan.walls == wall_pairs.len() => plan,
        _ => {
            let wall_cut = wall_cuts(&inc.ranges, wall_pairs);
            let (owner, late) = chunk_owners(inc, np, wall_pairs, &wall_cut);
            ChunkPlan {
                walls: wall_pairs.len(),
                wall_cut,
                owner,
                late,
            }
        }
    }
}

/// The arrays the tasks share in the region, as raw pointers (see the module's comment).
#[derive(Clone, Copy)]
struct Shared {
    vel: *mut Vec3,
    pos: *mut Vec3,
    disp: *mut Vec3,
    spin: *mut Vec3,
    rot: *mut Vec3,
    force: *mut Vec3,
    moment: *mut Vec3,
    np: usize,
    hot: *mut HotPair,
    nhot: usize,
    out: *mut PairForce,
    nout: usize,
    pieces: *mut WallPiece,
    npieces: usize,
    sums: *mut ChunkSums,
}

// SAFETY: the pointers are used by the tasks of one region on disjoint elements, or to
// read what no task writes any more (the access rules in `forces_and_moves`).
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}

impl Shared {
    /// The arrays of the region: the particles' (`p`), the hot pairs, force slots and
    /// wall pieces, and the chunks' sums.
    fn of(
        p: &mut Particles,
        (hot, out, pieces): (&mut [HotPair], &mut [PairForce], &mut [WallPiece]),
        sums: &mut [ChunkSums],
    ) -> Shared {
        Shared {
            vel: p.vel.as_mut_ptr(),
            pos: p.pos.as_mut_ptr(),
            disp: p.disp.as_mut_ptr(),
            spin: p.spin.as_mut_ptr(),
            rot: p.rot.as_mut_ptr(),
            force: p.force.as_mut_ptr(),
            moment: p.moment.as_mut_ptr(),
            np: p.len(),
            hot: hot.as_mut_ptr(),
            nhot: hot.len(),
            out: out.as_mut_ptr(),
            nout: out.len(),
            pieces: pieces.as_mut_ptr(),
            npieces: pieces.len(),
            sums: sums.as_mut_ptr(),
        }
    }

    /// # Safety
    /// The caller alone reads or writes the particles of chunk `c` while the arrays live.
    unsafe fn chunk<'a>(&self, c: usize) -> ChunkArrays<'a> {
        let lo = c * CHUNK;
        let n = CHUNK.min(self.np - lo);
        // SAFETY: `lo + n ≤ np` elements of each array; exclusive by the contract.
        unsafe {
            ChunkArrays {
                vel: std::slice::from_raw_parts_mut(self.vel.add(lo), n),
                pos: std::slice::from_raw_parts_mut(self.pos.add(lo), n),
                disp: std::slice::from_raw_parts_mut(self.disp.add(lo), n),
                spin: std::slice::from_raw_parts_mut(self.spin.add(lo), n),
                rot: std::slice::from_raw_parts_mut(self.rot.add(lo), n),
                force: std::slice::from_raw_parts_mut(self.force.add(lo), n),
                moment: std::slice::from_raw_parts_mut(self.moment.add(lo), n),
            }
        }
    }

    /// Task `t`'s wall piece, its hot pairs `pairs`, force slots `slots` and the forces and
    /// moments of its particle interval `parts`, to write.
    ///
    /// # Safety
    /// The caller is task `t` before it counts itself done; the ranges are its own.
    #[allow(clippy::type_complexity)]
    unsafe fn task<'a>(
        &self,
        t: usize,
        (pairs, slots, parts): (Range<usize>, Range<usize>, Range<usize>),
    ) -> (
        &'a mut WallPiece,
        &'a mut [HotPair],
        &'a mut [PairForce],
        &'a mut [Vec3],
        &'a mut [Vec3],
    ) {
        assert!(
            t < self.npieces
                && pairs.end <= self.nhot
                && slots.end <= self.nout
                && parts.end <= self.np
        );
        // SAFETY: in bounds (just checked); exclusive by the contract.
        unsafe {
            (
                &mut *self.pieces.add(t),
                std::slice::from_raw_parts_mut(self.hot.add(pairs.start), pairs.len()),
                std::slice::from_raw_parts_mut(self.out.add(slots.start), slots.len()),
                std::slice::from_raw_parts_mut(self.force.add(parts.start), parts.len()),
                std::slice::from_raw_parts_mut(self.moment.add(parts.start), parts.len()),
            )
        }
    }

    /// Task `t`'s wall piece, to read.
    ///
    /// # Safety
    /// Task `t` has counted itself done (nothing writes the piece any more).
    unsafe fn piece<'a>(&self, t: usize) -> &'a WallPiece {
        assert!(t < self.npieces);
        // SAFETY: in bounds; read-only by the contract.
        unsafe { &*self.pieces.add(t) }
    }

    /// All hot pairs, force slots and wall pieces, to read.
    ///
    /// # Safety
    /// Every task has counted itself done.
    unsafe fn all<'a>(&self) -> (&'a [HotPair], &'a [PairForce], &'a [WallPiece]) {
        // SAFETY: the arrays' lengths; read-only by the contract.
        unsafe {
            (
                std::slice::from_raw_parts(self.hot, self.nhot),
                std::slice::from_raw_parts(self.out, self.nout),
                std::slice::from_raw_parts(self.pieces, self.npieces),
            )
        }
    }

    /// Keeps chunk `c`'s sums.
    ///
    /// # Safety
    /// The caller updates chunk `c` (one writer per chunk).
    unsafe fn set_sums(&self, c: usize, s: ChunkSums) {
        assert!(c < self.np.div_ceil(CHUNK));
        // SAFETY: in bounds; one writer by the contract.
        unsafe { *self.sums.add(c) = s };
    }
}

/// The particle arrays of a chunk's update that no task writes in the region (masses,
/// aggregates, fixed components, radii).
type Fixed<'a> = (&'a [f64], &'a [u8], &'a [u8], &'a [f64]);

/// One task's own lists: its index, pairs, their contact states and its wall pairs.
type TaskLists<'a> = (
    usize,
    &'a mut [Pair],
    &'a mut [StateBlock],
    &'a mut [WallPair],
);

/// What a task's forces read: the pair context, the wall pairs' context, the walls with
/// their shapes, and whether the forces were left zero by the last update.
type ForceInputs<'a, 'c> = (
    &'a PairCtx<'c>,
    &'a PairCtx<'c>,
    (&'a [Wall], &'a [WallShape]),
    bool,
);

/// Both steps of a cycle's time step in one region (several threads): the contact forces
/// as `pair_forces` makes them and each chunk's update as `move_all` makes it. Returns the
/// pairs' energy increments (summed per block in block order), the wall pairs' (per block)
/// and the chunks' sums in chunk order.
pub(super) fn forces_and_moves<const ADH: bool, const LIQ: bool>(
    scene: &mut Scene,
    (model, laws_pp, laws_pw, shapes): (&Model, &Laws, &Laws, &[WallShape]),
    mv: &Mover,
    keep: bool,
) -> (Acc, Vec<Acc>, Vec<ChunkSums>) {
    let zeroed = std::mem::take(&mut scene.contacts.step.zeroed);
    let np = scene.particles.len();
    let Scene {
        particles: p,
        contacts,
        walls,
        size,
        settings,
        derived,
        ..
    } = scene;
    let StepParts {
        hot,
        pairs,
        blocks,
        out,
        scatter,
        wall_pairs,
        wall_out,
    } = contacts.step_parts();
    split_if_needed(scatter, hot, np, model.plan.threads);
    out.resize(scatter.slots, PairForce::default());
    let plan = plan(scatter, np, wall_pairs);
    let ntasks = scatter.ranges.len();
    wall_out.pieces.resize_with(ntasks, WallPiece::default);
    let mut sums: Vec<ChunkSums> = vec![ChunkSums::default(); np.div_ceil(CHUNK)];
    let sh = Shared::of(p, (hot, out, &mut wall_out.pieces), &mut sums);
    let inc = &*scatter;
    // SAFETY (the access rules of the region): a task reads positions, velocities and
    // spins of the particles its pairs and wall pairs touch — those of its interval and the
    // shared ones, which lie in late chunks — and of no chunk another task owns
    // (`chunk_owners`); owned chunks are written by their owner only, after its own pairs;
    // late chunks only once every task has counted itself done.
    let ctx = PairCtx {
        pos: unsafe { View::raw(sh.pos, np) },
        vel: unsafe { View::raw(sh.vel, np) },
        spin: unsafe { View::raw(sh.spin, np) },
        radius: &p.radius,
        mass: &p.mass,
        material: &p.material,
        model,
        laws: laws_pp,
        size: *size,
        periodic: settings.periodic,
        // (Not used with a deforming or sheared cell: `one_step`.)
        shift: 0.0,
        cell: None,
        stress: false,
        uni: UniPair::of(model),
        ext: (laws_pp.margin > 0.0).then_some(&derived.reach_ext[..]),
        ext_max: reach::largest(&derived.reach_ext[..]),
        reach: model.reach,
    };
    let wall_ctx = PairCtx {
        laws: laws_pw,
        ..ctx
    };
    let tasks = task_lists(inc, pairs, blocks, wall_pairs, &plan.wall_cut);
    let region = Region {
        sh,
        inc,
        plan: &plan,
        mv,
        fixed: (&p.mass[..], &p.agg[..], &p.fixed[..], &p.radius[..]),
        keep,
        started: AtomicUsize::new(0),
        done: AtomicUsize::new(0),
        next_late: AtomicUsize::new(0),
    };
    let inputs: ForceInputs = (&ctx, &wall_ctx, (&walls[..], shapes), zeroed);
    let results: Vec<(Vec<Acc>, Vec<Acc>, f64)> = tasks
        .into_par_iter()
        .with_max_len(1)
        .map(|lists| region.task::<ADH, LIQ>(lists, inputs))
        .collect();
    let (pair_acc, wall_acc) = task_sums(&results, &mut scatter.balance);
    scatter.plan = Some(plan);
    (pair_acc, wall_acc, sums)
}

/// Each task's own pairs, states and wall pairs (no other task reads them): the lists cut
/// at the tasks' pair ranges (the states at whole blocks) and at `wall_cut`.
fn task_lists<'a>(
    inc: &Incidence,
    mut pairs: &'a mut [Pair],
    mut blocks: &'a mut [StateBlock],
    mut wall_rest: &'a mut [WallPair],
    wall_cut: &[usize],
) -> Vec<TaskLists<'a>> {
    let mut tasks = Vec::with_capacity(inc.ranges.len());
    for (t, r) in inc.ranges.iter().enumerate() {
        let (pp, rest) = pairs.split_at_mut(r.pairs.len());
        pairs = rest;
        let (b, rest) = blocks.split_at_mut(r.pairs.len().div_ceil(super::BLOCK));
        blocks = rest;
        let (w, rest) = wall_rest.split_at_mut(wall_cut[t + 1] - wall_cut[t]);
        wall_rest = rest;
        tasks.push((t, pp, b, w));
    }
    tasks
}

/// What the tasks of one region share: the arrays (see [`Shared`]), the split and its
/// chunk plan, the update's constants, and the counters of the tasks started, of those done
/// and of the late chunks taken.
struct Region<'r> {
    sh: Shared,
    inc: &'r Incidence,
    plan: &'r ChunkPlan,
    mv: &'r Mover,
    fixed: Fixed<'r>,
    /// Keep the forces after the update (otherwise cleared chunk by chunk).
    keep: bool,
    started: AtomicUsize,
    done: AtomicUsize,
    next_late: AtomicUsize,
}

impl Region<'_> {
    /// One task of the region: its wall pairs and pairs, then the chunks it owns, then
    /// (with the tasks still there once every task's pairs are done) the late chunks.
    /// Returns the energy increments of its pair blocks and wall blocks and the time it
    /// took up to its own chunks (for the balance of the next split).
    fn task<const ADH: bool, const LIQ: bool>(
        &self,
        (t, pairs, blocks, wp): TaskLists<'_>,
        inputs: ForceInputs<'_, '_>,
    ) -> (Vec<Acc>, Vec<Acc>, f64) {
        self.started.fetch_add(1, Ordering::AcqRel);
        let t0 = std::time::Instant::now();
        let (accs, wall_accs) = self.task_forces::<ADH, LIQ>(t, (pairs, blocks, wp), inputs);
        self.done.fetch_add(1, Ordering::AcqRel);
        self.own_chunks(t);
        let took = t0.elapsed();
        self.late_chunks((took / WAIT_SHARE).clamp(MIN_WAIT, MAX_WAIT));
        let secs = took.as_secs_f64();
        (accs, wall_accs, secs)
    }

    /// Task `t`'s wall forces and pair forces (`wall_forces`, `task_pairs`), into its wall
    /// piece, its force slots and the forces of its interval.
    #[inline]
    fn task_forces<const ADH: bool, const LIQ: bool>(
        &self,
        t: usize,
        (pairs, blocks, wp): (&mut [Pair], &mut [StateBlock], &mut [WallPair]),
        (ctx, wall_ctx, walls_of, zeroed): ForceInputs<'_, '_>,
    ) -> (Vec<Acc>, Vec<Acc>) {
        let inc = self.inc;
        let r = &inc.ranges[t];
        let slots = inc.task_slots[t].clone();
        let np = self.sh.np;
        // SAFETY: until it counts itself done, task `t` alone touches its wall piece,
        // its range of hot pairs and force slots and the forces of its interval.
        let (piece, hots, outs, force, moment) = unsafe {
            self.sh
                .task(t, (r.pairs.clone(), slots.clone(), r.parts.clone()))
        };
        let wall_accs = wall_forces::<ADH, LIQ>(wp, piece, walls_of, wall_ctx, np);
        let accs = task_pairs::<ADH, LIQ>(
            (r, slots.start, inc),
            (hots, pairs, blocks, outs),
            (force, moment, zeroed),
            ctx,
        );
        (accs, wall_accs)
    }

    /// The chunks task `t` owns ([`chunk_owners`]), once its own pairs and wall pairs are
    /// done: what it left is its wall piece.
    #[inline]
    fn own_chunks(&self, t: usize) {
        // SAFETY: piece `t` is no longer written.
        let own = std::slice::from_ref(unsafe { self.sh.piece(t) });
        let owner = &self.plan.owner;
        for (c, _) in owner.iter().enumerate().filter(|(_, o)| **o == t as u32) {
            self.update(
                c,
                Left {
                    scatter: None,
                    walls: own,
                    roll: None,
                },
            );
        }
    }

    /// The late chunks go to the tasks still here once every task's pairs are done: wait
    /// for that at most `patience`, and only while every task has started (see
    /// `MAX_WAIT`). A task that gives up leaves them to the last one to be done, which
    /// does not wait.
    #[inline]
    fn late_chunks(&self, patience: std::time::Duration) {
        let ntasks = self.inc.ranges.len();
        let wait = std::time::Instant::now();
        while self.done.load(Ordering::Acquire) < ntasks
            && self.started.load(Ordering::Acquire) == ntasks
            && wait.elapsed() < patience
        {
            std::hint::spin_loop();
        }
        if self.done.load(Ordering::Acquire) == ntasks {
            // SAFETY: every task's pairs and wall pairs are done: the hot pairs, slots and
            // wall pieces are only read from here on.
            let (hot, out, pieces) = unsafe { self.sh.all() };
            let left = Left {
                scatter: Some((self.inc, hot, out)),
                walls: pieces,
                roll: None,
            };
            loop {
                let k = self.next_late.fetch_add(1, Ordering::Relaxed);
                let Some(&c) = self.plan.late.get(k) else {
                    break;
                };
                self.update(c as usize, left);
            }
        }
    }

    /// Updates chunk `c` as `move_all` does (after adding what the force step `left`),
    /// clears its forces unless they are kept, and keeps its sums.
    #[inline]
    fn update(&self, c: usize, left: Left<'_>) {
        let (sh, mv) = (&self.sh, self.mv);
        // SAFETY: chunk `c` is updated by this task alone (owned, or claimed once through
        // `next_late`), and no other task reads its particles now (the access rules).
        let s = mv.chunk(c, unsafe { sh.chunk(c) }, self.fixed, Some(left));
        if !self.keep && s.bad.is_none() {
            // Cleared while in the cache, as in `move_all`.
            let a = unsafe { sh.chunk(c) };
            a.force.fill(Vec3::zeros());
            a.moment.fill(Vec3::zeros());
        }
        // SAFETY: one writer per chunk (as above).
        unsafe { sh.set_sums(c, s) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::contacts::{ContactState, PairRange};

    fn wall_pair(i: u32) -> WallPair {
        WallPair {
            i,
            id: i,
            wall: 0,
            s: ContactState::default(),
        }
    }

    /// Two tasks over 5000 particles, cut at particle 2500.
    fn two_tasks() -> Incidence {
        Incidence {
            ranges: vec![
                PairRange {
                    pairs: 0..10,
                    parts: 0..2500,
                },
                PairRange {
                    pairs: 10..20,
                    parts: 2500..5000,
                },
            ],
            ..Default::default()
        }
    }

    /// 5000 particles in five chunks, two tasks cut at particle 2500: a chunk is its task's
    /// when it lies inside the task's interval, holds no shared particle and has no wall
    /// pair in the other task's stretch; the others are late, in order.
    #[test]
    fn a_chunk_is_its_tasks_only_when_no_other_task_touches_it() {
        assert_eq!(CHUNK, 1024, "the chunks below are of 1024 particles");
        let inc = Incidence {
            // 2600, 2700: in the chunk at the cut anyway; 3500: chunk 3.
            shared_list: vec![2600, 2700, 3500],
            ..two_tasks()
        };
        let late = LATE;
        let walls = [10, 20, 4500, 3000].map(wall_pair);
        let (owner, list) = chunk_owners(&inc, 5000, &walls, &[0, 2, 4]);
        assert_eq!(owner, vec![0, 0, late, late, 1]);
        assert_eq!(list, vec![2, 3]);
        // A wall pair of chunk 4 in the first task's stretch: chunk 4 is late too.
        let walls = [10, 4500, 4600, 3000].map(wall_pair);
        let (owner, list) = chunk_owners(&inc, 5000, &walls, &[0, 2, 4]);
        assert_eq!(owner, vec![0, 0, late, late, late]);
        assert_eq!(list, vec![2, 3, 4]);
        // One task over all (no shared particles): every chunk its own.
        let one = Incidence {
            ranges: vec![PairRange {
                pairs: 0..20,
                parts: 0..5000,
            }],
            ..Default::default()
        };
        let (owner, list) = chunk_owners(&one, 5000, &walls, &[0, 4]);
        assert_eq!(owner, vec![0; 5]);
        assert!(list.is_empty());
    }

    /// The plan is kept between the steps of a split, made anew when the wall pairs are not
    /// those it was made for, and dropped with the split.
    #[test]
    fn the_plan_is_kept_for_its_split_and_wall_pairs_only() {
        let mut inc = two_tasks();
        // (A few wall pairs all fall in the last task's stretch: the cut is at whole blocks.)
        let walls = [3000].map(wall_pair);
        let first = plan(&mut inc, 5000, &walls);
        assert_eq!(first.owner, vec![0, 0, LATE, 1, 1]);
        // Kept: a plan stored with other owners comes back as it was.
        inc.plan = Some(ChunkPlan {
            owner: vec![7; 5],
            ..first.clone()
        });
        assert_eq!(plan(&mut inc, 5000, &walls).owner, vec![7; 5]);
        // Other wall pairs (one more, of chunk 0, in the second task's stretch): made anew.
        inc.plan = Some(ChunkPlan {
            owner: vec![7; 5],
            ..first.clone()
        });
        let more = [10, 3000].map(wall_pair);
        assert_eq!(plan(&mut inc, 5000, &more).owner, vec![LATE, 0, LATE, 1, 1]);
        // Cleared with the split.
        inc.plan = Some(first);
        inc.clear();
        assert!(inc.plan.is_none());
    }
}
