//! Read access to a [`Scene`] for the rest of the program (session, output, plots,
//! checkpoints, analysis). The fields are private to `sim`: what changes a scene goes through
//! the methods of [`super::edit`], which keep its invariants (the flags of
//! `ContactStore::mark_stale` and [`super::Derived`]; see ARCHITECTURE.md, "The scene's
//! flags").

use super::cell::Cell;
use super::*;
use crate::sim::history::History;
use crate::sim::model::{ContactLaws, SizeDist};

impl Scene {
    /// The work-space's size (x, y, z), m: the periodic cell's current size.
    pub fn size(&self) -> [f64; 3] {
        self.size
    }
    /// `Start`'s boxes per side of the search grid.
    pub fn nbox(&self) -> usize {
        self.nbox
    }
    /// `Start`'s maximum number of particles.
    pub fn nball(&self) -> usize {
        self.nball
    }
    /// `Start`'s maximum number of walls.
    pub fn nwall(&self) -> usize {
        self.nwall
    }
    /// Radius of each size type (`RAdius`; 0 = unset).
    pub fn sizes(&self) -> &[f64] {
        &self.sizes
    }
    /// Radius distribution of each size type.
    pub fn size_dist(&self) -> &[SizeDist] {
        &self.size_dist
    }
    /// The material table (`Density`, `YMD`, `PRA`, `FRiction`, `COHesion`).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }
    /// The agglomerate regions (`AGGlomerate`).
    pub fn regions(&self) -> &[Option<Region>; 2] {
        &self.regions
    }
    pub fn particles(&self) -> &Particles {
        &self.particles
    }
    /// The id the next particle created gets.
    pub fn next_id(&self) -> u32 {
        self.next_id
    }
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }
    pub fn contacts(&self) -> &ContactStore {
        &self.contacts
    }
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
    /// Gravity (m/s²).
    pub fn gravity(&self) -> [f64; 3] {
        self.gravity
    }
    /// Centripetal gravity per agglomerate (m/s², 0 = off).
    pub fn cgravity(&self) -> [f64; 2] {
        self.cgravity
    }
    /// The mass multiplier of `FMM` (density scaling).
    pub fn fmm(&self) -> f64 {
        self.fmm
    }
    /// `Zero 1`: velocities are zeroed at every step.
    pub fn zero_always(&self) -> bool {
        self.zero_always
    }
    /// Rayleigh damping of particle–particle contacts.
    pub fn damping_pp(&self) -> Rayleigh {
        self.damping_pp
    }
    /// Rayleigh damping of particle–wall contacts.
    pub fn damping_pw(&self) -> Rayleigh {
        self.damping_pw
    }
    /// The binder (`LIQuid`), if any.
    pub fn liquid(&self) -> Option<Liquid> {
        self.liquid
    }
    /// `VELocity ... 1`: contacts made from now on take the materials' `gamma_base`.
    pub fn impact(&self) -> bool {
        self.impact
    }
    /// Cycles done so far.
    pub fn cycle(&self) -> u64 {
        self.cycle
    }
    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time
    }
    /// The energy ledger.
    pub fn ledger(&self) -> &Ledger {
        &self.ledger
    }
    /// Particles removed through open sides (or deleted after crossing a wall).
    pub fn lost(&self) -> u64 {
        self.lost
    }
    /// The reference state of `PLot SAve`, if one was taken.
    pub fn reference(&self) -> Option<&Reference> {
        self.reference.as_ref()
    }
    /// The history rows (`SET HIStory`).
    pub fn history(&self) -> &History {
        &self.history
    }
    /// The periodic cell's deformation.
    pub fn cell(&self) -> &Cell {
        &self.cell
    }
    /// What the last `Cycle` handed on to the next (saved).
    pub fn carried(&self) -> &super::Carried {
        &self.carried
    }
    /// The contact laws per material pair (`SET NORmal`, `SET ROLling`).
    pub fn laws(&self) -> &ContactLaws {
        &self.laws
    }
    /// The scene's derived state (never saved).
    pub fn derived(&self) -> &Derived {
        &self.derived
    }
    /// The particle with this id, by index.
    pub fn index_of(&self, id: usize) -> Option<usize> {
        self.particles.id.iter().position(|&x| x as usize == id)
    }
}

/// Mutable access to every part of a scene, for tests and tools that build states no
/// command can make (exact positions, a damaged ledger, a foreign reference). Whoever uses
/// it keeps the invariants that [`super::edit`] keeps (after a change that the contacts
/// see, `contacts.mark_stale()`).
pub struct Unchecked<'a> {
    pub size: &'a mut [f64; 3],
    pub sizes: &'a mut Vec<f64>,
    pub materials: &'a mut Vec<Material>,
    pub regions: &'a mut [Option<Region>; 2],
    pub particles: &'a mut Particles,
    pub next_id: &'a mut u32,
    pub walls: &'a mut Vec<Wall>,
    pub contacts: &'a mut ContactStore,
    pub settings: &'a mut Settings,
    pub gravity: &'a mut [f64; 3],
    pub liquid: &'a mut Option<Liquid>,
    pub impact: &'a mut bool,
    pub cycle: &'a mut u64,
    pub time: &'a mut f64,
    pub ledger: &'a mut Ledger,
    pub lost: &'a mut u64,
    pub reference: &'a mut Option<Reference>,
    pub history: &'a mut History,
    pub cell: &'a mut Cell,
    pub laws: &'a mut ContactLaws,
    pub carried: &'a mut super::Carried,
    pub derived: &'a mut Derived,
}

impl Scene {
    /// The scene's parts, mutable, without the checks of [`super::edit`] (see
    /// [`Unchecked`]).
    pub fn unchecked(&mut self) -> Unchecked<'_> {
        Unchecked {
            size: &mut self.size,
            sizes: &mut self.sizes,
            materials: &mut self.materials,
            regions: &mut self.regions,
            particles: &mut self.particles,
            next_id: &mut self.next_id,
            walls: &mut self.walls,
            contacts: &mut self.contacts,
            settings: &mut self.settings,
            gravity: &mut self.gravity,
            liquid: &mut self.liquid,
            impact: &mut self.impact,
            cycle: &mut self.cycle,
            time: &mut self.time,
            ledger: &mut self.ledger,
            lost: &mut self.lost,
            reference: &mut self.reference,
            history: &mut self.history,
            cell: &mut self.cell,
            laws: &mut self.laws,
            carried: &mut self.carried,
            derived: &mut self.derived,
        }
    }

    /// The random-number generator's state (`RGEnerate`).
    pub fn rng(&self) -> &Rng {
        &self.rng
    }
}
