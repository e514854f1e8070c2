//! The split of the pair list among threads as the contact store keeps it (derived from the
//! hot pairs at each rebuild, never saved): the tasks' ranges and shared particles
//! (`Incidence`), the cut's measured balance (`Balance`) and the one-region step's plan
//! (`ChunkPlan`). How they are made is `parallel::schedule`.

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
    /// ([`super::NOT_SHARED`]: not shared), and the list.
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
/// cost it was given (`cycle::pairs::pair_ranges`) and the seconds it took (its
/// pairs, its stretch of the wall pairs and the update of the chunks only it touches, which
/// it moves in the same region). A task whose pairs took longer per unit of cost
/// (denser contacts, walls, other data in its caches) gets fewer at the next split. Timing
/// chooses only where the pair list is cut; every particle's sum and every energy partial
/// sum is the same for any cut.
#[derive(Clone, Debug, Default)]
pub struct Balance {
    pub tasks: Vec<(f64, usize, f64)>,
}

/// A task of the multi-thread force loop: a range of whole blocks of pairs and an interval of
/// particles (the intervals of successive tasks follow each other and cover all particles).
#[derive(Clone, Debug, Default)]
pub struct PairRange {
    pub pairs: std::ops::Range<usize>,
    pub parts: std::ops::Range<usize>,
}
