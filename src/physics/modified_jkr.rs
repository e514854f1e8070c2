//! The "modified JKR" normal law of Pasha (2013) Ch. 5 (§5.1.1, Fig. 5.1), the law EDEM's
//! "JKR V2" describes: the JKR curve (3.41)–(3.42) for a positive overlap, the force jumping
//! to `−8/9 f_c` at first touch (`α = 0`), and the contact breaking as soon as the overlap
//! returns to zero. "All the work done during the loading stage is recovered when the contact
//! overlap becomes zero … the contact for this model breaks once the overlap becomes zero"
//! (Pasha 2013 p. 104): the law is conservative (no adhesion hysteresis), unlike full JKR,
//! which keeps the spheres together down to `α_s < 0` and dissipates the peeling work there.
//!
//! Conventions as in [`super::jkr`]: `γ` is the surface energy per surface, the thesis's
//! interface energy is `Γ = 2γ`, and `f_c = 3/2 π Γ R* = 3πγR*` (3.40). The largest tension
//! the law can carry is `8/9 f_c` (at `α = 0⁺`), not `f_c` (the JKR minimum `−f_c` lies at a
//! negative overlap, which this law never reaches).

use super::jkr::Jkr;

/// The contact radius and force of a contact at overlap `alpha` (positive in compression),
/// or `None` when the overlap is negative (the contact is broken, force 0). For `α ≥ 0` the
/// force is JKR's, Pasha 2013 (3.41) `F = 4E*a³/(3R*) − (8πΓE*a³)^{1/2}` with `a` from
/// (3.42) `α = a²/R* − (2πΓa/E*)^{1/2}`, solved on the stable branch by
/// [`Jkr::solve_a`] (`a_guess` is a warm start, e.g. the last step's radius).
pub fn force(j: &Jkr, alpha: f64, a_guess: f64) -> Option<(f64, f64)> {
    if !(alpha >= 0.0) {
        return None;
    }
    let a = j.solve_a(alpha, a_guess);
    Some((j.force_of_a(a), a))
}

/// The energy stored in a contact of radius `a` (on the `α ≥ 0` part of the curve) since it
/// was made: `∫_0^α F dα' = U(a) − U(a_0)` ([`Jkr::energy_of_a`]). It is zero at first touch
/// and again when the overlap returns to zero, so an approach and separation dissipate
/// nothing (the force jumps at `α = 0` do no work in the limit `Δt → 0`).
pub fn stored(j: &Jkr, a: f64) -> f64 {
    j.energy_of_a(a) - j.energy_of_a(j.a0())
}

/// The force at first touch, `−8/9 f_c` (Pasha 2013 §1.8: "on contact the force jumps to
/// −8/9 f_c"), with `f_c = 3πγR*` (3.40).
pub fn snap_force(j: &Jkr) -> f64 {
    -8.0 / 9.0 * j.pc()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    // Pasha's Ch. 5 glass (E = 55 GPa, ν = 0.25, like spheres: E* = E/(2(1 − ν²))),
    // R* = 0.25 mm (two 1 mm spheres), interface energy Γ = 0.5 J/m² (γ = Γ/2).
    const E_STAR: f64 = 55e9 / (2.0 * (1.0 - 0.0625));
    const R_STAR: f64 = 0.25e-3;
    const BIG_GAMMA: f64 = 0.5;

    fn law() -> Jkr {
        Jkr {
            e_star: E_STAR,
            r_star: R_STAR,
            gamma: BIG_GAMMA / 2.0,
        }
    }

    /// (3.42) and (3.41) written with Γ, as printed in the thesis.
    fn alpha_of(a: f64) -> f64 {
        a * a / R_STAR - (2.0 * PI * BIG_GAMMA * a / E_STAR).sqrt()
    }
    fn force_of(a: f64) -> f64 {
        4.0 * E_STAR * a.powi(3) / (3.0 * R_STAR)
            - (8.0 * PI * BIG_GAMMA * E_STAR * a.powi(3)).sqrt()
    }

    #[test]
    fn first_touch_gives_minus_eight_ninths_of_the_pull_off_force() {
        let f_c = 1.5 * PI * R_STAR * BIG_GAMMA; // (3.40): 0.589 mN
        assert!((f_c - 5.890486e-4).abs() < 1e-9);
        let (f, a) = force(&law(), 0.0, 0.0).unwrap();
        // At α = 0, (3.42) gives a³ = 2πΓR*²/E*, and (3.41) then −4/3 πΓR* = −8/9 f_c.
        let a0 = (2.0 * PI * BIG_GAMMA * R_STAR * R_STAR / E_STAR).cbrt();
        assert!((a - a0).abs() < 1e-12 * a0, "{a} {a0}");
        assert!((f + 8.0 / 9.0 * f_c).abs() < 1e-10 * f_c, "{f}");
        assert!((snap_force(&law()) + 8.0 / 9.0 * f_c).abs() < 1e-15);
    }

    #[test]
    fn on_the_jkr_curve_for_positive_overlaps() {
        let a0 = (2.0 * PI * BIG_GAMMA * R_STAR * R_STAR / E_STAR).cbrt();
        for k in 1..40 {
            let a = a0 * (1.0 + 0.25 * k as f64);
            let alpha = alpha_of(a);
            assert!(alpha > 0.0);
            let (f, a_got) = force(&law(), alpha, 0.0).unwrap();
            assert!((a_got - a).abs() < 1e-10 * a, "{a_got} {a}");
            assert!(
                (f - force_of(a)).abs() < 1e-9 * force_of(a).abs().max(1e-4),
                "{f}"
            );
        }
        // Far in compression the force tends to Hertz (3.14).
        let alpha = 1e-5;
        let (f, _) = force(&law(), alpha, 0.0).unwrap();
        let hertz = 4.0 / 3.0 * E_STAR * R_STAR.sqrt() * alpha.powf(1.5);
        assert!((f - hertz).abs() < 0.01 * hertz && f < hertz);
    }

    #[test]
    fn breaks_at_zero_overlap_and_the_tension_never_exceeds_eight_ninths_f_c() {
        assert!(force(&law(), -1e-15, 0.0).is_none());
        let f_c = 1.5 * PI * R_STAR * BIG_GAMMA;
        let amax = 1e-6;
        let mut min: f64 = 0.0;
        for k in 0..=1000 {
            let (f, _) = force(&law(), amax * k as f64 / 1000.0, 0.0).unwrap();
            min = min.min(f);
        }
        assert!((min + 8.0 / 9.0 * f_c).abs() < 1e-9 * f_c, "{min}");
    }

    /// The loop closes: the work of the force from first touch to α is U(a) − U(a_0), and it
    /// is zero back at α = 0 (no adhesion hysteresis, "all the work … is recovered").
    #[test]
    fn the_law_is_conservative() {
        let j = law();
        let amax = 2e-7;
        let n = 20000;
        let mut work = 0.0;
        let mut prev = force(&j, 0.0, 0.0).unwrap().0;
        for k in 1..=n {
            let alpha = amax * k as f64 / n as f64;
            let f = force(&j, alpha, 0.0).unwrap().0;
            work += 0.5 * (prev + f) * amax / n as f64;
            prev = f;
        }
        let (_, a) = force(&j, amax, 0.0).unwrap();
        let u = stored(&j, a);
        assert!((u - work).abs() < 1e-6 * work.abs(), "{u} {work}");
        let (_, a0) = force(&j, 0.0, 0.0).unwrap();
        assert!(stored(&j, a0).abs() < 1e-12 * work.abs());
    }
}
