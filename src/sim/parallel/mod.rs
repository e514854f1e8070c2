//! How work is shared among threads, never what is computed: how a `Cycle` runs, decided
//! once (`plan`), the split of the pair list into one range per task with its shared
//! particles (`schedule`), and the pool's workers kept polling through a `Cycle` (`awake`).
//! The parallel region of a step itself is `cycle::fused`.

pub mod awake;
pub mod plan;
pub mod schedule;
