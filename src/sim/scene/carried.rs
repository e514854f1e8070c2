//! What one `Cycle` hands to the next beyond the particles, walls and contacts: the energy
//! audit's reference, the work in flight at its end, each wall's velocity of its last step
//! and the stress servo it ended with. Saved in checkpoints (from format 14), so that a
//! command or a `Cycle` after `SAve` and `RESTart` does what it does after the uninterrupted
//! run, to the bit (doc/spec/DECISIONS.md, "Output, determinism, checkpoints"); older
//! formats read as [`Carried::unknown`].
use serde::{Deserialize, Serialize};

use super::cell::{Cell, Servo};

/// The state a `Cycle` leaves for the next one (see the module's note).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Carried {
    /// The books' residual when the last `Cycle` ended (or its blow-up snapshot was
    /// restored; 0 for a new scene, NaN when read from a checkpoint of format 13 or older,
    /// then the residual at the RESTart: `Scene::resume_audit`): what the residual moved by
    /// since then, commands moved (`cycle::Audit`).
    pub audit_end: f64,
    /// The work the walls did on the particles in the last step (booked in
    /// `Ledger::walls`): half of it is still in flight at the step's end
    /// (`cycle::in_flight`).
    pub wall_step_work: f64,
    /// The velocity and radial velocity each wall moved with in the last step (by index;
    /// walls are only appended): the work of the next step is booked over the mean of it and
    /// the velocity the wall goes on with, also when a command (`AWAll ... V`) changed the
    /// velocity between the two steps (`cycle::wall_loop::move_walls`). Empty for a new
    /// scene (and from older checkpoints): the walls' velocities then stand for it.
    pub wall_last_vel: Vec<([f64; 3], f64)>,
    /// The work in flight when the last `Cycle` ended (`cycle::in_flight`): the contact
    /// states are then a step behind the positions, and a re-evaluation after a command
    /// leaves this part out of what the command put in (`cycle::prime`); 0 once the states
    /// were re-evaluated, or after a restored snapshot.
    pub in_flight_end: f64,
    /// The stress servo the last `Cycle` ended with and the cell's rates, gain and mode
    /// then: a `Cycle` with the same targets goes on with it if no command changed the
    /// cell since (`Scene::continued_servo`), so that `Cycle 2000 S0 σ` and two
    /// `Cycle 1000 S0 σ` run the same steps. A `Cycle` without a servo forgets it.
    pub servo: Option<KeptServo>,
}

/// A stress servo kept from the last `Cycle`, with the cell's settings it ended with.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct KeptServo {
    pub servo: Servo,
    /// The cell's strain rates, gain and mode when the Cycle ended.
    pub rate: [f64; 6],
    pub gain: [f64; 2],
    pub mode: u8,
}

impl Carried {
    /// What a checkpoint of format 13 or older stands for: the audit's reference unknown
    /// (taken at the RESTart), nothing in flight, the walls' velocities for their last
    /// step's, no servo to go on with.
    pub fn unknown() -> Carried {
        Carried {
            audit_end: f64::NAN,
            ..Carried::default()
        }
    }
}

impl KeptServo {
    /// The servo as a `Cycle` ended with it over `cell`.
    pub fn of(servo: Servo, cell: &Cell) -> KeptServo {
        KeptServo {
            servo,
            rate: cell.rate,
            gain: cell.gain,
            mode: cell.mode,
        }
    }

    /// Whether a `Cycle` with these targets (kind and value, in order) over `cell` goes on
    /// with this servo: the same targets, to the bit, and the cell's rates, gain and mode
    /// as the last Cycle left them (no `GRID`, `GAIN` or `Mode` changed them since).
    pub fn continues(&self, targets: &[(super::cell::StressTarget, f64)], cell: &Cell) -> bool {
        let same_bits =
            |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        self.servo.targets.len() == targets.len()
            && self
                .servo
                .targets
                .iter()
                .zip(targets)
                .all(|(k, t)| k.0 == t.0 && k.1.to_bits() == t.1.to_bits())
            && same_bits(&self.rate, &cell.rate)
            && same_bits(&self.gain, &cell.gain)
            && self.mode == cell.mode
    }
}
