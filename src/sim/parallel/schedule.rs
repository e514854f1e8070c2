//! How the pair list is shared among threads: the cut into ranges of whole blocks
//! (`Balance`), the particles each range shares with another (`Incidence`), and the chunks
//! a task may update alone (`ChunkPlan`). Scheduling only: it decides who adds what, never
//! the sums.

use crate::sim::contacts::*;
use rayon::prelude::*;

/// For each particle, the pairs that touch it, in pair order, and how the force loop with
/// several threads splits the work (derived from the hot pairs at each rebuild).
#[derive(Clone, Debug, Default)]
pub struct Incidence {
    /// The pairs of the `s`-th shared particle (`shared_list[s]`) are
    /// `pairs[start[s]..start[s + 1]]` (made by `split`: only shared particles need them).
    pub start: Vec<u32>,
    pub pairs: Vec<u32>,
    /// The tasks (for `threads` threads): ranges of whole blocks and particle intervals.
    pub ranges: Vec<PairRange>,
    pub threads: usize,
    /// Particles whose pairs are not all in the task of their interval (summed from the
    /// pairs' slots after the tasks): for each particle its place in the list of them
    /// ([`NOT_SHARED`]: not shared), and the list.
    pub shared: Vec<u32>,
    pub shared_list: Vec<u32>,
    /// The force slot of each pair that touches a shared particle (`u32::MAX`: none), the
    /// slots of each task, and their number.
    pub slot: Vec<u32>,
    pub task_slots: Vec<std::ops::Range<usize>>,
    pub slots: usize,
    /// What the tasks took since the split, for the cut of the next one (kept by `clear`).
    pub balance: Balance,
    /// The one-region step's plan for this split ([`ChunkPlan`]; made at its first step).
    pub plan: Option<ChunkPlan>,
}

/// How the one-region step (`cycle::fused`) shares out the wall pairs and the particle
/// update for one split: where each task's stretch of wall pairs begins (`wall_cut`), the
/// task that updates each chunk as soon as its own pairs are done (`owner`) and the chunks
/// updated after every task's (`late`). It depends on the split and on the wall pairs'
/// particles, which change only where the incidence is cleared (a merge, particles lost
/// through an open side, the start of a `Cycle`); `walls`, their number when it was made,
/// is checked at every step as well.
#[derive(Clone, Debug, Default)]
pub struct ChunkPlan {
    pub walls: usize,
    pub wall_cut: Vec<usize>,
    pub owner: Vec<u32>,
    pub late: Vec<u32>,
}

/// Wall-clock times of the multi-thread force loop since the last split, for the cut of
/// the next one: per task, where its pairs end (as a fraction of the pair list), the pair
/// cost it was given ([`cycle::pair_ranges`](super::cycle)) and the seconds it took (its
/// pairs, its stretch of the wall pairs and the update of the chunks only it touches, which
/// it moves in the same region). A task whose pairs took longer per unit of cost
/// (denser contacts, walls, other data in its caches) gets fewer at the next split. Timing
/// chooses only where the pair list is cut; every particle's sum and every energy partial
/// sum is the same for any cut.
#[derive(Clone, Debug, Default)]
pub struct Balance {
    pub tasks: Vec<(f64, usize, f64)>,
}

impl Balance {
    /// Some task time has been measured since the last split.
    pub fn measured(&self) -> bool {
        self.tasks.iter().any(|t| t.2 > 0.0)
    }

    /// The relative time per unit of pair cost of the pairs at fraction `x` of the list
    /// (1 on average; clamped to 1/2 … 2 against a disturbed measurement); `None` before any
    /// measurement.
    pub fn rates(&self) -> Option<Vec<(f64, f64)>> {
        let cost: usize = self.tasks.iter().map(|t| t.1).sum();
        let secs: f64 = self.tasks.iter().map(|t| t.2).sum();
        let ok = cost > 0 && secs > 0.0 && secs.is_finite();
        if !ok {
            return None;
        }
        let mean = secs / cost as f64;
        let rates = self
            .tasks
            .iter()
            .map(|&(end, c, t)| {
                let r = if c > 0 { t / c as f64 / mean } else { 1.0 };
                (end, r.clamp(0.5, 2.0))
            })
            .collect();
        Some(rates)
    }
}

/// A task of the multi-thread force loop: a range of whole blocks of pairs and an interval of
/// particles (the intervals of successive tasks follow each other and cover all particles).
#[derive(Clone, Debug, Default)]
pub struct PairRange {
    pub pairs: std::ops::Range<usize>,
    pub parts: std::ops::Range<usize>,
}

impl Incidence {
    /// Sets the tasks, marks the particles they do not own (those with a pair outside the
    /// task of their interval) and gives each pair of a shared particle a force slot (slots
    /// in pair order, so each task's are contiguous); then the pair lists of the shared
    /// particles. The tasks' pairs are scanned in parallel; what is serial is over the few
    /// pairs of shared particles.
    pub fn split(
        &mut self,
        hot: &mut [HotPair],
        np: usize,
        ranges: Vec<PairRange>,
        threads: usize,
    ) {
        self.plan = None;
        // The particles each task's pairs touch outside its interval.
        let foreign: Vec<Vec<u32>> = ranges
            .par_iter()
            .map(|r| {
                let mut v = Vec::new();
                for h in &hot[r.pairs.clone()] {
                    for p in [h.i, h.j] {
                        if !r.parts.contains(&(p as usize)) {
                            v.push(p);
                        }
                    }
                }
                v
            })
            .collect();
        self.shared.clear();
        self.shared.resize(np, NOT_SHARED);
        for &p in foreign.iter().flatten() {
            self.shared[p as usize] = 0;
        }
        drop(foreign);
        let shared = &self.shared;
        self.shared_list.clear();
        self.shared_list.par_extend(
            (0..np as u32)
                .into_par_iter()
                .with_min_len(4096)
                .filter(|&q| shared[q as usize] != NOT_SHARED),
        );
        for (s, &q) in self.shared_list.iter().enumerate() {
            self.shared[q as usize] = s as u32;
        }
        let shared = &self.shared;
        // Each task's pairs get their ownership bits, and those that touch a shared
        // particle are listed (in pair order) for their slots.
        debug_assert!(
            ranges.first().is_none_or(|r| r.pairs.start == 0)
                && ranges
                    .windows(2)
                    .all(|w| w[0].pairs.end == w[1].pairs.start)
                && ranges.last().is_none_or(|r| r.pairs.end == hot.len()),
            "the tasks cover the pairs in order"
        );
        let mut pieces = Vec::with_capacity(ranges.len());
        let mut rest = &mut hot[..];
        for r in &ranges {
            let (piece, tail) = rest.split_at_mut(r.pairs.len());
            pieces.push((r.pairs.start, piece));
            rest = tail;
        }
        let touching: Vec<Vec<u32>> = pieces
            .into_par_iter()
            .map(|(first, piece)| {
                let mut t = Vec::new();
                for (k, h) in piece.iter_mut().enumerate() {
                    let (si, sj) = (shared[h.i as usize], shared[h.j as usize]);
                    h.shared = u8::from(si != NOT_SHARED) | (u8::from(sj != NOT_SHARED) << 1);
                    if h.shared != 0 {
                        t.push((first + k) as u32);
                    }
                }
                t
            })
            .collect();
        let hot = &*hot;
        self.slot.clear();
        self.slot
            .par_extend(rayon::iter::repeat_n(u32::MAX, hot.len()));
        self.task_slots.clear();
        let mut next = 0;
        for t in &touching {
            for (n, &k) in t.iter().enumerate() {
                self.slot[k as usize] = (next + n) as u32;
            }
            self.task_slots.push(next..next + t.len());
            next += t.len();
        }
        self.slots = next;
        // The pair lists of the shared particles: a counting sort over those pairs alone.
        let list = &self.shared_list;
        let place =
            |p: u32| Some(shared[p as usize] as usize).filter(|&s| s != NOT_SHARED as usize);
        self.start.clear();
        self.start.resize(list.len() + 1, 0);
        for &k in touching.iter().flatten() {
            let h = &hot[k as usize];
            for s in [place(h.i), place(h.j)].into_iter().flatten() {
                self.start[s + 1] += 1;
            }
        }
        for s in 0..list.len() {
            self.start[s + 1] += self.start[s];
        }
        let mut fill = self.start.clone();
        self.pairs.clear();
        self.pairs
            .resize(*self.start.last().unwrap_or(&0) as usize, 0);
        for &k in touching.iter().flatten() {
            let h = &hot[k as usize];
            for s in [place(h.i), place(h.j)].into_iter().flatten() {
                self.pairs[fill[s] as usize] = k;
                fill[s] += 1;
            }
        }
        self.ranges = ranges;
        self.threads = threads;
    }

    /// The lists and the split must be made (anew) for `np` particles and `threads` threads.
    pub fn needs_split(&self, np: usize, threads: usize) -> bool {
        self.is_empty() || self.shared.len() != np || self.threads != threads
    }

    /// Not built (or cleared).
    pub fn is_empty(&self) -> bool {
        self.start.is_empty()
    }

    pub fn clear(&mut self) {
        self.start.clear();
        self.pairs.clear();
        self.ranges.clear();
        self.shared.clear();
        self.shared_list.clear();
        self.slot.clear();
        self.task_slots.clear();
        self.slots = 0;
        self.plan = None;
    }

    /// The pairs of the `s`-th shared particle, in pair order.
    pub fn of_shared(&self, s: usize) -> &[u32] {
        &self.pairs[self.start[s] as usize..self.start[s + 1] as usize]
    }
}
