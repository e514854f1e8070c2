//! How a `Cycle` runs, decided once when it starts: the threads and whether the force step
//! and the update share one parallel region. The physics never depends on it: every choice
//! gives the same bits (`tests/it/threads.rs`), only the speed. The other specialisations:
//! the particles all alike is the model's (`Model::uniform`); the kernels compiled for the
//! scene's laws are chosen by `forces::forces` (adhesion, liquid); the 4-lane (AVX2) code is
//! chosen where it is called (`lanes::hertz_noslip`, `leapfrog::update`,
//! `update::step_factors`, `pairs::vector_reach`), because each of those `unsafe` calls must
//! check its own precondition to stay sound (std caches the detection: one atomic load).

/// The execution plan of a `Cycle` (kept in its `Model`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExecPlan {
    /// Worker threads of the pool the `Cycle` runs in.
    pub threads: usize,
    /// With several threads, the force step and the update in one parallel region
    /// (`fused`); otherwise two passes. `TRUBAL_STEP_REGIONS=1|2` forces one or two (for
    /// measurements); by default one unless there are more threads than cores (a task that
    /// waits for another then holds a core: 3 threads on 2 cores took 6 × the time).
    pub one_region: bool,
}

impl Default for ExecPlan {
    fn default() -> Self {
        ExecPlan::detect()
    }
}

impl ExecPlan {
    /// The plan for the current thread pool and processor.
    pub fn detect() -> ExecPlan {
        let threads = rayon::current_num_threads();
        let one_region = match step_regions() {
            Some(n) => n == 1,
            None => threads <= crate::sim::parallel::awake::cores(),
        };
        ExecPlan {
            threads,
            one_region,
        }
    }
}

/// `TRUBAL_STEP_REGIONS` = 1 or 2: the step with several threads in one parallel region or
/// in two (the force step, then the update), whatever the number of cores; otherwise
/// (`None`) one region unless there are more threads than cores. For measurements and
/// tests: both give the same bits.
fn step_regions() -> Option<u8> {
    static REGIONS: std::sync::OnceLock<Option<u8>> = std::sync::OnceLock::new();
    *REGIONS.get_or_init(|| match std::env::var("TRUBAL_STEP_REGIONS").as_deref() {
        Ok("1") => Some(1),
        Ok("2") => Some(2),
        _ => None,
    })
}
