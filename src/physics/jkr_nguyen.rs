//! The JKR contact as LIGGGHTS computes it (`normal_model jkr`), the implementation of
//! Nguyen et al. (2014) that Olsson (2017) used for his dry agglomerates (§3.3.1.1):
//! "contacts are broken once a finite separation distance is achieved" and van der Waals
//! forces are "non-ranged". Olsson states nothing more; what follows is what the
//! LIGGGHTS-PUBLIC source does (read to understand; doc/validation.md, "Olsson's dry contact law"),
//! expressed with the relations of [`super::jkr`] (the same JKR curve, `γ` per surface).
//!
//! * **One curve, no loop.** The normal force is a function of the overlap alone: the
//!   stable JKR branch `P(a)`, `α = a²/R* − sqrt(4πγa/E*)` (Lian 1994 (3.24), corrected
//!   (3.29); Olsson (12)–(15)) wherever `α > α_s = −3a_s²/R*` (Lian (3.38), the
//!   displacement-control separation point), and 0 below it. Two particles approaching
//!   feel the attraction from `α_s` on (`P = −5/9 P_c` there), exactly as they lose it when
//!   separating: no snap-in at `α = 0`, no hysteresis, no adhesive loss per contact
//!   (trubal's JKR snaps in at `α = 0` with `−8/9 P_c` and loses Lian's `W_p` (3.114) per
//!   contact made and broken).
//! * **Walls.** LIGGGHTS' wall contacts have no force at negative overlap: the JKR force
//!   acts for `α > 0` only; a particle leaves a wall at `α = 0` from `−8/9 P_c` (and snaps
//!   on at `α = 0` to the same value: again no loop).
//! * **Tangential and damping.** While `α > 0` only: the Mindlin spring
//!   `k_t = 8G* sqrt(R*α)` (the Hertz contact radius) capped at `μ F_H` with the *Hertz*
//!   force `F_H = 4/3 E* sqrt(R*) α^{3/2}` plus the normal dashpot, not the JKR force; in
//!   the neck (`α_s < α ≤ 0`) there is no tangential force. The normal dashpot is the Hertz
//!   restitution dashpot with `S_n = 2E* sqrt(R*α)`, also for `α > 0` only.
//!
//! Pure functions; never panic, no NaN for finite input with `E*`, `R*`, `γ > 0`.

use super::jkr::Jkr;

/// A JKR contact evaluated as LIGGGHTS' `normal_model jkr` does.
#[derive(Clone, Copy, Debug)]
pub struct NguyenJkr {
    pub jkr: Jkr,
    /// A particle–wall contact (force only at positive overlap).
    pub wall: bool,
}

impl NguyenJkr {
    /// Overlap below which there is no force: `α_s` (3.38) between particles, 0 at a wall.
    pub fn alpha_break(&self) -> f64 {
        if self.wall { 0.0 } else { self.jkr.alpha_s() }
    }

    /// Normal force (compressive positive) at overlap `alpha`: the stable JKR branch
    /// (Lian (3.24) at the root of corrected (3.29)) above [`NguyenJkr::alpha_break`], 0 at
    /// and below it, whether the contact is approaching or separating.
    pub fn force(&self, alpha: f64) -> f64 {
        if !(alpha > self.alpha_break()) {
            return 0.0;
        }
        self.jkr.force(alpha, f64::NAN).0
    }

    /// The contact at overlap `alpha`: `(force, contact radius, stored energy)` above
    /// [`NguyenJkr::alpha_break`], `None` at and below it. The radius solves (3.29) on the
    /// stable branch (`a_guess` a warm start); the stored energy is the work done on the
    /// contact from where its force vanishes, `U(a)` of [`Jkr::energy_of_a`] between
    /// particles (`U(a_s) = 0`), `U(a) − U(a_0)` at a wall (zero at `α = 0`).
    pub fn contact(&self, alpha: f64, a_guess: f64) -> Option<(f64, f64, f64)> {
        if !(alpha > self.alpha_break()) {
            return None;
        }
        let (f, a) = self.jkr.force(alpha, a_guess);
        let u = self.jkr.energy_of_a(a);
        let stored = if self.wall {
            u - self.jkr.energy_of_a(self.jkr.a0())
        } else {
            u
        };
        Some((f, a, stored))
    }

    /// Coulomb bound of the tangential force: `μ` times the Hertz force
    /// `4/3 E* sqrt(R*) α^{3/2}` (Lian (3.14)–(3.15)) for `α > 0`, 0 otherwise (the
    /// normal dashpot's share is the caller's).
    pub fn friction_bound(&self, mu: f64, alpha: f64) -> f64 {
        if !(alpha > 0.0) {
            return 0.0;
        }
        mu * super::hertz::force(self.jkr.e_star, self.jkr.r_star, alpha)
    }

    /// Tangential stiffness `8G* sqrt(R*α)` for `α > 0`, 0 otherwise (LIGGGHTS' `kt`).
    pub fn tangential_stiffness(&self, g_star: f64, alpha: f64) -> f64 {
        if !(alpha > 0.0) {
            return 0.0;
        }
        8.0 * g_star * (self.jkr.r_star * alpha).sqrt()
    }

    /// Work (J) to pull the contact from its zero-load equilibrium (`a³ = 9πγR*²/E*`,
    /// Lian (3.30)) to the point where its force vanishes: `−U(a_eq)` with `U` of
    /// [`Jkr::energy_of_a`] between particles (the same as trubal's JKR), `U(a_0) − U(a_eq)
    /// = −W_p − U(a_eq)` at a wall (it lets go at `α = 0`).
    pub fn bond_energy(&self) -> f64 {
        let a_eq = self.jkr.a_zero_load();
        let u = self.jkr.energy_of_a(a_eq);
        if self.wall {
            -self.jkr.peel_work() - u
        } else {
            -u
        }
    }

    /// Energy lost by the normal force over one approach from far away to any overlap and
    /// back: none (one curve). trubal's JKR loses [`Jkr::peel_work`] `W_p`.
    pub fn loop_loss(&self) -> f64 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Olsson's particle pair: E = 0.3 GPa, ν = 0.3 (E* = E/(2(1 − ν²))), two 11 µm
    /// spheres (R* = 5.5 µm), work of adhesion W = 0.09995 J/m² (γ = W/2).
    fn olsson(wall: bool) -> NguyenJkr {
        let e_star = 0.3e9 / (2.0 * (1.0 - 0.09));
        NguyenJkr {
            jkr: Jkr {
                e_star,
                r_star: if wall { 11e-6 } else { 5.5e-6 },
                gamma: 0.09995 / 2.0,
            },
            wall,
        }
    }

    /// Standard JKR closed forms, written out here: with `W = 2γ`, separation under
    /// displacement control at `δ_c = −¾ (π²W²R/E²)^{1/3}` with `P = −5/9 P_c`,
    /// `P_c = 3/2 πWR` (Olsson (14)); at `δ = 0`: `a³ = 2πWR²/E`, `P = −8/9 P_c`.
    #[test]
    fn force_curve_against_closed_forms() {
        let c = olsson(false);
        let (e, r, w) = (c.jkr.e_star, c.jkr.r_star, 2.0 * c.jkr.gamma);
        let pc = 1.5 * PI * w * r;
        let dc = -0.75 * (PI * PI * w * w * r / (e * e)).cbrt();
        assert!((c.alpha_break() / dc - 1.0).abs() < 1e-12);
        let just_above = c.force(dc * (1.0 - 1e-9));
        assert!(
            (just_above / (-5.0 / 9.0 * pc) - 1.0).abs() < 1e-4,
            "{just_above}"
        );
        assert_eq!(c.force(dc * 1.001), 0.0);
        assert!((c.force(0.0) / (-8.0 / 9.0 * pc) - 1.0).abs() < 1e-9);
        // At a positive overlap: P(a) with α(a) from the printed relations, by hand.
        let a: f64 = 2.0e-7;
        let alpha = a * a / r - (2.0 * PI * w * a / e).sqrt();
        let p = 4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a.powi(3)).sqrt();
        assert!(
            (c.force(alpha) / p - 1.0).abs() < 1e-9,
            "{} {p}",
            c.force(alpha)
        );
        // the wall has no neck: nothing below α = 0, −8/9 P_c just above
        let cw = olsson(true);
        let pcw = 1.5 * PI * w * cw.jkr.r_star;
        assert_eq!(cw.force(-1e-12), 0.0);
        assert!((cw.force(1e-18) / (-8.0 / 9.0 * pcw) - 1.0).abs() < 1e-4);
    }

    /// Approach and separation follow one curve: the loop encloses no area (trapezoid rule
    /// over the approach and back), whereas trubal's JKR (snap-in at 0, detachment at α_s)
    /// encloses `W_p = 4/45 (1 + 6·4^{1/3}) P_c |α_s|` (Lian (3.119)). The work to separate
    /// from zero load is `(4/9) P_c|α_s| (1/5 − x⁴/2 + x⁷/3 − x¹⁰/30)` at `x = 6^{1/3}`
    /// (`a_eq/a_s = 36^{1/3}`), `≈ 1.54259 P_c|α_s|`, checked by integrating the force.
    #[test]
    fn loop_and_bond_energy() {
        for wall in [false, true] {
            let c = olsson(wall);
            let pc = c.jkr.pc();
            let als = -c.jkr.alpha_s();
            let a_eq = c.jkr.a_zero_load();
            let alpha_eq = c.jkr.alpha_of_a(a_eq);
            // ∫ P dα from the break point to equilibrium (P < 0 there: the work to separate)
            let lo = c.alpha_break();
            let n = 200_000;
            let h = (alpha_eq - lo) / n as f64;
            let mut e = 0.0;
            for i in 0..n {
                let (x0, x1) = (lo + h * i as f64, lo + h * (i + 1) as f64);
                let f0 = if i == 0 {
                    c.force(x0 + 1e-9 * h)
                } else {
                    c.force(x0)
                };
                e -= 0.5 * (f0 + c.force(x1)) * h;
            }
            let x: f64 = 6f64.cbrt();
            let pair = 4.0 / 9.0
                * pc
                * als
                * (0.2 - x.powi(4) / 2.0 + x.powi(7) / 3.0 - x.powi(10) / 30.0);
            assert!(
                (pair / (pc * als) - 1.54259).abs() < 1e-5,
                "{}",
                pair / (pc * als)
            );
            let wp = 4.0 / 45.0 * (1.0 + 6.0 * 4f64.cbrt()) * pc * als;
            let want = if wall { pair - wp } else { pair };
            assert!((e / want - 1.0).abs() < 1e-4, "wall {wall}: {e} vs {want}");
            assert!((c.bond_energy() / want - 1.0).abs() < 1e-9);
            assert_eq!(c.loop_loss(), 0.0);
            assert!((c.jkr.peel_work() / wp - 1.0).abs() < 1e-12);
        }
    }

    /// `contact`: the force of the curve, and a stored energy that is the integral of the
    /// force from where it vanishes (trapezoid quadrature here), zero there; none below.
    #[test]
    fn contact_stores_the_work_along_the_curve() {
        for wall in [false, true] {
            let c = olsson(wall);
            let lo = c.alpha_break();
            let top = 3.0 * c.jkr.alpha_s().abs();
            let n = 100_000;
            let h = (top - lo) / n as f64;
            let mut w = 0.0;
            let mut a = f64::NAN;
            for i in 0..n {
                let (x0, x1) = (lo + h * i as f64, lo + h * (i + 1) as f64);
                let f0 = c.force(x0 + if i == 0 { 1e-9 * h } else { 0.0 });
                w += 0.5 * (f0 + c.force(x1)) * h;
                if i % 10_000 == 9_999 {
                    let (f, a1, stored) = c.contact(x1, a).unwrap();
                    a = a1;
                    assert!((f / c.force(x1) - 1.0).abs() < 1e-12);
                    assert!((stored - w).abs() < 1e-5 * c.jkr.pc() * top, "{stored} {w}");
                }
            }
            assert!(c.contact(lo, a).is_none());
            let (_, _, s0) = c.contact(lo + 1e-12 * top, f64::NAN).unwrap();
            assert!(s0.abs() < 1e-6 * c.jkr.pc() * top, "{s0}");
        }
    }

    /// Tangential: stiffness and Coulomb bound from the Hertz overlap only; none in the neck.
    #[test]
    fn tangential_from_hertz() {
        let c = olsson(false);
        let (g, mu, alpha) = (3.0e7, 0.17, 1e-8_f64);
        let fh = 4.0 / 3.0 * c.jkr.e_star * (c.jkr.r_star).sqrt() * alpha.powf(1.5);
        assert!((c.friction_bound(mu, alpha) / (mu * fh) - 1.0).abs() < 1e-12);
        let kt = 8.0 * g * (c.jkr.r_star * alpha).sqrt();
        assert!((c.tangential_stiffness(g, alpha) / kt - 1.0).abs() < 1e-12);
        assert_eq!(c.friction_bound(mu, -1e-9), 0.0);
        assert_eq!(c.tangential_stiffness(g, 0.0), 0.0);
    }
}
