//! Viscous (dynamic) forces of a liquid bridge, Lian 1994 §4.3 and §5.7.2.
//!
//! Sign convention: `v_n = (v_B − v_A)·n` (5.50) with `n` from A to B, so
//! `v_n > 0` while the particles separate. The returned normal force follows
//! the contact convention of the crate (compressive positive): the force on B
//! is `+N n`, on A `−N n`. A viscous bridge resists the relative motion, so it
//! is tensile (N < 0) while separating and compressive while approaching.

use std::f64::consts::PI;

/// Normal viscous force of the bridge, Lian 1994 (4.73) (Reynolds lubrication
/// between unequal spheres, also (2.6)):
/// `F_v = 6π η R*² v_n / max(S, S_min)`, returned as the normal force in the
/// compressive-positive convention, i.e. `N = −F_v`: it opposes the relative
/// normal velocity. `r_star` is `R1R2/(R1 + R2)` for two spheres and the particle
/// radius for a plane wall ((4.69), Chan & Horn). The gap is cut off at `s_min`
/// (§5.7.2; Lian used R/1000 < S_min < R/100), also while the solids overlap.
/// Returns 0 for non-positive `eta`, `r_star` or a non-finite input.
#[inline]
pub fn viscous_normal(eta: f64, r_star: f64, v_n: f64, s: f64, s_min: f64) -> f64 {
    let s_eff = if s > s_min { s } else { s_min };
    if !(eta > 0.0 && r_star > 0.0 && s_eff > 0.0 && v_n.is_finite() && s_eff.is_finite()) {
        return 0.0;
    }
    -6.0 * PI * eta * r_star * r_star * v_n / s_eff
}

/// The dashpot coefficient `c = 6π η R*² / max(S, S_min)` of (4.73) (N s/m),
/// so that `N = −c v_n`; used for the time-step bound of the viscous term.
#[inline]
pub fn viscous_normal_coefficient(eta: f64, r_star: f64, s: f64, s_min: f64) -> f64 {
    viscous_normal(eta, r_star, -1.0, s, s_min)
}

/// Tangential viscous force and moment for relative tangential translation,
/// Goldman, Cox & Brenner (1967) as quoted by Lian 1994 (4.76), (4.77), with
/// `R → R*` for two spheres:
/// `T_v = (8/15 ln(R*/S) + 0.9588) 6π η R* v_t` (4.76),
/// `M_v = (2/15 ln(R*/S) − 0.2527) 6π η R*² v_t` (4.77),
/// `S → max(S, S_min)`. Asymptotic for `S/R* < 0.3` (Goldman et al.).
///
/// `v_t` is the signed relative tangential speed of B with respect to A along
/// a tangential unit vector `t` ((5.51)). Returns `(T, M)`: the tangential force
/// on B is `T t` (on A `−T t`), with `T` opposing `v_t`; `M` is the magnitude
/// of the accompanying moment (same sign convention as `T`: it is the moment
/// about the axis `n × t` on each particle with the sign of `−v_t`, see
/// `doc/bridge.md`). Off by default, as in Lian's chapters 6–7.
#[inline]
pub fn viscous_tangential(eta: f64, r_star: f64, v_t: f64, s: f64, s_min: f64) -> (f64, f64) {
    let s_eff = if s > s_min { s } else { s_min };
    if !(eta > 0.0 && r_star > 0.0 && s_eff > 0.0 && v_t.is_finite() && s_eff.is_finite()) {
        return (0.0, 0.0);
    }
    let l = (r_star / s_eff).ln();
    let t = -(8.0 / 15.0 * l + 0.9588) * 6.0 * PI * eta * r_star * v_t;
    let m = -(2.0 / 15.0 * l - 0.2527) * 6.0 * PI * eta * r_star * r_star * v_t;
    (t, m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_sign_and_magnitude() {
        let (eta, r, s) = (0.01, 30e-6, 1e-6);
        let rs = 0.5 * r;
        // separating: tensile (negative), magnitude 6πηR*²v/S
        let n = viscous_normal(eta, rs, 0.2, s, 1e-8);
        let want = 6.0 * PI * eta * rs * rs * 0.2 / s;
        assert!((n + want).abs() < 1e-12 * want);
        assert!(n < 0.0);
        // approaching: compressive
        assert!(viscous_normal(eta, rs, -0.2, s, 1e-8) > 0.0);
        // equal spheres reduce to (4.68) 3πηR²v/(2S)
        let want = 3.0 * PI * eta * r * r * 0.2 / (2.0 * s);
        assert!((n + want).abs() < 1e-12 * want);
        // wall: (4.69) 6πηR²v/S with R* = R
        let nw = viscous_normal(eta, r, 0.2, s, 1e-8);
        assert!((nw + 6.0 * PI * eta * r * r * 0.2 / s).abs() < 1e-12 * nw.abs());
        // no velocity, no force
        assert_eq!(viscous_normal(eta, rs, 0.0, s, 1e-8), 0.0);
    }

    #[test]
    fn normal_gap_cut_off() {
        let (eta, rs, smin) = (0.1, 15e-6, 3e-8);
        let at_min = viscous_normal(eta, rs, 1.0, smin, smin);
        assert_eq!(viscous_normal(eta, rs, 1.0, 1e-12, smin), at_min);
        assert_eq!(viscous_normal(eta, rs, 1.0, 0.0, smin), at_min);
        assert_eq!(viscous_normal(eta, rs, 1.0, -1e-7, smin), at_min);
        assert!(viscous_normal(eta, rs, 1.0, 2.0 * smin, smin).abs() < at_min.abs());
        assert!(at_min.is_finite());
        // degenerate input never panics / never returns NaN
        assert_eq!(viscous_normal(eta, rs, 1.0, 0.0, 0.0), 0.0);
        assert_eq!(viscous_normal(f64::NAN, rs, 1.0, 1e-6, 0.0), 0.0);
        assert_eq!(
            viscous_normal_coefficient(eta, rs, 1e-6, smin),
            6.0 * PI * eta * rs * rs / 1e-6
        );
    }

    #[test]
    fn tangential_goldman() {
        let (eta, rs, s) = (0.01, 15e-6, 1.5e-7);
        let (t, m) = viscous_tangential(eta, rs, 0.3, s, 1e-9);
        let l = (100.0f64).ln();
        let tw = (8.0 / 15.0 * l + 0.9588) * 6.0 * PI * eta * rs * 0.3;
        let mw = (2.0 / 15.0 * l - 0.2527) * 6.0 * PI * eta * rs * rs * 0.3;
        assert!((t + tw).abs() < 1e-12 * tw && t < 0.0);
        assert!((m + mw).abs() < 1e-12 * mw.abs());
        let (t2, _) = viscous_tangential(eta, rs, -0.3, s, 1e-9);
        assert_eq!(t2, -t);
        let (a, _) = viscous_tangential(eta, rs, 0.3, 0.0, s);
        assert_eq!(a, t);
    }
}
