//! Incremental tangential contact laws acting on the **signed resultant** tangential
//! displacement `δ` and force `T` of one contact (Lian 1994 §5.6.2 steps 6–8).
//!
//! The caller owns the 3-D bookkeeping (contact-plane rotation, the signed resultant (5.23) and
//! the components (5.26)); this module receives the scalar increment `Δδ` along the current
//! positive direction, the normal force before and after this step's normal update, and returns
//! the new `T`, the frictional dissipation of the step and the tangent stiffness.
//! Equation numbers are those of Lian (1994), `seeds/000_6b8655e566374cea.txt`; see also
//! `doc/spec/physics-lian1994.md` §2 and §7 and `doc/spec/DECISIONS.md`.
//!
//! Two laws:
//! * [`mindlin_deresiewicz`] (`SET TANGENTIAL MD`; the default law of JKR pairs, Hertz pairs
//!   taking `physics::mdr`): Mindlin–Deresiewicz micro-slip with
//!   the Thornton–Randall θ-factor incremental stiffness (3.109)–(3.112); with adhesion, the
//!   Savkoor–Briggs no-slip/peeling stage (3.93), (3.101), (3.113) first, then micro-slip with the
//!   effective normal force `P_e = P + 2 P_c` and sliding at `μ (P + 2 P_c)` (3.103), Thornton (1991).
//! * [`noslip_coulomb`] (`SET TANGENTIAL NOSLIP`): linear spring `k_t = 8 G* a` (3.93)–(3.94),
//!   (5.18) with a Coulomb cap at `μ P_e`.
//!
//! # Decisions on the open points of the thesis (doc/spec/physics-lian1994.md §2.3 flags)
//! * **Updated normal force.** `c_j` uses `P_e^new = P_e + ΔP_e` in its denominators, as in
//!   (A.45), (A.46), (A.52), (A.61) (flag 1). The caller updates `N` before `T` (§2.4).
//! * **The `c_j = a` test** is the product form `(-1)^j ΔT ≤ μ ΔP_e ⇒ c_j = a` (flag 2), evaluated
//!   with the **no-slip trial** `ΔT = 8 G* a Δδ`. This trial is exactly self-consistent: with
//!   `ΔT = 8G*c_j Δδ + (-1)^j μ (1 − c_j/a) ΔP_e` (3.109) one has
//!   `(-1)^j ΔT − μ ΔP_e = (c_j/a) [(-1)^j 8 G* a Δδ − μ ΔP_e]`, so the trial and the actual
//!   increment always agree on the sign of the test, whatever `c_j` turns out to be.
//! * **Order of (3.111) and (3.112).** `c_j` is evaluated with the turning points of the start of
//!   the step; they are shifted by (3.112) afterwards. This is what maps the state onto the
//!   "equivalent curve of constant normal force" at `P_e^new` (the `2μΔP_e` in (3.111) is one
//!   `μΔP_e` for the turning point and one for the force), see [`mindlin_deresiewicz`].
//!   (3.112) is applied to every stored turning point (they all describe frozen annuli), and a
//!   shifted turning point is kept within `±μ P_e^new`.
//! * **Guarded cube root** (flag 3): an argument `≤ 0` means the slip annulus has reached the
//!   centre: the contact slides at `T = ±μ P_e^new`. An argument `> 1` (possible only when `P_e`
//!   falls) is clamped to 1 (`c_j = a`).
//! * **Path memory** (flag 5): Masing/Mindlin–Deresiewicz turning-point memory kept as a small
//!   stack. `tp[0]` is Lian's `T_1` (C(12)), `tp[1]` his `T_2` (C(13)); deeper entries record
//!   nested inner loops (an extension of TRUBAL's two slots, exact for Mindlin at constant `P`).
//!   A reversal of `Δδ` pushes the current `T`; a branch that reaches the previous turning point
//!   of the same sense erases the last two (reload reaching `T_1` → loading, memory erased); the
//!   first unloading branch reaching `−T_1` becomes virgin loading in the opposite sense. Full
//!   sliding erases all memory. If more than [`MAX_TURNING_POINTS`] would be needed, the outermost
//!   pair is forgotten (the current branch stays exact).
//! * **C(14)** ("distance that the tangential force falls short of its equivalent curve of
//!   constant normal force", flag 4) is not needed: (3.111) computes `c_j` from the *force* `T`,
//!   so the force law never needs the displacement on the equivalent curve. It is not stored.
//! * **Peeling with adhesion.** Before peeling is complete `k_t = 8 G* a` with no loss and no
//!   Coulomb cap; the step in which `|T|` reaches `T_p` (3.101) is split at `T_p`. If at that
//!   moment `T_p ≥ μ (P + 2P_c)` (the `P < P_2` case of (3.106)) `T` falls to `±μ (P + 2P_c)`.
//!   `peeled` is irreversible for the contact.
//!
//! # Energy ledger
//! Every step returns `work = ∫ T dδ` over the step (trapezoid, split at the point where the
//! Coulomb cap is reached) and `dissipated_slip ≥ 0`; the state keeps the stored tangential
//! elastic energy `stored` so that, exactly (to rounding), `Δstored + dissipated_slip = work`.
//! * Partial slip: the thesis increment (A.53) ≡ (3.121)/(A.60) (written without the division by
//!   `c_j`), evaluated with the same `c_j` as the force update. Zero when `c_j = a` (3.120).
//! * No-slip stages (`c_j = a`, Savkoor–Briggs stage, the linear law below the cap): no loss
//!   (A.5); the work goes to `stored`.
//! * Whenever a step ends in full sliding the elastic field is known exactly and `stored` is
//!   re-synchronised to it: `3 (μP_e)² / (40 G* a)` (integral of (A.54)×(A.56)) for the MD law,
//!   `(μP_e)² / (16 G* a)` (3.96) for the linear law; `dissipated_slip = work − Δstored`. At
//!   constant `P` this is exactly `μ P_e |Δδ|`. The thesis's (3.122)/(A.58) `3μ²P_eΔP_e/(20G*a)`
//!   is the same energy differentiated at fixed `a`; the re-synchronisation includes the change
//!   of `a` (with Hertz `a ∝ P^{1/3}` it is `μ²P_eΔP_e/(8G*a)`). If `work − Δstored` would be
//!   negative (an artefact of the incremental law, e.g. after `a` shrank) it is reported as zero
//!   and the remainder stays in `stored` until the next sliding step. One such case is built into
//!   Thornton's adhesive model: at the end of peeling (`P > P_2`) the no-slip field of energy
//!   `T_p²/(16G*a)` is continued on the Mindlin curve as if `T_p` had been reached by micro-slip,
//!   whose field holds slightly more energy; that difference is repaid by the first sliding steps.
//! * When a contact is deleted the caller books [`release`]'s return value (the remaining
//!   `stored`) as dissipated.
//!
//! For a constant normal force the stored energy agrees with the exact Mindlin–Deresiewicz
//! field energy [`mindlin_state_energy`], and a closed load–unload–reload cycle dissipates the
//! Mindlin et al. (1951) loop energy (A.1).

use serde::{Deserialize, Serialize};

/// Capacity of the turning-point memory (Lian's `T_1`, `T_2` plus nested inner loops).
pub const MAX_TURNING_POINTS: usize = 8;

/// Cube-root arguments of (3.111) below this count as zero (full sliding): a force held at the
/// cap while `P_e` changes gives an argument that is zero up to rounding, and the cube root
/// would amplify that noise to `θ ~ 1e-5`.
const ARG_EPS: f64 = 1e-12;

/// Per-contact tangential state (plain data, serialisable for checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TangentialState {
    /// Signed resultant tangential force `T` (N), Lian's C(11); positive along the current
    /// positive direction of the resultant displacement.
    pub t: f64,
    /// Turning points, oldest first: `tp[0] = T_1` (unloading commenced, C(12)), `tp[1] = T_2`
    /// (reloading commenced, C(13)), then nested inner loops. Only `tp[..n_tp]` is meaningful.
    pub tp: [f64; MAX_TURNING_POINTS],
    /// Number of live turning points; 0 on the (virgin) loading path.
    pub n_tp: u8,
    /// Sense of the loading path (`+1`/`−1`); 0 before the first movement.
    pub sense: i8,
    /// Savkoor–Briggs peeling completed (irreversible). Ignored without adhesion.
    pub peeled: bool,
    /// Stored tangential elastic energy (J) of the ledger, see the module docs.
    pub stored: f64,
}

impl TangentialState {
    /// Loading path index `j` of Lian (3.109): 0 loading, 1 unloading, 2 reloading.
    pub fn path(&self) -> u8 {
        match self.n_tp {
            0 => 0,
            n if n % 2 == 1 => 1,
            _ => 2,
        }
    }

    /// The live turning points, oldest first.
    pub fn turning_points(&self) -> &[f64] {
        &self.tp[..(self.n_tp as usize).min(MAX_TURNING_POINTS)]
    }

    /// `T_1`: force at which the current (innermost) unloading commenced; 0 if none.
    pub fn t1(&self) -> f64 {
        let n = self.turning_points().len();
        match n {
            0 => 0.0,
            n if n % 2 == 1 => self.tp[n - 1],
            n => self.tp[n - 2],
        }
    }

    /// `T_2`: force at which the current (innermost) reloading commenced; 0 if none.
    pub fn t2(&self) -> f64 {
        let n = self.turning_points().len();
        match n {
            0 | 1 => 0.0,
            n if n % 2 == 0 => self.tp[n - 1],
            n => self.tp[n - 2],
        }
    }

    /// Direction `(-1)^j` of the current branch in absolute terms: `+1` if `T` grows along it.
    fn direction(&self) -> f64 {
        let s = if self.sense < 0 { -1.0 } else { 1.0 };
        if self.n_tp % 2 == 1 { -s } else { s }
    }

    /// Push a turning point (a reversal of `Δδ`). When full, forget the outermost pair.
    fn push(&mut self, t: f64) {
        let mut n = (self.n_tp as usize).min(MAX_TURNING_POINTS);
        if n == MAX_TURNING_POINTS {
            self.tp.copy_within(2..MAX_TURNING_POINTS, 0);
            n -= 2;
        }
        self.tp[n] = t;
        self.n_tp = (n + 1) as u8;
    }

    fn clear_memory(&mut self, sense: f64) {
        self.n_tp = 0;
        self.sense = sign_i8(sense);
    }
}

/// Inputs of one step of one contact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TangentialInput {
    /// Effective shear modulus `G*`, `1/G* = (2−ν1)/G1 + (2−ν2)/G2` (3.95).
    pub g_star: f64,
    /// Friction coefficient `μ` (the smaller of the two materials').
    pub mu: f64,
    /// Contact radius `a` after this step's normal update.
    pub a: f64,
    /// Normal force before this step's normal update (compressive positive).
    pub p_old: f64,
    /// Normal force after this step's normal update (compressive positive).
    pub p_new: f64,
    /// JKR pull-off force `P_c = 3πγR*`; 0 without adhesion.
    pub pc: f64,
    /// Effective modulus `E*` (3.16); only used for the peeling force (3.101).
    pub e_star: f64,
    /// Increment `Δδ` of the signed resultant tangential displacement (5.24).
    pub d_delta: f64,
}

/// Result of one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TangentialOutput {
    /// Energy dissipated by frictional slip/sliding in this step (J), `≥ 0`.
    pub dissipated_slip: f64,
    /// The force is at the Coulomb limit at the end of the step.
    pub sliding: bool,
    /// Tangent stiffness `dT/dδ` at the start of the step along `δ`: `8 G* c_j` (the `δ` part of
    /// (3.109)); `8 G* a` without slip; 0 while sliding.
    pub kt: f64,
    /// Work done on the contact in this step, `∫ T dδ` (J); `Δstored + dissipated_slip = work`.
    pub work: f64,
}

/// Savkoor–Briggs critical peeling force `T_p = 4 sqrt(G*/E* (P P_c + P_c²))`, Lian 1994 (3.101)
/// (= `T_c` of (A.62)). Zero when the bracket is negative or the inputs are not positive.
pub fn peeling_force(g_star: f64, e_star: f64, p: f64, pc: f64) -> f64 {
    if !(g_star > 0.0 && e_star > 0.0 && pc > 0.0) {
        return 0.0;
    }
    let b = g_star / e_star * pc * (p + pc);
    if b > 0.0 && b.is_finite() {
        4.0 * b.sqrt()
    } else {
        0.0
    }
}

/// Normal forces `P_2` at which the peeling curve (3.101) meets the sliding line
/// `T = μ(P + 2P_c)` (3.103): Lian 1994 (3.106),
/// `P_2 = 2P_c [(4G*/(μ²E*) − 1) ± sqrt(4G*/(μ²E*) (4G*/(μ²E*) − 1))]`, smaller root first.
/// For `P` between the roots peeling ends below the sliding force (smooth transition); outside,
/// `T` falls to the sliding value when peeling completes. `None` if there is no real root.
pub fn peel_slide_intersection(g_star: f64, e_star: f64, mu: f64, pc: f64) -> Option<[f64; 2]> {
    if !(g_star > 0.0 && e_star > 0.0 && mu > 0.0) {
        return None;
    }
    let q = 4.0 * g_star / (mu * mu * e_star);
    let disc = q * (q - 1.0);
    if !disc.is_finite() || disc < 0.0 {
        return None;
    }
    let r = disc.sqrt();
    Some([2.0 * pc * (q - 1.0 - r), 2.0 * pc * (q - 1.0 + r)])
}

/// Elastic energy of a fully sliding Mindlin contact, `3 (μ P_e)² / (40 G* a)`: half the
/// integral of the traction (A.54) times the displacement (A.56) of both spheres. 0 if `a ≤ 0`.
pub fn sliding_energy(g_star: f64, mu: f64, p_e: f64, a: f64) -> f64 {
    if g_star > 0.0 && a > 0.0 {
        let cap = mu * p_e;
        3.0 * cap * cap / (40.0 * g_star * a)
    } else {
        0.0
    }
}

/// Elastic energy of the Mindlin–Deresiewicz traction field described by `state` (`T` and its
/// turning points) **at a constant normal force** `p_e` with contact radius `a`.
///
/// Exact superposition (Mindlin 1949; Lian App. A, (A.8)–(A.9), (A.22)–(A.24), (A.33)–(A.36)):
/// the traction is `Σ_k m_k d_k μP_e [E(a) − θ_k³ E(c_k)]` where `E(ρ)` is the unit-force elliptic
/// distribution `3/(2πρ³) sqrt(ρ² − r²)`, `m_0 = 1`, `m_k = 2` after a turning point, `d_k` the
/// branch direction and `θ_k³ = 1 − |X_k − X_{k−1}| / (m_k μ P_e)` ((A.10), (A.25), (A.37)). With
/// the displacement of an elliptic distribution (Johnson 1985, Lian (A.7)/(A.56)) the mutual
/// energy of two unit distributions of radii `c ≤ ρ` is `3 (5ρ² − c²) / (80 G* ρ³)`, and
/// `U = ½ Σ_i Σ_j F_i F_j K(ρ_i, ρ_j)`. Virgin loading gives
/// `U = 9μ²P_e²/(16G*a) (2/15 − θ³/3 + θ⁵/5)`, the integral of (A.21).
///
/// This is a reference (for tests and diagnostics); the ledger uses `state.stored`. The sum
/// cancels for small forces: its relative accuracy is about `1e-16 / (T/μP_e)²`.
pub fn mindlin_state_energy(
    state: &TangentialState,
    g_star: f64,
    mu: f64,
    p_e: f64,
    a: f64,
) -> f64 {
    let cap = mu * p_e;
    if !(g_star > 0.0 && a > 0.0 && cap > 0.0) {
        return 0.0;
    }
    let tps = state.turning_points();
    let s0 = if state.sense < 0 {
        -1.0
    } else if state.sense > 0 {
        1.0
    } else if state.t < 0.0 {
        -1.0
    } else {
        1.0
    };
    // (radius, force) components; all full-radius parts are lumped into `f_a`.
    let mut comps: [(f64, f64); MAX_TURNING_POINTS + 1] = [(0.0, 0.0); MAX_TURNING_POINTS + 1];
    let mut f_a = 0.0;
    let mut x_prev = 0.0;
    for k in 0..=tps.len() {
        let x = if k < tps.len() { tps[k] } else { state.t };
        let d = if k % 2 == 1 { -s0 } else { s0 };
        let m = if k == 0 { 1.0 } else { 2.0 };
        let cube = (1.0 - (d * (x - x_prev)).max(0.0) / (m * cap)).clamp(0.0, 1.0);
        f_a += m * d * cap;
        comps[k] = (a * cube.cbrt(), -m * d * cap * cube);
        x_prev = x;
    }
    let kern = |c: f64, rho: f64| {
        let (lo, hi) = if c <= rho { (c, rho) } else { (rho, c) };
        3.0 * (5.0 * hi * hi - lo * lo) / (80.0 * g_star * hi * hi * hi)
    };
    let n = tps.len() + 1;
    let mut u = 0.5 * f_a * f_a * kern(a, a);
    for i in 0..n {
        let (ri, fi) = comps[i];
        if ri <= 0.0 || fi == 0.0 {
            continue;
        }
        u += f_a * fi * kern(ri, a);
        for &(rj, fj) in comps.iter().take(n) {
            if rj > 0.0 && fj != 0.0 {
                u += 0.5 * fi * fj * kern(ri, rj);
            }
        }
    }
    u
}

/// Stored tangential elastic energy of the contact for the energy ledger (J).
pub fn stored_energy(state: &TangentialState) -> f64 {
    state.stored
}

/// Contact deleted: returns the remaining stored energy (to be booked as dissipated by the
/// caller) and resets the state.
pub fn release(state: &mut TangentialState) -> f64 {
    let e = state.stored;
    *state = TangentialState::default();
    if e.is_finite() { e } else { 0.0 }
}

/// Sanitised copy of the inputs: non-finite values become 0, moduli/μ/a/P_c are non-negative.
struct Params {
    g: f64,
    mu: f64,
    a: f64,
    p_old: f64,
    p_new: f64,
    pc: f64,
    e: f64,
    dd: f64,
}

fn fin(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

fn params(inp: &TangentialInput) -> Params {
    Params {
        g: fin(inp.g_star).max(0.0),
        mu: fin(inp.mu).max(0.0),
        a: fin(inp.a).max(0.0),
        p_old: fin(inp.p_old),
        p_new: fin(inp.p_new),
        pc: fin(inp.pc).max(0.0),
        e: fin(inp.e_star).max(0.0),
        dd: fin(inp.d_delta),
    }
}

fn sign_i8(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// `±1` from the sign of `x`; from the sign of `fallback` if `x` is zero or NaN (`+1` if both).
fn sign_or(x: f64, fallback: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 || fallback < 0.0 {
        -1.0
    } else {
        1.0
    }
}

fn sanitize_state(st: &mut TangentialState) {
    if !st.t.is_finite() {
        st.t = 0.0;
        st.n_tp = 0;
    }
    if !st.stored.is_finite() {
        st.stored = 0.0;
    }
    if st.n_tp as usize > MAX_TURNING_POINTS {
        st.n_tp = MAX_TURNING_POINTS as u8;
    }
    for x in st.tp.iter_mut() {
        *x = fin(*x);
    }
}

/// Work of a step whose trial force `t_trial` was cut back to the cap value `t_new`: trapezoid
/// up to the point where the cap is reached (linear interpolation), then `t_new Δδ`.
fn capped_work(t_old: f64, t_trial: f64, t_new: f64, dd: f64) -> f64 {
    let f = (t_new - t_old) / (t_trial - t_old);
    let f = if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        0.0
    };
    0.5 * (t_old + t_new) * f * dd + t_new * (1.0 - f) * dd
}

/// Re-synchronise `stored` to the known elastic energy `target` of a sliding state; returns the
/// dissipation `work − Δstored`, or 0 (keeping the remainder in `stored`) if that is negative.
fn sync(st: &mut TangentialState, e_old: f64, work: f64, target: f64) -> f64 {
    let raw = work - (target - e_old);
    if raw >= 0.0 {
        st.stored = target;
        raw
    } else if raw < 0.0 {
        st.stored = e_old + work;
        0.0
    } else {
        st.stored = target;
        0.0
    }
}

/// The contact cannot carry a tangential force (`a = 0`, `G* = 0` or `μ P_e ≤ 0`): `T` drops to
/// zero, the memory is cleared and the stored energy is released as dissipation.
fn no_capacity(st: &mut TangentialState, dd: f64) -> TangentialOutput {
    let t_old = st.t;
    let e_old = st.stored;
    st.t = 0.0;
    st.clear_memory(0.0);
    let diss = sync(st, e_old, 0.0, 0.0);
    TangentialOutput {
        dissipated_slip: diss,
        sliding: t_old != 0.0 || dd != 0.0,
        kt: 0.0,
        work: 0.0,
    }
}

/// Mindlin–Deresiewicz step with the Thornton–Randall θ factors, for an already "peeled"
/// contact (or one without adhesion), effective normal force `pe_old → pe_new`.
fn md_step(
    st: &mut TangentialState,
    g: f64,
    mu: f64,
    a: f64,
    pe_old: f64,
    pe_new: f64,
    dd: f64,
) -> TangentialOutput {
    let cap = mu * pe_new;
    if !(a > 0.0 && g > 0.0 && cap > 0.0 && cap.is_finite()) {
        return no_capacity(st, dd);
    }
    let t_old = st.t;
    let e_old = st.stored;
    let kn = 8.0 * g * a;
    let dpe = pe_new - pe_old;

    // Path transitions on a reversal of Δδ (flag 5).
    if dd != 0.0 {
        let sdd = dd.signum();
        if st.n_tp == 0 && (st.sense == 0 || t_old == 0.0) {
            st.sense = sign_i8(sdd);
        } else if sdd != st.direction() {
            st.push(t_old);
        }
    }
    let d = st.direction();
    let n = st.n_tp as usize;

    // Product-form slip test with the no-slip trial ΔT = 8G*aΔδ (flag 2; (3.110), (3.120)).
    let s = d * kn * dd - mu * dpe;
    let mut theta = 1.0;
    let mut full_slide = false;
    if s > 0.0 {
        // (3.111)/(A.61) with P_e^new in the denominators (flag 1); m = 1 loading, 2 otherwise.
        let (m, t_o) = if n == 0 {
            (1.0, 0.0)
        } else {
            (2.0, st.tp[n - 1])
        };
        let arg = 1.0 - (d * (t_old - t_o) + m * mu * dpe) / (m * cap);
        if arg > ARG_EPS {
            theta = arg.min(1.0).cbrt();
        } else {
            // Guarded cube root (flag 3): the slip annulus has reached the centre.
            theta = 0.0;
            full_slide = true;
        }
    }
    let (t_trial, diss_slip) = if full_slide {
        (d * cap, 0.0)
    } else {
        // ΔT = k_t Δδ with k_t of (3.109), written without the division by Δδ.
        let dt = kn * theta * dd + d * mu * (1.0 - theta) * dpe;
        // (A.53) ≡ (3.121)/(A.60): μP_e^new/2 (2 − 3θ + θ³) ((-1)^j Δδ − μΔP_e/(8G*a)).
        let diss = if s > 0.0 {
            0.5 * cap * (2.0 - 3.0 * theta + theta * theta * theta) * (s / kn)
        } else {
            0.0
        };
        (t_old + dt, diss)
    };

    if t_trial.is_nan() || t_trial.abs() >= cap {
        // Sliding (§2.4 step 8): reset to the limiting value keeping the sign; memory erased.
        let sg = sign_or(t_trial, d);
        let t_new = sg * cap;
        let work = capped_work(t_old, t_trial, t_new, dd);
        let diss = sync(st, e_old, work, sliding_energy(g, mu, pe_new, a));
        st.t = t_new;
        st.clear_memory(sg);
        return TangentialOutput {
            dissipated_slip: diss,
            sliding: true,
            kt: 0.0,
            work,
        };
    }

    let work = 0.5 * (t_old + t_trial) * dd;
    st.t = t_trial;
    st.stored = e_old + work - diss_slip;

    // (3.112): T_j ← T_j − (−1)^j μ ΔP (after c_j was evaluated), kept within the new cap.
    if dpe != 0.0 {
        let s0 = if st.sense < 0 { -1.0 } else { 1.0 };
        for k in 0..n {
            let dk = if k % 2 == 0 { -s0 } else { s0 };
            st.tp[k] = (st.tp[k] - dk * mu * dpe).clamp(-cap, cap);
        }
    }
    // Erasure of memory (Masing): a branch reaching the previous turning point of its sense.
    loop {
        let n = st.n_tp as usize;
        if n == 0 {
            break;
        }
        let d = st.direction();
        let target = if n == 1 { -st.tp[0] } else { st.tp[n - 2] };
        if d * (st.t - target) >= 0.0 {
            if n == 1 {
                st.clear_memory(d);
            } else {
                st.n_tp -= 2;
            }
        } else {
            break;
        }
    }
    TangentialOutput {
        dissipated_slip: diss_slip,
        sliding: false,
        kt: kn * theta,
        work,
    }
}

/// Mindlin–Deresiewicz tangential law with the Thornton–Randall θ factors
/// (Lian 1994 (3.107)–(3.113)), and with adhesion the Savkoor–Briggs/Thornton (1991) scheme
/// ((3.93), (3.101), (3.103), (3.106)). Updates `state` and returns the step's dissipation.
///
/// Per step, with `d = (−1)^j` the direction of the current branch (`j` = 0 loading,
/// 1 unloading, 2 reloading), `k = 8G*a` and `T_o` the branch's last turning point:
/// 1. a reversal of `Δδ` starts a new branch at the current `T` (pushes a turning point);
/// 2. slip if `d·k·Δδ > μΔP_e` (product form, no-slip trial), then
///    `θ = c_j/a = cbrt(1 − (d(T − T_o) + m μΔP_e)/(m μ P_e^new))`, `m = 1` on the virgin path
///    (`T_o = 0`), `m = 2` otherwise ((3.111)/(A.61)); else `θ = 1` ((3.110));
/// 3. `ΔT = kθΔδ + d μ(1 − θ)ΔP_e` ((3.109)); loss (A.53);
/// 4. `|T| ≥ μP_e^new` → `T = ±μP_e^new`, sliding, memory erased;
/// 5. turning points shifted by (3.112); memory erased where a branch meets its origin.
///
/// Before peeling (adhesion only) `ΔT = 8G*aΔδ` ((3.113)) until `|T| ≥ T_p` (3.101).
pub fn mindlin_deresiewicz(state: &mut TangentialState, inp: &TangentialInput) -> TangentialOutput {
    sanitize_state(state);
    let p = params(inp);
    let adhesive = p.pc > 0.0;
    let (pe_old, pe_new) = if adhesive {
        (p.p_old + 2.0 * p.pc, p.p_new + 2.0 * p.pc)
    } else {
        (p.p_old, p.p_new)
    };
    if !adhesive || state.peeled {
        return md_step(state, p.g, p.mu, p.a, pe_old, pe_new, p.dd);
    }

    // Savkoor–Briggs no-slip stage: k_t = 8G*a (3.113), no loss (A.5), no Coulomb cap.
    if !(p.a > 0.0 && p.g > 0.0) {
        return no_capacity(state, p.dd);
    }
    let kn = 8.0 * p.g * p.a;
    let t_peel = peeling_force(p.g, p.e, p.p_new, p.pc);
    let t_old = state.t;
    let e_old = state.stored;
    let t_trial = t_old + kn * p.dd;
    if t_trial.abs() < t_peel {
        let work = 0.5 * (t_old + t_trial) * p.dd;
        state.t = t_trial;
        state.stored = e_old + work;
        state.clear_memory(t_trial);
        return TangentialOutput {
            dissipated_slip: 0.0,
            sliding: false,
            kt: kn,
            work,
        };
    }

    // Peeling complete (irreversible). Split the step at |T| = T_p.
    state.peeled = true;
    let (t_start, dd_rem, w1) = if t_old.abs() >= t_peel {
        // Completed by a change of the normal force, not by Δδ.
        (t_old, p.dd, 0.0)
    } else {
        let tp_signed = if t_trial < 0.0 { -t_peel } else { t_peel };
        let dd_p = (tp_signed - t_old) / kn;
        (tp_signed, p.dd - dd_p, 0.5 * (t_old + tp_signed) * dd_p)
    };
    state.t = t_start;
    state.stored = e_old + w1;
    state.clear_memory(t_start);
    let cap = p.mu * pe_new;
    if !(cap > 0.0 && cap.is_finite()) {
        let mut o = no_capacity(state, dd_rem);
        o.work += w1;
        return o;
    }
    if t_start.abs() >= cap {
        // P < P_2 (3.106): at the end of peeling T falls to the sliding value (Thornton 1991).
        let sg = sign_or(t_start, p.dd);
        let t_new = sg * cap;
        let work = w1 + t_new * dd_rem;
        let diss = sync(state, e_old, work, sliding_energy(p.g, p.mu, pe_new, p.a));
        state.t = t_new;
        state.clear_memory(sg);
        return TangentialOutput {
            dissipated_slip: diss,
            sliding: true,
            kt: 0.0,
            work,
        };
    }
    // P > P_2: smooth transition to micro-slip with P_e = P + 2P_c (3.103), (3.107).
    let mut o = md_step(state, p.g, p.mu, p.a, pe_new, pe_new, dd_rem);
    o.work += w1;
    o
}

/// Rotation of a shear vector into a new contact plane, keeping its length; Lian 1994
/// (5.19)–(5.21): `w = v − n (n·v)`, `v' = w |v|/|w|`. A zero vector stays; a vector along
/// the new normal (no projection) becomes zero. Branch-free (selects), so that the vectorised
/// kernel (`sim::lanes`) can use it as the general one (`sim::interact`) does.
#[inline(always)]
pub fn rotate_into_plane(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let [ox, oy, oz] = v;
    let [nx, ny, nz] = n;
    let len2 = 0.0 + (ox * ox + oy * oy + oz * oz);
    let nd = nx * ox + ny * oy + nz * oz;
    let (wx, wy, wz) = (ox - nx * nd, oy - ny * nd, oz - nz * nd);
    let wl2 = 0.0 + (wx * wx + wy * wy + wz * wz);
    let r = (len2 / wl2).sqrt();
    let keep = len2 == 0.0;
    let proj = wl2 > 0.0;
    [
        select(keep, ox, select(proj, wx * r, 0.0)),
        select(keep, oy, select(proj, wy * r, 0.0)),
        select(keep, oz, select(proj, wz * r, 0.0)),
    ]
}

/// [`rotate_into_plane`] with an early return for a zero vector: the same result, for the
/// general kernel, where many contacts carry no shear history (a new contact, a law
/// without friction) and the branch-free form's root and division would be paid for nothing
/// (measured: 1.9 % of all instructions of a moist agglomerate).
#[inline(always)]
pub fn rotate_into_plane_lazy(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let len2 = 0.0 + (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if len2 == 0.0 {
        v
    } else {
        rotate_into_plane(v, n)
    }
}

/// One step of the vector no-slip law (`SET TANgential NOSLIP`, the law of the contact
/// kernels): the spring `T = T_old − k_t Δδ` with `k_t = 8 G* a` (3.93)–(3.94), (5.18),
/// capped at `|T| ≤ μ P_e` along its own direction (`P_e = P + 2 P_c` with adhesion, (3.103);
/// a tensile `P_e` gives no capacity). `t_old` is the force of the last step already rotated
/// into the contact plane, `dd` the step's tangential displacement of B relative to A
/// (the force is the one on B). Returns the new force, the work done on the spring over the
/// step `−½ (T_old + T)·Δδ` and its stored energy `|T|²/(2 k_t)`: the friction loss is
/// `work − Δstored`. Branch-free, for both kernels.
#[inline(always)]
pub fn noslip_spring(t_old: [f64; 3], dd: [f64; 3], kt: f64, mu: f64, pe: f64) -> NoSlipStep {
    let [tx, ty, tz] = t_old;
    let [ddx, ddy, ddz] = dd;
    let (fx0, fy0, fz0) = (tx - ddx * kt, ty - ddy * kt, tz - ddz * kt);
    let cap = mu * pe.max(0.0);
    let fl2 = 0.0 + (fx0 * fx0 + fy0 * fy0 + fz0 * fz0);
    let scale = select(fl2 > cap * cap, cap / fl2.sqrt(), 1.0);
    let (fx, fy, fz) = (fx0 * scale, fy0 * scale, fz0 * scale);
    let (sx, sy, sz) = (tx + fx, ty + fy, tz + fz);
    let work = -0.5 * (sx * ddx + sy * ddy + sz * ddz);
    let energy = select(
        kt > 0.0,
        (0.0 + (fx * fx + fy * fy + fz * fz)) / (2.0 * kt),
        0.0,
    );
    NoSlipStep {
        force: [fx, fy, fz],
        work,
        energy,
        slid: fl2 > cap * cap,
    }
}

/// What [`noslip_spring`] gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoSlipStep {
    /// The new tangential force on B.
    pub force: [f64; 3],
    /// Work done on the spring over the step.
    pub work: f64,
    /// Energy stored in the spring.
    pub energy: f64,
    /// The spring reached its cap this step (the contact slides).
    pub slid: bool,
}

#[inline(always)]
fn select(c: bool, a: f64, b: f64) -> f64 {
    if c { a } else { b }
}

/// Linear "Mindlin no-slip + Coulomb" law: `ΔT = 8 G* a Δδ` (Lian 1994 (3.93)–(3.94), (5.18)),
/// capped at `|T| ≤ μ P_e` keeping the sign, `P_e = P + 2P_c` with adhesion (3.103), `P` without.
///
/// Ledger: below the cap no loss, the work goes to `stored` (equal to the spring energy
/// `T²/(2k_t) = T²/(16 G* a)` (3.96) while `a` is constant; an incremental spring whose stiffness
/// changes is not conservative, and that difference stays in `stored`). At the cap `stored` is
/// re-synchronised to `T²/(16 G* a)` and `dissipated_slip = work − Δstored`, which is
/// `μ P_e |Δδ|` (minus the elastic part of the step) at constant `P`.
pub fn noslip_coulomb(state: &mut TangentialState, inp: &TangentialInput) -> TangentialOutput {
    sanitize_state(state);
    let p = params(inp);
    let pe = if p.pc > 0.0 {
        p.p_new + 2.0 * p.pc
    } else {
        p.p_new
    };
    let cap = p.mu * pe;
    if !(p.a > 0.0 && p.g > 0.0 && cap > 0.0 && cap.is_finite()) {
        return no_capacity(state, p.dd);
    }
    let kn = 8.0 * p.g * p.a;
    let t_old = state.t;
    let e_old = state.stored;
    let t_trial = t_old + kn * p.dd;
    if t_trial.abs() < cap {
        let work = 0.5 * (t_old + t_trial) * p.dd;
        state.t = t_trial;
        state.stored = e_old + work;
        state.clear_memory(t_trial);
        return TangentialOutput {
            dissipated_slip: 0.0,
            sliding: false,
            kt: kn,
            work,
        };
    }
    let sg = sign_or(t_trial, p.dd);
    let t_new = sg * cap;
    let work = capped_work(t_old, t_trial, t_new, p.dd);
    let diss = sync(state, e_old, work, cap * cap / (2.0 * kn));
    state.t = t_new;
    state.clear_memory(sg);
    TangentialOutput {
        dissipated_slip: diss,
        sliding: true,
        kt: 0.0,
        work,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Glass-like spheres: E = 70 GPa, ν = 0.3, R = 100 µm each, μ = 0.3.
    const E: f64 = 70e9;
    const NU: f64 = 0.3;
    const R_STAR: f64 = 50e-6;
    const MU: f64 = 0.3;

    fn e_star() -> f64 {
        E / (2.0 * (1.0 - NU * NU))
    }
    fn g_star() -> f64 {
        let g = E / (2.0 * (1.0 + NU));
        g / (2.0 * (2.0 - NU))
    }
    fn hertz_a(p: f64) -> f64 {
        (3.0 * p.max(0.0) * R_STAR / (4.0 * e_star())).cbrt()
    }
    fn inp(p_old: f64, p_new: f64, a: f64, dd: f64) -> TangentialInput {
        TangentialInput {
            g_star: g_star(),
            mu: MU,
            a,
            p_old,
            p_new,
            pc: 0.0,
            e_star: e_star(),
            d_delta: dd,
        }
    }
    /// (5.19)–(5.21): the rotated shear vector lies in the new plane with its old length; a
    /// vector in the plane is unchanged, one along the normal vanishes, zero stays zero.
    #[test]
    fn rotation_into_the_contact_plane() {
        let n = [0.0, 0.6, 0.8];
        let v = [3.0, 4.0, -1.0];
        let r = rotate_into_plane(v, n);
        let dot = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
        let len = |x: [f64; 3]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        assert!(dot.abs() < 1e-15, "{dot}");
        assert!((len(r) - len(v)).abs() < 1e-14 * len(v));
        // The projection's direction: v − n (n·v) = (3, 4 − 0.6·1.6, −1 − 0.8·1.6).
        let w = [3.0, 4.0 - 0.96, -1.0 - 1.28];
        let k = len(v) / len(w);
        for c in 0..3 {
            assert!((r[c] - w[c] * k).abs() < 1e-14);
        }
        let inplane = [0.0, 0.8, -0.6];
        assert_eq!(rotate_into_plane(inplane, n), inplane);
        assert_eq!(rotate_into_plane([0.0, 1.2, 1.6], n), [0.0; 3]);
        assert_eq!(rotate_into_plane([0.0; 3], n), [0.0; 3]);
        for v in [v, inplane, [0.0, 1.2, 1.6], [0.0; 3], [1e-170, 0.0, 0.0]] {
            assert_eq!(rotate_into_plane_lazy(v, n), rotate_into_plane(v, n));
        }
    }

    /// The vector no-slip law: below the cap T = T_old − 8 G* a Δδ, stored T²/(2 k_t) and no
    /// loss from rest; at the cap |T| = μ P_e along the trial force, and the loss is the work
    /// minus the change of stored energy; a tensile P_e carries nothing. Along one direction
    /// it gives the force of the scalar law [`noslip_coulomb`].
    #[test]
    fn vector_noslip_spring_closed_forms() {
        let (g, a, p) = (g_star(), 5e-6, 0.01);
        let kt = 8.0 * g * a;
        // Elastic from rest: T = −k_t Δδ, work = stored = k_t |Δδ|²/2.
        let dd = [1e-9, -2e-9, 0.0];
        let st = noslip_spring([0.0; 3], dd, kt, MU, p);
        for c in 0..3 {
            assert!((st.force[c] + kt * dd[c]).abs() <= 1e-15 * kt * 2e-9);
        }
        let d2 = 1e-18 + 4e-18;
        assert!((st.energy - 0.5 * kt * d2).abs() < 1e-12 * st.energy);
        assert!((st.work - st.energy).abs() < 1e-12 * st.energy);
        // Far beyond the cap: |T| = μ P along the trial direction.
        let big = [1e-5, 0.0, 0.0];
        let st = noslip_spring([0.0; 3], big, kt, MU, p);
        assert!((st.force[0] + MU * p).abs() < 1e-15);
        assert_eq!(st.force[1], 0.0);
        // The loss of that step: work − stored > 0.
        assert!(st.work - st.energy > 0.0);
        // No capacity under tension.
        let st = noslip_spring([1e-3, 0.0, 0.0], big, kt, MU, -p);
        assert_eq!(st.force, [0.0; 3]);
        // Collinear steps against the scalar law (force on B = −T of the contact).
        let mut state = TangentialState::default();
        let mut t = [0.0; 3];
        for k in 0..40 {
            let h = if k < 25 { 2e-9 } else { -3e-9 };
            let sc = noslip_coulomb(&mut state, &inp(p, p, a, h));
            let _ = sc;
            t = noslip_spring(t, [h, 0.0, 0.0], kt, MU, p).force;
            assert!(
                (t[0] + state.t).abs() <= 1e-12 * state.t.abs().max(1e-12),
                "step {k}: vector {} scalar {}",
                t[0],
                state.t
            );
        }
    }

    /// Virgin Mindlin loading (3.107): T(δ).
    fn t_load(mu_p: f64, a: f64, delta: f64) -> f64 {
        let x = 1.0 - 16.0 * g_star() * a * delta / (3.0 * mu_p);
        mu_p * (1.0 - x.max(0.0).powf(1.5))
    }
    /// Branch from (T_r, δ_r) in direction d ((A.25)/(A.26), (A.37)/(A.38)): T(δ).
    fn t_branch(mu_p: f64, a: f64, t_r: f64, delta_r: f64, d: f64, delta: f64) -> f64 {
        let x = 1.0 - 8.0 * g_star() * a * d * (delta - delta_r) / (3.0 * mu_p);
        t_r + d * 2.0 * mu_p * (1.0 - x.max(0.0).powf(1.5))
    }
    /// Mindlin et al. (1951) full-cycle (±T*) loop energy, Lian (A.1).
    fn loop_energy(mu_p: f64, a: f64, t_star: f64) -> f64 {
        let x = 1.0 - t_star / mu_p;
        9.0 * mu_p * mu_p / (10.0 * g_star() * a)
            * (1.0 - x.powf(5.0 / 3.0) - 5.0 * t_star / (6.0 * mu_p) * (1.0 + x.powf(2.0 / 3.0)))
    }

    struct Run {
        st: TangentialState,
        diss: f64,
        work: f64,
    }
    impl Run {
        fn new() -> Self {
            Run {
                st: TangentialState::default(),
                diss: 0.0,
                work: 0.0,
            }
        }
        fn step(&mut self, i: &TangentialInput) -> TangentialOutput {
            let o = mindlin_deresiewicz(&mut self.st, i);
            assert!(o.dissipated_slip >= 0.0 && o.dissipated_slip.is_finite());
            assert!(o.work.is_finite() && o.kt.is_finite() && self.st.t.is_finite());
            self.diss += o.dissipated_slip;
            self.work += o.work;
            o
        }
        fn ledger_ok(&self) -> bool {
            let lhs = self.work;
            let rhs = self.st.stored + self.diss;
            (lhs - rhs).abs() <= 1e-9 * (lhs.abs() + self.diss + self.st.stored.abs()) + 1e-30
        }
    }

    #[test]
    fn monotonic_loading_matches_3_107_and_converges() {
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let delta_s = 3.0 * mu_p / (16.0 * g_star() * a);
        let mut errs = Vec::new();
        for &m in &[10usize, 100, 1000] {
            let n = 20 * m;
            let h = delta_s / n as f64;
            let mut run = Run::new();
            let mut max_rel: f64 = 0.0;
            for k in 1..=n {
                let o = run.step(&inp(p, p, a, h));
                assert!(run.st.t <= mu_p * (1.0 + 1e-12));
                assert!(o.kt <= 8.0 * g_star() * a * (1.0 + 1e-12));
                if k % m == 0 {
                    let exact = t_load(mu_p, a, k as f64 * h);
                    max_rel = max_rel.max((run.st.t - exact).abs() / exact);
                }
            }
            assert!(run.ledger_ok());
            errs.push(max_rel);
        }
        println!(
            "monotonic loading, max rel. error at 20 points for 200/2000/20000 steps: {errs:?}"
        );
        assert!(errs[2] < 0.005, "{errs:?}");
        assert!(
            errs[1] < errs[0] && errs[2] < errs[1],
            "no convergence: {errs:?}"
        );
        // Then sliding: dissipation per step is exactly μP|Δδ| and T stays at μP.
        let mut run = Run::new();
        let h = delta_s / 1000.0;
        for _ in 0..1100 {
            run.step(&inp(p, p, a, h));
        }
        for _ in 0..50 {
            let o = run.step(&inp(p, p, a, h));
            assert!(o.sliding);
            assert_eq!(run.st.t, mu_p);
            assert!((o.dissipated_slip - mu_p * h).abs() < 1e-12 * mu_p * h);
        }
        assert!((run.st.stored - sliding_energy(g_star(), MU, p, a)).abs() < 1e-15);
        assert!(run.ledger_ok());
    }

    #[test]
    fn closed_loop_follows_mindlin_and_dissipates_a1() {
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let t_star = 0.6 * mu_p;
        let delta1 =
            3.0 * mu_p / (16.0 * g_star() * a) * (1.0 - (1.0 - t_star / mu_p).powf(2.0 / 3.0));
        let n = 2000;
        let h = delta1 / n as f64;
        let mut run = Run::new();
        let mut delta = 0.0;
        for _ in 0..n {
            run.step(&inp(p, p, a, h));
            delta += h;
        }
        let t1 = run.st.t;
        assert!((t1 - t_star).abs() < 0.005 * t_star, "{t1} {t_star}");
        let d_load = run.diss;
        // (A.20) integrated: 3μ²P²/(16G*a) [1/5 − θ0² + θ0³ − θ0⁵/5].
        let th0 = (1.0 - t_star / mu_p).cbrt();
        let a_load = 3.0 * mu_p * mu_p / (16.0 * g_star() * a)
            * (0.2 - th0.powi(2) + th0.powi(3) - th0.powi(5) / 5.0);
        assert!((d_load - a_load).abs() < 0.01 * a_load, "{d_load} {a_load}");
        // Stored energy after loading vs the exact Mindlin field energy.
        let u_exact = mindlin_state_energy(&run.st, g_star(), MU, p, a);
        assert!((run.st.stored - u_exact).abs() < 0.01 * u_exact);
        let w_before = run.work;
        let diss_before = run.diss;
        // Unload to −δ1: (A.25)/(A.26).
        let mut max_err: f64 = 0.0;
        for _ in 0..2 * n {
            run.step(&inp(p, p, a, -h));
            delta -= h;
            assert_eq!(run.st.path(), 1);
            let ex = t_branch(mu_p, a, t1, delta1, -1.0, delta);
            max_err = max_err.max((run.st.t - ex).abs() / t_star);
        }
        assert!(max_err < 0.01, "unloading error {max_err}");
        let t2 = run.st.t;
        assert!((t2 + t_star).abs() < 0.01 * t_star);
        let u_exact = mindlin_state_energy(&run.st, g_star(), MU, p, a);
        assert!((run.st.stored - u_exact).abs() < 0.01 * u_exact);
        // Reload to +δ1: (A.37)/(A.38).
        max_err = 0.0;
        for _ in 0..2 * n {
            run.step(&inp(p, p, a, h));
            delta += h;
            let ex = t_branch(mu_p, a, t2, -delta1, 1.0, delta);
            max_err = max_err.max((run.st.t - ex).abs() / t_star);
        }
        assert!(max_err < 0.01, "reloading error {max_err}");
        // The loop closes.
        assert!((run.st.t - t1).abs() < 0.01 * t_star, "{} {}", run.st.t, t1);
        let cycle = run.diss - diss_before;
        let a1 = loop_energy(mu_p, a, t_star);
        println!(
            "loop: dissipated {cycle:e} J, (A.1) {a1:e} J, rel {:e}",
            cycle / a1 - 1.0
        );
        assert!((cycle - a1).abs() < 0.01 * a1, "{cycle} {a1}");
        // Work around the loop = loop area = dissipation (stored returns to its value).
        let loop_work = run.work - w_before;
        assert!((loop_work - a1).abs() < 0.01 * a1);
        assert!(run.ledger_ok());
        // Continue: memory erased at T1, then the virgin curve (3.107).
        for _ in 0..n {
            run.step(&inp(p, p, a, h));
            delta += h;
        }
        assert_eq!(run.st.n_tp, 0);
        let ex = t_load(mu_p, a, delta);
        assert!((run.st.t - ex).abs() < 0.01 * ex, "{} {ex}", run.st.t);
    }

    #[test]
    fn half_loop_is_half_of_a1() {
        // (A.1) is the full ±T* cycle: unloading alone dissipates exactly half of it.
        let p = 0.02;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let t_star = 0.9 * mu_p;
        let delta1 =
            3.0 * mu_p / (16.0 * g_star() * a) * (1.0 - (1.0 - t_star / mu_p).powf(2.0 / 3.0));
        let n = 4000;
        let h = delta1 / n as f64;
        let mut run = Run::new();
        for _ in 0..n {
            run.step(&inp(p, p, a, h));
        }
        let d0 = run.diss;
        for _ in 0..2 * n {
            run.step(&inp(p, p, a, -h));
        }
        let half = run.diss - d0;
        let a1 = loop_energy(mu_p, a, run.st.tp[0]);
        assert!((half - 0.5 * a1).abs() < 0.01 * a1, "{half} {a1}");
    }

    #[test]
    fn nested_inner_loop_rejoins_outer_branch() {
        // Masing memory: load to 0.8μP, unload to −0.2μP, reload to 0.5μP, unload again. After
        // passing T2 = −0.2μP the force follows the outer unloading branch from T1.
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let k = 8.0 * g_star() * a;
        let h = mu_p / k / 2000.0;
        let mut run = Run::new();
        let mut delta = 0.0;
        while run.st.t < 0.8 * mu_p {
            run.step(&inp(p, p, a, h));
            delta += h;
        }
        let (t1, d1) = (run.st.t, delta);
        while run.st.t > -0.2 * mu_p {
            run.step(&inp(p, p, a, -h));
            delta -= h;
        }
        assert_eq!(run.st.path(), 1);
        while run.st.t < 0.5 * mu_p {
            run.step(&inp(p, p, a, h));
            delta += h;
        }
        assert_eq!(run.st.path(), 2);
        let u_exact = mindlin_state_energy(&run.st, g_star(), MU, p, a);
        assert!((run.st.stored - u_exact).abs() < 0.01 * u_exact);
        let mut checked = 0;
        while delta > -d1 * 0.9 {
            run.step(&inp(p, p, a, -h));
            delta -= h;
            if run.st.t < -0.3 * mu_p {
                assert_eq!(run.st.n_tp, 1, "inner loop erased");
                let ex = t_branch(mu_p, a, t1, d1, -1.0, delta);
                assert!((run.st.t - ex).abs() < 0.01 * mu_p, "{} {ex}", run.st.t);
                checked += 1;
            }
        }
        assert!(checked > 100);
        let u_exact = mindlin_state_energy(&run.st, g_star(), MU, p, a);
        assert!((run.st.stored - u_exact).abs() < 0.01 * u_exact);
        assert!(run.ledger_ok());
    }

    #[test]
    fn state_energy_kernel_checks() {
        // Virgin loading: U = 9μ²P²/(16G*a)(2/15 − θ³/3 + θ⁵/5); small T: T²/(16G*a).
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        for &f in &[1e-3, 0.3, 0.7, 1.0] {
            let st = TangentialState {
                t: f * mu_p,
                sense: 1,
                ..Default::default()
            };
            let th = (1.0 - f).cbrt();
            let ex = 9.0 * mu_p * mu_p / (16.0 * g_star() * a)
                * (2.0 / 15.0 - th.powi(3) / 3.0 + th.powi(5) / 5.0);
            let u = mindlin_state_energy(&st, g_star(), MU, p, a);
            // (Cancellation: the relative accuracy is about 1e-16 / (T/μP)².)
            assert!((u - ex).abs() < 1e-8 * ex, "{f} {u} {ex}");
        }
        let st = TangentialState {
            t: 1e-3 * mu_p,
            sense: 1,
            ..Default::default()
        };
        let u = mindlin_state_energy(&st, g_star(), MU, p, a);
        // Small T: U = T²/(16G*a) (1 + t/9 + …), t = T/(μP) (no-slip spring (3.96)).
        let lin = st.t * st.t / (16.0 * g_star() * a) * (1.0 + 1e-3 / 9.0);
        assert!((u - lin).abs() < 1e-5 * lin, "{u} {lin}");
        // Unloaded to −T1 is the mirror of the virgin state at T1.
        let mut st = TangentialState {
            t: -0.5 * mu_p,
            sense: 1,
            n_tp: 1,
            ..Default::default()
        };
        st.tp[0] = 0.5 * mu_p;
        let v = TangentialState {
            t: 0.5 * mu_p,
            sense: 1,
            ..Default::default()
        };
        let (u1, u2) = (
            mindlin_state_energy(&st, g_star(), MU, p, a),
            mindlin_state_energy(&v, g_star(), MU, p, a),
        );
        assert!((u1 - u2).abs() < 1e-9 * u2);
    }

    #[test]
    fn proportional_loading_below_mu_does_not_slip() {
        // T and P increase together with ΔT/ΔP = 0.5μ: c_j = a, no dissipation, ΔT = 8G*aΔδ.
        let p0 = 0.005;
        let mut run = Run::new();
        // First a constant-P tangential preload with slip.
        let a0 = hertz_a(p0);
        let h0 = MU * p0 / (8.0 * g_star() * a0) / 1000.0;
        while run.st.t < 0.3 * MU * p0 {
            run.step(&inp(p0, p0, a0, h0));
        }
        let diss0 = run.diss;
        assert!(diss0 > 0.0);
        let t0 = run.st.t;
        let ratio = 0.5 * MU;
        let n = 5000;
        let dp = 2.0 * p0 / n as f64;
        let mut p = p0;
        for _ in 0..n {
            let a = hertz_a(p + dp);
            let dd = ratio * dp / (8.0 * g_star() * a);
            let o = run.step(&inp(p, p + dp, a, dd));
            assert_eq!(o.dissipated_slip, 0.0);
            assert!((o.kt - 8.0 * g_star() * a).abs() < 1e-9 * o.kt);
            assert!(!o.sliding);
            p += dp;
        }
        assert_eq!(run.diss, diss0);
        let ex = t0 + ratio * (p - p0);
        assert!((run.st.t - ex).abs() < 1e-9 * ex);
        // With frozen tractions the true Mindlin–Deresiewicz energy equals the work done.
        assert!(run.ledger_ok());
    }

    #[test]
    fn proportional_loading_above_mu_slips_within_cap() {
        let p0 = 0.005;
        let mut run = Run::new();
        let ratio = 2.0 * MU;
        let n = 4000;
        let dp = p0 / n as f64;
        let mut p = p0;
        let mut slipped = false;
        for _ in 0..n {
            let a = hertz_a(p + dp);
            let dd = ratio * dp / (8.0 * g_star() * a);
            let o = run.step(&inp(p, p + dp, a, dd));
            slipped |= o.dissipated_slip > 0.0;
            assert!(run.st.t <= MU * (p + dp) * (1.0 + 1e-12));
            p += dp;
        }
        assert!(slipped);
        assert!(run.ledger_ok());
    }

    #[test]
    fn decreasing_normal_force_at_fixed_delta() {
        // Δδ = 0 and P falls: (3.109) gives ΔT = μ(1−θ)ΔP < 0, with (A.53) loss ≥ 0; T ≤ μP.
        let p0 = 0.01;
        let a0 = hertz_a(p0);
        let mut run = Run::new();
        let h = MU * p0 / (8.0 * g_star() * a0) / 1000.0;
        while run.st.t < 0.7 * MU * p0 {
            run.step(&inp(p0, p0, a0, h));
        }
        let t_start = run.st.t;
        let n = 2000;
        let mut p = p0;
        let dp = -0.999 * p0 / n as f64;
        let mut slid = false;
        for _ in 0..n {
            let o = run.step(&inp(p, p + dp, hertz_a(p + dp), 0.0));
            p += dp;
            assert!(run.st.t <= MU * p * (1.0 + 1e-12));
            assert!(run.st.t <= t_start);
            slid |= o.sliding;
        }
        assert!(slid);
        assert!(run.ledger_ok());
        // Contact lost: P = 0 releases everything.
        let o = run.step(&inp(p, 0.0, 0.0, 0.0));
        assert_eq!(run.st.t, 0.0);
        assert!(o.dissipated_slip >= 0.0);
        assert!(run.ledger_ok());
    }

    #[test]
    fn sliding_with_growing_normal_force() {
        // Sliding while P grows: T = μP_new every step; loss = work − Δ(3μ²P²/(40G*a)) > 0.
        let p0 = 0.01;
        let a0 = hertz_a(p0);
        let mut run = Run::new();
        let k = 8.0 * g_star() * a0;
        let h = MU * p0 / k / 200.0;
        for _ in 0..400 {
            run.step(&inp(p0, p0, a0, h));
        }
        assert!((run.st.t - MU * p0).abs() < 1e-15);
        let mut p = p0;
        for _ in 0..500 {
            let pn = p * 1.0005;
            let (ao, an) = (hertz_a(p), hertz_a(pn));
            let s_old = run.st.stored;
            let o = run.step(&inp(p, pn, an, h));
            assert!(o.sliding);
            assert_eq!(run.st.t, MU * pn);
            // The force rises with the cap from μP to μP_new over the step (trapezoid).
            let w = 0.5 * MU * (p + pn) * h;
            assert!((o.work - w).abs() < 1e-12 * w, "{} {w}", o.work);
            let du = sliding_energy(g_star(), MU, pn, an) - sliding_energy(g_star(), MU, p, ao);
            assert!((s_old - sliding_energy(g_star(), MU, p, ao)).abs() < 1e-20);
            assert!((o.dissipated_slip - (w - du)).abs() < 1e-9 * o.dissipated_slip);
            // Hertz a ∝ P^{1/3}: ΔU ≈ μ²PΔP/(8G*a).
            let approx = MU * MU * p * (pn - p) / (8.0 * g_star() * ao);
            assert!((du - approx).abs() < 2e-3 * approx);
            p = pn;
        }
        assert!(run.ledger_ok());
    }

    #[test]
    fn reversal_from_sliding_is_elastic_then_micro_slip() {
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let k = 8.0 * g_star() * a;
        let h = mu_p / k / 500.0;
        let mut run = Run::new();
        for _ in 0..1000 {
            run.step(&inp(p, p, a, h));
        }
        assert_eq!(run.st.n_tp, 0);
        let o = run.step(&inp(p, p, a, -h));
        assert_eq!(run.st.path(), 1);
        assert_eq!(run.st.t1(), mu_p);
        assert!((run.st.t - (mu_p - k * h)).abs() < 1e-12 * mu_p);
        assert_eq!(o.dissipated_slip, 0.0); // first step: θ = 1 exactly
        let o = run.step(&inp(p, p, a, -h));
        assert!(o.kt < k && o.dissipated_slip > 0.0);
        // Unloading all the way to −μP: slides in the negative sense.
        for _ in 0..2000 {
            run.step(&inp(p, p, a, -h));
        }
        assert_eq!(run.st.t, -mu_p);
        assert_eq!(run.st.sense, -1);
        assert!(run.ledger_ok());
    }

    fn adhesive_inp(p_old: f64, p_new: f64, pc: f64, a: f64, dd: f64) -> TangentialInput {
        TangentialInput {
            pc,
            ..inp(p_old, p_new, a, dd)
        }
    }
    /// JKR contact radius for load P.
    fn jkr_a(p: f64, pc: f64) -> f64 {
        (3.0 * R_STAR / (4.0 * e_star()) * (p + 2.0 * pc + (4.0 * p * pc + 4.0 * pc * pc).sqrt()))
            .cbrt()
    }

    #[test]
    fn p2_intersection() {
        let pc = 1e-4;
        let [lo, hi] = peel_slide_intersection(g_star(), e_star(), MU, pc).unwrap();
        for p2 in [lo, hi] {
            let tp = peeling_force(g_star(), e_star(), p2, pc);
            assert!((tp - MU * (p2 + 2.0 * pc)).abs() < 1e-9 * tp);
        }
        assert!(hi > 30.0 * pc && lo < 0.0 && lo > -pc);
    }

    #[test]
    fn adhesion_smooth_transition_above_p2() {
        let pc = 1e-4;
        let [_, p2] = peel_slide_intersection(g_star(), e_star(), MU, pc).unwrap();
        let p = 1.5 * p2;
        let a = jkr_a(p, pc);
        let pe = p + 2.0 * pc;
        let mu_pe = MU * pe;
        let tp = peeling_force(g_star(), e_star(), p, pc);
        assert!(tp < mu_pe);
        let k = 8.0 * g_star() * a;
        let n_peel = 3000;
        let h = tp / k / n_peel as f64 * 1.0000001;
        let mut run = Run::new();
        let mut delta = 0.0;
        // Savkoor–Briggs: T = 8G*aδ exactly, no loss, until T_p.
        while !run.st.peeled {
            let o = run.step(&adhesive_inp(p, p, pc, a, h));
            delta += h;
            if !run.st.peeled {
                assert_eq!(o.dissipated_slip, 0.0);
                assert!((run.st.t - k * delta).abs() < 1e-9 * run.st.t);
            }
        }
        // Then the virgin Mindlin curve with P_e, shifted to start at (δ_p, T_p).
        let delta_p = tp / k;
        let x_p = 3.0 * mu_pe / (16.0 * g_star() * a) * (1.0 - (1.0 - tp / mu_pe).powf(2.0 / 3.0));
        let mut max_err: f64 = 0.0;
        let mut slid = false;
        let mut delta_slide = 0.0;
        let mut last_diss = 0.0;
        for _ in 0..20 * n_peel {
            let o = run.step(&adhesive_inp(p, p, pc, a, h));
            delta += h;
            assert!(run.st.t <= mu_pe * (1.0 + 1e-12));
            if o.sliding {
                assert_eq!(run.st.t, mu_pe);
                if !slid {
                    delta_slide = delta;
                }
                slid = true;
                last_diss = o.dissipated_slip;
            } else {
                let ex = t_load(mu_pe, a, delta - delta_p + x_p);
                max_err = max_err.max((run.st.t - ex).abs() / ex);
            }
        }
        assert!(slid);
        assert!(max_err < 0.005, "{max_err}");
        assert!(run.ledger_ok());
        assert!(run.st.peeled);
        // Steady sliding at constant P: loss = μ(P + 2P_c)|Δδ| per step.
        assert!((last_diss - mu_pe * h).abs() < 1e-9 * mu_pe * h);
        assert_eq!(run.st.stored, sliding_energy(g_star(), MU, pe, a));
        // Independent total: work of the analytic curve (linear to T_p, Mindlin (3.107) to
        // μP_e, then sliding) minus the sliding-field energy.
        let th_p = (1.0 - tp / mu_pe).cbrt();
        let w_md =
            3.0 * mu_pe * mu_pe / (8.0 * g_star() * a) * (th_p.powi(2) / 2.0 - th_p.powi(5) / 5.0);
        let delta_s = delta_p + 3.0 * mu_pe / (16.0 * g_star() * a) * th_p * th_p;
        assert!(
            (delta_slide - delta_s).abs() < 0.01 * delta_s,
            "{delta_slide} {delta_s}"
        );
        let w_total = tp * tp / (2.0 * k) + w_md + mu_pe * (delta - delta_s);
        let ex = w_total - sliding_energy(g_star(), MU, pe, a);
        assert!((run.diss - ex).abs() < 0.005 * ex, "{} {ex}", run.diss);
    }

    #[test]
    fn adhesion_drop_below_p2() {
        let pc = 1e-4;
        let p = 0.0;
        let a = jkr_a(p, pc);
        let pe = p + 2.0 * pc;
        let mu_pe = MU * pe;
        let tp = peeling_force(g_star(), e_star(), p, pc);
        assert!(tp > mu_pe);
        let k = 8.0 * g_star() * a;
        let h = tp / k / 1000.0 / 0.99999;
        let mut run = Run::new();
        let mut max_t: f64 = 0.0;
        let mut drop = None;
        for _ in 0..1100 {
            let before = (run.st.t, run.st.stored);
            let o = run.step(&adhesive_inp(p, p, pc, a, h));
            max_t = max_t.max(run.st.t);
            if o.sliding && drop.is_none() {
                drop = Some((before, o));
            }
        }
        // T exceeded μP_e before peeling, reached T_p, then fell to μP_e.
        assert!(max_t > mu_pe && max_t < tp);
        assert_eq!(run.st.t, mu_pe);
        let ((t_b, s_b), o) = drop.unwrap();
        // Released energy: stored spring energy at T_p (plus the step's work) minus the sliding
        // field energy 3(μP_e)²/(40G*a).
        let dd_p = (tp - t_b) / k;
        let w = 0.5 * (t_b + tp) * dd_p + mu_pe * (h - dd_p);
        let ex = s_b + w - sliding_energy(g_star(), MU, pe, a);
        assert!(
            (o.dissipated_slip - ex).abs() < 1e-9 * ex,
            "{} {ex}",
            o.dissipated_slip
        );
        assert!((s_b + 0.5 * (t_b + tp) * dd_p - tp * tp / (2.0 * k)).abs() < 1e-3 * tp * tp / k);
        assert!(run.ledger_ok());
    }

    #[test]
    fn adhesion_tensile_contact() {
        // P = −0.5 P_c: P_e = 1.5 P_c > 0, tangential force still carried.
        let pc = 1e-4;
        let p = -0.5 * pc;
        let a = jkr_a(p, pc);
        let k = 8.0 * g_star() * a;
        let mut run = Run::new();
        let h = MU * 1.5 * pc / k / 100.0;
        for _ in 0..1000 {
            run.step(&adhesive_inp(p, p, pc, a, h));
            assert!(run.st.t.is_finite());
        }
        assert!(run.st.peeled);
        assert!((run.st.t - MU * 1.5 * pc).abs() < 1e-12);
        assert!(run.ledger_ok());
    }

    #[test]
    fn degenerate_inputs_never_nan() {
        let p = 0.01;
        let a = hertz_a(p);
        let cases = [
            inp(p, p, 0.0, 1e-6),
            inp(p, 0.0, a, 1e-6),
            inp(0.0, 0.0, 0.0, 0.0),
            inp(p, p, a, 1e3),
            inp(p, p, a, -1e30),
            inp(p, p, a, 0.0),
            inp(p, 1e-300, a, 1e-9),
            inp(p, -p, a, 1e-9),
            TangentialInput {
                pc: 1e-4,
                ..inp(-5e-5, -9e-5, a, 1e-7)
            },
            TangentialInput {
                pc: 1e-4,
                ..inp(-5e-5, -5e-4, a, 1e-7)
            },
            TangentialInput {
                pc: 1e-4,
                e_star: 0.0,
                ..inp(p, p, a, 1e-9)
            },
            TangentialInput {
                g_star: 0.0,
                ..inp(p, p, a, 1e-9)
            },
            TangentialInput {
                mu: 0.0,
                ..inp(p, p, a, 1e-9)
            },
            TangentialInput {
                d_delta: f64::NAN,
                ..inp(p, p, a, 0.0)
            },
            TangentialInput {
                a: f64::INFINITY,
                ..inp(p, p, a, 1e-9)
            },
        ];
        for law in [mindlin_deresiewicz, noslip_coulomb] {
            for start in 0..cases.len() {
                let mut st = TangentialState::default();
                for i in 0..3 * cases.len() {
                    let c = &cases[(start + i) % cases.len()];
                    let s_old = st.stored;
                    let o = law(&mut st, c);
                    assert!(
                        o.dissipated_slip >= 0.0 && o.dissipated_slip.is_finite(),
                        "{o:?}"
                    );
                    assert!(o.kt.is_finite() && o.kt >= 0.0);
                    assert!(o.work.is_finite());
                    assert!(st.t.is_finite() && st.stored.is_finite());
                    let cap = c.mu.max(0.0) * (c.p_new + 2.0 * c.pc);
                    assert!(st.t.abs() <= cap.max(0.0) * (1.0 + 1e-12) || !st.peeled && c.pc > 0.0);
                    let scale = s_old.abs() + st.stored.abs() + o.work.abs() + 1e-300;
                    assert!((s_old + o.work - st.stored - o.dissipated_slip).abs() <= 1e-9 * scale);
                }
            }
        }
        // Zero increment and zero force change: nothing happens.
        let mut st = TangentialState::default();
        let o = mindlin_deresiewicz(&mut st, &inp(p, p, a, 0.0));
        assert_eq!(st.t, 0.0);
        assert_eq!(o.dissipated_slip, 0.0);
        assert_eq!(o.work, 0.0);
    }

    #[test]
    fn fuzz_invariants_and_ledger() {
        let mut seed: u64 = 0x1234_5678_9abc_def0;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..24 {
            let adhesive = case % 3 == 2;
            let pc = if adhesive { 2e-3 } else { 0.0 };
            let use_md = case % 2 == 0;
            let mut st = TangentialState::default();
            let (mut work, mut diss) = (0.0, 0.0);
            let mut p: f64 = 0.01;
            for _ in 0..20000 {
                let pn = (p * (1.0 + 0.02 * (rnd() - 0.5))).max(1e-5);
                let a = hertz_a(pn.max(1e-9));
                let k = 8.0 * g_star() * a;
                let scale = MU * (pn + 2.0 * pc) / k;
                let dd = scale * 0.05 * (rnd() - 0.48);
                let i = TangentialInput {
                    pc,
                    ..inp(p, pn, a, dd)
                };
                let t_old = st.t;
                let o = if use_md {
                    mindlin_deresiewicz(&mut st, &i)
                } else {
                    noslip_coulomb(&mut st, &i)
                };
                assert!(o.dissipated_slip >= 0.0 && o.dissipated_slip.is_finite());
                assert!(st.t.is_finite() && st.stored.is_finite());
                let cap = MU * (pn + 2.0 * pc);
                if !adhesive || st.peeled || !use_md {
                    assert!(st.t.abs() <= cap * (1.0 + 1e-12), "{} {cap}", st.t);
                }
                if o.sliding {
                    assert!(st.t.abs() >= cap * (1.0 - 1e-12) || st.t == 0.0, "{t_old}");
                }
                work += o.work;
                diss += o.dissipated_slip;
                p = pn;
            }
            let rhs = st.stored + diss;
            assert!(
                (work - rhs).abs() <= 1e-9 * (work.abs() + diss + st.stored.abs()),
                "ledger {work} {rhs}"
            );
            assert!(st.turning_points().len() <= MAX_TURNING_POINTS);
        }
    }

    #[test]
    fn trial_test_is_self_consistent() {
        // (-1)^j ΔT − μΔP_e = θ [(-1)^j 8G*aΔδ − μΔP_e]: check on random slip steps.
        let mut st = TangentialState::default();
        let p = 0.01;
        let a = hertz_a(p);
        let k = 8.0 * g_star() * a;
        let h = MU * p / k / 300.0;
        for _ in 0..200 {
            mindlin_deresiewicz(&mut st, &inp(p, p, a, h));
        }
        for &(dp, dd) in &[
            (1e-4, 2.0 * h),
            (-1e-4, 0.5 * h),
            (5e-5, 0.01 * h),
            (-3e-4, -h),
        ] {
            let mut s2 = st;
            let t_old = s2.t;
            let a2 = hertz_a(p + dp);
            let k2 = 8.0 * g_star() * a2;
            let o = mindlin_deresiewicz(&mut s2, &inp(p, p + dp, a2, dd));
            if o.sliding {
                continue;
            }
            let d = if dd > 0.0 { 1.0 } else { -1.0 };
            let lhs = d * (s2.t - t_old) - MU * dp;
            let rhs = (o.kt / k2) * (d * k2 * dd - MU * dp);
            let trial_slip = d * k2 * dd - MU * dp > 0.0;
            if trial_slip {
                assert!(
                    (lhs - rhs).abs() < 1e-9 * (lhs.abs() + MU * dp.abs()),
                    "{lhs} {rhs}"
                );
                assert!(lhs > 0.0);
            } else {
                assert_eq!(o.dissipated_slip, 0.0);
            }
        }
    }

    #[test]
    fn noslip_coulomb_basics() {
        let p = 0.01;
        let a = hertz_a(p);
        let k = 8.0 * g_star() * a;
        let mu_p = MU * p;
        let h = mu_p / k / 100.0;
        let mut st = TangentialState::default();
        let (mut work, mut diss) = (0.0, 0.0);
        for i in 1..=50 {
            let o = noslip_coulomb(&mut st, &inp(p, p, a, h));
            work += o.work;
            diss += o.dissipated_slip;
            assert!((st.t - k * h * i as f64).abs() < 1e-12 * st.t);
            assert_eq!(o.kt, k);
            assert_eq!(o.dissipated_slip, 0.0);
        }
        assert!((st.stored - st.t * st.t / (2.0 * k)).abs() < 1e-12 * st.stored);
        // Elastic cycle below the cap: no loss, energy returns.
        for _ in 0..100 {
            let o = noslip_coulomb(&mut st, &inp(p, p, a, -h));
            work += o.work;
            diss += o.dissipated_slip;
        }
        assert_eq!(diss, 0.0);
        assert!((st.t + 0.5 * mu_p).abs() < 1e-9 * mu_p);
        for _ in 0..50 {
            let o = noslip_coulomb(&mut st, &inp(p, p, a, h));
            work += o.work;
            diss += o.dissipated_slip;
        }
        assert!(st.t.abs() < 1e-9 * mu_p && st.stored.abs() < 1e-9 * mu_p * mu_p / k);
        // Closed elastic cycle: the work returns (to rounding) and nothing was dissipated.
        assert_eq!(diss, 0.0);
        assert!(work.abs() < 1e-9 * mu_p * mu_p / k);
        // To the cap, with a step that crosses it: loss = μP × (part of Δδ beyond the cap).
        for _ in 0..99 {
            noslip_coulomb(&mut st, &inp(p, p, a, h));
        }
        let t_b = st.t;
        let s_b = st.stored;
        let o = noslip_coulomb(&mut st, &inp(p, p, a, 3.5 * h));
        assert!(o.sliding);
        assert_eq!(st.t, mu_p);
        let beyond = 3.5 * h - (mu_p - t_b) / k;
        assert!((o.dissipated_slip - mu_p * beyond).abs() < 1e-9 * mu_p * h);
        assert!((st.stored - mu_p * mu_p / (2.0 * k)).abs() < 1e-12 * st.stored);
        assert!((s_b + o.work - st.stored - o.dissipated_slip).abs() < 1e-20);
        for _ in 0..10 {
            let o = noslip_coulomb(&mut st, &inp(p, p, a, h));
            assert!((o.dissipated_slip - mu_p * h).abs() < 1e-12 * mu_p * h);
        }
        // Reversal from the cap is elastic with k = 8G*a.
        let o = noslip_coulomb(&mut st, &inp(p, p, a, -h));
        assert!(!o.sliding && (st.t - (mu_p - k * h)).abs() < 1e-12 * mu_p);
        // Adhesion raises the cap to μ(P + 2P_c).
        let pc = 1e-3;
        let mut st = TangentialState::default();
        for _ in 0..1000 {
            noslip_coulomb(
                &mut st,
                &TangentialInput {
                    pc,
                    ..inp(p, p, a, h)
                },
            );
        }
        assert_eq!(st.t, MU * (p + 2.0 * pc));
    }

    #[test]
    fn decaying_oscillation_overflows_memory_gracefully() {
        // Amplitude shrinking by 0.85 per half cycle: every reversal pushes a turning point
        // (nothing is erased), so the memory overflows; the innermost branch must stay exact.
        let p = 0.01;
        let a = hertz_a(p);
        let mu_p = MU * p;
        let k = 8.0 * g_star() * a;
        let h = mu_p / k / 4000.0;
        let mut run = Run::new();
        let mut delta = 0.0;
        let mut amp = 0.9 * mu_p;
        let mut sgn = 1.0;
        for _ in 0..30 {
            let mut last = (run.st.t, delta);
            let mut steps = 0;
            while sgn * run.st.t < amp || steps == 0 {
                run.step(&inp(p, p, a, sgn * h));
                delta += sgn * h;
                if steps == 0 {
                    last = (run.st.t - sgn * k * h, delta - sgn * h);
                }
                steps += 1;
                assert!(run.st.turning_points().len() <= MAX_TURNING_POINTS);
                if run.st.n_tp > 0 && steps > 1 {
                    let ex = t_branch(mu_p, a, last.0, last.1, sgn, delta);
                    assert!(
                        (run.st.t - ex).abs() < 0.01 * amp.max(0.05 * mu_p),
                        "{} {ex}",
                        run.st.t
                    );
                }
            }
            sgn = -sgn;
            amp *= 0.85;
        }
        assert_eq!(run.st.n_tp as usize, MAX_TURNING_POINTS - 1);
        assert!(run.ledger_ok());
    }

    #[test]
    fn serde_roundtrip() {
        let mut st = TangentialState::default();
        let p = 0.01;
        let a = hertz_a(p);
        mindlin_deresiewicz(&mut st, &inp(p, p, a, 1e-9));
        mindlin_deresiewicz(&mut st, &inp(p, p, a, -1e-10));
        mindlin_deresiewicz(&mut st, &inp(p, p, a, 1e-11));
        assert_eq!(st.n_tp, 2);
        let json = serde_json::to_string(&st).unwrap();
        let back: TangentialState = serde_json::from_str(&json).unwrap();
        // (serde_json without "float_roundtrip" may differ in the last bit; bincode is exact.)
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-15 * x.abs().max(y.abs());
        assert!(close(back.t, st.t) && close(back.stored, st.stored));
        assert!(back.tp.iter().zip(st.tp.iter()).all(|(x, y)| close(*x, *y)));
        assert_eq!(
            (back.n_tp, back.sense, back.peeled),
            (st.n_tp, st.sense, st.peeled)
        );
    }
}
