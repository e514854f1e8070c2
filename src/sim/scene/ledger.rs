//! The energy ledger's accounts: what went in and what was dissipated, booked as a run
//! goes (`sim::energy` has what is stored and the books' residual). Saved in checkpoints.

use serde::{Deserialize, Serialize};

/// Accumulated energy terms (J).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Ledger {
    /// Energy changed by commands (creation, VELocity, Zero, FRO, ...) — the initial energy of
    /// a scene enters here when its particles are created.
    pub commands: f64,
    pub gravity: f64,
    pub walls: f64,
    pub friction: f64,
    pub damping_mass: f64,
    pub damping_contact: f64,
    pub viscous: f64,
    pub adhesion: f64,
    pub rupture: f64,
    /// The books' residual that commands left (energy they changed without booking it),
    /// summed over the scene's life: the energy audit of a `Cycle` (`cycle::Audit`) holds
    /// the residual's growth beyond this — the energy cycling created since the scene was
    /// made — against a tolerance, whatever the lengths of the Cycles. NaN in a scene read
    /// from a checkpoint of format 8 or older (unknown: taken as the residual at the next
    /// Cycle's start). Not an input nor a loss: no sum of the books includes it.
    pub unbooked: f64,
}

/// The ledger as checkpoint formats 1 to 8 wrote it (frozen: never change): without
/// `unbooked`.
#[derive(Deserialize)]
pub(in crate::sim) struct LedgerV8 {
    commands: f64,
    gravity: f64,
    walls: f64,
    friction: f64,
    damping_mass: f64,
    damping_contact: f64,
    viscous: f64,
    adhesion: f64,
    rupture: f64,
}

impl From<LedgerV8> for Ledger {
    fn from(o: LedgerV8) -> Ledger {
        Ledger {
            commands: o.commands,
            gravity: o.gravity,
            walls: o.walls,
            friction: o.friction,
            damping_mass: o.damping_mass,
            damping_contact: o.damping_contact,
            viscous: o.viscous,
            adhesion: o.adhesion,
            rupture: o.rupture,
            unbooked: f64::NAN,
        }
    }
}

impl Ledger {
    pub fn input(&self) -> f64 {
        self.commands + self.gravity + self.walls
    }
    pub fn dissipated(&self) -> f64 {
        self.friction
            + self.damping_mass
            + self.damping_contact
            + self.viscous
            + self.adhesion
            + self.rupture
    }
}
