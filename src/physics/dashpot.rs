//! The velocity-proportional normal forces of a contact over one leap-frog step: the
//! restitution dashpot `C α^{1/4} α'` (Tsuji et al. 1992, calibrated in
//! [`super::restitution`]), Rayleigh contact damping `β k_n α'` (Lian 1994 (5.11)) and the
//! viscous force of a liquid bridge `6πηR*² α'/S` (Lian 1994 (4.73)), integrated so that the
//! coefficient of restitution holds at the default step.
//!
//! ## Why
//! The leap-frog scheme (Lian 1994 (5.9)–(5.14)) samples the force at `t_n` from the
//! positions at `t_n` and the velocities at `t_{n−1/2}`, and applies it over
//! `[t_{n−1/2}, t_{n+1/2}]`. For the elastic force that is second order. A dashpot evaluated
//! with the lagging velocity `v_{n−1/2}` is first order; worse, `C α^{1/4}` rises like
//! `(t − t_0)^{1/4}` from the instant of first touch, so the sample at `t_n` misjudges the
//! dashpot's impulse of the step in which the contact starts by up to the whole of it,
//! depending on where in the step the contact began. At FRAction 0.2 (9–17 steps per
//! contact) the restitution came out 2–40 % low for `e = 0.1` and up to ±4 % for `e = 0.5`
//! (doc/timestep.md).
//!
//! ## The scheme
//! Write `v` for the separation rate (relative normal velocity, positive opening) at
//! `t_{n−1/2}`, `α` for the overlap at `t_n`, `m*` for the reduced mass, `F_s` for the
//! normal forces that do not depend on the velocity (Hertz or JKR, the bridge's capillary
//! force; compressive positive) and `c` for the linear viscous coefficients
//! (`β k_n + 6πηR*²/S`).
//!
//! 1. **The step's mean dashpot coefficient.** Along the step the overlap runs from
//!    `α_{n−1/2} = α + v Δt/2` to `α_{n+1/2} = α − v_n Δt/2`, `v_n` being the separation rate
//!    at `t_n`. The dashpot's impulse over that path is exactly
//!    `C ∫ α^{1/4} dα = (4/5) C (α_{n+1/2}^{5/4} − α_{n−1/2}^{5/4})` (the same integral that
//!    makes the continuous problem solvable, [`super::restitution`]), i.e. the mean of
//!    `C α_+^{1/4}` over the interval times `α'` ([`mean_quarter`]). A contact that starts
//!    within the step gets the part of the step it spends in contact, including the step
//!    before the first overlap at `t_n` (the pair is then evaluated while approaching, within
//!    half a step's travel).
//! 2. **The velocity at `t_n`** is taken implicitly, as Lian's global damping takes it
//!    ((5.9): `(v_old + v_new)/2`): `v_n = v + Δt/2 · (F_s/m* + a_o − C_t v_n/m*)`, i.e.
//!    [`midpoint_rate`], with `C_t` the total viscous coefficient and `a_o` the relative
//!    acceleration that the particles' *other* forces give the pair, estimated from the last
//!    step: `a_o = (v − v_prev)/Δt − F_prev/m*` (the change of the separation rate over the
//!    last step less what this pair's own force of that step did). For an isolated pair
//!    (a binary collision, a particle against a wall) `a_o = 0` exactly and the step is the
//!    trapezoidal rule for the viscous force; in a bed at rest `a_o` cancels `F_s/m*` and the
//!    viscous force is zero, as it must be (without `a_o` a resting contact would be
//!    softened by ~`C Δt/(2m*)`).
//! 3. Two passes: the first estimates `v_n` with the coefficient sampled at `α` and to first
//!    order in the damping (in a contact that was touching in the last step; otherwise with
//!    the mean up to `α − v Δt/2` and the implicit step), the second takes the
//!    mean over `[α_{n−1/2}, α − v_n Δt/2]` and gives the `v_n` the force uses. The force is
//!    `−C_t v_n` (then the tension clamp of the restitution model).
//!
//! The energy booking is unchanged: the ledger books ½(F_old + F_new)·v Δt with the half-step
//! velocities, which is the exact work of the scheme whatever the forces are.
//!
//! Measured on the discrete map of one contact (the tests below, 64 phases of first touch
//! within the step): at 15 steps per contact every `e` in 0.1 … 0.9 within 0.5 %; at 9 steps
//! within 1.1 % (the lagging dashpot: −38 % … +0.3 % for `e = 0.1`, ±4 % for `e = 0.5`).

/// Below this restitution a dashpot is heavy: the default step shrinks for it
/// ([`heavy_step_share`]).
pub const HEAVY_E: f64 = 0.1;

/// The restitution whose dashpot, at the default step, sets the step of a heavy one.
pub const HEAVY_REFERENCE_E: f64 = 0.2;

/// The share of the default step that a pair with a heavy dashpot (`e <` [`HEAVY_E`]) takes:
/// `ζ_ref/ζ`, `ζ_ref` being the dashpot constant of `e =` [`HEAVY_REFERENCE_E`] in the same
/// form, so that `ζ Δt` is no larger than that of an `e = 0.2` pair at the default step; 1
/// for `e ≥ 0.1` (or no dashpot). The error of the scheme is low by an amount that grows
/// with `ζ Δt` (the rebound is a small difference of large impulses): at e = 0.05 the
/// discrete map of one contact is −0.3 … −2.8 % at 9 steps per contact (the test
/// `a_heavy_dashpot_is_second_order_with_a_large_constant`), and the binary's sphere at
/// 10–30 m/s, FRAction 0.2, −0.3 … −2.7 % (doc/limits.md). `zeta_ref`: `ζ` of
/// [`HEAVY_REFERENCE_E`] in the pair's form.
pub fn heavy_step_share(e: f64, zeta: f64, zeta_ref: f64) -> f64 {
    if e < HEAVY_E && zeta > zeta_ref && zeta_ref > 0.0 {
        zeta_ref / zeta
    } else {
        1.0
    }
}

/// Mean of `max(y, 0)^{1/4}` for `y` uniform on the interval between `lo` and `hi` (either
/// order): `(4/5)(b^{5/4} − a^{5/4})/(b − a)` for `0 < a ≤ b`, written without cancellation as
/// `(4/5)(q⁴ + q³p + q²p² + qp³ + p⁴)/((q + p)(q² + p²))` with `q = b^{1/4}`, `p = a^{1/4}`
/// (exact also for `a = b`: `q`); `(4/5) b^{5/4}/(b − a)` when only `b > 0`; 0 when the
/// interval holds no positive value. Branch-free, one division (the vectorised contact
/// kernel runs it on arrays; every operation is the same in both).
#[inline(always)]
pub fn mean_quarter(lo: f64, hi: f64) -> f64 {
    let a = if lo < hi { lo } else { hi };
    let b = if lo < hi { hi } else { lo };
    let q = (if b > 0.0 { b } else { 0.0 }).sqrt().sqrt();
    let p = (if a > 0.0 { a } else { 0.0 }).sqrt().sqrt();
    let (q2, p2) = (q * q, p * p);
    let inside = a > 0.0;
    let num = if inside {
        q2 * q2 + q2 * q * p + q2 * p2 + q * p2 * p + p2 * p2
    } else {
        b * q
    };
    let den = if inside { (q + p) * (q2 + p2) } else { b - a };
    let mean = 0.8 * num / den;
    if b > 0.0 { mean } else { 0.0 }
}

/// The relative acceleration without the viscous forces, `F_s/m* + a_o` (item 2 of the
/// module doc), `a_o = (v − v_prev)/Δt − F_prev/m*` being what the other forces on the two
/// particles gave the pair in the last step (the change of its separation rate less what its
/// own force did); `a_o = 0` when the last step left no separation rate (`v_prev` not
/// finite: the pair was not evaluated with a viscous force, or the state predates it).
/// `inv_m = 1/m*`, `inv_dt = 1/Δt`.
#[inline(always)]
pub fn drive(f_static: f64, f_prev: f64, v: f64, v_prev: f64, inv_m: f64, inv_dt: f64) -> f64 {
    let with = (f_static - f_prev) * inv_m + (v - v_prev) * inv_dt;
    let without = f_static * inv_m;
    if v_prev.is_finite() { with } else { without }
}

/// What one step of the viscous normal forces needs of a contact.
#[derive(Clone, Copy, Debug)]
pub struct ViscousIn {
    /// Overlap at `t_n` (m; negative: gap).
    pub alpha: f64,
    /// Separation rate at `t_{n−1/2}` (m/s, positive opening).
    pub v: f64,
    /// `F_s/m* + a_o` (m/s²): the relative acceleration without the viscous forces
    /// ([`drive`]).
    pub drive: f64,
    /// The dashpot's constant `k = ζ sqrt(4/3 E*)`: its force is `k (s α)^{1/4} α'` with
    /// `s = m*² R*` (the `ζ sqrt(m* K) α^{1/4}` of [`super::restitution`], `K = 4/3 E* √R*`);
    /// 0: no dashpot.
    pub dash: f64,
    /// `m*² R*` (kg² m).
    pub scale: f64,
    /// The contact was touching in the last step and overlaps now: the first pass takes the
    /// coefficient at α, `dash · point` with `point = (s α)^{1/4}`, and the velocity at
    /// `t_n` to first order in the damping (otherwise the mean over the half step ahead and
    /// the implicit step).
    pub steady: bool,
    pub point: f64,
    /// Linear viscous coefficient (N·s/m): `β k_n` plus the bridge's `6πηR*²/S`.
    pub linear: f64,
    /// 1/m*.
    pub inv_m: f64,
    pub dt: f64,
}

/// The step's viscous normal forces: `(coef, v_n)` — the dashpot's coefficient over the step
/// (item 1 of the module doc) and the separation rate at `t_n` (items 2–3); the dashpot's
/// force is `−coef · v_n`, each linear term's `−c · v_n`.
#[inline(always)]
pub fn viscous_step(x: &ViscousIn) -> (f64, f64) {
    let h = 0.5 * x.dt;
    let lo = x.scale * (x.alpha + x.v * h);
    let ahead = x.v + h * x.drive;
    // First pass: an estimate of v_n for the end of the path.
    let v1 = if x.steady {
        ahead * (1.0 - h * (x.dash * x.point + x.linear) * x.inv_m)
    } else {
        let q = mean_quarter(lo, x.scale * (x.alpha - x.v * h));
        ahead / (1.0 + h * (x.dash * q + x.linear) * x.inv_m)
    };
    // Second pass: the mean over the step's path with the velocity at t_n ahead.
    let hi = x.scale * (x.alpha - v1 * h);
    let coef = x.dash * mean_quarter(lo, hi);
    let vn = ahead / (1.0 + h * (coef + x.linear) * x.inv_m);
    (coef, vn)
}

/// The tangential dashpot of the Hertz–Mindlin law as EDEM and LIGGGHTS write it (`SET
/// TANgential HM`): `C_t = ζ (2/3 m* k_t)^{1/2}` (N·s/m), with `ζ` the restitution dashpot's
/// constant of the pair ([`super::restitution`]) and `k_t` the tangential spring's stiffness.
/// The normal dashpot is `ζ (m* K)^{1/2} α^{1/4} = ζ (2/3 m* k_n)^{1/2}` with the Hertz
/// stiffness `k_n = 2E*(R*α)^{1/2} = 3/2 K α^{1/2}`, so `C_t/C_n = (k_t/k_n)^{1/2}`: EDEM's
/// `2(5/6)^{1/2} β (S m*)^{1/2}` for both, with `S_n = k_n` and `S_t = k_t` (Altair's EDEM
/// manual, "Hertz-Mindlin (no slip)"). (Our `ζ` gives the restitution exactly; EDEM's `β`
/// is its closed-form approximation.)
#[inline]
pub fn tangential_coefficient(zeta: f64, m_star: f64, k_t: f64) -> f64 {
    zeta * (2.0 / 3.0 * m_star * k_t).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::restitution::{restitution_of_zeta, zeta_for_restitution};

    /// The mean against a fine midpoint quadrature of max(y,0)^{1/4}.
    #[test]
    fn mean_quarter_is_the_mean_over_the_interval() {
        let quad = |lo: f64, hi: f64| {
            let n = 200_000;
            let w = (hi - lo) / n as f64;
            (0..n)
                .map(|k| (lo + (k as f64 + 0.5) * w).max(0.0).powf(0.25))
                .sum::<f64>()
                / n as f64
        };
        for (lo, hi) in [
            (1.0, 2.0),
            (2.0, 1.0),
            (0.5, 0.5000001),
            (-1.0, 1.0),
            (-0.1, 3.0),
            (1e-3, 5.0),
            (0.0, 1.0),
        ] {
            let m = mean_quarter(lo, hi);
            assert!(
                (m - quad(lo, hi)).abs() < 2e-6 * m,
                "{lo} {hi}: {m} vs {}",
                quad(lo, hi)
            );
        }
        // Closed forms: a point, a half-open interval, nothing in contact.
        assert_eq!(mean_quarter(16.0, 16.0), 2.0);
        assert!((mean_quarter(0.0, 16.0) - 1.6).abs() < 1e-15);
        assert!((mean_quarter(-16.0, 16.0) - 0.8).abs() < 1e-15);
        assert_eq!(mean_quarter(-2.0, -1.0), 0.0);
        assert_eq!(mean_quarter(-2.0, 0.0), 0.0);
    }

    /// One head-on impact on the discrete map of the leap-frog scheme in the dimensionless
    /// units of `restitution` (m* = 1, K = 1, approach speed 1, so D = ζ and R* = 1): `steps`
    /// steps per elastic contact (τ_c ≈ 3.218), first touch at fraction `phase` of a step.
    /// `exact`: this module's scheme; otherwise the lagging dashpot ζ α^{1/4} v_{n−1/2}.
    fn impact(zeta: f64, steps: f64, phase: f64, exact: bool) -> f64 {
        let dt = 3.218 / steps;
        let mut x = -phase * dt; // overlap at t_n
        let mut v = -1.0; // separation rate at t_{n-1/2}
        let (mut v_prev, mut f_prev) = (f64::INFINITY, 0.0);
        let mut touched = false;
        let mut was = false;
        for _ in 0..100_000 {
            let fs = x.max(0.0).powf(1.5);
            let mut f = 0.0;
            let lo_half = x - v * 0.5 * dt; // overlap half a step ahead at the lagging rate
            if exact && (x > 0.0 || (v < 0.0 && lo_half > 0.0)) {
                let (coef, vn) = viscous_step(&ViscousIn {
                    alpha: x,
                    v,
                    drive: drive(fs, f_prev, v, v_prev, 1.0, 1.0 / dt),
                    dash: zeta,
                    scale: 1.0,
                    steady: was && x > 0.0,
                    point: x.max(0.0).powf(0.25),
                    linear: 0.0,
                    inv_m: 1.0,
                    dt,
                });
                f = (fs - coef * vn).max(0.0);
                v_prev = v;
            } else if !exact && x > 0.0 {
                f = (fs - zeta * x.powf(0.25) * v).max(0.0);
            } else {
                v_prev = f64::INFINITY;
            }
            f_prev = f;
            was = x > 0.0;
            touched |= x > 0.0;
            if touched && x <= 0.0 && f == 0.0 && v > 0.0 {
                return v;
            }
            v += f * dt;
            x -= v * dt;
        }
        panic!("the contact did not end");
    }

    /// The coefficient of restitution of the discrete map against the closed form e(ζ), over
    /// 64 phases of first touch: within 1 % for e = 0.2 … 0.9 and 1.5 % for e = 0.1 at
    /// 9 steps per contact (the fewest FRAction 0.2 gives at 10 m/s in the study of
    /// doc/timestep.md), within 0.6 % at 15; the lagging dashpot misses by far more.
    #[test]
    fn restitution_holds_on_the_discrete_map_at_few_steps_per_contact() {
        for e in [0.1, 0.2, 0.3, 0.5, 0.7, 0.9] {
            let zeta = zeta_for_restitution(e);
            assert!((restitution_of_zeta(zeta) - e).abs() < 1e-12);
            for (steps, tol) in [(9.0, if e < 0.15 { 0.015 } else { 0.01 }), (15.0, 0.006)] {
                let mut worst: f64 = 0.0;
                let mut worst_lagging: f64 = 0.0;
                for k in 0..64 {
                    let phase = k as f64 / 64.0;
                    worst = worst.max((impact(zeta, steps, phase, true) / e - 1.0).abs());
                    worst_lagging =
                        worst_lagging.max((impact(zeta, steps, phase, false) / e - 1.0).abs());
                }
                assert!(
                    worst < tol,
                    "e = {e}, {steps} steps: worst relative error {worst}"
                );
                if e <= 0.5 {
                    assert!(
                        worst_lagging > 2.0 * worst,
                        "e = {e}, {steps}: {worst_lagging}"
                    );
                }
            }
        }
    }

    /// A heavy dashpot, e = 0.05 (issue 49 item 8), on the discrete map over 64 phases of first
    /// touch: the rebound is low, by an error that falls about as the step squared but with a
    /// large constant (the rebound is a small difference of large impulses): up to
    /// 2.8 % at 9 steps per contact (FRAction 0.2 gives 7.5–11 at 10–30 m/s in
    /// tests/it/restitution.rs's scene), 0.9 % at 15, 0.65 % at 18, 0.21 % at 36, always low.
    /// The default step is shortened for such a pair ([`heavy_step_share`]; doc/limits.md).
    #[test]
    fn a_heavy_dashpot_is_second_order_with_a_large_constant() {
        let e = 0.05;
        let zeta = zeta_for_restitution(e);
        let worst = |steps: f64| {
            (0..64)
                .map(|k| impact(zeta, steps, k as f64 / 64.0, true) / e - 1.0)
                .fold((0.0f64, f64::MAX), |(lo, hi), x| (lo.min(x), hi.min(-x)))
        };
        for (steps, bound) in [(9.0, 0.03), (15.0, 0.01), (18.0, 0.007), (36.0, 0.0025)] {
            let (low, neg_high) = worst(steps);
            eprintln!("{steps} steps: {:+.4} … {:+.4}", low, -neg_high);
            assert!(
                low > -bound && -neg_high < 0.0,
                "{steps}: {low} {}",
                -neg_high
            );
        }
        // Doubling the steps from 18 cuts the worst error threefold (the mean 3.4-fold).
        assert!(worst(18.0).0 / worst(36.0).0 > 2.5);
    }

    /// The step a heavy dashpot takes ([`heavy_step_share`]): for e = 0.02 and 0.05, the 9
    /// steps per contact of FRAction 0.2 at 10 m/s become 9/share, and the discrete map then
    /// holds e within 1 % of the closed form over 64 phases; e ≥ 0.1 keeps its step.
    #[test]
    fn a_heavy_dashpot_within_one_percent_at_its_shortened_step() {
        let zeta_ref = zeta_for_restitution(HEAVY_REFERENCE_E);
        for e in [0.02, 0.05] {
            let zeta = zeta_for_restitution(e);
            let share = heavy_step_share(e, zeta, zeta_ref);
            assert!(share < 0.5 && share > 0.2, "{e}: {share}");
            let worst = (0..64)
                .map(|k| (impact(zeta, 9.0 / share, k as f64 / 64.0, true) / e - 1.0).abs())
                .fold(0.0f64, f64::max);
            assert!(worst < 0.01, "e = {e}: {worst}");
        }
        for e in [0.1, 0.5] {
            assert_eq!(heavy_step_share(e, zeta_for_restitution(e), zeta_ref), 1.0);
        }
        assert_eq!(heavy_step_share(0.05, 0.0, zeta_ref), 1.0);
    }

    /// A contact at rest (F_s balanced by the other forces, v = v_prev = 0) gets no viscous
    /// force: the estimate of the other forces cancels the elastic drive.
    #[test]
    fn a_contact_at_rest_gets_no_viscous_force() {
        let (fs, m) = (2.5, 0.3);
        let dt = 1e-3;
        let (coef, vn) = viscous_step(&ViscousIn {
            alpha: 1e-3,
            v: 0.0,
            drive: drive(fs, fs, 0.0, 0.0, 1.0 / m, 1.0 / dt),
            dash: 7.0,
            scale: m * m * 0.01,
            steady: true,
            point: (m * m * 0.01 * 1e-3f64).powf(0.25),
            linear: 3.0,
            inv_m: 1.0 / m,
            dt,
        });
        assert!(coef > 0.0);
        assert_eq!(vn, 0.0);
        // Without the last step (no v_prev) the pair is treated as isolated.
        assert_eq!(
            drive(fs, 1.0, 1.0, f64::INFINITY, 1.0 / m, 1.0 / dt),
            fs / m
        );
    }

    /// A linear dashpot alone on an isolated pair is the trapezoidal rule: the step's
    /// v_{n+1/2} = v − Δt (c/m*) (v + v_{n+1/2})/2, which decays by (1 − h)/(1 + h) per step.
    #[test]
    fn a_linear_dashpot_is_the_trapezoidal_rule() {
        let (c, m, dt) = (4.0, 2.0, 0.1);
        let v = -3.0;
        let (coef, vn) = viscous_step(&ViscousIn {
            alpha: 1.0,
            v,
            drive: 0.0,
            dash: 0.0,
            scale: 1.0,
            steady: false,
            point: 1.0,
            linear: c,
            inv_m: 1.0 / m,
            dt,
        });
        assert_eq!(coef, 0.0);
        let v_new = v - dt * c * vn / m;
        let h = 0.5 * dt * c / m;
        assert!((v_new - v * (1.0 - h) / (1.0 + h)).abs() < 1e-15);
    }

    /// EDEM's Hertz–Mindlin writes both dashpots as `2(5/6)^{1/2} β (S m*)^{1/2}` with
    /// `S_n = 2E*(R*α)^{1/2}` and `S_t = 8G*(R*α)^{1/2}`: their ratio is `(4G*/E*)^{1/2}`
    /// whatever the overlap and mass. The normal dashpot here is the coefficient the
    /// viscous step takes at α (`dash · (m*² R* α)^{1/4}`, `dash = ζ (4/3 E*)^{1/2}`).
    #[test]
    fn tangential_dashpot_stands_to_the_normal_one_as_edem_writes_them() {
        let (e_star, g_star): (f64, f64) = (3.0e9, 1.1e9);
        for (zeta, m, r, alpha) in [(0.3f64, 1e-6f64, 5e-4f64, 1e-7f64), (1.2, 3e-3, 2e-3, 4e-6)] {
            let c_n = zeta * (4.0 / 3.0 * e_star).sqrt() * (m * m * r * alpha).powf(0.25);
            let k_t = 8.0 * g_star * (r * alpha).sqrt();
            let c_t = tangential_coefficient(zeta, m, k_t);
            let ratio = (4.0 * g_star / e_star).sqrt();
            assert!((c_t / c_n / ratio - 1.0).abs() < 1e-12, "{c_t} {c_n}");
        }
        assert_eq!(tangential_coefficient(0.0, 1.0, 1.0), 0.0);
    }
}
