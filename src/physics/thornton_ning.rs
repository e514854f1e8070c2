//! Thornton & Ning (1998) elastic–plastic adhesive normal law, as reviewed by Pasha (2013)
//! §3.4.4.1 (equations (3.27)–(3.32), (3.55)–(3.59); doc/spec pasha2013.md §1.5, §1.11).
//!
//! * Elastic–adhesive loading on the JKR curve (3.41)–(3.42) with `R*`, the force jumping to
//!   `−8/9 f_ce` at first touch, until the contact radius reaches `a_y`, where JKR's central
//!   pressure equals the limiting contact pressure `p_y` (3.55)
//!   `p_y = 2E*a_y/(πR*) − (2ΓE*/(πa_y))^{1/2}`.
//! * Plastic loading beyond `α_y`: the pressure is capped at `p_y`, so each new area carries
//!   `p_y`: `F = F_y + πp_y R*(α − α_y)` (3.28) with `a² = a_y² + R*(α − α_y)` (`F_y`, `α_y`:
//!   the JKR force and overlap at `a_y`; for `Γ = 0` they are (3.27) and (3.29)).
//! * Unloading and reloading below the largest overlap `α_max` follow a JKR curve of larger
//!   radius `R_p*` (3.58) `R_p* = R* F*_max / (F_max + (4F_ce F*_max)^{1/2})`, shifted by the
//!   overlap `α_p` where its contact radius is zero, with pull-off force (3.59)
//!   `F_cp = 3/2 πΓR_p*`. Here `F*_max = 4E*a_max³/(3R*)`, the Hertz force of the contact
//!   radius reached (the thesis leaves `F*_max` undefined, erratum 6 of the spec): with it the
//!   curve passes exactly through `(α_max, F_max)`, and for `Γ = 0` `R_p*` is Thornton's
//!   (3.30) and `α_p` is (3.32).
//! * The contact breaks at the curve's separation point (`F = −5/9 F_cp`, displacement
//!   control) and is made again, when the surfaces approach, at `α = α_p` with
//!   `F = −8/9 F_cp` (Pasha 2013 p. 64); loading beyond `α_max` is plastic again.
//!
//! Conventions of [`super::jkr`]: `γ` per surface, `Γ = 2γ`, `F_ce = 3/2 πΓR* = 3πγR*`.

use serde::{Deserialize, Serialize};

use super::jkr::Jkr;
use std::f64::consts::PI;

/// The law's constants for one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThorntonNing {
    pub e_star: f64,
    pub r_star: f64,
    /// Surface energy per surface γ (J/m²); `Γ = 2γ`.
    pub gamma: f64,
    /// Limiting contact pressure p_y (Pa), Pasha 2013 (3.27)–(3.29), (3.55).
    pub p_y: f64,
}

/// The history of one contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TnState {
    /// Contact radius at first yield `a_y` (3.55), set at first touch (0 before).
    pub a_y: f64,
    /// Largest overlap of plastic loading (0 while the contact has not yielded).
    pub alpha_max: f64,
    /// Radius of the unloading curve `R_p*` (3.58) (`R*` before yield).
    pub r_p: f64,
    /// Overlap where the unloading curve's contact radius is zero (0 before yield).
    pub alpha_p: f64,
}

/// The outcome of one evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tn {
    /// In contact: force (compressive positive), contact radius, and the energy stored on
    /// the current elastic curve measured from its separation point (`U(a) ≥ −W_peel`,
    /// zero at separation; see [`Jkr::energy_of_a`]).
    Contact { force: f64, a: f64, stored: f64 },
    /// Apart (the contact broke, or has not been made again).
    Apart,
}

impl ThorntonNing {
    fn elastic(&self, r: f64) -> Jkr {
        Jkr {
            e_star: self.e_star,
            r_star: r,
            gamma: self.gamma,
        }
    }

    /// `F_ce = 3/2 πΓR*` (3.40), the elastic pull-off force.
    pub fn f_ce(&self) -> f64 {
        3.0 * PI * self.gamma * self.r_star
    }

    /// The contact radius at first yield: the root of (3.55) (for `Γ = 0`,
    /// `a_y = πR*p_y/(2E*)`). With `u = a^{1/2}`, (3.55) is the cubic
    /// `c₁u³ − p_y u − c₀ = 0` (`c₁ = 2E*/(πR*)`, `c₀ = (2ΓE*/π)^{1/2}`), which has one
    /// positive root; Newton from an upper bound decreases monotonically to it.
    pub fn yield_radius(&self) -> f64 {
        let c1 = 2.0 * self.e_star / (PI * self.r_star);
        let c0 = (2.0 * 2.0 * self.gamma * self.e_star / PI).max(0.0).sqrt();
        let py = self.p_y;
        let mut u = (2.0 * py / c1).sqrt() + (2.0 * c0 / c1).cbrt();
        for _ in 0..100 {
            let g = c1 * u * u * u - py * u - c0;
            let dg = 3.0 * c1 * u * u - py;
            let next = u - g / dg;
            if !(next < u) {
                break;
            }
            u = next;
        }
        u * u
    }

    /// Overlap and force at first yield, `(α_y, F_y)`: the JKR curve at `a_y`.
    pub fn yield_point(&self, a_y: f64) -> (f64, f64) {
        let j = self.elastic(self.r_star);
        (j.alpha_of_a(a_y), j.force_of_a(a_y))
    }

    /// Plastic loading to `α_max ≥ α_y`: the force (3.28), the contact radius, and the
    /// unloading curve `(R_p*, α_p)` (3.58).
    pub fn plastic(&self, a_y: f64, alpha_max: f64) -> (f64, f64, f64, f64) {
        let (alpha_y, f_y) = self.yield_point(a_y);
        let f_max = f_y + PI * self.p_y * self.r_star * (alpha_max - alpha_y);
        let a_max = (a_y * a_y + self.r_star * (alpha_max - alpha_y)).sqrt();
        let f_star = 4.0 * self.e_star * a_max.powi(3) / (3.0 * self.r_star);
        let r_p = self.r_star * f_star / (f_max + (4.0 * self.f_ce() * f_star).sqrt());
        let alpha_p = alpha_max - self.elastic(r_p).alpha_of_a(a_max);
        (f_max, a_max, r_p, alpha_p)
    }

    /// One evaluation at overlap `alpha` of a contact whose state is `st` and which was in
    /// contact at the last evaluation (`touching`); `a_guess` warm-starts the radius.
    pub fn step(&self, st: &mut TnState, alpha: f64, touching: bool, a_guess: f64) -> Tn {
        if st.a_y == 0.0 {
            st.a_y = self.yield_radius();
            st.r_p = self.r_star;
            st.alpha_p = 0.0;
        }
        let j = self.elastic(st.r_p);
        let x = alpha - st.alpha_p;
        if !(x >= if touching { j.alpha_s() } else { 0.0 }) {
            return Tn::Apart;
        }
        let (alpha_y, _) = self.yield_point(st.a_y);
        if alpha >= alpha_y && alpha >= st.alpha_max {
            let (f, a, r_p, alpha_p) = self.plastic(st.a_y, alpha);
            st.alpha_max = alpha;
            st.r_p = r_p;
            st.alpha_p = alpha_p;
            let stored = self.elastic(r_p).energy_of_a(a);
            return Tn::Contact {
                force: f,
                a,
                stored,
            };
        }
        let a = j.solve_a(x, a_guess);
        Tn::Contact {
            force: j.force_of_a(a),
            a,
            stored: j.energy_of_a(a),
        }
    }

    /// The pull-off force of the current unloading curve, `F_cp = 3/2 πΓR_p*` (3.59).
    pub fn f_cp(&self, st: &TnState) -> f64 {
        3.0 * PI * self.gamma * st.r_p.max(self.r_star)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Pasha 2013 Table 4.1: ammonium fluorescein sphere (R = 2.45 µm, E = 1.2 GPa, ν = 0.3) on
    // silicon (E = 182 GPa, ν = 0.3), Γ = 0.2 J/m², p_y = 35.3 MPa.
    fn e_star() -> f64 {
        1.0 / ((1.0 - 0.09) / 1.2e9 + (1.0 - 0.09) / 182e9)
    }
    const R: f64 = 2.45e-6;
    const PY: f64 = 35.3e6;

    fn law(big_gamma: f64) -> ThorntonNing {
        ThorntonNing {
            e_star: e_star(),
            r_star: R,
            gamma: big_gamma / 2.0,
            p_y: PY,
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// Without adhesion the law is Thornton's (1997): (3.27)–(3.32).
    #[test]
    fn without_adhesion_it_is_thorntons_elastic_plastic_law() {
        let t = law(0.0);
        let e = e_star();
        let a_y = t.yield_radius();
        let (alpha_y, f_y) = t.yield_point(a_y);
        // (3.29), (3.27).
        assert!(rel(alpha_y, PI * PI * R * PY * PY / (4.0 * e * e)) < 1e-12);
        assert!(rel(f_y, PI.powi(3) * R * R * PY.powi(3) / (6.0 * e * e)) < 1e-12);
        // (3.28): plastic loading, slope π p_y R*.
        let alpha_max = 20.0 * alpha_y;
        let (f_max, _, r_p, alpha_p) = t.plastic(a_y, alpha_max);
        assert!(rel(f_max, f_y + PI * PY * R * (alpha_max - alpha_y)) < 1e-12);
        // (3.30) and (3.32).
        let rp_30 = 4.0 * e / (3.0 * f_max) * ((2.0 * f_max + f_y) / (2.0 * PI * PY)).powf(1.5);
        assert!(rel(r_p, rp_30) < 1e-12, "{r_p} {rp_30}");
        assert!(rel(alpha_p, alpha_max * (1.0 - R / rp_30)) < 1e-10);
        // (3.31) with R_p* (erratum 3): Hertz unloading of the flattened sphere.
        let mut st = TnState::default();
        let mut touching = false;
        for k in 0..=200 {
            let alpha = alpha_max * k as f64 / 200.0;
            touching = matches!(t.step(&mut st, alpha, touching, 0.0), Tn::Contact { .. });
        }
        assert!(touching && rel(st.alpha_max, alpha_max) < 1e-15);
        let alpha = 0.5 * (alpha_p + alpha_max);
        let Tn::Contact { force, .. } = t.step(&mut st, alpha, true, 0.0) else {
            panic!("apart")
        };
        let hertz = 4.0 / 3.0 * e * rp_30.sqrt() * (alpha - alpha_p).powf(1.5);
        assert!(rel(force, hertz) < 1e-9, "{force} {hertz}");
        // Apart below α_p, no tension.
        assert_eq!(t.step(&mut st, alpha_p * 0.999, true, 0.0), Tn::Apart);
    }

    /// With adhesion: a_y solves (3.55); the unloading curve passes through (α_max, F_max);
    /// its pull-off force is (3.59) `3/2 πΓR_p*`; it breaks at −5/9 F_cp and is made again
    /// at −8/9 F_cp.
    #[test]
    fn with_adhesion_the_unloading_curve_has_the_plastic_pull_off_force() {
        let big_gamma = 0.2;
        let t = law(big_gamma);
        let e = e_star();
        let a_y = t.yield_radius();
        let py = 2.0 * e * a_y / (PI * R) - (2.0 * big_gamma * e / (PI * a_y)).sqrt();
        assert!(rel(py, PY) < 1e-10, "{py}");
        let (alpha_y, _) = t.yield_point(a_y);
        let alpha_max = 50.0 * alpha_y.abs().max(1e-9);
        let mut st = TnState::default();
        let mut touching = false;
        let n = 2000;
        let mut f_max = 0.0;
        for k in 0..=n {
            let alpha = alpha_max * k as f64 / n as f64;
            if let Tn::Contact { force, .. } = t.step(&mut st, alpha, touching, 0.0) {
                touching = true;
                f_max = force;
            }
        }
        let (f_plastic, _, r_p, alpha_p) = t.plastic(a_y, alpha_max);
        assert_eq!(f_max, f_plastic);
        assert!(r_p > R, "the curvature radius grows: {r_p}");
        // The unloading curve starts at (α_max, F_max) (continuity, the definition of R_p*).
        let Tn::Contact { force, .. } = t.step(&mut st, alpha_max * (1.0 - 1e-12), true, 0.0)
        else {
            panic!()
        };
        assert!(rel(force, f_max) < 1e-6, "{force} {f_max}");
        // Unload: the largest tension is F_cp = 3/2 πΓR_p* (3.59), the last force −5/9 F_cp.
        let f_cp = 1.5 * PI * big_gamma * r_p;
        assert!(rel(t.f_cp(&st), f_cp) < 1e-12);
        let mut min: f64 = 0.0;
        let mut last = 0.0;
        let mut alpha = alpha_max;
        let d = alpha_max / 200_000.0;
        loop {
            alpha -= d;
            match t.step(&mut st, alpha, true, 0.0) {
                Tn::Contact { force, .. } => {
                    min = min.min(force);
                    last = force;
                }
                Tn::Apart => break,
            }
        }
        assert!(rel(-min, f_cp) < 1e-6, "{min} {f_cp}");
        // (The force has a square-root slope at the separation point: within 2 % a step before.)
        assert!(rel(-last, 5.0 / 9.0 * f_cp) < 2e-2, "{last}");
        assert!(alpha < alpha_p);
        // Apart until the surfaces reach α_p again; then −8/9 F_cp.
        assert_eq!(t.step(&mut st, alpha_p - 1e-12, false, 0.0), Tn::Apart);
        let Tn::Contact { force, .. } = t.step(&mut st, alpha_p, false, 0.0) else {
            panic!()
        };
        assert!(rel(-force, 8.0 / 9.0 * f_cp) < 1e-9, "{force}");
    }
}
