//! Viscoelastic Hertz normal dashpot calibrated to an exact coefficient of restitution.
//!
//! ## Model
//! For a head-on collision with reduced mass `m*`, overlap `α ≥ 0` and overlap rate `α'`:
//!
//! `m* α'' = −max(K α^{3/2} + C α^{1/4} α', 0)`, `K = 4/3 E* sqrt(R*)` (Hertz, Lian 1994
//! (3.14)–(3.15)),
//!
//! i.e. the Hertz force plus a dashpot `C α^{1/4} α'` whose coefficient grows like the square
//! root of the contact radius — the form of Tsuji, Tanaka & Ishida (1992). The total normal
//! force is clamped at `≥ 0`: the dashpot never pulls the particles together. Once the clamp
//! engages during restitution it stays engaged (the Hertz part keeps shrinking while `α'` stays
//! fixed), so the particles leave with the velocity they had when the total force first reached
//! zero; with `C = 0` the contact ends at `α = 0`. The coefficient of restitution is
//! `e = −α'_end / v`.
//!
//! ## `e` depends only on `ζ = C / sqrt(m* K)` (proof)
//! Let `v > 0` be the impact speed and scale `α = L ξ`, `t = T τ` with
//! `T = (m* / (K sqrt(v)))^{2/5}` and `L = vT`, so that `m* L / T² = K L^{3/2}`
//! (because `T^{5/2} K sqrt(v) = m*`). Dividing the equation of motion by `m* L / T²` gives
//!
//! `ξ'' = −max(ξ^{3/2} + ζ̃ ξ^{1/4} ξ', 0)`, `ξ(0) = 0`, `ξ'(0) = vT/L = 1`,
//!
//! with `ζ̃ = C L^{1/4} (L/T) / (m* L/T²) = C L^{1/4} T / m*`. Since `T² = m*/(K L^{1/2})`,
//! `T = sqrt(m*) / (sqrt(K) L^{1/4})` and hence `ζ̃ = C / sqrt(m* K) = ζ`: the velocity has
//! dropped out. The clamp `max(·, 0)` commutes with the positive rescaling. The dimensionless
//! problem therefore depends on `ζ` alone, and so does `e = −ξ'(τ_end)`, at every impact speed.
//! (A dashpot without the `α^{1/4}` factor would not have this property.)
//!
//! ## Exact solution
//! While the force is non-negative, `ξ'' + f(ξ) ξ' + ξ^{3/2} = 0` with `f = ζ ξ^{1/4}` is a
//! Liénard equation whose restoring term is proportional to `F f`, `F(ξ) = ∫_0^ξ f =
//! (4/5) ζ ξ^{5/4}`: `ξ^{3/2} = ω² F(ξ) f(ξ)` with `ω² = 5/(4ζ²)`. The Sundman transformation
//! `u = F(ξ)`, `ds = f(ξ) dτ` gives `du/ds = ξ'` and `d²u/ds² = ξ''/f = −u̇ − ω² u`: a **linear**
//! damped oscillator with `u(0) = 0`, `u̇(0) = 1`. The total force is
//! `f (ω² u + u̇) = −f ü`, so the tension clamp engages at the first inflection point `ü = 0`
//! of `u(s)`, and the particles leave with `ξ' = u̇` there. For `ω_d² = ω² − 1/4 > 0`,
//! `u = e^{−s/2} sin(ω_d s)/ω_d`, `ü ∝ (1/(4ω_d) − ω_d) sin θ − cos θ` (`θ = ω_d s`) vanishes
//! first at `θ* = 2 arctan(2ω_d)`, where `u̇ = −exp(−θ*/(2ω_d))`. Hence, with `w = 2ω_d`:
//!
//! * `e(ζ) = exp(−2 arctan(w)/w)`, `w = sqrt(5 − ζ²)/ζ` for `ζ < √5`;
//! * `e(√5) = e^{−2}` (critical damping of the linear oscillator);
//! * `e(ζ) = exp(−2 artanh(w)/w)`, `w = sqrt(ζ² − 5)/ζ` for `ζ > √5`;
//! * limits `e ≈ 1 − πζ/√5` (`ζ → 0`) and `e ≈ 5/(4ζ²)` (`ζ → ∞`).
//!
//! [`restitution_of_zeta`] evaluates this closed form (relative accuracy ~1e-15, ~50 ns);
//! [`restitution_of_zeta_ode`] integrates the dimensionless ODE directly (adaptive
//! Dormand–Prince 5(4)) and is kept as an independent reference; the tests check that they
//! agree to ~1e-9 and that a dimensional integration at 0.1 and 10 m/s rebounds with the
//! requested `e`.
//!
//! ## Tsuji's formula
//! Without the clamp the contact would end at `u = 0` (`θ = π`), giving
//! `e = exp(−π/(2ω_d)) = exp(−πβ/sqrt(1 − β²))`, `β = ζ/√5`: **exactly** the relation of Tsuji
//! et al. (1992), `ζ_T = −√5 ln e / sqrt(ln² e + π²)` (in LIGGGHTS `hertz` form:
//! `γ_n = −2 sqrt(5/6) β sqrt(S_n m*)`, `S_n = 2E* sqrt(R* α)`), see [`tsuji_zeta`]. So Tsuji's
//! formula is exact for a dashpot that may pull, and wrong for the tension-free contact used
//! here: it is exact only as `e → 1` and underestimates the needed `ζ` by 0.2 % (e = 0.99),
//! 2 % (0.9), 8 % (0.7), 16 % (0.5), 28 % (0.3), 52 % (0.1) and 83 % (0.01); a contact
//! calibrated with `ζ_T` rebounds with `e = 0.90, 0.72, 0.55, 0.40, 0.25, 0.17` instead of
//! `0.9, 0.7, 0.5, 0.3, 0.1, 0.01` (test `tsuji_formula_discrepancy` prints the table).

// `!(x > y)` comparisons are deliberate: they also route NaN to the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::hertz;

/// Smallest coefficient of restitution accepted by [`zeta_for_restitution`]; smaller (including
/// non-positive) requests are raised to this value, because `e = 0` needs `ζ = ∞`.
/// `ζ(1e-12) ≈ 1.1e6`.
pub const E_MIN: f64 = 1e-12;

/// Dormand–Prince 5(4) tableau (the system is autonomous, so the nodes `c` are not needed).
const A: [[f64; 6]; 7] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus 4th-order weights (error estimate).
const EW: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Right-hand side of the dimensionless problem: `(ξ', ξ'')`.
fn rhs(zeta: f64, y: [f64; 2]) -> [f64; 2] {
    let xi = y[0].max(0.0);
    let q = xi.sqrt().sqrt(); // ξ^{1/4}
    let f = xi * xi.sqrt() + zeta * q * y[1];
    [y[1], -f.max(0.0)]
}

/// One Dormand–Prince step of size `h`; returns the 5th-order solution and the error estimate.
fn dp_step(zeta: f64, y: [f64; 2], h: f64) -> ([f64; 2], [f64; 2]) {
    let mut k = [[0.0; 2]; 7];
    k[0] = rhs(zeta, y);
    for s in 1..7 {
        let mut ys = y;
        for (j, kj) in k.iter().enumerate().take(s) {
            ys[0] += h * A[s][j] * kj[0];
            ys[1] += h * A[s][j] * kj[1];
        }
        k[s] = rhs(zeta, ys);
    }
    // FSAL: stage 7 is evaluated at the 5th-order solution.
    let mut y5 = y;
    for (j, kj) in k.iter().enumerate().take(6) {
        y5[0] += h * A[6][j] * kj[0];
        y5[1] += h * A[6][j] * kj[1];
    }
    let mut err = [0.0; 2];
    for (j, kj) in k.iter().enumerate() {
        err[0] += h * EW[j] * kj[0];
        err[1] += h * EW[j] * kj[1];
    }
    (y5, err)
}

/// End-of-contact indicator, active during restitution (`ξ' < 0`): the sign of the total force
/// `ξ^{1/4} (ξ^{5/4} + ζ ξ')`, continued as `−|ξ|^{5/4} + ζ ξ'` for `ξ < 0` so that it is
/// continuous and also catches the `ζ = 0` end at `ξ = 0`.
fn indicator(zeta: f64, y: [f64; 2]) -> f64 {
    let x = y[0];
    let p = x.abs().powf(1.25);
    (if x >= 0.0 { p } else { -p }) + zeta * y[1]
}

fn ended(zeta: f64, y: [f64; 2]) -> bool {
    y[1] < 0.0 && indicator(zeta, y) <= 0.0
}

/// Reference (numerical) coefficient of restitution of the tension-clamped viscoelastic Hertz
/// contact `m* α'' = −max(Kα^{3/2} + Cα^{1/4}α', 0)` (Hertz part: Lian 1994 (3.14)–(3.15)),
/// obtained by integrating the dimensionless equation `ξ'' = −max(ξ^{3/2} + ζξ^{1/4}ξ', 0)`,
/// `ξ(0) = 0`, `ξ'(0) = 1` (see the module doc) with adaptive Dormand–Prince 5(4) (tolerance
/// `1e-12`) and bisection of the end-of-contact event (total force reaching 0 while
/// separating, or `ξ = 0`). Agrees with the closed form [`restitution_of_zeta`] to ~1e-9.
/// Costs ~0.06–0.1 ms for `0.01 ≤ ζ ≤ 100` (more for much larger `ζ`, where the explicit
/// scheme is limited by the stiff dashpot). Returns 1 for `ζ ≤ 0` or NaN and 0 for `ζ = +∞`.
pub fn restitution_of_zeta_ode(zeta: f64) -> f64 {
    if !(zeta > 0.0) {
        return 1.0;
    }
    if zeta == f64::INFINITY {
        return 0.0;
    }
    let tol = 1e-12;
    let mut y = [0.0_f64, 1.0_f64];
    // Start small: the ξ^{1/4} factor is not smooth at τ = 0.
    let mut h = 1e-6_f64.min(0.1 / zeta);
    let mut t = 0.0_f64;
    for _ in 0..1_000_000 {
        let (yn, err) = dp_step(zeta, y, h);
        let sc0 = tol * (1.0 + y[0].abs().max(yn[0].abs()));
        let sc1 = tol * (1.0 + y[1].abs().max(yn[1].abs()));
        let en = (err[0] / sc0).abs().max((err[1] / sc1).abs());
        if !(en <= 1.0) {
            let fac = if en.is_finite() {
                (0.9 * en.powf(-0.2)).max(0.1)
            } else {
                0.1
            };
            h *= fac;
            if !(h > 1e-300) {
                break; // cannot happen for finite ζ; avoid an infinite loop anyway
            }
            continue;
        }
        if ended(zeta, yn) {
            // Bisection on the step length: find h* with the event exactly at the end.
            let (mut lo, mut hi) = (0.0_f64, h);
            let mut yhi = yn;
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if !(mid > lo && mid < hi) {
                    break;
                }
                let (ym, _) = dp_step(zeta, y, mid);
                if ended(zeta, ym) {
                    hi = mid;
                    yhi = ym;
                } else {
                    lo = mid;
                }
            }
            return (-yhi[1]).clamp(0.0, 1.0);
        }
        y = yn;
        t += h;
        let fac = if en > 0.0 {
            (0.9 * en.powf(-0.2)).clamp(0.2, 5.0)
        } else {
            5.0
        };
        h *= fac;
        // Safety: the contact always ends; this bound is never reached for finite ζ.
        if t > 1e12 {
            break;
        }
    }
    (-y[1]).clamp(0.0, 1.0)
}

/// Coefficient of restitution `e(ζ)` of the tension-clamped viscoelastic Hertz contact
/// `m* α'' = −max(Kα^{3/2} + Cα^{1/4}α', 0)`, `ζ = C/sqrt(m*K)`, `K = 4/3 E*sqrt(R*)` (Hertz
/// part: Lian 1994 (3.14)–(3.15); dashpot form: Tsuji et al. 1992), in the exact closed form
/// derived in the module doc: `e = exp(−2 arctan(w)/w)`, `w = sqrt(5 − ζ²)/ζ` (`ζ < √5`),
/// continued as `exp(−2 artanh(w)/w)`, `w = sqrt(ζ² − 5)/ζ` (`ζ > √5`); `e(√5) = e^{−2}`.
/// Strictly decreasing from 1 (`ζ = 0`) to 0 (`ζ → ∞`). Returns 1 for `ζ ≤ 0` or NaN.
pub fn restitution_of_zeta(zeta: f64) -> f64 {
    if !(zeta > 0.0) {
        return 1.0;
    }
    // x = w² for ζ < √5, −w² for ζ > √5; h = arctan(√x)/√x, analytically continued.
    let x = 5.0 / (zeta * zeta) - 1.0;
    let h = if x.abs() < 1e-4 {
        // 1 − x/3 + x²/5 − x³/7 + …, truncation error < x⁴/9 < 1.2e-17.
        1.0 - x * (1.0 / 3.0 - x * (0.2 - x / 7.0))
    } else if x > 0.0 {
        let w = x.sqrt();
        w.atan() / w
    } else {
        // w = sqrt(1 − 5/ζ²) < 1; artanh(w) = ½ ln((1+w)/(1−w)) = ln((1+w) ζ/√5) without the
        // cancellation in 1 − w.
        let w = (-x).sqrt();
        ((1.0 + w).ln() + zeta.ln() - 0.5 * 5.0_f64.ln()) / w
    };
    (-2.0 * h).exp()
}

/// Tsuji et al. (1992) closed form `ζ_T = −√5 ln e / sqrt(ln² e + π²)`, which is exact for the
/// viscoelastic Hertz dashpot **without** the tension clamp (see the module doc) and a lower
/// bound of the clamped model's `ζ` ([`zeta_for_restitution`]). Returns 0 for `e ≥ 1` or NaN
/// and `√5` for `e ≤ 0`. Provided for comparison with other codes (Hertz part: Lian 1994
/// (3.14)–(3.15)).
pub fn tsuji_zeta(e: f64) -> f64 {
    if !(e < 1.0) {
        return 0.0;
    }
    if !(e > 0.0) {
        return 5.0_f64.sqrt();
    }
    let l = e.ln();
    -5.0_f64.sqrt() * l / (l * l + std::f64::consts::PI * std::f64::consts::PI).sqrt()
}

/// Dimensionless dashpot constant `ζ = C/sqrt(m*K)` that gives the coefficient of restitution
/// `e` exactly for the tension-clamped model of [`restitution_of_zeta`] (Hertz part: Lian 1994
/// (3.14)–(3.15)). Inverse of the closed form by bisection in `ln ζ` to full double precision,
/// bracketed below by [`tsuji_zeta`] (a rigorous lower bound: the clamp only raises `e`).
/// `e ≥ 1` or NaN gives 0; `e < E_MIN` (including `e ≤ 0`) is raised to [`E_MIN`].
/// Costs a few µs.
pub fn zeta_for_restitution(e: f64) -> f64 {
    if !(e < 1.0) {
        return 0.0;
    }
    let e = e.max(E_MIN);
    let mut lo = tsuji_zeta(e);
    if restitution_of_zeta(lo) <= e {
        return lo; // only possible through rounding as e → 1
    }
    // Upper bound: e(ζ) < 5/(4ζ²)·(…) for large ζ; double from max(2ζ_T, sqrt(5/(4e))).
    let mut hi = (2.0 * lo).max((1.25 / e).sqrt());
    let mut n = 0;
    while restitution_of_zeta(hi) > e && n < 2000 {
        lo = hi;
        hi *= 2.0;
        n += 1;
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if !(mid > lo && mid < hi) {
            break;
        }
        if restitution_of_zeta(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Dashpot coefficient `C = ζ(e) sqrt(m* K)`, `K = 4/3 E* sqrt(R*)` (Lian 1994 (3.14)–(3.15)),
/// for the normal force `K α^{3/2} + C α^{1/4} α'` (clamped at ≥ 0) to give the coefficient of
/// restitution `e` at every impact speed. Units: N·s·m^{-5/4}. See [`zeta_for_restitution`]
/// for the accepted range of `e`.
pub fn dashpot_coefficient(e: f64, m_star: f64, e_star: f64, r_star: f64) -> f64 {
    let k = hertz::force_constant(e_star, r_star);
    zeta_for_restitution(e) * (m_star * k).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Independent fixed-step RK4 of the dimensionless problem, with or without the tension
    /// clamp, linear interpolation of the end event. Less accurate near τ = 0 (ξ^{1/4} is not
    /// smooth there) but fine at the 1e-6 level with h = 1e-4.
    fn rk4_dimensionless(z: f64, h: f64, clamp: bool) -> f64 {
        let f = |y: [f64; 2]| -> [f64; 2] {
            let x = y[0].max(0.0);
            let force = x.powf(1.5) + z * x.powf(0.25) * y[1];
            [y[1], -if clamp { force.max(0.0) } else { force }]
        };
        let mut y = [0.0, 1.0];
        for _ in 0..10_000_000 {
            let k1 = f(y);
            let k2 = f([y[0] + 0.5 * h * k1[0], y[1] + 0.5 * h * k1[1]]);
            let k3 = f([y[0] + 0.5 * h * k2[0], y[1] + 0.5 * h * k2[1]]);
            let k4 = f([y[0] + h * k3[0], y[1] + h * k3[1]]);
            let yn = [
                y[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
                y[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
            ];
            if yn[1] < 0.0 {
                // End indicator: total force (clamped) or overlap (unclamped).
                let gi = |y: [f64; 2]| {
                    if clamp {
                        y[0].max(0.0).powf(1.25) + z * y[1]
                    } else {
                        y[0]
                    }
                };
                let (g0, g1) = (gi(y), gi(yn));
                if g1 <= 0.0 {
                    let s = g0 / (g0 - g1);
                    return -(y[1] + s * (yn[1] - y[1]));
                }
            }
            y = yn;
        }
        f64::NAN
    }

    #[test]
    fn elastic_limit_and_first_order_slope() {
        assert_eq!(restitution_of_zeta(0.0), 1.0);
        assert_eq!(restitution_of_zeta(-1.0), 1.0);
        assert_eq!(restitution_of_zeta(f64::NAN), 1.0);
        assert_eq!(restitution_of_zeta_ode(0.0), 1.0);
        assert_eq!(zeta_for_restitution(1.0), 0.0);
        assert_eq!(zeta_for_restitution(1.5), 0.0);
        assert_eq!(zeta_for_restitution(f64::NAN), 0.0);
        // First-order perturbation: ½(1 − e²) ≈ ζ ∫ ξ^{1/4} ξ'² dτ along the undamped Hertz path
        // (ξ'² = 1 − (4/5)ξ^{5/2}), = 2ζ ∫_0^{ξm} ξ^{1/4} sqrt(1 − (4/5)ξ^{5/2}) dξ
        // = ζ (4/5) sqrt(5/4) B(1/2, 3/2) = ζ π/√5, so e ≈ 1 − πζ/√5.
        for &z in &[1e-6, 1e-5, 1e-4, 1e-3] {
            let lin = 1.0 - PI / 5.0_f64.sqrt() * z;
            let e = restitution_of_zeta(z);
            let e_ode = restitution_of_zeta_ode(z);
            assert!(
                (e - lin).abs() < 2.0 * z * z + 1e-15,
                "ζ={z} e={e} lin={lin}"
            );
            assert!(
                (e_ode - lin).abs() < 2.0 * z * z + 1e-10,
                "ζ={z} ode={e_ode} lin={lin}"
            );
        }
    }

    #[test]
    fn closed_form_special_values() {
        let s5 = 5.0_f64.sqrt();
        // Critical damping of the linearised oscillator: e = e^{−2}, continuous across √5.
        let e2 = (-2.0_f64).exp();
        assert!((restitution_of_zeta(s5) - e2).abs() < 1e-15);
        for &d in &[1e-12, 1e-8, 1e-5, 1e-4 * 0.99, 1e-4 * 1.01, 1e-3] {
            let below = restitution_of_zeta(s5 * (1.0 - d));
            let above = restitution_of_zeta(s5 * (1.0 + d));
            assert!(below > e2 && e2 > above || d < 1e-10);
            // de/dζ at √5, from the series: e = exp(−2(1 − x/3 + …)), x = 5/ζ² − 1,
            // dx/dζ = −10/ζ³ = −2/√5 ⇒ de/dζ = e^{−2}·(2/3)·(−2/√5).
            let slope = e2 * (2.0 / 3.0) * (-2.0 / s5);
            let fd = (above - below) / (2.0 * s5 * d);
            assert!(
                d < 1e-10 || (fd - slope).abs() < 1e-6 + 3.0 * d,
                "d={d} fd={fd}"
            );
        }
        // Large ζ: e ≈ 5/(4ζ²) (1 + O(ln ζ / ζ²)).
        for &z in &[1e2, 1e3, 1e5, 1e8] {
            let r = restitution_of_zeta(z) * 4.0 * z * z / 5.0;
            assert!(
                (r - 1.0).abs() < 10.0 * z.ln() * 5.0 / (z * z),
                "ζ={z} r={r}"
            );
        }
        assert_eq!(restitution_of_zeta(f64::INFINITY), 0.0);
        assert!(restitution_of_zeta(1e300) >= 0.0);
    }

    #[test]
    fn closed_form_matches_ode_integration() {
        let mut z = 1e-4;
        while z < 60.0 {
            let e = restitution_of_zeta(z);
            let e_ode = restitution_of_zeta_ode(z);
            assert!(
                (e - e_ode).abs() < 1e-8 * e.max(1e-2),
                "ζ={z} closed={e} ode={e_ode}"
            );
            z *= 1.7;
        }
        for &z in &[0.01, 0.1, 0.5, 2.0, 5.0] {
            let e_rk4 = rk4_dimensionless(z, 1e-4, true);
            let e = restitution_of_zeta(z);
            assert!((e - e_rk4).abs() < 1e-6, "ζ={z} e={e} rk4={e_rk4}");
        }
    }

    #[test]
    fn monotone_decreasing() {
        let mut last = 1.0;
        let mut z = 1e-8;
        while z < 1e8 {
            let e = restitution_of_zeta(z);
            assert!(e < last && e > 0.0, "ζ={z} e={e}");
            last = e;
            z *= 1.05;
        }
        // Also the ODE reference on a coarser grid.
        let mut last = 1.0;
        for k in 0..30 {
            let e = restitution_of_zeta_ode(1e-3 * 1.4_f64.powi(k));
            assert!(e < last && e > 0.0);
            last = e;
        }
    }

    #[test]
    fn round_trip() {
        for &e in &[0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999_999, 1e-4, 1e-9] {
            let z = zeta_for_restitution(e);
            let back = restitution_of_zeta(z);
            assert!(((back - e) / e).abs() < 1e-12, "e={e} ζ={z} back={back}");
            // Independently of the closed form, the ODE rebounds with e.
            if z < 60.0 {
                let ode = restitution_of_zeta_ode(z);
                assert!(
                    (ode - e).abs() < 1e-8 * e.max(1e-2),
                    "e={e} ζ={z} ode={ode}"
                );
            }
        }
        assert_eq!(zeta_for_restitution(0.0), zeta_for_restitution(E_MIN));
        assert_eq!(zeta_for_restitution(-3.0), zeta_for_restitution(E_MIN));
        assert!(zeta_for_restitution(0.0).is_finite());
    }

    /// Dimensional integration (classical RK4 on m* α'' = −max(Kα^{3/2} + Cα^{1/4}α', 0)) at
    /// impact speeds 100× apart, with C from `dashpot_coefficient`.
    #[test]
    fn independent_of_impact_velocity() {
        let (r, e_mod, nu, rho) = (30e-6, 70e9, 0.3, 2650.0);
        let es = hertz::e_star(e_mod, nu, e_mod, nu);
        let rs = hertz::r_star(r, r);
        let m = rho * 4.0 / 3.0 * PI * r * r * r;
        let ms = m / 2.0;
        let k = hertz::force_constant(es, rs);
        for &e_req in &[0.01, 0.1, 0.3, 0.7, 0.9] {
            let c = dashpot_coefficient(e_req, ms, es, rs);
            assert!((c / (ms * k).sqrt() - zeta_for_restitution(e_req)).abs() < 1e-12);
            for &v in &[0.1, 10.0] {
                let tc = hertz::impact_duration(ms, rs, es, v);
                let dt = tc / 20000.0;
                let acc = |a: f64, w: f64| -> f64 {
                    let a = a.max(0.0);
                    -(k * a.powf(1.5) + c * a.powf(0.25) * w).max(0.0) / ms
                };
                let (mut a, mut w) = (0.0_f64, v);
                let mut out = f64::NAN;
                for _ in 0..2_000_000 {
                    let (k1a, k1w) = (w, acc(a, w));
                    let (a2, w2) = (a + 0.5 * dt * k1a, w + 0.5 * dt * k1w);
                    let (k2a, k2w) = (w2, acc(a2, w2));
                    let (a3, w3) = (a + 0.5 * dt * k2a, w + 0.5 * dt * k2w);
                    let (k3a, k3w) = (w3, acc(a3, w3));
                    let (a4, w4) = (a + dt * k3a, w + dt * k3w);
                    let (k4a, k4w) = (w4, acc(a4, w4));
                    a += dt / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a);
                    w += dt / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
                    // Contact over once the overlap is gone (free flight after the clamp).
                    if a <= 0.0 && w < 0.0 {
                        out = -w / v;
                        break;
                    }
                }
                assert!(
                    (out - e_req).abs() < 1e-3 * e_req.max(0.1),
                    "e={e_req} v={v} got {out}"
                );
            }
        }
    }

    #[test]
    fn tsuji_formula_discrepancy() {
        // Without the tension clamp Tsuji's relation is exact (module doc): an independent RK4
        // run of the unclamped model with ζ_T rebounds with e.
        for &e in &[0.01, 0.1, 0.3, 0.5, 0.9] {
            let unclamped = rk4_dimensionless(tsuji_zeta(e), 1e-4, false);
            assert!((unclamped - e).abs() < 1e-5, "e={e} unclamped={unclamped}");
        }
        // With the clamp (our model) it is not. Information table:
        println!("   e    ζ exact     ζ Tsuji   Δζ/ζ     e obtained with ζ_Tsuji");
        let mut worst: f64 = 0.0;
        for &e in &[0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.99] {
            let zt = tsuji_zeta(e);
            let z = zeta_for_restitution(e);
            let dz = (zt - z) / z;
            let e_t = restitution_of_zeta(zt);
            println!(
                "{e:5.2}  {z:9.6}  {zt:9.6}  {:+6.1} %   {e_t:.4}",
                100.0 * dz
            );
            assert!(zt < z && e_t > e); // ζ_T is a lower bound
            worst = worst.max(dz.abs());
        }
        println!("worst ζ discrepancy {:.1} %", 100.0 * worst);
        let rel = |e: f64| (tsuji_zeta(e) / zeta_for_restitution(e) - 1.0).abs();
        assert!(rel(0.999) < 2e-3); // exact as e → 1
        assert!(rel(0.5) > 0.10 && rel(0.5) < 0.20);
        assert!(rel(0.01) > 0.5);
    }
}
