//! The model choices of a scene: wall geometry and servo, size distributions, the contact
//! and liquid laws chosen with `SET`, the plot view. They belong to the simulation (the
//! command language maps its words onto them, `lang::command` re-exports them), and they
//! are serialised in checkpoints: the order of variants and fields is part of the
//! checkpoint format (`checkpoint::VERSION`), so a change here needs a new format version
//! and a reader of the old one.

use serde::{Deserialize, Serialize};

use crate::physics::bridge::{self, BridgeModel};

/// Radius distribution of a size type: every generated particle draws its radius.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum SizeDist {
    /// All particles have radius r.
    #[default]
    Fixed,
    /// Normal with standard deviation sd, truncated at ±3 sd (Lian ch. 7: 30 ± 3 µm).
    Normal { sd: f64 },
    /// Uniform in [rmin, rmax] (Olsson's size ranges).
    Uniform { min: f64, max: f64 },
    /// A discrete distribution given by a number-frequency table (Pasha 2013, Table 5.1):
    /// radius `radius[k]` is drawn with probability `freq[k] / Σ freq` (the frequencies as
    /// typed, in any unit: per cent, counts).
    Table { radius: Vec<f64>, freq: Vec<f64> },
}

/// Geometry of a wall: a plane `a x + b y + c z = d`, a spherical container (particles inside),
/// a spherical obstacle/indenter (particles outside) or a cylindrical die (particles inside).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum WallGeom {
    Plane {
        normal: [f64; 3],
        d: f64,
    },
    Sphere {
        centre: [f64; 3],
        radius: f64,
    },
    Obstacle {
        centre: [f64; 3],
        radius: f64,
    },
    /// An infinitely long circular cylinder, particles inside (a die): its axis passes
    /// through `point` along the unit vector `axis` (made unit by `DWAll`).
    Cylinder {
        point: [f64; 3],
        axis: [f64; 3],
        radius: f64,
    },
}

/// Servo control of a wall: target force, maximum speed and gain (`SE F vmax g`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Servo {
    pub force: f64,
    pub vmax: f64,
    pub gain: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum BridgeChoice {
    Fit,
    Toroidal,
    Laplace,
    /// Olsson (2017): Rabinovich force, Willett rupture, Nase viscous forces
    /// (`physics::bridge::rabinovich`); appended last (checkpoint format).
    Rabinovich,
}

/// The tangential law (`SET TANgential`); new variants go at the end (checkpoint format).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TangentialChoice {
    /// Mindlin–Deresiewicz with Thornton's θ factors (Lian 1994), `physics::tangential`.
    Md,
    /// Mindlin no-slip spring with a Coulomb cap, `physics::tangential::noslip_spring`.
    NoSlip,
    /// Walton's incremental Mindlin–Deresiewicz (Shang 1998 (2.28)–(2.38)), `physics::walton`.
    Walton,
    /// EDEM's and LIGGGHTS' Hertz–Mindlin tangential law: the no-slip spring of `NoSlip` and
    /// a tangential dashpot from the pair's restitution, `C_t = ζ (2/3 m* k_t)^{1/2}`
    /// (`physics::dashpot::tangential_coefficient`); the Mindlin springs of `SET NORmal MJKR
    /// EDEM` and `NGUYEN` pairs take the dashpot too. Appended last (checkpoint format 8).
    HertzMindlin,
    /// The exact Hertz–Mindlin tangential contact by the method of dimensionality reduction
    /// (Popov & Heß 2015): a row of springs that keeps the traction field
    /// (`physics::mdr`); the pairs with a surface energy or a law of `SET NORmal` keep `Md`.
    /// The default (`Settings::default`). Appended last (checkpoint format 9).
    Mdr,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LiquidMode {
    Lian,
    Conserve,
}

/// Projection of plots: looking along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum View {
    /// Side view: x to the right, z up (looking along +y).
    Xz,
    /// Side view: y to the right, z up.
    Yz,
    /// Top view: x to the right, y up.
    Xy,
}

/// The normal contact law of a material pair (`SET NORmal`, doc/contact_laws.md). The
/// parameters are those the law needs beyond the materials' constants (E, ν, the surface
/// energy of `COHesion`: Pasha's interface energy is Γ = 2γ).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum NormalLaw {
    /// Hertz, or JKR when the pair has a surface energy (Lian 1994; the default).
    Hertz,
    /// EDEM-style "modified JKR": JKR for α ≥ 0, broken at zero overlap (Pasha 2013 §5.1.1).
    ModifiedJkr,
    /// Thornton–Ning (1998) elastic–plastic adhesive law with limiting contact pressure
    /// `p_y` (Pa) (Pasha 2013 (3.27)–(3.32), (3.55)–(3.59)).
    ThorntonNing { p_y: f64 },
    /// Pasha's linear elasto-plastic adhesive law, full version (Pasha 2013 §4.1):
    /// stiffnesses `k_e`, `k_p` and tangential `k_t` (N/m).
    PashaFull { k_e: f64, k_p: f64, k_t: f64 },
    /// Pasha's simplified linear law (Pasha 2013 §4.1.5, Ch. 6): `k_e`, `k_p`, the
    /// pull-off locus `k_cp` (N/m) and `f_0p` (N), tangential `k_t` (N/m).
    PashaSimplified {
        k_e: f64,
        k_p: f64,
        k_cp: f64,
        f_0p: f64,
        k_t: f64,
    },
    /// The JKR contact as LIGGGHTS computes it (Nguyen et al. 2014), Olsson 2017's dry law
    /// (`physics::jkr_nguyen`): the JKR curve from `α_s` on, approaching and separating, no
    /// adhesion hysteresis; at a wall only while `α > 0`; Mindlin's tangential spring capped
    /// at μ times the Hertz force. Appended last (checkpoint format).
    Nguyen,
    /// The modified JKR with EDEM's friction (`SET NORmal MJKR EDEM [ROLling]`): the
    /// Coulomb limit of sliding taken on the repulsive (Hertzian) part of the force,
    /// `4E*a³/(3R*)`, instead of `P + 2P_c`; with `rolling`, the rolling moment's limit too,
    /// instead of `P`. Appended last (checkpoint format 7).
    ModifiedJkrEdem { rolling: bool },
}

impl NormalLaw {
    /// Whether the rolling moment's limit is on the Hertzian part of the force (`SET NORmal
    /// MJKR EDEM ROLling`).
    pub fn hertz_rolling(self) -> bool {
        self == NormalLaw::ModifiedJkrEdem { rolling: true }
    }
}

/// Which material pairs a rule of `SET NORmal` or `SET ROLling` applies to: all pairs, the
/// pairs involving one material, or one pair (unordered).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Pairs {
    All,
    With(u16),
    Pair(u16, u16),
}

impl Pairs {
    /// The rule applies to the pair of materials (1-based) `a`, `b`.
    pub fn covers(&self, a: usize, b: usize) -> bool {
        match *self {
            Pairs::All => true,
            Pairs::With(m) => a == m as usize || b == m as usize,
            Pairs::Pair(m, n) => {
                (a, b) == (m as usize, n as usize) || (a, b) == (n as usize, m as usize)
            }
        }
    }
    /// Every pair this rule covers is covered by `other`.
    pub fn within(&self, other: &Pairs) -> bool {
        match (*self, *other) {
            (_, Pairs::All) => true,
            (Pairs::With(m), Pairs::With(n)) => m == n,
            (Pairs::Pair(a, b), o) => o.covers(a as usize, b as usize),
            _ => false,
        }
    }
}

/// The form of the restitution dashpot of a material pair (`SET DASHpot`,
/// doc/contact_laws.md). All three are the force `C α^{1/4} α'` of Tsuji et al. (1992) on a
/// Hertzian contact; they differ in the constant `ζ = C/sqrt(m* K)` a restitution `e` gives
/// and in whether the total normal force may pull (`physics::restitution`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DashpotForm {
    /// trubal's: `ζ` calibrated so that the tension-free contact rebounds with `e` exactly
    /// (`restitution::zeta_for_restitution`); the dashpot never pulls a non-adhesive contact.
    #[default]
    Exact,
    /// LIGGGHTS' `hertz` (and EDEM's Hertz–Mindlin, the same formula in its manual):
    /// `F = −2 sqrt(5/6) β sqrt(S_n m*) α'`, `β = ln e / sqrt(ln² e + π²)`, `S_n =
    /// 2E* sqrt(R* α)`, i.e. `ζ = sqrt(5) |β|` (`restitution::tsuji_zeta`), and the total
    /// force may pull at the end of a contact (LIGGGHTS' default `limitForce off`).
    Liggghts,
    /// The same `ζ` with LIGGGHTS' `limitForce on`: the total force never pulls (a
    /// non-adhesive contact), so the rebound is livelier than `e`
    /// (`restitution::restitution_of_zeta`).
    LiggghtsLimited,
}

impl DashpotForm {
    /// The dashpot constant `ζ` this form gives the restitution `e`.
    pub fn zeta(self, e: f64) -> f64 {
        use crate::physics::restitution;
        match self {
            DashpotForm::Exact => restitution::zeta_for_restitution(e),
            DashpotForm::Liggghts | DashpotForm::LiggghtsLimited => restitution::tsuji_zeta(e),
        }
    }
    /// The total normal force of a non-adhesive contact may be tensile (no clamp).
    pub fn pulls(self) -> bool {
        self == DashpotForm::Liggghts
    }
}

/// The friction and restitution of one material pair given with `SET PAIr`, instead of
/// TRUBAL's rule (the smaller of the two materials' values); `None`: the rule.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairValues {
    pub friction: Option<f64>,
    pub restitution: Option<f64>,
}

/// The contact laws chosen per material pair (checkpoint format 5; `pair_values` since
/// format 6): the rules in the order given, the last that covers a pair deciding. A new
/// rule drops the older ones it covers entirely, so the list stays short.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactLaws {
    pub normal: Vec<(Pairs, NormalLaw)>,
    /// Rolling friction coefficients μ_r (`SET ROLling`, `physics::rolling`).
    pub rolling: Vec<(Pairs, f64)>,
    /// Friction and restitution of single material pairs (`SET PAIr`; always
    /// `Pairs::Pair(m1, m2)` with `m1 ≤ m2`, one entry per pair).
    pub pair_values: Vec<(Pairs, PairValues)>,
    /// The dashpot's form (`SET DASHpot`; since format 10).
    pub dashpot: Vec<(Pairs, DashpotForm)>,
}

impl ContactLaws {
    /// The normal law of a pair of materials (1-based).
    pub fn normal_of(&self, a: usize, b: usize) -> NormalLaw {
        self.normal
            .iter()
            .rev()
            .find(|(p, _)| p.covers(a, b))
            .map_or(NormalLaw::Hertz, |r| r.1)
    }
    /// The rolling friction coefficient of a pair of materials (1-based).
    pub fn rolling_of(&self, a: usize, b: usize) -> f64 {
        self.rolling
            .iter()
            .rev()
            .find(|(p, _)| p.covers(a, b))
            .map_or(0.0, |r| r.1)
    }
    /// The dashpot form of a pair of materials (1-based).
    pub fn dashpot_of(&self, a: usize, b: usize) -> DashpotForm {
        self.dashpot
            .iter()
            .rev()
            .find(|(p, _)| p.covers(a, b))
            .map_or(DashpotForm::Exact, |r| r.1)
    }
    pub fn set_dashpot(&mut self, pairs: Pairs, form: DashpotForm) {
        self.dashpot.retain(|(p, _)| !p.within(&pairs));
        if !(pairs == Pairs::All && form == DashpotForm::Exact) {
            self.dashpot.push((pairs, form));
        }
    }
    pub fn set_rolling(&mut self, pairs: Pairs, mu_r: f64) {
        self.rolling.retain(|(p, _)| !p.within(&pairs));
        if !(pairs == Pairs::All && mu_r == 0.0) {
            self.rolling.push((pairs, mu_r));
        }
    }
    /// The friction and restitution given for a pair of materials (1-based), if any.
    pub fn values_of(&self, a: usize, b: usize) -> PairValues {
        self.pair_values
            .iter()
            .find(|(p, _)| p.covers(a, b))
            .map_or(PairValues::default(), |r| r.1)
    }
    /// `SET PAIr m1 m2 ...`: the values given replace the pair's, the others stay; both
    /// `None` returns the pair to TRUBAL's rule.
    pub fn set_pair_values(&mut self, m1: u16, m2: u16, v: PairValues) {
        let key = Pairs::Pair(m1.min(m2), m1.max(m2));
        let old = self.values_of(m1 as usize, m2 as usize);
        self.pair_values.retain(|(p, _)| *p != key);
        if v == PairValues::default() {
            return;
        }
        let new = PairValues {
            friction: v.friction.or(old.friction),
            restitution: v.restitution.or(old.restitution),
        };
        self.pair_values.push((key, new));
        self.pair_values.sort_by_key(|(p, _)| match *p {
            Pairs::Pair(a, b) => (a, b),
            _ => (0, 0),
        });
    }
    pub fn set_normal(&mut self, pairs: Pairs, law: NormalLaw) {
        self.normal.retain(|(p, _)| !p.within(&pairs));
        if !(pairs == Pairs::All && law == NormalLaw::Hertz) {
            self.normal.push((pairs, law));
        }
    }
}

/// The bridge model of `physics::bridge` that a `SET BRIdge` choice names.
pub fn bridge_model(b: BridgeChoice) -> BridgeModel {
    match b {
        BridgeChoice::Fit => BridgeModel::Fit,
        BridgeChoice::Toroidal => BridgeModel::Toroidal,
        BridgeChoice::Laplace => BridgeModel::Laplace,
        BridgeChoice::Rabinovich => BridgeModel::Rabinovich,
    }
}

/// The default minimum gap of a bridge's viscous forces as a fraction of R*: Lian's R*/100
/// (doc/spec/DECISIONS.md), Olsson's 0.1 % for his Rabinovich model (§3.3.2).
#[inline]
pub fn smin_ratio(b: BridgeChoice) -> f64 {
    if b == BridgeChoice::Rabinovich {
        bridge::rabinovich::OLSSON_SMIN_RATIO
    } else {
        0.01
    }
}

/// The tangential viscous force of bridges acts: `SET GOLdman ON`, or Olsson's model, which
/// has Nase's tangential force (56) (the same Goldman form).
#[inline]
pub fn tangential_viscous(goldman: bool, b: BridgeChoice) -> bool {
    goldman || b == BridgeChoice::Rabinovich
}
