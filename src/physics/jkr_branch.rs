//! The stable branch of a JKR contact (`a ≥ a_s`) in the reduced variable of `physics::jkr`'s
//! module doc, `x = (a/a_s)^{1/2} = 1 + t`: the quantities a contact's step needs, as
//! polynomials in `x` from the root `t` of the corrected Lian 1994 (3.29), so that one
//! solution gives the load (3.24), the energy (3.116) and the stiffness (3.41) without the
//! square roots and divisions of the same formulas written in `a`:
//!
//! * `a = a_s x²`, `α = (a_s²/R*)(x⁴ − 4x)`, `D = 3(α − α_s)/|α_s| = t⁴ + 4t³ + 6t²`;
//! * `P = (P_c/9)(x⁶ − 6x³)` (3.24);
//! * `U = 4πγa_s² [x¹⁰/30 − x⁷/3 + x⁴/2 − 1/5]` (the integral of (3.24) along (3.29) from
//!   `a_s`, `Jkr::energy_of_a`; `16E*a_s⁵/R*² = 4πγa_s²` by (3.117)), and the energy counted
//!   from the touch `E = U + W_p` (3.119);
//! * `k = dP/dα = 2E*a_s x² (x³ − 3)/(x³ − 1)` (3.41).
//!
//! A step solves (3.29) twice, at `α_n` and at the end of its path, each from a root near by:
//! [`taylor_start`] carries a known root `t` of `D` to `D + ΔD` by the inverse function's
//! Taylor polynomial, so that the Newton iteration of `Jkr::solve_t` starts within `O(ΔD³)`
//! of its root instead of `O(ΔD)`.

use super::jkr::Jkr;

/// The constants of one contact's branch, computed once a step from its separation radius
/// `a_s` (3.117) ([`Jkr::branch`]).
#[derive(Clone, Copy, Debug)]
pub struct Branch {
    /// `a_s` (3.117).
    pub a_s: f64,
    /// `α_s = −3a_s²/R*` (3.38).
    pub alpha_s: f64,
    /// `dD/dα = 3/|α_s| = R*/a_s²`.
    pub c_d: f64,
    /// `W_p` (3.119), `Jkr::peel_work_with`.
    pub w_p: f64,
    /// `P_c/9 = πγR*/3`.
    pub pc9: f64,
    /// `4πγa_s²`.
    pub u_scale: f64,
    /// `2E*a_s`.
    pub k_scale: f64,
}

impl Jkr {
    /// The constants of the branch of a contact whose separation radius is `a_s`
    /// ([`Jkr::a_s`], computed once when the contact formed). Requires `γ > 0`, `a_s > 0`.
    pub fn branch(&self, a_s: f64) -> Branch {
        Branch {
            a_s,
            alpha_s: -3.0 * a_s * a_s / self.r_star,
            c_d: self.r_star / (a_s * a_s),
            w_p: self.peel_work_with(a_s),
            pc9: std::f64::consts::FRAC_PI_3 * self.gamma * self.r_star,
            u_scale: 4.0 * std::f64::consts::PI * self.gamma * a_s * a_s,
            k_scale: 2.0 * self.e_star * a_s,
        }
    }

    /// The root `t ≥ 0` of the corrected (3.29) at the approach `alpha` (`Jkr::solve_a_with`
    /// in `t`: the same safeguarded Newton iteration, from the warm start `t_guess`, which may
    /// be anything); 0 at and beyond `α_s`.
    pub fn solve_t(&self, b: &Branch, alpha: f64, t_guess: f64) -> f64 {
        if !(alpha > b.alpha_s) {
            return 0.0;
        }
        let d = (alpha - b.alpha_s) * b.c_d;
        if !(d <= 1e60) {
            return (self.solve_a(alpha, f64::NAN) / b.a_s).sqrt() - 1.0;
        }
        super::jkr::newton_t(d, t_guess)
    }

    /// The energy counted from the touch, the force and the root at `alpha`: `(E, P, t)`
    /// (`Jkr::branch_energy`: beyond `α_s` the contact has broken, `(W_p, 0, 0)`).
    pub fn branch_at(&self, b: &Branch, alpha: f64, t_guess: f64) -> (f64, f64, f64) {
        let t = self.solve_t(b, alpha, t_guess);
        let p = if alpha > b.alpha_s { b.force(t) } else { 0.0 };
        (b.energy(t), p, t)
    }
}

impl Branch {
    /// The contact radius `a = a_s x²`.
    pub fn radius(&self, t: f64) -> f64 {
        let x = 1.0 + t;
        self.a_s * x * x
    }

    /// The load (3.24), `P = (P_c/9)(x⁶ − 6x³)`: `−5/9 P_c` at `a_s`, `−8/9 P_c` at `a_0`.
    pub fn force(&self, t: f64) -> f64 {
        let x = 1.0 + t;
        let x3 = x * x * x;
        self.pc9 * x3 * (x3 - 6.0)
    }

    /// The energy counted from the touch, `E = U + W_p` (`Jkr::branch_energy`), `U` the
    /// integral of (3.24) along (3.29) from `a_s` (`Jkr::energy_of_a`, the same polynomial
    /// in `t` near `a_s`, where it starts at `−5/2 t²`, and in `1/x` beyond `t = 1`).
    pub fn energy(&self, t: f64) -> f64 {
        let u = if t <= 1.0 {
            self.u_scale * t * t * super::jkr::fold_series(t)
        } else {
            // x¹⁰ [1/30 − x⁻³/3 + x⁻⁶/2 − x⁻¹⁰/5]: no inf − inf for huge x.
            let x = 1.0 + t;
            let ix = 1.0 / x;
            let ix2 = ix * ix;
            let ix3 = ix2 * ix;
            let x2 = x * x;
            let x10 = x2 * x2 * x2 * x2 * x2;
            let bracket = 1.0 / 30.0 - ix3 / 3.0 + 0.5 * ix3 * ix3 - ix3 * ix3 * ix2 * ix2 / 5.0;
            self.u_scale * x10 * bracket
        };
        u + self.w_p
    }

    /// The stiffness `dP/dα` (3.41), `2E*a (x³ − 3)/(x³ − 1)`, with `|x³ − 1|` floored at
    /// [`super::jkr::STIFFNESS_POLE_FLOOR`] at the pole `a = a_s` (as `Jkr::stiffness_of_a`).
    pub fn stiffness(&self, t: f64) -> f64 {
        let x = 1.0 + t;
        let x3 = x * x * x;
        let k_hertz = self.k_scale * x * x;
        if x3 > 1e100 {
            let ix = 1.0 / x3;
            return k_hertz * (1.0 - 3.0 * ix) / (1.0 - ix);
        }
        let floor = super::jkr::STIFFNESS_POLE_FLOOR;
        let den = x3 - 1.0;
        let den = if den.abs() < floor {
            if den < 0.0 { -floor } else { floor }
        } else {
            den
        };
        k_hertz * (x3 - 3.0) / den
    }
}

/// A start for the root of `g(t) = t⁴ + 4t³ + 6t² = D + dd` from the root `t > 0` of `g = D`:
/// the inverse function's Taylor polynomial to second order, `t + u − (g''/2g') u²`,
/// `u = dd/g'(t)`, `g' = 4t(t² + 3t + 3)`, `g'' = 12(1 + t)²`; within `O(u³)` of the root
/// where Newton's own first step from `t` is within `O(u²)`. Not finite (so ignored by the
/// solve) for `t = 0`, the fold, where `g'` vanishes.
pub fn taylor_start(t: f64, dd: f64) -> f64 {
    let x = 1.0 + t;
    let inv = 1.0 / (4.0 * t * (3.0 + t * (3.0 + t)));
    let u = dd * inv;
    t + u * (1.0 - 6.0 * x * x * inv * u)
}

/// `t = (a/a_s)^{1/2} − 1` of a contact radius on the branch (`a > a_s`), else NaN (no start).
pub fn t_of_a(a_s: f64, a: f64) -> f64 {
    let y = a / a_s;
    if y.is_finite() && y > 1.0 {
        y.sqrt() - 1.0
    } else {
        f64::NAN
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GAMMAS: [f64; 3] = [0.4, 1e-6, 10.0];

    fn jkr(gamma: f64) -> Jkr {
        // Two 30 µm glass spheres (E = 70 GPa, ν = 0.3).
        Jkr {
            e_star: 70e9 / (2.0 * (1.0 - 0.09)),
            r_star: 15e-6,
            gamma,
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// The approaches from just above the fold `α_s` to deep compression.
    fn alphas(j: &Jkr) -> Vec<f64> {
        let als = j.alpha_s();
        (-12..=6)
            .map(|k| als + als.abs() * 10f64.powf(k as f64 * 0.7))
            .collect()
    }

    /// The polynomials in `x` are the closed forms written in `a`: (3.24) `Jkr::force_of_a`,
    /// the energy `Jkr::energy_of_a_with` + `W_p` (3.119) and (3.41) `Jkr::stiffness_with`,
    /// and the root of `Jkr::solve_t` is `Jkr::solve_a_with`'s, from any start.
    #[test]
    fn branch_is_the_closed_forms_in_a() {
        for &g in &GAMMAS {
            let j = jkr(g);
            let a_s = j.a_s();
            let b = j.branch(a_s);
            assert!(rel(b.alpha_s, j.alpha_s()) < 1e-15);
            assert!(rel(b.w_p, j.peel_work()) < 1e-14);
            // U(a_s) = 0, so E(α_s) = W_p; P(a_s) = −5/9 P_c (3.37); P(a_0) = −8/9 P_c.
            assert_eq!(b.energy(0.0), b.w_p);
            assert!(rel(b.force(0.0), -5.0 / 9.0 * j.pc()) < 1e-15);
            let t0 = j.solve_t(&b, 0.0, f64::NAN);
            assert!(rel(b.force(t0), -8.0 / 9.0 * j.pc()) < 1e-14);
            assert!(b.energy(t0).abs() < 1e-13 * b.w_p);
            for alpha in alphas(&j) {
                let a = j.solve_a_with(a_s, alpha, 0.0);
                for tg in [f64::NAN, -1.0, 0.0, 1e-3, 0.5, 3.0, 1e6, f64::INFINITY] {
                    let t = j.solve_t(&b, alpha, tg);
                    assert!(rel(b.radius(t), a) < 1e-14, "γ {g} α {alpha} tg {tg}");
                }
                let t = j.solve_t(&b, alpha, f64::NAN);
                let p = j.force_of_a(a);
                assert!(
                    (b.force(t) - p).abs() < 1e-13 * p.abs().max(j.pc()),
                    "α {alpha}"
                );
                let e = j.energy_of_a_with(a_s, a) + b.w_p;
                assert!(
                    (b.energy(t) - e).abs() < 1e-13 * e.abs().max(b.w_p),
                    "α {alpha}"
                );
                let k = j.stiffness_with(a_s, a);
                let scale = 2.0 * j.e_star * a;
                assert!(
                    (b.stiffness(t) - k).abs() < 1e-12 * k.abs().max(scale),
                    "α {alpha}"
                );
            }
            // Beyond the fold: broken, (W_p, 0, 0).
            assert_eq!(j.branch_at(&b, 2.0 * b.alpha_s, 1.0), (b.w_p, 0.0, 0.0));
            // Huge approaches: finite, positive.
            let t = j.solve_t(&b, 1e100, 1.0);
            assert!(t.is_finite() && b.force(t) > 0.0 && b.energy(t) > 0.0);
            assert!(b.stiffness(t) > 0.0 && !b.stiffness(t).is_nan());
        }
    }

    /// The Taylor start is within `O(u³)` of the root (`u = ΔD/g'`): its error falls by
    /// 10³ for every 10 × smaller step, where the first-order start's (Newton's first
    /// iterate from `t`) falls by 10².
    #[test]
    fn taylor_start_is_of_the_second_order() {
        let g = |t: f64| t * t * (6.0 + t * (4.0 + t));
        for &t in &[0.05, 0.5, 0.8173, 2.0, 30.0] {
            let d = g(t);
            let mut last = f64::NAN;
            for k in 2..6 {
                let dd = d * 10f64.powi(-k);
                let root = super::super::jkr::newton_t(d + dd, f64::NAN);
                let err = (taylor_start(t, dd) - root).abs() / root;
                let g1 = 4.0 * t * (3.0 + t * (3.0 + t));
                let first = (t + dd / g1 - root).abs() / root;
                if last.is_finite() && err > 1e-14 {
                    assert!(err < 2e-3 * last, "t {t} k {k}: {err} after {last}");
                }
                assert!(
                    err < first || first < 1e-15,
                    "t {t} k {k}: {err} vs {first}"
                );
                last = err;
            }
        }
        // At the fold there is no start.
        assert!(!taylor_start(0.0, 1e-3).is_finite());
        assert!(t_of_a(1.0, 1.0).is_nan() && t_of_a(1.0, f64::NAN).is_nan());
        assert_eq!(t_of_a(1.0, 4.0), 1.0);
    }
}
