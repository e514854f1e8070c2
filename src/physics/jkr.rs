//! JKR adhesive normal contact of elastic spheres (Johnson, Kendall & Roberts 1971) as used in
//! Lian (1994) §3.3, plus the Savkoor–Briggs peeling relations (3.100)–(3.101).
//!
//! Conventions (`doc/spec/DECISIONS.md`): `γ` is the surface energy **per surface** (work of
//! adhesion `Γ = 2γ` for like solids), the pull-off force is `P_c = 3πγR*`, the approach `α` is
//! positive in compression and negative at separation, and the force `P` is compressive-positive.
//!
//! Corrected approach–radius relation (the printed (3.29) has a spurious ½, see
//! doc/spec/physics-lian1994.md §1.3):
//! `α(a) = a²/R* − sqrt(4πγa/E*)`, and the load is (3.24) `P(a) = 4E*a³/(3R*) − sqrt(16πγE*a³)`.
//!
//! ## Dimensionless form used internally
//! With the separation radius `a_s` (3.117), `a_s³ = πγR*²/(4E*)`, write `a = a_s x²`. Then
//! (exactly, because `sqrt(4πγ a_s/E*) = 4 a_s²/R*` and `P_c = 12 E* a_s³/R*`):
//!
//! * `α = (a_s²/R*) (x⁴ − 4x)`, so `α_s = α(x = 1) = −3 a_s²/R*`;
//! * `P = P_c (x⁶ − 6x³) / 9`, so `P(a_s) = −5/9 P_c`, `P(a_0) = −8/9 P_c` (`x³ = 4`) and the
//!   minimum `−P_c` is at `x³ = 3` (`a_c`, (3.33));
//! * `dα/da ∝ x³ − 1` vanishes at `a_s` (the displacement-control separation point), and
//!   `dP/dα = 2E*a (x³ − 3)/(x³ − 1)`, which is (3.41).
//!
//! With `x = 1 + t` the equation `α(a) = α` becomes `t⁴ + 4t³ + 6t² = D`,
//! `D = 3 (α − α_s)/|α_s| ≥ 0`, a convex increasing polynomial in `t ≥ 0` without cancellation,
//! which is what [`Jkr::solve_a`] solves.
//!
//! All functions are pure and never panic; they never return NaN for finite inputs with
//! `E* > 0`, `R* > 0`, `γ ≥ 0`. `γ = 0` (or anything not `> 0`) gives exact Hertz behaviour.

// `!(x > y)` comparisons are deliberate: they also route NaN to the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use serde::{Deserialize, Serialize};

use super::hertz;
use super::jkr_branch::{Branch, t_of_a, taylor_start};

/// Floor applied to `|x³ − 1| = |dα/da| · (…)` in [`Jkr::stiffness_of_a`] near the pole at
/// `a = a_s`: the returned stiffness is bounded by `2E*a · 2 / STIFFNESS_POLE_FLOOR`.
pub const STIFFNESS_POLE_FLOOR: f64 = 1e-9;

/// JKR contact of two elastic spheres (or a sphere and a wall) with effective modulus
/// `e_star` (Lian 1994 (3.16)), effective radius `r_star` ((3.5)) and surface energy per
/// surface `gamma` (J/m²).
#[derive(Clone, Copy, Debug)]
pub struct Jkr {
    /// Effective contact modulus `E*` (Pa), Lian 1994 (3.16).
    pub e_star: f64,
    /// Effective radius `R*` (m), Lian 1994 (3.5).
    pub r_star: f64,
    /// Surface energy per surface `γ` (J/m²); `P_c = 3πγR*`.
    pub gamma: f64,
}

/// The path of one leap-frog step of a JKR contact ([`Jkr::step_force`]): the approach runs
/// from `lo = α_{n−1/2} = α_n + v Δt/2` to `α_{n+1/2} = base − lag · P̄` (`v` the separation
/// rate of the half step before, `base` the end without the contact's own force of the step,
/// `lag = Δt²/(2m*)`), and the contact's energy at its start is `e_lo`
/// ([`Jkr::branch_energy`] at `lo`; 0 for a contact snapping in within the step).
#[derive(Clone, Copy, Debug)]
pub struct StepPath {
    pub lo: f64,
    pub e_lo: f64,
    pub base: f64,
    pub lag: f64,
}

/// The last point of a JKR contact's step path where its energy was evaluated (the end of
/// the path, or its middle on a path too short for a chord; [`Jkr::step_force_at`]): the
/// approach `alpha`, the energy `e` ([`Jkr::branch_energy`]), the force `p = dE/dα` and the
/// stiffness `k = dp/dα` there (3.41), with the `E*` and `R*` of the law they belong to. The
/// next step's path starts where the pair went, within the prediction error of the other
/// forces of this point ([`Jkr::leap_frog_force`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathEnd {
    pub alpha: f64,
    pub e: f64,
    pub p: f64,
    pub k: f64,
    pub e_star: f64,
    pub r_star: f64,
}

/// Where the path of a JKR contact's step starts ([`Jkr::leap_frog_force`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathStart {
    /// The contact snapped in at this step: `E = 0` at `α = 0`, no force before.
    Touch,
    /// It snapped in while a `Cycle` primed the states (at this step's `α`): its force acts
    /// from this step on, from the energy the priming gave it, `E(α_n)`.
    Primed,
    /// It was touching: `E(α_{n−1/2})`.
    Path,
}

impl PathStart {
    /// Made while priming (the marker `v_prev = −∞`), or made now (not touching before).
    pub fn of(primed: bool, was_touching: bool) -> PathStart {
        if primed {
            PathStart::Primed
        } else if !was_touching {
            PathStart::Touch
        } else {
            PathStart::Path
        }
    }
}

/// One leap-frog step of a JKR contact ([`Jkr::leap_frog_force`]): the overlap `alpha` at
/// `t_n`, the start of the path `lo = α_{n−1/2}`, the separation rate `v` at `t_{n−1/2}`
/// (positive opening), the step, the reduced mass, the contact's force of the last step, the
/// separation rate of the last step (`v_prev`, not finite if unknown), the dashpot's force
/// of the last step, where the path starts and the last evaluated point of the last step's
/// path (if known).
#[derive(Clone, Copy, Debug)]
pub struct LeapFrog {
    pub alpha: f64,
    pub lo: f64,
    pub v: f64,
    pub dt: f64,
    pub m_star: f64,
    pub p_old: f64,
    pub v_prev: f64,
    pub f_damp: f64,
    pub from: PathStart,
    pub end: Option<PathEnd>,
}

impl Jkr {
    /// True when adhesion is absent (`γ` not positive, or so small that `a_s` underflows), in
    /// which case every method reduces exactly to Hertz, Lian 1994 (3.14)–(3.15).
    fn is_hertz(&self) -> bool {
        !(self.gamma > 0.0 && self.a_s() > 0.0)
    }

    /// Pull-off force under load control, `P_c = 3πγR*`; Lian 1994 (3.31)–(3.32).
    pub fn pc(&self) -> f64 {
        3.0 * std::f64::consts::PI * self.gamma * self.r_star
    }

    /// Equivalent Hertz load `P_1 = 4E*a³/(3R*)` of a JKR contact of radius `a`;
    /// Lian 1994 (3.17). At `a = a_s`, `P_1 = P_c/9` (the pole of (3.41)).
    pub fn p1_of_a(&self, a: f64) -> f64 {
        let a = a.max(0.0);
        4.0 * self.e_star * a * a * a / (3.0 * self.r_star)
    }

    /// Contact radius at first touch (`α = 0`), `a_0 = (4πγR*²/E*)^{1/3}`; Lian 1994 (3.118).
    /// A new adhesive contact snaps in to this radius with `P = −8/9 P_c`.
    pub fn a0(&self) -> f64 {
        (4.0 * std::f64::consts::PI * self.gamma * self.r_star * self.r_star / self.e_star).cbrt()
    }

    /// Contact radius at zero load, `a³ = 9πγR*²/E*`; Lian 1994 (3.30).
    pub fn a_zero_load(&self) -> f64 {
        (9.0 * std::f64::consts::PI * self.gamma * self.r_star * self.r_star / self.e_star).cbrt()
    }

    /// Contact radius at separation under displacement control (`dα/da = 0`),
    /// `a_s = (πγR*²/(4E*))^{1/3}`; Lian 1994 (3.117), equivalently (3.36) `a_s³ = P_cR*/(12E*)`.
    pub fn a_s(&self) -> f64 {
        (std::f64::consts::PI * self.gamma * self.r_star * self.r_star / (4.0 * self.e_star)).cbrt()
    }

    /// Contact radius at the pull-off point under load control (`P = −P_c`),
    /// `a_c³ = 3R*P_c/(4E*)`; Lian 1994 (3.33).
    pub fn a_c(&self) -> f64 {
        (3.0 * self.r_star * self.pc() / (4.0 * self.e_star)).cbrt()
    }

    /// Approach at separation (negative), `α_s = −(3P_c²/(16E*²R*))^{1/3}
    /// = −(27π²γ²R*/(16E*²))^{1/3}`; Lian 1994 (3.38), (3.115). Computed as the identical
    /// `α_s = −3a_s²/R*`. The contact breaks when `α < α_s` (`P = −5/9 P_c` there).
    pub fn alpha_s(&self) -> f64 {
        let a_s = self.a_s();
        -3.0 * a_s * a_s / self.r_star
    }

    /// Approach at the load-control pull-off point `a = a_c`,
    /// `α_c = −(4P_c²/(3E*²R*))^{1/3} + (9P_c²/(16E*²R*))^{1/3}`; Lian 1994 (3.34).
    pub fn alpha_c(&self) -> f64 {
        let q = self.pc() * self.pc() / (self.e_star * self.e_star * self.r_star);
        -(4.0 / 3.0 * q).cbrt() + (9.0 / 16.0 * q).cbrt()
    }

    /// Approach as a function of contact radius, `α = a²/R* − sqrt(4πγa/E*)`: Lian 1994 (3.29)
    /// **corrected** (the printed `a²/(2R*)` is a typo; see doc/spec/physics-lian1994.md §1.3).
    /// Negative `a` is treated as 0.
    pub fn alpha_of_a(&self, a: f64) -> f64 {
        let a = a.max(0.0);
        let adh = if self.gamma > 0.0 {
            (4.0 * std::f64::consts::PI * self.gamma * a / self.e_star).sqrt()
        } else {
            0.0
        };
        a * a / self.r_star - adh
    }

    /// JKR load as a function of contact radius, `P = 4E*a³/(3R*) − sqrt(16πγE*a³)`;
    /// Lian 1994 (3.24). Negative `a` is treated as 0.
    pub fn force_of_a(&self, a: f64) -> f64 {
        let a = a.max(0.0);
        let c = if self.gamma > 0.0 {
            4.0 * (std::f64::consts::PI * self.gamma * self.e_star).sqrt()
        } else {
            0.0
        };
        // a^{3/2} (4E*a^{3/2}/(3R*) − 4sqrt(πγE*)): no inf − inf for huge a.
        let a15 = a * a.sqrt();
        a15 * (4.0 * self.e_star * a15 / (3.0 * self.r_star) - c)
    }

    /// Normal stiffness `k_n = dP/dα = 2E*a (3 − 3sqrt(P_c/P_1)) / (3 − sqrt(P_c/P_1))`,
    /// `P_1 = 4E*a³/(3R*)`; Lian 1994 (3.41), evaluated as `2E*a (x³ − 3)/(x³ − 1)` with
    /// `x³ = (a/a_s)^{3/2}`.
    ///
    /// The stiffness is zero at `a_c` (`P = −P_c`), negative for `a_s < a < a_c` and has a pole
    /// at `a = a_s` (`P_1 = P_c/9`, where `dα/da = 0`): it tends to `−∞` as `a → a_s⁺` and to
    /// `+∞` as `a → a_s⁻`. To stay finite, `|x³ − 1|` is floored at [`STIFFNESS_POLE_FLOOR`]
    /// (sign kept; exactly at the pole the stable-side value, a large **negative** number
    /// `≈ −4E*a_s / STIFFNESS_POLE_FLOOR`, is returned). Never NaN or infinite for finite `a`.
    /// For `γ = 0` it is Hertz `2E*a`.
    pub fn stiffness_of_a(&self, a: f64) -> f64 {
        if self.is_hertz() {
            return 2.0 * self.e_star * a.max(0.0);
        }
        self.stiffness_with(self.a_s(), a)
    }

    /// [`Jkr::stiffness_of_a`] with `a_s` (3.117) given by the caller (as
    /// [`Jkr::solve_a_with`]). Requires `γ > 0` and `a_s = self.a_s() > 0`.
    pub fn stiffness_with(&self, a_s: f64, a: f64) -> f64 {
        let a = a.max(0.0);
        let k_hertz = 2.0 * self.e_star * a;
        let y = a / a_s;
        let x3 = y * y.sqrt();
        if x3 > 4.0 {
            let ix = 1.0 / x3;
            return k_hertz * (1.0 - 3.0 * ix) / (1.0 - ix);
        }
        let mut den = x3 - 1.0;
        if den.abs() < STIFFNESS_POLE_FLOOR {
            den = if den < 0.0 {
                -STIFFNESS_POLE_FLOOR
            } else {
                STIFFNESS_POLE_FLOOR
            };
        }
        k_hertz * (x3 - 3.0) / den
    }

    /// Contact radius on the stable (displacement-control) branch `a ≥ a_s` for the approach
    /// `alpha`, i.e. the root of the corrected Lian 1994 (3.29) `α = a²/R* − sqrt(4πγa/E*)`
    /// (with `a(α) ≥ a_s`). For `alpha ≤ α_s` (3.38) it returns `a_s` (the caller decides that
    /// the contact is broken when `α < α_s`). For `γ = 0` it is Hertz `sqrt(R*α)` (0 for `α ≤ 0`).
    ///
    /// Method: safeguarded Newton on `g(t) = t⁴ + 4t³ + 6t² − D` (`a = a_s(1 + t)²`,
    /// `D = 3(α − α_s)/|α_s|`, see the module doc). `g` is convex and increasing on `t ≥ 0`, and
    /// both `sqrt(D/6)` and `D^{1/4}` are upper bounds of the root, so Newton started from the
    /// smaller of them — or from the warm start `a_guess` when that is a tighter upper bound (a
    /// guess below the root is first turned into an upper bound by one Newton step, which
    /// overshoots by convexity) — decreases monotonically and quadratically to the root; it
    /// stops after a step below 1e-8 of `t`, when the next would be below an ulp. Because
    /// `g` has no cancellation the root `t` is found to a few ulps in relative terms even when
    /// `α → α_s` (`dα/da → 0`, `t ≈ sqrt(D/6)`). For astronomically large `D > 1e60` a
    /// fixed-point form `a = sqrt(R*(α + sqrt(4πγa/E*)))` is used (contraction factor
    /// `< 1e-22`). `a_guess` may be anything (NaN, ≤ 0, ∞ are ignored).
    pub fn solve_a(&self, alpha: f64, a_guess: f64) -> f64 {
        if self.is_hertz() {
            return hertz::contact_radius(self.r_star, alpha);
        }
        self.solve_a_with(self.a_s(), alpha, a_guess)
    }

    /// [`Jkr::solve_a`] with `a_s` (3.117) given by the caller, who computed it once when the
    /// contact formed (the cube root costs more than the Newton solve). Requires `γ > 0` and
    /// `a_s = self.a_s() > 0`.
    pub fn solve_a_with(&self, a_s: f64, alpha: f64, a_guess: f64) -> f64 {
        let alpha_s = -3.0 * a_s * a_s / self.r_star;
        if !(alpha > alpha_s) {
            return a_s;
        }
        let d = 3.0 * (alpha - alpha_s) / (-alpha_s);
        if !(d <= 1e60) {
            return self.solve_a_huge(alpha);
        }
        let x = 1.0 + newton_t(d, t_of_a(a_s, a_guess));
        a_s * x * x
    }

    /// Root of the corrected (3.29) for `α ≫ |α_s|` by fixed point (see [`Jkr::solve_a`]).
    fn solve_a_huge(&self, alpha: f64) -> f64 {
        let c = (4.0 * std::f64::consts::PI * self.gamma / self.e_star).sqrt();
        let sr = self.r_star.sqrt();
        let mut a = sr * alpha.sqrt();
        for _ in 0..4 {
            // a = sqrt(R*) sqrt(α) sqrt(1 + c sqrt(a)/α), overflow-free.
            a = sr * alpha.sqrt() * (1.0 + c * a.sqrt() / alpha).sqrt();
        }
        a
    }

    /// JKR normal force and contact radius `(P, a)` at approach `alpha`, `P` from Lian 1994
    /// (3.24) at `a =` [`Jkr::solve_a`]`(alpha, a_guess)` (corrected (3.29)); drift-free,
    /// as required by doc/spec/DECISIONS.md. For `alpha ≤ α_s` it returns the separation point
    /// `(−5/9 P_c, a_s)`; breaking the contact there is the caller's decision.
    pub fn force(&self, alpha: f64, a_guess: f64) -> (f64, f64) {
        if self.is_hertz() {
            return (
                hertz::force(self.e_star, self.r_star, alpha),
                hertz::contact_radius(self.r_star, alpha),
            );
        }
        let a = self.solve_a(alpha, a_guess);
        (self.force_of_a(a), a)
    }

    /// Work of adhesive peeling, the energy dissipated in one JKR approach–separation loop
    /// (snap-in at `α = 0`, `a = a_0`; separation at `α_s`):
    /// `W_p = ∫_0^{α_s} P dα = −4/45 (1 + 6·4^{1/3}) P_c α_s ≈ −0.9355 P_c α_s
    /// = 2/5 (12 + 2^{1/3}) (π⁵γ⁵R*⁴/(4E*²))^{1/3}`; Lian 1994 (3.114)–(3.119). Positive.
    pub fn peel_work(&self) -> f64 {
        if self.is_hertz() {
            return 0.0;
        }
        4.0 / 45.0 * (1.0 + 6.0 * 4.0_f64.cbrt()) * self.pc() * (-self.alpha_s())
    }

    /// Work function of the JKR contact in terms of the contact radius on the stable branch,
    /// `U(a) = ∫_{α_s}^{α(a)} P dα'` (integral of (3.24) along the corrected (3.29), the same
    /// integrand as Lian 1994 (3.116)), in closed form:
    ///
    /// `U = (16E*/R*²) [a⁵/30 − a_s^{3/2} a^{7/2}/3 + a_s³ a²/2 − a_s⁵/5]`
    /// ` = (4/9) P_c|α_s| [x¹⁰/30 − x⁷/3 + x⁴/2 − 1/5]`, `x = sqrt(a/a_s)`.
    ///
    /// Derivation: with `a = a_s x²`, `P dα = (16E*a_s⁵/R*²)(x⁶/3 − 2x³)(x³ − 1) dx
    /// = (16E*a_s⁵/R*²)(x⁹/3 − 7x⁶/3 + 2x³) dx`; integrate from `x = 1`. Near `a_s` the same
    /// polynomial is evaluated in `t = x − 1` (it starts at `−5/2 t²`) to avoid cancellation.
    ///
    /// Properties: `U(a_s) = 0`; `U(a_0) = −W_p` ([`Jkr::peel_work`]); for `γ = 0` it is the
    /// Hertz strain energy `8/15 E*sqrt(R*)α^{5/2}`. It is a potential of the contact force:
    /// the work done **on** the contact between two states on the stable branch is
    /// `U(a₂) − U(a₁)`, i.e. the contact force does `−(U(a₂) − U(a₁))` on the particles.
    /// Energy ledger: with the separated state at energy 0, a snap-in (`U` jumps from 0 to
    /// `U(a_0) = −W_p` at fixed `α = 0`) books the loss `W_p`, and separation at `α_s` is
    /// continuous (`U(a_s) = 0`); equivalently use `U + W_p` (zero at snap-in) and book `W_p`
    /// when the bond breaks. Values for `a < a_s` follow the (unstable) analytic continuation.
    pub fn energy_of_a(&self, a: f64) -> f64 {
        if self.is_hertz() {
            let a = a.max(0.0);
            let scale = 16.0 * self.e_star / (self.r_star * self.r_star);
            return scale * a.powi(5) / 30.0;
        }
        self.energy_of_a_with(self.a_s(), a)
    }

    /// [`Jkr::energy_of_a`] with `a_s` (3.117) given by the caller (as
    /// [`Jkr::solve_a_with`]). Requires `γ > 0` and `a_s = self.a_s() > 0`.
    pub fn energy_of_a_with(&self, a_s: f64, a: f64) -> f64 {
        let a = a.max(0.0);
        let scale = 16.0 * self.e_star / (self.r_star * self.r_star);
        let x = (a / a_s).sqrt();
        let t = x - 1.0;
        if t.abs() <= 1.0 {
            scale * a_s.powi(5) * t * t * fold_series(t)
        } else {
            // a⁵ [1/30 − r^{3/2}/3 + r³/2 − r⁵/5], r = a_s/a < 1/4: overflow-free, no inf − inf.
            let r = a_s / a;
            let r15 = r * r.sqrt();
            let bracket = 1.0 / 30.0 - r15 / 3.0 + r15 * r15 / 2.0 - r15 * r15 * r * r / 5.0;
            scale * a.powi(5) * bracket
        }
    }

    /// [`Jkr::peel_work`] with `a_s` given (`α_s = −3a_s²/R*`). Requires `γ > 0`.
    pub fn peel_work_with(&self, a_s: f64) -> f64 {
        // 4/45 (1 + 6·4^{1/3}) (3.119).
        const K: f64 = 0.935_502_783_271_928_6;
        K * self.pc() * (3.0 * a_s * a_s / self.r_star)
    }

    /// The force of a touching JKR contact in one leap-frog step: [`Jkr::step_force`] on the
    /// step's path, from `E = 0` at the touch in the step of snap-in, from the energy the
    /// priming gave it (`E(α_n)`) in the first step of a contact made while priming, else from
    /// `E(α_{n−1/2})`. The path ends where the particles go: `v_{n+1/2} = v + Δt(P̄ −
    /// P_old)/m* + (v − v_prev)`, the last step's change of the separation rate less this
    /// contact's force then standing for the other forces (as `dashpot::drive` takes them),
    /// or `v + Δt(P̄ + F_dashpot)/m*` without the last step's rate. `t` is the root of (3.29)
    /// at `α_n` on the branch `b` ([`Jkr::solve_t`]). Returns `P̄` and the last evaluated point
    /// of the path, for the next step's `x.end`.
    ///
    /// `E(α_{n−1/2})` is where the last step's path ended up to the prediction error `δ` of
    /// the other forces: from its last evaluated point `x.end` it is the Taylor polynomial
    /// `E + Pδ + kδ²/2` ([`Jkr::energy_from_end`]) when that is exact to 1e-10 of the work of
    /// half a step, else (and without `x.end`) a solution of (3.29) at `α_{n−1/2}`.
    pub fn leap_frog_force(&self, b: &Branch, t: f64, x: &LeapFrog) -> (f64, Option<PathEnd>) {
        let e_lo = match x.from {
            PathStart::Touch => 0.0,
            PathStart::Primed => b.energy(t),
            PathStart::Path => match x
                .end
                .and_then(|end| self.end_energy(b, &end, x.lo, x.alpha))
            {
                Some(e) => e,
                None => {
                    let tg = taylor_start(t, (x.lo - x.alpha) * b.c_d);
                    self.branch_at(b, x.lo, tg).0
                }
            },
        };
        let inv_m = 1.0 / x.m_star;
        let v_ahead = if x.v_prev.is_finite() {
            2.0 * x.v - x.v_prev - x.dt * x.p_old * inv_m
        } else {
            x.v + x.dt * x.f_damp * inv_m
        };
        let path = StepPath {
            lo: x.lo,
            e_lo,
            base: x.alpha - 0.5 * x.dt * v_ahead,
            lag: 0.5 * x.dt * x.dt * inv_m,
        };
        let (p, _, at) = self.step_force_t(b, &path, guess(b, t, x, &path), (x.alpha, t));
        let end = at.map(|(alpha, e, p, t)| PathEnd {
            alpha,
            e,
            p,
            k: b.stiffness(t),
            e_star: self.e_star,
            r_star: self.r_star,
        });
        (p, end)
    }

    /// The energy at `lo` ([`Jkr::branch_energy`]) from a point `end` where it was
    /// evaluated, by the Taylor polynomial `E + Pδ + kδ²/2`, `δ = lo − α_end`, when `end`
    /// belongs to this law (`E*`, `R*`) and lies on the branch (`ρ = α_end − α_s > 0`,
    /// (3.38)), and `|δ|³ ≤ 1e-10 ρ² |α − α_end|` (`alpha` = `α_n`). `E(α)` is analytic
    /// within `ρ` of `α_end` (its nearest singularity is the fold at `α_s`, where `a − a_s ∝
    /// (α − α_s)^{1/2}`), and `|E'''| ≲ max(|P|, P_c)/ρ²` (at the fold `P_c t/(3ρ²)`, `t =
    /// x − 1`; Hertz `3P/(4α²)`), so the remainder `|E'''||δ|³/6` is below 1e-10 of the work
    /// `max(|P|, P_c)|α − α_end|` of the half step: the tolerance of [`Jkr::step_force`]'s own
    /// iteration. Else `None` (a solution of (3.29) is needed).
    pub fn energy_from_end(&self, a_s: f64, end: &PathEnd, lo: f64, alpha: f64) -> Option<f64> {
        self.end_energy(&self.branch(a_s), end, lo, alpha)
    }

    /// [`Jkr::energy_from_end`] on the branch `b`.
    fn end_energy(&self, b: &Branch, end: &PathEnd, lo: f64, alpha: f64) -> Option<f64> {
        if end.e_star != self.e_star || end.r_star != self.r_star {
            return None;
        }
        let rho = end.alpha - b.alpha_s;
        let d = lo - end.alpha;
        let h = (alpha - end.alpha).abs();
        if rho > 0.0 && d.abs() * d * d <= 1e-10 * rho * rho * h {
            Some(end.e + d * (end.p + 0.5 * end.k * d))
        } else {
            None
        }
    }

    /// The energy of a contact on its (touching) branch at the approach `alpha`, counted from
    /// snap-in: `E(α) = U(a(α)) + W_p` ([`Jkr::energy_of_a`], [`Jkr::peel_work`]), so that
    /// `E(0) = 0` (snap-in at `a_0`, (3.118)) and `E(α_s) = W_p` (3.119), with the force
    /// `dE/dα = P(α)` of (3.24) on the corrected (3.29). Beyond the separation point
    /// (`α ≤ α_s`, (3.38)) the contact has broken: `E = W_p` and the force is 0. Returns
    /// `(E, P, a)`, `a` the contact radius ([`Jkr::solve_a_with`], `a_s` beyond `α_s`).
    /// `w_p` is [`Jkr::peel_work_with`]`(a_s)`.
    pub fn branch_energy(&self, a_s: f64, w_p: f64, alpha: f64, a_guess: f64) -> (f64, f64, f64) {
        let a = self.solve_a_with(a_s, alpha, a_guess);
        let p = if alpha > -3.0 * a_s * a_s / self.r_star {
            self.force_of_a(a)
        } else {
            0.0
        };
        (self.energy_of_a_with(a_s, a) + w_p, p, a)
    }

    /// The force of one leap-frog step of a JKR contact: the mean of the force over the
    /// step's path, `P̄ = (E(α_{n+1/2}) − E_lo)/(α_{n+1/2} − α_{n−1/2})`
    /// ([`Jkr::branch_energy`]), so that the work the step does on the particles,
    /// `−P̄ (α_{n+1/2} − α_{n−1/2})` (the leap-frog change of kinetic energy between the
    /// half-step velocities), is exactly the change of the contact's energy. The jumps of
    /// the force are at their true places on the path: a contact snapping in within the
    /// step starts from `E = 0` at `α = 0` (`E_lo = 0`; the force is 0 on the part of the
    /// path before it), one that crosses `α_s` within it ends at `E = W_p` with no force
    /// beyond; the step's work is then the change of `E`, and the loop's only loss is the
    /// `W_p` (3.119) of the detachment. The sampled force `P(α_n)` is not: across a jump the
    /// scheme's work differs from the change of `E` by `O(P_c v Δt)`, of either sign, and
    /// at 20 m/s two glass spheres of 30 µm rebounded with `e` up to 1.00007.
    ///
    /// The end of the path depends on the force: `α_{n+1/2} = path.base − path.lag · P̄`
    /// (`base`: where the pair goes without this contact's force of the step, `lag` =
    /// `Δt²/(2m*)`). The equation `P̄ = (E(base − lag P̄) − E_lo)/(base − lag P̄ − lo)` is
    /// solved by Newton's method from `p_guess` (its derivative `1 + lag (P(α) − P̄)/(α −
    /// lo)` is `1 + (ωΔt)²/4` in a Hertzian contact) until the end of the path moves by
    /// less than 1e-10 of its length, or by less than 1e-5 of it with the last step taken
    /// on the chord's tangent (usually one evaluation), at most eight, stopping where the
    /// derivative falls below 1/4; returns `(P̄, α_{n+1/2})`.
    /// On a path shorter than `1e-9` of its scale the mean is the force at its middle.
    pub fn step_force(&self, a_s: f64, path: &StepPath, p_guess: f64, a_guess: f64) -> (f64, f64) {
        let b = self.branch(a_s);
        let seed = (self.alpha_of_a(a_guess), t_of_a(a_s, a_guess));
        let (p, end, _) = self.step_force_t(&b, path, p_guess, seed);
        (p, end)
    }

    /// [`Jkr::step_force`] on the branch `b`, each solution of (3.29) started from the last
    /// one by [`taylor_start`], the first from `seed`, a point `(α, t)` of the branch (`t` not
    /// finite: none); with the last point of the path where the energy was evaluated:
    /// `(α, E, P, t)` ([`Jkr::branch_at`]), `None` if none was.
    pub fn step_force_t(
        &self,
        b: &Branch,
        path: &StepPath,
        p_guess: f64,
        seed: (f64, f64),
    ) -> (f64, f64, Option<(f64, f64, f64, f64)>) {
        let StepPath {
            lo,
            e_lo,
            base,
            lag,
        } = *path;
        let alpha_s = b.alpha_s;
        let mut p = if p_guess.is_finite() { p_guess } else { 0.0 };
        let (mut alpha_0, mut t_0) = seed;
        let mut out = (p, base - lag * p);
        let mut at = None;
        for _ in 0..8 {
            let hi = base - lag * p;
            let d = hi - lo;
            let scale = lo.abs().max(hi.abs()).max(-alpha_s);
            if !(d.abs() > 1e-9 * scale) {
                // (Also a NaN path: the force at its middle, which is then NaN too.)
                let mid = 0.5 * (lo + hi);
                let tg = taylor_start(t_0, (mid - alpha_0) * b.c_d);
                let (em, pm, tm) = self.branch_at(b, mid, tg);
                return (pm, hi, Some((mid, em, pm, tm)));
            }
            let tg = taylor_start(t_0, (hi - alpha_0) * b.c_d);
            let (e, ph, t) = self.branch_at(b, hi, tg);
            at = Some((hi, e, ph, t));
            (alpha_0, t_0) = (hi, t);
            let inv_d = 1.0 / d;
            let chord = (e - e_lo) * inv_d;
            out = (chord, hi);
            let g = p - chord;
            // Converged when the end of the path moves by less than 1e-10 of the path (the
            // step's work then misses ~1e-10 of its variation; the chord's own round-off,
            // ε|E|/|α − lo|, keeps a path of a contact at rest from doing better).
            if !(lag * g.abs() > 1e-10 * d.abs()) {
                break;
            }
            // Newton. Its derivative is ≥ 1 where the force stiffens; where it softens
            // steeply, near α_s when the force moves the pair much farther in a step than
            // its velocity does (quasi-static, or particles whose velocity is held, which
            // the force does not move), the equation may have other roots far away: the
            // chord on the path of the guess is kept.
            let slope = 1.0 + lag * (ph - chord) * inv_d;
            if !(slope > 0.25) {
                break;
            }
            p -= g / slope;
            // A short move on the same side of α_s: the chord at the new end is its linear
            // estimate, which is the Newton iterate itself (the work then misses
            // ½ C'' Δh² |α − lo| < 1e-10 of the step's, C the chord as a function of the end).
            let dh = lag * g / slope;
            if dh.abs() <= 1e-5 * d.abs() && (hi - alpha_s) * (hi + dh - alpha_s) > 0.0 {
                return (p, hi + dh, at);
            }
        }
        (out.0, out.1, at)
    }
}

/// The first guess of the mean force `P̄` of a step ([`Jkr::step_force`]): the mean over the
/// path of the force's tangent at `α_n`, `P_n + k_n (α_m − α_n)`, `α_m = (lo + α_{n+1/2})/2`
/// the middle of the path, whose end depends on `P̄` (`α_{n+1/2} = base − lag P̄`), so
/// `P̄ = (P_n + k_n((lo + base)/2 − α_n))/(1 + k_n lag/2)`, `k_n` (3.41). `P̄ − P_n` is of
/// the first order in the step (the middle of the path moves with the pair's acceleration),
/// this guess's error of the second (the force's curvature over the path), so that the
/// iteration usually stops after one solution of (3.29) instead of two. `P_n` itself for a
/// path that starts at the touch, and where `k_n lag` is not small (near the pole at `a_s`).
fn guess(b: &Branch, t: f64, x: &LeapFrog, path: &StepPath) -> f64 {
    let p_n = b.force(t);
    if x.from != PathStart::Path {
        return p_n;
    }
    let k = b.stiffness(t);
    let kl = 0.5 * k * path.lag;
    let p = (p_n + k * (0.5 * (path.lo + path.base) - x.alpha)) / (1.0 + kl);
    if kl.abs() < 0.25 && p.is_finite() {
        p
    } else {
        p_n
    }
}

/// The root `t ≥ 0` of `g(t) = t⁴ + 4t³ + 6t² − D` ([`Jkr::solve_a_with`]'s iteration,
/// `D ≤ 1e60`) by safeguarded Newton from the warm start `tg` (anything: not finite or not
/// positive means none), decreasing monotonically from the start of [`start`].
pub(crate) fn newton_t(d: f64, tg: f64) -> f64 {
    let mut t = start(d, tg);
    for _ in 0..200 {
        let step = newton_step(t, d);
        if !(step > 0.0) {
            break; // at (or, by rounding, just below) the root
        }
        let tn = t - step;
        if !(tn < t) || tn <= 0.0 {
            break;
        }
        t = tn;
        // Quadratic convergence from above: the next step would be at most
        // 3(t+1)²/(2(t²+3t+3)) (step/t)² t < 1.5e-16 t, below the 2ε t at which it stops
        // (the root to within an ulp of t).
        if step <= 1e-8 * t {
            break;
        }
    }
    t
}

/// The start of the Newton iteration of [`Jkr::solve_a_with`] for `g(t) = t⁴ + 4t³ + 6t² − D`
/// given the warm start `tg` (`sqrt(a_guess/a_s) − 1`, or a Taylor start): the smallest of the
/// upper bounds `sqrt(D/6)` (`g = t⁴ + 4t³ ≥ 0` there), `D^{1/4}` (`g = 4t³ + 6t² ≥ 0`) and
/// the warm start when it is one (`g(t_g) ≥ 0`), else the Newton iterate from it (above the
/// root by convexity). A warm start inside the bounds by a margin (`6t² < D` and `t⁴ < D` with
/// `1e-12` to spare, more than the rounding of the bounds) is taken without computing them:
/// the same start, three square roots fewer.
fn start(d: f64, tg: f64) -> f64 {
    let inside = |t: f64| {
        let t2 = t * t;
        let lim = d * (1.0 - 1e-12);
        6.0 * t2 < lim && t2 * t2 < lim
    };
    let mut g = f64::NAN;
    if tg > 0.0 {
        g = tg * tg * (6.0 + tg * (4.0 + tg)) - d;
        if g >= 0.0 && inside(tg) {
            return tg;
        }
        if g < 0.0 {
            let tn = tg - newton_step(tg, d);
            if inside(tn) {
                return tn;
            }
        }
    }
    let mut t = (d / 6.0).sqrt().min(d.sqrt().sqrt());
    if tg > 0.0 && tg < t {
        if g >= 0.0 {
            t = tg;
        } else {
            let tn = tg - newton_step(tg, d);
            if tn < t {
                t = tn;
            }
        }
    }
    t
}

/// Newton step `g/g'` for `g(t) = t⁴ + 4t³ + 6t² − D`, written without overflow for large `t`.
fn newton_step(t: f64, d: f64) -> f64 {
    if t > 1.0 {
        let it = 1.0 / t;
        (t + 4.0 + 6.0 * it - d * it * it * it) / (4.0 * (1.0 + 3.0 * it + 3.0 * it * it))
    } else {
        (t * t * (6.0 + t * (4.0 + t)) - d) / (4.0 * t * (3.0 + t * (3.0 + t)))
    }
}

/// Savkoor–Briggs critical tangential ("peeling") force
/// `T_p = 4 sqrt((G*/E*)(P P_c + P_c²))`; Lian 1994 (3.101) (= `T_c` of (A.62)).
/// `g_star` from (3.95), `e_star` from (3.16), `p` the normal force (compressive positive),
/// `pc = 3πγR*`. Returns 0 when `P ≤ −P_c` (no peeling stage left).
pub fn peeling_force(g_star: f64, e_star: f64, p: f64, pc: f64) -> f64 {
    let arg = g_star / e_star * (p * pc + pc * pc);
    if arg > 0.0 { 4.0 * arg.sqrt() } else { 0.0 }
}

/// Savkoor–Briggs contact radius under combined normal force `p` and tangential force `t`:
/// `a³ = 3R*/(4E*) [P + 2P_c + (4PP_c + 4P_c² − E*T²/(4G*))^{1/2}]`; Lian 1994 (3.100)
/// (stable "+" branch of (3.98)–(3.99)). For `T = 0` it is the JKR radius (3.23); at
/// `|T| = T_p` (3.101) it reaches `a_p³ = 3R*(P + 2P_c)/(4E*)` (3.102). For `|T| > T_p` there is
/// no real solution; the square root is clamped at 0 so `a_p` is returned (peeling complete),
/// and a negative bracket is clamped to `a = 0`.
pub fn savkoor_briggs_a(g_star: f64, e_star: f64, r_star: f64, p: f64, pc: f64, t: f64) -> f64 {
    let disc = 4.0 * p * pc + 4.0 * pc * pc - e_star * t * t / (4.0 * g_star);
    let root = if disc > 0.0 { disc.sqrt() } else { 0.0 };
    let bracket = p + 2.0 * pc + root;
    if bracket > 0.0 {
        (3.0 * r_star / (4.0 * e_star) * bracket).cbrt()
    } else {
        0.0
    }
}

/// `U / (u t²)` near the fold, `U` the energy of the JKR branch from `a_s` (the integral of
/// (3.24) along (3.29)) and `t = (a/a_s)^{1/2} − 1`: the polynomial `−5/2 − 17/3 t − …`
/// both `Jkr::energy_of_a_with` and `jkr_branch` evaluate for `|t| ≤ 1`.
pub(crate) fn fold_series(t: f64) -> f64 {
    -2.5 + t
        * (-17.0 / 3.0
            + t * (-25.0 / 6.0
                + t * (7.0 / 5.0
                    + t * (14.0 / 3.0
                        + t * (11.0 / 3.0 + t * (1.5 + t * (1.0 / 3.0 + t / 30.0)))))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const R: f64 = 30e-6;
    const E: f64 = 70e9;
    const NU: f64 = 0.3;
    const GAMMAS: [f64; 3] = [0.4, 1e-6, 10.0];

    fn jkr(gamma: f64) -> Jkr {
        Jkr {
            e_star: E / (2.0 * (1.0 - NU * NU)),
            r_star: R / 2.0,
            gamma,
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// Composite Simpson rule on [lo, hi] with n (even) intervals.
    fn simpson(f: impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> f64 {
        let h = (hi - lo) / n as f64;
        let mut s = f(lo) + f(hi);
        for k in 1..n {
            s += f(lo + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    /// Corrected (3.116) factor dα/da = a/R*·2 − sqrt(πγ/(E*a)) — written independently.
    fn dalpha_da(j: &Jkr, a: f64) -> f64 {
        2.0 * a / j.r_star - (PI * j.gamma / (j.e_star * a)).sqrt()
    }

    #[test]
    fn pull_off_is_minimum_of_load_3_31_to_3_34() {
        for &g in &GAMMAS {
            let j = jkr(g);
            assert!(rel(j.pc(), 3.0 * PI * g * R / 2.0) < 1e-15);
            // Golden-section minimisation of P(a) on [a_s, a_0].
            let (mut lo, mut hi) = (j.a_s(), j.a0());
            let phi = (5.0_f64.sqrt() - 1.0) / 2.0;
            for _ in 0..200 {
                let m1 = hi - phi * (hi - lo);
                let m2 = lo + phi * (hi - lo);
                if j.force_of_a(m1) < j.force_of_a(m2) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            let amin = 0.5 * (lo + hi);
            // Minimum load is −P_c (3.31–3.32), at a_c (3.33), α_c (3.34).
            assert!(rel(j.force_of_a(amin), -j.pc()) < 1e-14);
            let ac_333 = (3.0 * j.r_star * j.pc() / (4.0 * j.e_star)).cbrt();
            assert!(rel(amin, ac_333) < 1e-7);
            assert!(rel(j.a_c(), ac_333) < 1e-15);
            let q = j.pc().powi(2) / (j.e_star.powi(2) * j.r_star);
            let alpha_c_334 = -(4.0 * q / 3.0).cbrt() + (9.0 * q / 16.0).cbrt();
            assert!(rel(j.alpha_of_a(ac_333), alpha_c_334) < 1e-13);
            assert!(rel(j.alpha_c(), alpha_c_334) < 1e-15);
            assert!(rel(alpha_c_334, -0.275_160 * q.cbrt()) < 1e-5);
            // Stiffness (3.41) vanishes at pull-off.
            assert!(j.stiffness_of_a(ac_333).abs() < 1e-12 * 2.0 * j.e_star * ac_333);
            // Maugis form (3.88) with Γ = 2γ is the same load.
            let a = 1.7 * j.a_c();
            let maugis = 4.0 * j.e_star * a.powi(3) / (3.0 * j.r_star)
                - (8.0 * PI * 2.0 * g * j.e_star * a.powi(3)).sqrt();
            assert!(rel(j.force_of_a(a), maugis) < 1e-13);
        }
    }

    #[test]
    fn characteristic_points() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let (es, rs, pc) = (j.e_star, j.r_star, j.pc());
            // α_s from (3.38) and (3.115).
            let as_338 = -(3.0 * pc * pc / (16.0 * es * es * rs)).cbrt();
            let as_3115 = -(27.0 * PI * PI * g * g * rs / (16.0 * es * es)).cbrt();
            assert!(rel(as_338, as_3115) < 1e-14);
            assert!(rel(j.alpha_s(), as_338) < 1e-14);
            assert!(rel(j.alpha_of_a(j.a_s()), as_338) < 1e-14);
            assert!(rel(as_338, -0.572_357 * (pc * pc / (es * es * rs)).cbrt()) < 1e-5);
            // a_s from (3.36) and (3.117); dα/da = 0 there.
            assert!(rel(j.a_s(), (pc * rs / (12.0 * es)).cbrt()) < 1e-14);
            assert!(dalpha_da(&j, j.a_s()).abs() < 1e-14 * j.a_s() / rs);
            // Separation force −5/9 P_c (3.37); P_1 = P_c/9 there.
            assert!(rel(j.force_of_a(j.a_s()), -5.0 / 9.0 * pc) < 1e-14);
            assert!(rel(j.p1_of_a(j.a_s()), pc / 9.0) < 1e-14);
            // Snap-in: α(a_0) = 0, P(a_0) = −8/9 P_c.
            assert!(j.alpha_of_a(j.a0()).abs() < 1e-14 * as_338.abs());
            assert!(rel(j.force_of_a(j.a0()), -8.0 / 9.0 * pc) < 1e-14);
            let (p, a) = j.force(0.0, 0.0);
            assert!(rel(a, j.a0()) < 1e-14 && rel(p, -8.0 / 9.0 * pc) < 1e-13);
            // Zero load (3.30).
            assert!(j.force_of_a(j.a_zero_load()).abs() < 1e-14 * pc);
            // (3.22)/(3.23): a³ = 3R*P_1/(4E*) with the "+" branch at P.
            let p = 2.0 * pc;
            let p1 = p + 2.0 * pc + ((p + 2.0 * pc).powi(2) - p * p).sqrt();
            let a = (3.0 * rs * p1 / (4.0 * es)).cbrt();
            assert!(rel(j.force_of_a(a), p) < 1e-13);
        }
    }

    #[test]
    fn stiffness_matches_numerical_derivative_and_3_41() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let sc = j.alpha_s().abs();
            let mut n = 0;
            for k in 0..40 {
                // α from just above α_s to ~10⁴ |α_s|.
                let alpha = j.alpha_s() + sc * 1e-3 * 1.35_f64.powi(k);
                let a = j.solve_a(alpha, 0.0);
                if a < j.a_s() * (1.0 + 1e-3) {
                    continue;
                }
                let h = 1e-6 * (alpha - j.alpha_s());
                let (pp, _) = j.force(alpha + h, a);
                let (pm, _) = j.force(alpha - h, a);
                let num = (pp - pm) / (2.0 * h);
                let k_n = j.stiffness_of_a(a);
                let scale = 2.0 * j.e_star * a;
                assert!(
                    (k_n - num).abs() < 1e-6 * k_n.abs().max(scale),
                    "g={g} α={alpha} k={k_n} num={num}"
                );
                // Printed (3.41).
                let r = (j.pc() / j.p1_of_a(a)).sqrt();
                let k341 = 2.0 * j.e_star * a * (3.0 - 3.0 * r) / (3.0 - r);
                assert!((k_n - k341).abs() < 1e-9 * k_n.abs().max(scale));
                n += 1;
            }
            assert!(n > 30);
        }
    }

    #[test]
    fn solve_a_round_trips() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let als = j.alpha_s();
            let mut alphas = vec![als, 0.0, j.alpha_c(), 1e-9, 1e-6, 1e-3, 1.0, 1e100, 1e300];
            for k in -16..=16 {
                alphas.push(als + als.abs() * 10f64.powi(k));
            }
            let guesses = |a: f64| [0.0, -1.0, f64::NAN, f64::INFINITY, a, 0.5 * a, 2.0 * a, 1e9];
            for &alpha in &alphas {
                let a_ref = j.solve_a(alpha, 0.0);
                for &ag in &guesses(a_ref) {
                    let a = j.solve_a(alpha, ag);
                    assert!(a.is_finite() && a >= j.a_s(), "α={alpha} guess={ag} a={a}");
                    let back = j.alpha_of_a(a);
                    assert!(
                        (back - alpha).abs() <= 1e-10 * alpha.abs().max(als.abs()),
                        "g={g} α={alpha} back={back}"
                    );
                    // Warm starts only change the last ulps.
                    assert!(rel(a, a_ref) < 1e-13, "g={g} α={alpha} {a} {a_ref}");
                }
            }
            // a → α → a on the stable branch.
            for k in 0..30 {
                let a = j.a_s() * (1.0 + 1e-4 * 1.7_f64.powi(k));
                let a2 = j.solve_a(j.alpha_of_a(a), a * 1.01);
                assert!(rel(a2, a) < 1e-10, "a={a} a2={a2}");
            }
            // Below α_s: a_s.
            assert_eq!(j.solve_a(2.0 * als, 1.0), j.a_s());
            assert_eq!(j.solve_a(-1e300, 1.0), j.a_s());
        }
    }

    /// Independent parametric closed form: for a load P, (3.21)–(3.23) give P_1 and a, and
    /// (3.28) at r = 0 gives α = 3P_1/(4E*a) − (P_1 − P)/(2E*a). "+" branch for P ≥ −P_c,
    /// "−" branch for −P_c ≤ P ≤ −5/9 P_c (displacement control, a_s ≤ a ≤ a_c).
    #[test]
    fn force_overlap_curve_matches_parametric_closed_form() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let (es, rs, pc) = (j.e_star, j.r_star, j.pc());
            let mut pts = Vec::new();
            for k in 0..20 {
                pts.push((-pc + pc * 0.05 * (k as f64).powi(2), 1.0));
            }
            for k in 0..8 {
                pts.push((-pc + (4.0 / 9.0) * pc * k as f64 / 7.0, -1.0));
            }
            for &(p, branch) in &pts {
                let s = (p + 2.0 * pc).powi(2) - p * p;
                let p1 = p + 2.0 * pc + branch * s.max(0.0).sqrt();
                let a = (3.0 * rs * p1 / (4.0 * es)).cbrt();
                let alpha = 3.0 * p1 / (4.0 * es * a) - (p1 - p) / (2.0 * es * a);
                let (pf, af) = j.force(alpha, 0.0);
                assert!((pf - p).abs() < 1e-9 * pc, "g={g} P={p} got {pf}");
                assert!(rel(af, a) < 1e-7, "g={g} P={p} a={a} got {af}");
            }
        }
    }

    #[test]
    fn peel_work_3_119() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let wp = j.peel_work();
            assert!(wp > 0.0);
            // −0.9355 P_c α_s (3.119).
            assert!(rel(wp, -0.9355 * j.pc() * j.alpha_s()) < 1e-3);
            // First form of (3.119).
            let form1 = 0.4
                * (12.0 + 2.0_f64.cbrt())
                * (PI.powi(5) * g.powi(5) * j.r_star.powi(4) / (4.0 * j.e_star.powi(2))).cbrt();
            assert!(rel(wp, form1) < 1e-13);
            // (3.116) corrected: ∫_{a_0}^{a_s} P(a) α'(a) da (parametrised by a).
            let num_a = simpson(
                |a| j.force_of_a(a) * dalpha_da(&j, a),
                j.a0(),
                j.a_s(),
                2000,
            );
            assert!(rel(num_a, wp) < 1e-6);
            // Through the solver: ∫_0^{α_s} P dα with α = α_s + s² (smooth in s).
            let smax = j.alpha_s().abs().sqrt();
            let num_alpha = simpson(
                |s| j.force(j.alpha_s() + s * s, 0.0).0 * 2.0 * s,
                0.0,
                smax,
                2000,
            );
            assert!(rel(-num_alpha, wp) < 1e-6, "{num_alpha} {wp}");
            // The work function ledger.
            assert!(j.energy_of_a(j.a_s()).abs() < 1e-15 * wp);
            assert!(rel(j.energy_of_a(j.a0()), -wp) < 1e-12);
        }
    }

    #[test]
    fn energy_of_a_is_potential_of_force() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let pts: Vec<f64> = (0..12)
                .map(|k| j.a_s() * (1.0 + 1e-3 * 3.0_f64.powi(k)))
                .collect();
            for w in pts.windows(2) {
                let (a1, a2) = (w[0], w[1]);
                let num = simpson(|a| j.force_of_a(a) * dalpha_da(&j, a), a1, a2, 2000);
                let d = j.energy_of_a(a2) - j.energy_of_a(a1);
                assert!((d - num).abs() < 1e-9 * num.abs().max(j.peel_work()));
            }
            // Both evaluation branches agree at the switch point t = 1 (a = 4 a_s).
            let a = 4.0 * j.a_s();
            let below = j.energy_of_a(a * (1.0 - 1e-9));
            let above = j.energy_of_a(a * (1.0 + 1e-9));
            let mid = j.energy_of_a(a);
            assert!((0.5 * (below + above) - mid).abs() < 1e-12 * j.peel_work());
        }
    }

    /// `branch_energy` is the integral of the force from the touch (E(0) = 0, E(α_s) = W_p,
    /// constant beyond), and `step_force` on the leap-frog map of one head-on impact (m* = 1
    /// in units where the approach speed is v) gives back the kinetic energy less exactly
    /// W_p, wherever in the step the touch falls; the sampled force P(α_n) did not.
    #[test]
    fn step_force_conserves_energy_on_the_leap_frog_map() {
        let j = jkr(0.4);
        let (a_s, als) = (j.a_s(), j.alpha_s());
        let wp = j.peel_work_with(a_s);
        assert!(rel(wp, j.peel_work()) < 1e-15);
        let (e0, p0, _) = j.branch_energy(a_s, wp, 0.0, 0.0);
        assert!(e0.abs() < 1e-12 * wp && rel(p0, -8.0 / 9.0 * j.pc()) < 1e-13);
        let (es, ps, _) = j.branch_energy(a_s, wp, als, 0.0);
        assert!(rel(es, wp) < 1e-13 && ps == 0.0);
        assert_eq!(j.branch_energy(a_s, wp, 2.0 * als, 0.0).0, es);
        let num = simpson(
            |s| j.force(als + s * s, 0.0).0 * 2.0 * s,
            0.0,
            (-als).sqrt(),
            2000,
        );
        assert!(rel(-num, wp) < 1e-6);
        // The map: mass m (kg) of a 30 µm glass pair, speeds from sticking to 20 m/s.
        let m = 2650.0 * 4.0 / 3.0 * PI * R.powi(3) / 2.0;
        let dt = 3.2e-9;
        for &v0 in &[0.2, 1.0, 20.0] {
            let (mut emin, mut emax) = (f64::INFINITY, f64::NEG_INFINITY);
            let (mut smin, mut smax) = (f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..32 {
                let phase = k as f64 / 32.0;
                // α at t_n, separation rate v at t_{n−1/2}: touch at `phase` of step 3.
                let (mut alpha, mut v) = (-(2.0 + phase) * v0 * dt, -v0);
                let (mut touching, mut p_old, mut v_prev) = (false, 0.0, f64::INFINITY);
                let (mut a, mut sampled_v) = (0.0, -v0);
                let mut alpha_s_map = alpha;
                let mut sampled_touching = false;
                for _ in 0..100_000 {
                    // The sampled force, the old scheme, alongside.
                    if !sampled_touching && alpha_s_map >= 0.0 {
                        sampled_touching = true;
                    } else if sampled_touching && alpha_s_map < als {
                        sampled_touching = false;
                    }
                    let p_s = if sampled_touching {
                        j.force(alpha_s_map, 0.0).0
                    } else {
                        0.0
                    };
                    sampled_v += dt * p_s / m;
                    alpha_s_map -= sampled_v * dt;
                    // The step-mean force, as interact.rs drives it.
                    let lo = alpha + 0.5 * v * dt;
                    let mut p = 0.0;
                    let was = touching;
                    if !touching && alpha >= 0.0 {
                        touching = true;
                    } else if touching && lo < als {
                        touching = false;
                    }
                    if touching {
                        a = j.solve_a_with(a_s, alpha, a);
                        let e_lo = if was {
                            j.branch_energy(a_s, wp, lo, a).0
                        } else {
                            0.0
                        };
                        let v_ahead = if v_prev.is_finite() {
                            2.0 * v - v_prev - dt * p_old / m
                        } else {
                            v
                        };
                        let path = StepPath {
                            lo,
                            e_lo,
                            base: alpha - 0.5 * dt * v_ahead,
                            lag: 0.5 * dt * dt / m,
                        };
                        p = j.step_force(a_s, &path, j.force_of_a(a), a).0;
                        v_prev = v;
                    } else {
                        v_prev = f64::INFINITY;
                    }
                    p_old = p;
                    v += dt * p / m;
                    alpha -= v * dt;
                    if !touching && was && alpha < 10.0 * als {
                        break;
                    }
                }
                assert!(!touching && v > 0.0, "v0 {v0} phase {phase}: stuck");
                // Kinetic energy lost: exactly W_p.
                let lost = 0.5 * m * (v0 * v0 - v * v) / wp;
                emin = emin.min(lost);
                emax = emax.max(lost);
                let lost_s = 0.5 * m * (v0 * v0 - sampled_v * sampled_v) / wp;
                smin = smin.min(lost_s);
                smax = smax.max(lost_s);
            }
            assert!(
                (emin - 1.0).abs() < 1e-6 && (emax - 1.0).abs() < 1e-6,
                "v0 {v0}: kinetic energy lost {emin}..{emax} W_p"
            );
            // The sampled force made energy at some phases at 20 m/s.
            if v0 == 20.0 {
                assert!(smin < 0.0, "sampled: {smin}..{smax} W_p");
            }
        }
    }

    #[test]
    fn vanishing_adhesion_is_hertz() {
        let es = jkr(0.0).e_star;
        let rs = R / 2.0;
        let j0 = jkr(0.0);
        for k in 0..20 {
            let alpha = 1e-10 * 1.6_f64.powi(k);
            let ph = hertz::force(es, rs, alpha);
            assert_eq!(j0.force(alpha, 0.0).0, ph);
            assert_eq!(j0.solve_a(alpha, 0.0), hertz::contact_radius(rs, alpha));
            assert_eq!(
                j0.stiffness_of_a(j0.solve_a(alpha, 0.0)),
                hertz::stiffness(es, rs, alpha)
            );
            let eh = hertz::energy(es, rs, alpha);
            assert!(rel(j0.energy_of_a(j0.solve_a(alpha, 0.0)), eh) < 1e-13);
            // γ → 0: relative difference shrinks like sqrt(P_c/P_1) (P = P_1 − 2sqrt(P_1 P_c)).
            let mut last = f64::INFINITY;
            for &g in &[1e-6, 1e-9, 1e-12, 1e-15, 1e-18] {
                let j = jkr(g);
                let (p, a) = j.force(alpha, 0.0);
                let d = rel(p, ph);
                assert!(
                    d < 3.0 * (j.pc() / ph).sqrt() + 1e-14,
                    "γ={g} α={alpha} d={d}"
                );
                assert!(d < last || d < 1e-14);
                last = d;
                assert!(rel(a, hertz::contact_radius(rs, alpha)) < 3.0 * (j.pc() / ph).sqrt());
                let e = j.energy_of_a(a) - j.energy_of_a(j.a0());
                assert!(rel(e, eh) < 10.0 * (j.pc() / ph).sqrt() + 1e-12);
            }
            assert!(last < 1e-6);
        }
        assert_eq!(j0.peel_work(), 0.0);
        assert_eq!(j0.force(-1e-9, 0.0), (0.0, 0.0));
    }

    #[test]
    fn singular_points_are_finite() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let (als, a_s, pc) = (j.alpha_s(), j.a_s(), j.pc());
            let alphas = [
                als,
                als.next_up(),
                als.next_down(),
                als * (1.0 - 1e-16),
                als * (1.0 - 1e-15),
                als * (1.0 - 1e-12),
                als * (1.0 - 1e-8),
                als * (1.0 + 1e-12),
            ];
            for &alpha in &alphas {
                for &ag in &[0.0, a_s, a_s.next_up(), a_s.next_down(), f64::NAN, j.a0()] {
                    let (p, a) = j.force(alpha, ag);
                    assert!(p.is_finite() && a.is_finite() && a >= a_s);
                    // P → −5/9 P_c and a → a_s as α → α_s.
                    assert!((p + 5.0 / 9.0 * pc).abs() < 1e-3 * pc, "α={alpha} P={p}");
                    assert!(rel(a, a_s) < 1e-3);
                    let k = j.stiffness_of_a(a);
                    assert!(k.is_finite() && k <= 0.0, "α={alpha} k={k}");
                }
            }
            // Exactly at α_s.
            assert_eq!(j.solve_a(als, 123.0), a_s);
            assert!(rel(j.force(als, 0.0).0, -5.0 / 9.0 * pc) < 1e-14);
            // P_1 → P_c/9 as a → a_s: stiffness finite on both sides, sign flips across the pole.
            for &a in &[a_s, a_s.next_up(), a_s.next_down(), a_s * (1.0 + 1e-13)] {
                let k = j.stiffness_of_a(a);
                assert!(k.is_finite(), "a={a} k={k}");
                assert!(rel(j.p1_of_a(a), pc / 9.0) < 1e-12);
            }
            assert!(j.stiffness_of_a(a_s) < 0.0);
            assert!(j.stiffness_of_a(a_s * (1.0 + 1e-6)) < 0.0);
            assert!(j.stiffness_of_a(a_s * (1.0 - 1e-6)) > 0.0);
            let cap = 2.0 * j.e_star * a_s * 2.0 / STIFFNESS_POLE_FLOOR * 1.000_001;
            assert!(j.stiffness_of_a(a_s).abs() <= cap);
            // Convergence rate near α_s: a − a_s ≈ a_s sqrt(2(α − α_s)/|α_s|)·… (t ≈ sqrt(D/6)).
            let d = 1e-10;
            let a = j.solve_a(als + als.abs() * d / 3.0, 0.0);
            let t = (a / a_s).sqrt() - 1.0;
            assert!(rel(t, (d / 6.0).sqrt()) < 1e-4);
            // Energy and stiffness at a = 0, negative a, huge α.
            assert!(j.stiffness_of_a(0.0) == 0.0 && j.stiffness_of_a(-1.0) == 0.0);
            assert!(j.energy_of_a(0.0).is_finite());
            let (p, a) = j.force(1e100, 0.0);
            assert!(p.is_finite() && a.is_finite() && p > 0.0);
            assert!(j.solve_a(f64::MAX, 0.0).is_finite());
            for &a in &[1e30, 1e100, 1e200, 1e300, f64::MAX] {
                let k = j.stiffness_of_a(a);
                let u = j.energy_of_a(a);
                assert!(
                    !k.is_nan() && k > 0.0 && !u.is_nan() && u > 0.0,
                    "a={a} k={k} U={u}"
                );
                assert!(!j.force_of_a(a).is_nan());
            }
        }
    }

    #[test]
    fn savkoor_briggs_peeling() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let (es, rs, pc) = (j.e_star, j.r_star, j.pc());
            let gs = hertz::g_star(
                hertz::shear_modulus(E, NU),
                NU,
                hertz::shear_modulus(E, NU),
                NU,
            );
            for &p in &[-0.9 * pc, -0.5 * pc, 0.0, pc, 10.0 * pc] {
                let tp = peeling_force(gs, es, p, pc);
                assert!(tp > 0.0);
                // T = 0: the JKR contact radius of load P on the "+" branch.
                let a0 = savkoor_briggs_a(gs, es, rs, p, pc, 0.0);
                assert!((j.force_of_a(a0) - p).abs() < 1e-12 * pc);
                // T = T_p: a_p (3.102); beyond it, clamped to a_p.
                let ap = (3.0 * rs * (p + 2.0 * pc) / (4.0 * es)).cbrt();
                assert!(rel(savkoor_briggs_a(gs, es, rs, p, pc, tp), ap) < 1e-6);
                assert!(rel(savkoor_briggs_a(gs, es, rs, p, pc, 2.0 * tp), ap) < 1e-15);
                // Stationarity of the total potential energy (3.97) in P_1 at 0 < T < T_p.
                let t = 0.6 * tp;
                let a = savkoor_briggs_a(gs, es, rs, p, pc, t);
                let p1 = 4.0 * es * a.powi(3) / (3.0 * rs);
                let u = |p1: f64| {
                    (9.0 / (16.0 * es * es * rs * p1)).cbrt() / 15.0
                        * (p1 * p1
                            - 5.0 * p * p1
                            - 5.0 * p * p
                            - 30.0 * PI * g * rs * p1
                            - 5.0 * es / (4.0 * gs) * t * t)
                };
                let h = 1e-5 * p1;
                let du = (u(p1 + h) - u(p1 - h)) / (2.0 * h);
                let scale = (u(p1) / p1).abs();
                assert!(du.abs() < 1e-7 * scale, "du={du} scale={scale}");
                // Contact area shrinks as T grows.
                assert!(a < a0 && a > ap);
            }
            assert_eq!(peeling_force(gs, es, -pc, pc), 0.0);
            assert_eq!(peeling_force(gs, es, -2.0 * pc, pc), 0.0);
            // γ = 0: no peeling stage.
            assert_eq!(peeling_force(gs, es, 1.0, 0.0), 0.0);
        }
    }

    /// The start of a step's path from the last evaluated point of the last one
    /// (`energy_from_end`): wherever it is accepted (`|δ|³ ≤ 1e-10 ρ²h`), the Taylor
    /// polynomial is the energy solved afresh to 1e-10 of the half step's work
    /// `max(|P|, P_c) h` (plus the round-off of `E` itself), from just above the fold `α_s`
    /// to deep compression; it is refused beyond the bound, at or beyond `α_s`, and for
    /// another law; `δ = 0` gives the stored energy itself.
    #[test]
    fn energy_from_end_is_the_branch_energy_within_its_bound() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let (a_s, als) = (j.a_s(), j.alpha_s());
            let wp = j.peel_work_with(a_s);
            let mut n = 0;
            for k in -6..=4 {
                let alpha_end = als + als.abs() * 10f64.powi(k);
                let rho = alpha_end - als;
                let (e, p, a) = j.branch_energy(a_s, wp, alpha_end, 0.0);
                let end = PathEnd {
                    alpha: alpha_end,
                    e,
                    p,
                    k: j.stiffness_with(a_s, a),
                    e_star: j.e_star,
                    r_star: j.r_star,
                };
                assert_eq!(
                    j.energy_from_end(a_s, &end, alpha_end, alpha_end + rho),
                    Some(e)
                );
                for h in [1e-2 * rho, 1e-5 * rho, 1e-9 * rho] {
                    // α_n, and the half step as the rounding of α_n leaves it.
                    let alpha = alpha_end - h;
                    let h = (alpha - alpha_end).abs();
                    let d_max = (1e-10 * rho * rho * h).cbrt();
                    for f in [0.98, 0.5, -0.5, -0.98] {
                        let lo = alpha_end + f * d_max;
                        let got = j.energy_from_end(a_s, &end, lo, alpha);
                        let exact = j.branch_energy(a_s, wp, lo, a).0;
                        let tol = 1e-10 * p.abs().max(j.pc()) * h + 1e-14 * (wp + exact.abs());
                        let got = got.unwrap_or_else(|| panic!("γ {g} k {k} h {h} f {f}"));
                        assert!(
                            (got - exact).abs() <= tol,
                            "γ {g} k {k} h {h} f {f}: {got} vs {exact} (tol {tol})"
                        );
                        n += 1;
                    }
                    // Beyond the bound: solved afresh.
                    let lo = alpha_end + 1.05 * d_max;
                    assert_eq!(j.energy_from_end(a_s, &end, lo, alpha), None);
                }
                // Another law (a modulus changed between Cycles): solved afresh.
                let other = Jkr {
                    e_star: 2.0 * j.e_star,
                    ..j
                };
                assert_eq!(other.energy_from_end(a_s, &end, alpha_end, alpha_end), None);
            }
            assert_eq!(n, 11 * 3 * 4);
            // An end at or beyond the fold (a path that crossed α_s): solved afresh.
            let (e, p, a) = j.branch_energy(a_s, wp, als, 0.0);
            let end = PathEnd {
                alpha: als,
                e,
                p,
                k: j.stiffness_with(a_s, a),
                e_star: j.e_star,
                r_star: j.r_star,
            };
            assert_eq!(
                j.energy_from_end(a_s, &end, als, als + 1e-3 * als.abs()),
                None
            );
        }
    }
}
