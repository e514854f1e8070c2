//! How the pair list is shared among threads: the cut into ranges of whole blocks
//! (`Balance`), the particles each range shares with another (`Incidence`), and the chunks
//! a task may update alone (`ChunkPlan`); the contact store keeps them (`contacts::split`).
//! Scheduling only: it decides who adds what, never the sums.

use crate::sim::contacts::*;
use rayon::prelude::*;

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
