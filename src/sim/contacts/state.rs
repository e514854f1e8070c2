//! The state of one contact: what every law keeps (`ContactState`), the optional
//! extension of JKR, Mindlin–Deresiewicz and the liquid-return fields (`ContactExt`), and a
//! liquid bridge (`BridgeState`).

use super::*;

/// State of a liquid bridge (Lian §5.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BridgeState {
    /// Liquid volume (m³).
    pub volume: f64,
    /// Rupture distance S_c (m) of the bridge model in use.
    pub s_c: f64,
    /// Static (capillary) force of the last step, attractive magnitude (N).
    pub f_static: f64,
    /// Viscous normal force of the last step, compressive positive (N).
    pub f_visc: f64,
    /// Gap of the last step (m).
    pub gap: f64,
    /// Work done against the static force since formation (J).
    pub work: f64,
    /// Liquid drawn from particle A and B (conserving mode; zero in Lian's mode).
    pub share: [f64; 2],
    /// Not yet settled with the particles' liquid (conserving mode).
    pub fresh: bool,
    /// Tangential viscous force on B of the last step (Goldman, `SET GOLdman ON`).
    pub f_tang: Vec3,
    /// Precomputed shape coefficients of the bridge model (rebuilt on load).
    pub coeffs: BridgeCoeffs,
}

impl BridgeState {
    pub fn new(model: BridgeModel, b: Bridge, gap: f64, share: [f64; 2]) -> Self {
        let coeffs = BridgeCoeffs::new(model, &b);
        BridgeState {
            volume: b.volume,
            s_c: coeffs.rupture_distance(),
            f_static: 0.0,
            f_visc: 0.0,
            gap,
            work: 0.0,
            share,
            fresh: share != [0.0; 2],
            f_tang: Vec3::zeros(),
            coeffs,
        }
    }

    /// Recomputes the coefficients for another model or new liquid parameters.
    pub fn rebuild(&mut self, model: BridgeModel) {
        self.coeffs = BridgeCoeffs::new(model, self.coeffs.bridge());
        self.s_c = self.coeffs.rupture_distance();
    }

    /// Half-filling angle on the first sphere at the last gap (rad).
    pub fn phi(&self) -> f64 {
        crate::physics::bridge::half_filling_angle(
            self.coeffs.model(),
            self.coeffs.bridge(),
            self.gap.max(0.0),
        )
    }
}

/// State of one contact: the part every contact law reads and writes at every step, kept
/// small (the force loop streams it), with the state of the laws only some scenes use (JKR,
/// Mindlin–Deresiewicz, liquid bridges) behind pointers that stay empty otherwise ("model
/// only what a scene needs": a Hertz contact with the no-slip law is 120 bytes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// A solid contact is active (Hertz: overlap > 0; JKR: made and not yet detached).
    pub touching: bool,
    /// Overlap α (positive = compression) of the last step.
    pub overlap: f64,
    /// Elastic normal force P (compressive positive).
    pub normal_force: f64,
    /// Dashpot normal force of the last step (restitution and Rayleigh).
    pub damp_force: f64,
    /// Separation rate of the last step if it had a velocity-dependent normal force (the
    /// history of `physics::dashpot::others`); +∞ otherwise.
    pub v_prev: f64,
    /// Stored tangential elastic energy.
    pub tang_energy: f64,
    /// Contact radius a.
    pub a: f64,
    /// Tangential force on B.
    pub tforce: Vec3,
    /// Tangential dashpot force on B (Rayleigh contact damping).
    pub tdamp: Vec3,
    /// JKR and Mindlin–Deresiewicz state, and liquid to return; `None` while all of it is
    /// at its default (Hertz contacts with the no-slip law never allocate it).
    pub ext: Option<Box<ContactExt>>,
    /// Liquid bridge, if any.
    pub bridge: Option<Box<BridgeState>>,
    /// Where the contact's row is kept in its block's lists, if it has one there
    /// ([`RowSlot`]): the spring row of `SET TANgential MDR`, or the JKR row of a touching
    /// JKR pair ([`JkrRow`]); a particle–wall contact keeps both in `ext`.
    #[serde(skip, default)]
    pub row: RowSlot,
}

/// The place of a particle pair's row in its block's lists (`StateBlock::rows`, the MDR
/// spring rows `physics::mdr::MdrRow`; `StateBlock::jkr`, the JKR rows [`JkrRow`]), or none.
/// The rows sit beside the states, in pair order after each merge, so the force loop reads
/// them as a forward stream (a row behind its own pointer, allocated where and when the
/// contact formed, cost a cache miss a contact a step; doc/performance.md, "The figures", on
/// the default law's step). A contact has at most one: an MDR row while a Hertz contact
/// touches, a JKR row while a JKR contact touches. Where a row is kept is not part of the
/// contact's state: every two slots compare equal, the row itself is compared
/// ([`PairView`]) and saved (in `ext.mdr` and `ext.end`, the checkpoint's layout).
#[derive(Clone, Copy)]
pub struct RowSlot(pub(super) u32);

impl RowSlot {
    /// No row in the block's lists.
    pub const NONE: RowSlot = RowSlot(u32::MAX);
    /// The mark of a JKR row's index.
    const JKR: u32 = 1 << 31;
    /// Row `i` of the MDR list.
    #[inline(always)]
    pub(super) fn mdr_at(i: usize) -> RowSlot {
        RowSlot(i as u32 & !Self::JKR)
    }
    /// Row `i` of the JKR list.
    #[inline(always)]
    pub(super) fn jkr_at(i: usize) -> RowSlot {
        RowSlot(i as u32 | Self::JKR)
    }
    /// The contact has a row in one of its block's lists.
    #[inline(always)]
    pub fn is_some(self) -> bool {
        self.0 != u32::MAX
    }
    /// Its index in the block's MDR list, if it has a row there.
    #[inline(always)]
    pub fn mdr(self) -> Option<usize> {
        (self.0 & Self::JKR == 0).then_some(self.0 as usize)
    }
    /// Its index in the block's JKR list, if it has a row there.
    #[inline(always)]
    pub fn jkr(self) -> Option<usize> {
        (self.is_some() && self.0 & Self::JKR != 0).then_some((self.0 & !Self::JKR) as usize)
    }
}

/// The JKR state a touching particle pair reads and writes at every step (`sim::interact`'s
/// normal law, Lian 1994 (3.29), (3.117); `physics::jkr::Jkr::leap_frog_force`), kept in its
/// block's list (`StateBlock::jkr`) beside the states. `gamma` and `a_s` are copies of the
/// extension's (`ContactExt`, which every other reader of the contact uses; both are set at
/// snap-in only); `end` is the contact's own while it has a row, and goes back to
/// `ContactExt::end` in a checkpoint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JkrRow {
    /// Surface energy of the contact (J/m²).
    pub gamma: f64,
    /// JKR separation radius a_s (3.117).
    pub a_s: f64,
    /// The last evaluated point of the last step's path (`physics::jkr::PathEnd`).
    pub end: Option<crate::physics::jkr::PathEnd>,
}

impl JkrRow {
    /// The row of a contact's extension.
    pub fn of(e: &ContactExt) -> JkrRow {
        JkrRow {
            gamma: e.gamma,
            a_s: e.a_s,
            end: e.end,
        }
    }
}

impl Default for RowSlot {
    fn default() -> Self {
        RowSlot::NONE
    }
}

impl PartialEq for RowSlot {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for RowSlot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.is_some() { "kept" } else { "none" })
    }
}

/// The part of a contact's state that only some laws use.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactExt {
    /// JKR separation radius a_s (3.117), computed at snap-in.
    pub a_s: f64,
    /// Surface energy of this contact (J/m²); 0 for a Hertz contact.
    pub gamma: f64,
    /// Accumulated tangential displacement vector δ (of B relative to A); kept by the
    /// Mindlin–Deresiewicz law (the no-slip law, like LIGGGHTS' and LAMMPS' shear history,
    /// keeps only the force).
    pub delta: Vec3,
    /// Signed resultant tangential displacement (Lian (5.23)).
    pub tdelta: f64,
    /// Signed resultant tangential law state.
    pub tang: TangentialState,
    /// Liquid returned to A and B by a bridge that ruptured in this step (conserving mode).
    pub released: [f64; 2],
    /// Walton's law's turning point and history (`SET TANgential WALTON`; checkpoint
    /// format 4).
    pub walton: WaltonState,
    /// The state of the laws of `SET NORmal` and `SET ROLling` (checkpoint format 5), behind
    /// a pointer of its own: the contacts of the other laws keep their size.
    pub laws: Option<Box<LawState>>,
    /// The spring row of `SET TANgential MDR` (`physics::mdr`; checkpoint format 9), behind
    /// a pointer of its own (288 bytes): the contacts of the other laws pay for the pointer
    /// only. A particle–wall contact keeps its row here; a particle pair keeps it in its
    /// block's row list (`ContactState::row`, `StateBlock`) and has it here only in a
    /// checkpoint.
    pub mdr: Option<Box<MdrRow>>,
    /// JKR: the last evaluated point of the last step's path (`physics::jkr::PathEnd`;
    /// checkpoint format 11), from which the next step's path starts. A touching particle
    /// pair keeps it in its block's JKR row ([`JkrRow`], `ContactState::row`) and has it
    /// here only in a checkpoint.
    pub end: Option<crate::physics::jkr::PathEnd>,
}

/// The state of the laws of `SET NORmal` and `SET ROLling` in a contact.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LawState {
    /// The history of the elasto-plastic and modified-JKR normal laws.
    pub normal: NormalHistory,
    /// Rolling moment on A of the rolling spring (`physics::rolling`) and its energy.
    pub roll: Vec3,
    pub roll_energy: f64,
    /// The rolling dashpot's moment on A of the last step.
    pub roll_damp: Vec3,
}

static DEFAULT_LAWS: std::sync::LazyLock<LawState> = std::sync::LazyLock::new(LawState::default);

impl ContactExt {
    /// The state of the laws of `SET NORmal`/`ROLling` (the defaults if there is none).
    pub fn laws(&self) -> &LawState {
        self.laws.as_deref().unwrap_or(&DEFAULT_LAWS)
    }
    /// The same, allocated (at its defaults) if there was none.
    pub fn laws_mut(&mut self) -> &mut LawState {
        self.laws.get_or_insert_with(Box::default)
    }
}

/// The history a normal law other than Hertz/JKR keeps (`sim::model::NormalLaw`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum NormalHistory {
    /// Hertz or JKR (the state above says all).
    #[default]
    None,
    /// Modified JKR: the energy stored since the contact was made.
    ModifiedJkr { stored: f64 },
    /// Thornton–Ning: the unloading curve, and the energy stored on it.
    ThorntonNing {
        st: crate::physics::thornton_ning::TnState,
        stored: f64,
    },
    /// Pasha's linear law (both versions): the largest overlap, and the energy stored on the
    /// reversible branch.
    Linear {
        st: crate::physics::pasha_linear::LinState,
        stored: f64,
    },
    /// LIGGGHTS' JKR (Nguyen et al. 2014): the energy on its curve (zero where the force
    /// vanishes: `α_s` between particles, `α = 0` at a wall). Appended last (format 6).
    Nguyen { stored: f64 },
}

impl NormalHistory {
    /// Hertz or JKR: no history (a test of the variant only).
    #[inline(always)]
    pub fn is_none(&self) -> bool {
        matches!(self, NormalHistory::None)
    }
    /// The normal energy stored in the contact (booked as `strain_normal`).
    pub fn stored(&self) -> f64 {
        match *self {
            NormalHistory::None => 0.0,
            NormalHistory::ModifiedJkr { stored }
            | NormalHistory::ThorntonNing { stored, .. }
            | NormalHistory::Linear { stored, .. }
            | NormalHistory::Nguyen { stored } => stored,
        }
    }
}

impl Default for ContactState {
    fn default() -> ContactState {
        ContactState {
            touching: false,
            overlap: 0.0,
            normal_force: 0.0,
            damp_force: 0.0,
            v_prev: f64::INFINITY,
            tang_energy: 0.0,
            a: 0.0,
            tforce: Vec3::zeros(),
            tdamp: Vec3::zeros(),
            ext: None,
            bridge: None,
            row: RowSlot::NONE,
        }
    }
}

pub(super) static DEFAULT_EXT: std::sync::LazyLock<ContactExt> =
    std::sync::LazyLock::new(ContactExt::default);

impl ContactState {
    /// The law-specific state (the default values if the contact has none).
    pub fn ext(&self) -> &ContactExt {
        self.ext.as_deref().unwrap_or(&DEFAULT_EXT)
    }
    /// The law-specific state, allocated (at its defaults) if the contact had none.
    pub fn ext_mut(&mut self) -> &mut ContactExt {
        self.ext.get_or_insert_with(Box::default)
    }
    /// The pair must be evaluated in the next step whether or not it is within reach: a
    /// solid contact, a bridge, or a dashpot force or separation rate of the last step to
    /// pair with (an approach that turned away books the second half of its force and drops
    /// its rate).
    #[inline(always)]
    pub fn live(&self) -> bool {
        self.touching || self.bridge.is_some() || self.damp_force != 0.0 || self.v_prev.is_finite()
    }
    /// Surface energy of the contact (0: Hertz).
    pub fn gamma(&self) -> f64 {
        self.ext.as_ref().map_or(0.0, |e| e.gamma)
    }
    /// The contact follows a law of the adhesive kernel: JKR (a surface energy) or a law of
    /// `SET NORmal` other than Hertz (a history).
    #[inline(always)]
    pub fn needs_adhesive_kernel(&self) -> bool {
        self.ext
            .as_ref()
            .is_some_and(|e| e.gamma > 0.0 || e.laws.as_ref().is_some_and(|l| !l.normal.is_none()))
    }
}
