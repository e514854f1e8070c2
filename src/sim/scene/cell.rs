//! The state of the periodic cell (`sim::cell` has what moves it): its deformation so far,
//! saved in checkpoints, and the stress servo a `Cycle` holds (kept for the next Cycle:
//! `scene::Carried`).
use serde::{Deserialize, Serialize};

use super::Vec3;

/// The state of the periodic cell's deformation (saved in checkpoints from format 4).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// The strain rates of `GRID`: ed11 ed22 ed33 ed12 ed23 ed31 (1/s).
    pub rate: [f64; 6],
    /// The strains accumulated since the start, ∫ ed dt (same order).
    pub strain: [f64; 6],
    /// Lees–Edwards offset: x displacement of the images above the cell (y + L_y), in
    /// [0, L_x) (m).
    pub shift: f64,
    /// The stress servo's gain g (1/(s Pa): the rate, or in mode 0 its change per step, per
    /// pascal of error) and the largest strain rate it may set (1/s) (`GAIN g edmax`).
    pub gain: [f64; 2],
    /// Servo mode: 0 velocity-increment control, 1 velocity control (`Mode n`).
    pub mode: u8,
    /// A bound of how much the mean field changed the branch vector of a pair within reach
    /// since the last rebuild of the candidate list (m, `cell::deform`); saved, so that a
    /// restarted run rebuilds when the continued one does.
    pub travel: f64,
    /// Work put in by the cell's deformation, −∫ V σ:G dt (J), up to the state of the
    /// last forces: a term of the energy books' input (`energy::residual`). Each step's
    /// deformation is booked by the trapezoid rule, `−½ V (σⁿ + σⁿ⁺¹):G Δt`, once the
    /// forces at its end are known (the next step), like the other terms of the books.
    pub work: f64,
    /// `−½ V G Δt` of the last step's deformation, whose second half `σⁿ⁺¹ : half` is still
    /// to be booked.
    pub half: [[f64; 3]; 3],
    /// The first half of the last step's work, `σⁿ : half`, booked with the second.
    pub pending: f64,
}

impl Cell {
    /// The Lees–Edwards offset as a user reads it: the images' x displacement is defined
    /// modulo the cell's length `lx`, and [`Cell::shift`] keeps it in [0, L_x), where a
    /// small shear the negative way reads L_x − ε; this is the representative in
    /// [−L_x/2, L_x/2), −ε for it (`PRint Grid`).
    pub fn signed_offset(&self, lx: f64) -> f64 {
        if self.shift >= 0.5 * lx {
            self.shift - lx
        } else {
            self.shift
        }
    }

    /// The velocity gradient G (G[i][j] = ∂v_i/∂x_j) of the rates.
    pub fn gradient(&self) -> [[f64; 3]; 3] {
        let r = &self.rate;
        [[r[0], r[3], 0.0], [0.0, r[1], 0.0], [0.0, 0.0, r[2]]]
    }

    /// Whether the cell moves at all (a strain rate is set).
    pub fn is_active(&self) -> bool {
        self.rate.iter().any(|&r| r != 0.0)
    }

    /// Whether the pair loop must know of the cell: it moves, or a Lees–Edwards offset is
    /// left from a shear.
    pub fn in_use(&self) -> bool {
        self.is_active() || self.shift != 0.0
    }

    /// Whether the end of a step needs the average stress: the cell moves or is sheared, or
    /// the last deformation's second half is still to be booked.
    pub fn needs_stress(&self) -> bool {
        self.in_use() || self.half != [[0.0; 3]; 3]
    }

    /// The mean-field velocity difference `G l` across a branch vector `l`.
    #[inline(always)]
    pub fn field(&self, l: &Vec3) -> Vec3 {
        let r = &self.rate;
        Vec3::new(r[0] * l.x + r[3] * l.y, r[1] * l.y, r[2] * l.z)
    }
}

/// A stress the servo holds (`Cycle n S0 σ`, …), compression positive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StressTarget {
    /// The mean stress (σ11 + σ22 + σ33)/3.
    Mean,
    /// The mean in the x–y plane (σ11 + σ22)/2.
    Mean12,
    /// One principal direction: σ11, σ22 or σ33 (axis 0, 1, 2).
    Axis(usize),
    /// The angle θ of the major principal stress in the x–y plane, from x towards y
    /// (TRUBAL's `RING`, ring shear; the target is θ in degrees): see `cell::ring_error`.
    Ring,
}

/// The stress servo of a `Cycle`: its targets and the axes each adjusts (set by the session
/// for the Cycle, or the one the last Cycle ended with when this one goes on with it:
/// `Scene::continued_servo`; saved as [`super::KeptServo`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Servo {
    /// Each target, its value and the rates it adjusts (ed11, ed22, ed33, ed12; only a
    /// `Ring` target adjusts ed12).
    pub targets: Vec<(StressTarget, f64, [bool; 4])>,
    /// The strain rates when the Cycle started: in mode 1 a rate that only the `Ring`
    /// target adjusts is this plus the servo's part (a prescribed shear rate stays the
    /// base of a ring-shear servo).
    pub base: [f64; 6],
    /// Consecutive steps in which an adjusted rate jumped from one limit ±edmax to the
    /// other: the servo hunting, a sign of a gain too high for the packing it has made.
    pub flips: u32,
}

/// Steps of hunting between ±edmax after which the Cycle stops (`cycle::update`).
pub const HUNTING_STEPS: u32 = 200;
