//! How work is shared among threads, never what is computed: the split of the pair list
//! into one range per task with its shared particles (`schedule`), and the pool's workers
//! kept polling through a `Cycle` (`awake`). The parallel region of a step itself is
//! `cycle::fused`; the decision of how a `Cycle` runs is `cycle::plan`.

pub mod awake;
pub mod schedule;
