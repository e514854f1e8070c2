//! What the force of one contact reads and books besides its state: the contact's geometry
//! and kinematics at a step (`Kin`), the laws a `Cycle` asks of every contact (`Laws`), the
//! energy increments of the step (`Acc`), and the end of a solid contact (`reset_solid`).
//! The force laws (`interact`, `elastoplastic`, `mdr`, `lanes`) share them, and the step
//! (`cycle`) fills and sums them.

use super::contacts::ContactState;
use super::scene::{Liquid, Vec3};
use crate::sim::model::{BridgeChoice, TangentialChoice};

/// Geometry and kinematics of a contact at this step. A is the particle, B the other
/// particle or the wall; `n` points from A to B.
#[derive(Clone, Copy)]
pub struct Kin {
    pub n: Vec3,
    /// Gap between surfaces (negative = overlap).
    pub gap: f64,
    /// Velocity of B's contact point relative to A's.
    pub v_rel: Vec3,
    pub r_star: f64,
    pub m_star: f64,
    /// Radii for the liquid bridge (r2 = ∞ for a plane wall).
    pub r1: f64,
    pub r2: f64,
}

impl Kin {
    pub const ZERO: Kin = Kin {
        n: Vec3::new(0.0, 0.0, 0.0),
        gap: 0.0,
        v_rel: Vec3::new(0.0, 0.0, 0.0),
        r_star: 0.0,
        m_star: 0.0,
        r1: 0.0,
        r2: 0.0,
    };
}

/// What the scene asks of contacts, fixed for a `Cycle` command.
pub struct Laws<'a> {
    pub dt: f64,
    pub tangential: TangentialChoice,
    pub rotation: bool,
    /// Rayleigh stiffness-proportional coefficient β_R for this contact set.
    pub beta: f64,
    pub liquid: Option<&'a Liquid>,
    pub bridge: BridgeChoice,
    /// Minimum gap of the viscous force (None: R*/100 of each pair, doc/spec/DECISIONS.md).
    pub smin: Option<f64>,
    /// Impact flag: contacts made now use the base surface energy.
    pub impact: bool,
    /// Liquid-conserving bookkeeping: the share of a particle's liquid a new bridge draws.
    pub liquid_share: Option<f64>,
    /// Tangential viscous force of bridges (Goldman, Lian (4.76)).
    pub goldman: bool,
    /// How far beyond touching a pair (a particle–wall pair) is evaluated this step, so that
    /// one approaching within half a step's travel gets its share of the dashpot
    /// (`physics::dashpot`): Δt times a bound of the relative speeds; 0 without a dashpot.
    pub margin: f64,
    /// The normal laws of `SET NORmal` the pairs use (`PairConst::law`, `params::Model::laws`).
    /// (For particle–wall contacts `params::Model::wall_laws`: the same laws, marked as a
    /// wall's.)
    pub pair_laws: &'a [super::params::PairLaw],
    /// The Hertz contacts without dissipation take the corrections of their edges
    /// (`interact::edges`, `physics::hertz_edge`): a step (Δt > 0) of a scene without
    /// Rayleigh or global damping and without liquid.
    pub edges: bool,
}

impl Laws<'static> {
    /// Dry laws with rotation and no damping or liquid, for the tests of the kernels.
    #[cfg(test)]
    pub fn dry(dt: f64, tangential: TangentialChoice) -> Laws<'static> {
        Laws {
            dt,
            tangential,
            rotation: true,
            beta: 0.0,
            liquid: None,
            bridge: BridgeChoice::Fit,
            smin: None,
            impact: false,
            liquid_share: None,
            goldman: false,
            margin: 0.0,
            pair_laws: &[],
            edges: false,
        }
    }
}

/// Energy increments of this step.
#[derive(Default, Clone, Copy)]
pub struct Acc {
    pub friction: f64,
    pub damping_contact: f64,
    pub viscous: f64,
    pub adhesion: f64,
    pub rupture: f64,
    /// Σ f ⊗ l of the particle pairs (row-major; `sim::stress`), summed only when the pair
    /// loop is asked for it (`PairCtx::stress`: a deforming or servo-held cell), and only
    /// the components 11, 22, 33 and 12 that the cell's share of a step reads
    /// (`cycle::update`).
    pub stress: [f64; 9],
}

impl Acc {
    pub fn add(&mut self, o: &Acc) {
        self.friction += o.friction;
        self.damping_contact += o.damping_contact;
        self.viscous += o.viscous;
        self.adhesion += o.adhesion;
        self.rupture += o.rupture;
        for (a, b) in self.stress.iter_mut().zip(&o.stress) {
            *a += b;
        }
    }
}

/// Force on B (total) and its tangential part (for moments).
pub struct Out {
    pub f: Vec3,
    pub ft: Vec3,
}

/// Ends a solid contact; the energy left in its tangential and rolling springs is lost
/// (friction).
pub(super) fn reset_solid(s: &mut ContactState, acc: &mut Acc) {
    acc.friction += s.tang_energy;
    s.touching = false;
    s.normal_force = 0.0;
    s.damp_force = 0.0;
    s.a = 0.0;
    s.tang_energy = 0.0;
    s.tforce = Vec3::zeros();
    // (A particle pair's MDR or JKR row, kept in its block's list, is left unused there.)
    s.row = super::contacts::RowSlot::NONE;
    if let Some(e) = s.ext.as_deref_mut() {
        e.delta = Vec3::zeros();
        e.tang = Default::default();
        e.walton = Default::default();
        e.tdelta = 0.0;
        e.mdr = None;
        e.end = None;
        if let Some(l) = e.laws.as_deref_mut() {
            // The rolling spring's energy is lost with the contact (`sim::rolling`); the
            // history of the laws of `SET NORmal` stays.
            acc.friction += l.roll_energy;
            l.roll = Vec3::zeros();
            l.roll_energy = 0.0;
            l.roll_damp = Vec3::zeros();
            if l.normal.is_none() {
                e.laws = None;
            }
        }
        // Nothing left that differs from the defaults `ext()` reads for a contact without
        // one (bit for bit): free it (a Mindlin–Deresiewicz bed keeps ~3 candidate pairs
        // with a state that once touched for every touching one).
        let zero = |x: f64| x.to_bits() == 0;
        if zero(e.a_s)
            && zero(e.gamma)
            && zero(e.released[0])
            && zero(e.released[1])
            && e.laws.is_none()
        {
            s.ext = None;
        }
    }
    s.overlap = 0.0;
}
