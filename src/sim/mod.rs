//! The simulation core: state, generation, contact search, contact forces, time stepping and
//! the energy ledger. No I/O happens here: the session asks and formats.
//!
//! # Layers
//!
//! The modules stand in layers, lowest first. A module imports only from its own layer or
//! below, and no two modules import each other, directly or around a circle; a module that
//! needs something from above is handed it (a function argument, a plain value). A
//! module's files (`cycle/update.rs` of `cycle`) are in its layer unless named here.
//! `tests/it/architecture.rs` reads this list and holds the code to it.
//!
//! 1. **base** (`model`, `rng`, `history`, `parallel`, `range`): what knows no scene: the
//!    model choices a scene stores, the random numbers, the history's columns, how a `Cycle`
//!    runs on threads (`parallel::plan`, `parallel::awake`), ranges and groups as plain data.
//! 2. **state** (`scene`, `contacts`): the scene as plain data: particles,
//!    walls, materials, settings, the contact store (with its split among threads), the
//!    cell's strains and servo targets, the ledger's accounts, the index that generation
//!    keeps, the reference of `PLot SAve`; reading it, checking a decoded one.
//! 3. **geometry** (`walls`, `cell`): wall gaps, normals and motion; the periodic cell's
//!    images, deformation and stress servo rule.
//! 4. **measures** (`energy`, `stress`): what a state holds: the energy stored and the books'
//!    residual, the average stress.
//! 5. **laws** (`params`, `kinematics`, `interact`, `elastoplastic`, `mdr`, `rolling`,
//!    `liquid`, `lanes`, `contact_time`): the per-pair constants, the force of one contact,
//!    rolling, liquid bridges, the step limit.
//! 6. **search** (`search`, `scene/touch`, `aggregate`): the candidate pairs (cell lists, the
//!    Lees–Edwards cell); which pairs touch now (the one definition of every output: the
//!    contact state, or the surfaces' gap, found by the search before a first Cycle); the sums
//!    and averages over a range (its coordination counts touching pairs).
//! 7. **step** (`cycle`, `leapfrog`, `parallel/schedule`): a `Cycle`: forces, update,
//!    checks, the cell's share of a step, the history's rows, the split among threads.
//! 8. **drivers** (`place`, `generate`, `probe`, `scene/edit`, `sim`): what commands do to a
//!    scene: placement and generation, `PRObe`, every edit; this module, which re-exports.

pub mod aggregate;
pub mod cell;
pub mod contact_time;
pub mod contacts;
pub mod cycle;
pub mod elastoplastic;
pub mod energy;
pub mod generate;
pub mod history;
pub mod interact;
pub mod kinematics;
pub mod lanes;
pub mod leapfrog;
pub mod liquid;
pub mod mdr;
pub mod model;
pub mod parallel;
pub mod params;
pub mod place;
pub mod probe;
pub mod range;
pub mod rng;
pub mod rolling;
pub mod scene;
pub mod search;
pub mod stress;
pub mod walls;

pub use scene::{Scene, Vec3};
