//! Pasha's linear elasto-plastic adhesive normal law (Pasha 2013 Ch. 4; doc/spec
//! pasha2013.md §1.14–1.17), in its full version (§4.1, Fig. 4.1) and its simplified version
//! (§4.1.5, Fig. 4.20; the law of his Ch. 6 and 7).
//!
//! Both are piecewise linear in the overlap `α` (positive in compression), with the elastic
//! stiffness `k_e`, the plastic stiffness `k_p` and `f_ce = 3/2 πΓR*` (4.1):
//!
//! * **Virgin loading** (`α ≥ α_max`, the largest overlap so far). Full: the elastic-adhesive
//!   line (4.2) `F = k_eα − 8/9 f_ce` up to `α_0 = 8f_ce/(9k_e)` (A2.6), then fully plastic
//!   (4.3) `F = k_p(α − α_0)`. Simplified: plastic from first touch, `F = k_p(α − α_0)` with
//!   `k_pα_0 = 8/9 f_ce` (A3.3). Either way the force jumps to `−8/9 f_ce` at first touch.
//! * **Unloading and reloading** (`α < α_max`, reversible): (4.4) `F = k_e(α − α_p)`, the
//!   plastic overlap `α_p = α_max − k_p(α_max − α_0)/k_e` (continuity at `α_max`), down to
//!   the pull-off force `−f_cp` at `α_cp`; beyond it the branch (4.5)
//!   `F = k_e(2α_cp − α_p − α)` of slope `−k_e`, until the contact breaks at `α_fp`.
//! * **Pull-off force.** Full: load dependent through the plastic contact area, (4.6)–(4.11)
//!   and (A1.2), in the closed form `f_cp = (162/137 k_e Γ A_p)^{1/2}`,
//!   `A_p = π(2R*α_pd − α_pd²)`, `α_pd = α_p − α_0` (spec §1.14, derived exactly from
//!   (4.10)–(4.11)), never below `f_ce` (the formula gives less than `f_ce` for
//!   `α_pd` below about a nanometre; the bound keeps the unloading curve continuous with the
//!   elastic one at `α_max = α_0` — the thesis says `f_cp` is "always larger than" `f_ce`);
//!   `α_cp = α_p − f_cp/k_e`; breakage at `−5/9 f_cp`, (A1.5) `α_fp = 13/9 α_cp − 4/9 α_p`.
//!   Simplified: the linear pull-off locus (4.17) `f_cp = k_cpα_cp + f_0p`, met by the
//!   unloading line at `α_cp = (k_eα_p − f_0p)/(k_e + k_cp)`; breakage at zero force, as in
//!   Pasha's EDEM implementation, `α_fp = 2α_cp − α_p`.
//! * **After breakage** the history is kept; approaching surfaces make the contact again on
//!   the same reversible branch when `α` reaches `α_fp` (if `α_fp > 0`: the dent is deeper
//!   than the gap; the thesis, p. 79), or when they touch (`α = 0`) if `α_fp < 0` (so a
//!   pair is only ever re-engaged at contact; the force then jumps to the branch's value at
//!   `α = 0`, booked by the caller's energy ledger).
//!
//! With `Γ = 0` (and `k_cp = f_0p = 0`) both versions reduce to Walton & Braun's linear
//! hysteretic law (3.36)–(3.37), with restitution `(k_p/k_e)^{1/2}`.

use serde::{Deserialize, Serialize};

/// The version of the law and the parameters only it has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Version {
    /// Full model (§4.1): needs `R*` and the interface energy `Γ` for the pull-off force.
    Full { r_star: f64, big_gamma: f64 },
    /// Simplified model (§4.1.5): the pull-off locus (4.17) `f_cp = k_cp α_cp + f_0p`.
    Simplified { k_cp: f64, f_0p: f64 },
}

/// The law's constants for one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear {
    pub k_e: f64,
    pub k_p: f64,
    /// `f_ce = 3/2 πΓR*` (4.1).
    pub f_ce: f64,
    pub version: Version,
}

/// The reversible branch of a contact that has been loaded to `α_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    /// Overlap at zero force of the unloading line (4.4).
    pub alpha_p: f64,
    /// Overlap of the pull-off point (4.10) / (4.17).
    pub alpha_cp: f64,
    /// Pull-off force (magnitude).
    pub f_cp: f64,
    /// Overlap of breakage (A1.5), or of zero force (simplified).
    pub alpha_fp: f64,
}

/// The history of one contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LinState {
    /// Largest overlap of virgin loading.
    pub alpha_max: f64,
    /// The contact was made once (its branch is that of `alpha_max`).
    pub made: bool,
}

/// The outcome of one evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lin {
    /// In contact: force (compressive positive), the stiffness of the branch in use (`k_p`
    /// on plastic loading, `k_e` otherwise, for the damping (4.25)), and the energy the
    /// contact returns when unloaded along its reversible branch to breakage,
    /// `∫_{α_fp}^{α} F dα'` (negative while adhesion dominates).
    Contact {
        force: f64,
        k_n: f64,
        stored: f64,
    },
    Apart,
}

/// `∫_{x0}^{x1} k (x − c) dx`.
fn ramp(k: f64, c: f64, x0: f64, x1: f64) -> f64 {
    0.5 * k * ((x1 - c) * (x1 - c) - (x0 - c) * (x0 - c))
}

impl Linear {
    /// The overlap where the virgin plastic line crosses zero force: `8f_ce/(9k_e)` (full,
    /// (A2.6)) or `8f_ce/(9k_p)` (simplified, (A3.3)).
    pub fn alpha_0(&self) -> f64 {
        let k = match self.version {
            Version::Full { .. } => self.k_e,
            Version::Simplified { .. } => self.k_p,
        };
        8.0 * self.f_ce / (9.0 * k)
    }

    /// The force on virgin loading, (4.2)–(4.3) (full) or Fig. 4.20 A→B (simplified), and
    /// the stiffness of that line.
    pub fn virgin(&self, alpha: f64) -> (f64, f64) {
        let a0 = self.alpha_0();
        match self.version {
            Version::Full { .. } if alpha < a0 => {
                (self.k_e * alpha - 8.0 / 9.0 * self.f_ce, self.k_e)
            }
            _ => (self.k_p * (alpha - a0), self.k_p),
        }
    }

    /// The reversible branch after loading to `alpha_max`.
    pub fn branch(&self, alpha_max: f64) -> Branch {
        let a0 = self.alpha_0();
        match self.version {
            Version::Full { r_star, big_gamma } => {
                // Elastic so far: the line (4.2) itself, the elastic pull-off f_ce.
                let (alpha_p, f_cp) = if alpha_max <= a0 {
                    (a0, self.f_ce)
                } else {
                    let alpha_p = alpha_max - self.k_p * (alpha_max - a0) / self.k_e;
                    let pd = alpha_p - a0;
                    let area = std::f64::consts::PI * (2.0 * r_star * pd - pd * pd).max(0.0);
                    let f = (162.0 / 137.0 * self.k_e * big_gamma * area).sqrt();
                    (alpha_p, f.max(self.f_ce))
                };
                let alpha_cp = alpha_p - f_cp / self.k_e;
                Branch {
                    alpha_p,
                    alpha_cp,
                    f_cp,
                    alpha_fp: 13.0 / 9.0 * alpha_cp - 4.0 / 9.0 * alpha_p,
                }
            }
            Version::Simplified { k_cp, f_0p } => {
                let alpha_p = alpha_max - self.k_p * (alpha_max - a0) / self.k_e;
                let alpha_cp = (self.k_e * alpha_p - f_0p) / (self.k_e + k_cp);
                Branch {
                    alpha_p,
                    alpha_cp,
                    f_cp: k_cp * alpha_cp + f_0p,
                    alpha_fp: 2.0 * alpha_cp - alpha_p,
                }
            }
        }
    }

    /// The force on a branch at `alpha` (`None` below breakage), (4.4)–(4.5).
    pub fn on_branch(&self, b: &Branch, alpha: f64) -> Option<f64> {
        if alpha >= b.alpha_cp {
            Some(self.k_e * (alpha - b.alpha_p))
        } else if alpha >= b.alpha_fp {
            Some(self.k_e * (2.0 * b.alpha_cp - b.alpha_p - alpha))
        } else {
            None
        }
    }

    /// `∫_{α_fp}^{α} F dα'` along the branch (`α ≥ α_fp`).
    pub fn stored(&self, b: &Branch, alpha: f64) -> f64 {
        let c1 = 2.0 * b.alpha_cp - b.alpha_p;
        let k = self.k_e;
        if alpha < b.alpha_cp {
            -ramp(k, c1, b.alpha_fp, alpha)
        } else {
            -ramp(k, c1, b.alpha_fp, b.alpha_cp) + ramp(k, b.alpha_p, b.alpha_cp, alpha)
        }
    }

    /// One evaluation at overlap `alpha` of a contact with history `st`, in contact at the
    /// last evaluation or not (`touching`).
    pub fn step(&self, st: &mut LinState, alpha: f64, touching: bool) -> Lin {
        if !st.made {
            if !(alpha >= 0.0) {
                return Lin::Apart;
            }
            st.made = true;
            st.alpha_max = alpha;
        }
        if alpha >= st.alpha_max {
            st.alpha_max = alpha;
            let (force, k_n) = self.virgin(alpha);
            let b = self.branch(alpha);
            return Lin::Contact {
                force,
                k_n,
                stored: self.stored(&b, alpha),
            };
        }
        let b = self.branch(st.alpha_max);
        // Made again only at the breakage point or at touch, whichever comes later.
        if !touching && !(alpha >= b.alpha_fp.max(0.0)) {
            return Lin::Apart;
        }
        match self.on_branch(&b, alpha) {
            Some(force) => {
                // On the elastic part of the full model's virgin line the stiffness is k_e
                // too; k_p only on plastic loading (above).
                Lin::Contact {
                    force,
                    k_n: self.k_e,
                    stored: self.stored(&b, alpha),
                }
            }
            None => Lin::Apart,
        }
    }

    /// The tangential force limit `μ (F_n + f_cp − f_ce)` (4.27), full, or
    /// `μ (F_n + k_cp α + f_0p − f_ce)` (4.28), simplified, not below zero (the thesis does
    /// not say what a tensile limit means; spec §1.16).
    pub fn friction_limit(&self, mu: f64, f_n: f64, alpha: f64, st: &LinState) -> f64 {
        let extra = match self.version {
            Version::Full { .. } => self.branch(st.alpha_max).f_cp,
            Version::Simplified { k_cp, f_0p } => k_cp * alpha + f_0p,
        };
        (mu * (f_n + extra - self.f_ce)).max(0.0)
    }
}

/// Damping coefficient of the linear law (4.24)–(4.25):
/// `β = (4 ln²e m* k_n / (ln²e + π²))^{1/2}`, the linear spring–dashpot with restitution `e`
/// for the stiffness `k_n` in use.
pub fn damping(e: f64, m_star: f64, k_n: f64) -> f64 {
    let l2 = e.ln().powi(2);
    (4.0 * l2 * m_star * k_n / (l2 + std::f64::consts::PI.powi(2))).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    // Pasha 2013 Table 4.1 and 4.2: the ammonium fluorescein sphere on silicon.
    const R: f64 = 2.45e-6;
    const KE: f64 = 1500.0;
    const KP: f64 = 210.0;
    const KCP: f64 = 20.0;
    const F0P: f64 = 4.0e-6;
    const BIG_GAMMA: f64 = 0.2;

    fn f_ce() -> f64 {
        1.5 * PI * R * BIG_GAMMA
    }
    fn simplified() -> Linear {
        Linear {
            k_e: KE,
            k_p: KP,
            f_ce: f_ce(),
            version: Version::Simplified {
                k_cp: KCP,
                f_0p: F0P,
            },
        }
    }
    fn full() -> Linear {
        Linear {
            k_e: KE,
            k_p: KP,
            f_ce: f_ce(),
            version: Version::Full {
                r_star: R,
                big_gamma: BIG_GAMMA,
            },
        }
    }
    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1e-30)
    }

    /// Loads to `alpha_max` and unloads to breakage in `n` steps each; returns the forces.
    fn cycle(l: &Linear, alpha_max: f64, n: usize) -> (LinState, Vec<(f64, f64)>) {
        let mut st = LinState::default();
        let mut out = vec![];
        let mut touching = false;
        for k in 0..=n {
            let a = alpha_max * k as f64 / n as f64;
            if let Lin::Contact { force, .. } = l.step(&mut st, a, touching) {
                touching = true;
                out.push((a, force));
            }
        }
        for k in 1..=3 * n {
            let a = alpha_max * (1.0 - k as f64 / n as f64);
            match l.step(&mut st, a, touching) {
                Lin::Contact { force, .. } => out.push((a, force)),
                Lin::Apart => break,
            }
        }
        (st, out)
    }

    #[test]
    fn simplified_model_branches_and_stiffness_relations() {
        let l = simplified();
        // k_p α_0 = 8/9 f_ce (A3.3): at first touch the force is −8/9 f_ce.
        let a0 = 8.0 / 9.0 * f_ce() / KP;
        assert!(close(l.alpha_0(), a0, 1e-15));
        let mut st = LinState::default();
        let Lin::Contact { force, k_n, .. } = l.step(&mut st, 0.0, false) else {
            panic!()
        };
        assert!(close(force, -8.0 / 9.0 * f_ce(), 1e-14) && k_n == KP);
        // Loading to 0.2 µm on the plastic line, F_max = k_p (α_max − α_0).
        let am = 0.2e-6;
        let Lin::Contact { force: fmax, .. } = l.step(&mut st, am, true) else {
            panic!()
        };
        assert!(close(fmax, KP * (am - a0), 1e-14));
        // Unloading: slope k_e through (α_max, F_max); zero force at α_p.
        let ap = am - fmax / KE;
        let Lin::Contact { force, k_n, .. } = l.step(&mut st, ap, true) else {
            panic!()
        };
        assert!(force.abs() < 1e-12 * fmax && k_n == KE);
        // The pull-off point lies on the locus −(k_cp α + f_0p) and on the unloading line.
        let acp = (KE * ap - F0P) / (KE + KCP);
        let b = l.branch(am);
        assert!(close(b.alpha_cp, acp, 1e-12));
        assert!(close(b.f_cp, KCP * acp + F0P, 1e-12));
        assert!(close(KE * (acp - ap), -(KCP * acp + F0P), 1e-9));
        // Beyond it slope −k_e, zero force (breakage) at 2α_cp − α_p.
        let mid = 0.5 * (acp + b.alpha_fp);
        let Lin::Contact { force, .. } = l.step(&mut st, mid, true) else {
            panic!()
        };
        assert!(close(force, -(KCP * acp + F0P) * 0.5, 1e-9), "{force}");
        assert!(close(b.alpha_fp, 2.0 * acp - ap, 1e-12));
        assert_eq!(l.step(&mut st, b.alpha_fp - 1e-15, true), Lin::Apart);
        // Reloading from below: made again at α_fp (when it is positive) or at α = 0.
        assert_eq!(
            l.step(&mut st, b.alpha_fp.max(0.0) - 1e-12, false),
            Lin::Apart
        );
        assert!(matches!(
            l.step(&mut st, b.alpha_fp.max(0.0) + 1e-12, false),
            Lin::Contact { .. }
        ));
        // Reloading past α_max resumes the plastic line.
        let Lin::Contact { force, .. } = l.step(&mut st, 1.5 * am, true) else {
            panic!()
        };
        assert!(close(force, KP * (1.5 * am - a0), 1e-13));
    }

    #[test]
    fn full_model_branches_and_load_dependent_pull_off() {
        let l = full();
        // k_e α_0 = 8/9 f_ce (A2.6); the elastic line meets the A→B branch at
        // α_B = −f_ce/(9k_e) with −f_ce, and breaks at α_fe = −5f_ce/(9k_e) with −5/9 f_ce.
        let a0 = 8.0 * f_ce() / (9.0 * KE);
        assert!(close(l.alpha_0(), a0, 1e-15));
        let b = l.branch(0.5 * a0);
        assert!(close(b.alpha_cp, -f_ce() / (9.0 * KE), 1e-12));
        assert!(close(b.alpha_fp, -5.0 * f_ce() / (9.0 * KE), 1e-12));
        assert!(close(
            l.on_branch(&b, b.alpha_fp).unwrap(),
            -5.0 / 9.0 * f_ce(),
            1e-12
        ));
        assert!(close(
            l.on_branch(&b, 0.0).unwrap(),
            -8.0 / 9.0 * f_ce(),
            1e-12
        ));
        // Plastic: F = k_p (α − α_0), α_p = α_max − k_p(α_max − α_0)/k_e.
        let am = 0.2e-6;
        let (f, k) = l.virgin(am);
        assert!(close(f, KP * (am - a0), 1e-14) && k == KP);
        let b = l.branch(am);
        let ap = am - KP * (am - a0) / KE;
        assert!(close(b.alpha_p, ap, 1e-14));
        // f_cp from (4.10)–(4.11) and (A1.2), as printed.
        let pg = PI * BIG_GAMMA;
        let c = 162.0 / (137.0 * KE)
            * ((137.0 / 162.0 * KE + pg) * ap * ap - 2.0 * pg * (R + a0) * ap
                + pg * a0 * a0
                + 2.0 * pg * R * a0);
        let acp = ap - (ap * ap - c).sqrt();
        let fcp = KE * (ap - acp);
        assert!(close(b.f_cp, fcp, 1e-6), "{} {fcp}", b.f_cp);
        assert!(b.f_cp > f_ce());
        assert!(close(b.alpha_cp, acp, 1e-6));
        // (A1.5) and breakage at −5/9 f_cp.
        assert!(close(b.alpha_fp, 13.0 / 9.0 * acp - 4.0 / 9.0 * ap, 1e-6));
        assert!(close(
            l.on_branch(&b, b.alpha_fp).unwrap(),
            -5.0 / 9.0 * fcp,
            1e-6
        ));
        // |W_ad| (4.9): the area from α_fp to α_p under the unloading curve.
        let w = 137.0 / 162.0 * KE * (acp - ap).powi(2);
        assert!(
            close(-l.stored(&b, ap), w, 1e-9),
            "{} {w}",
            l.stored(&b, ap)
        );
    }

    /// The simplified model's impact energetics (A3.6), (A3.9): the rebound speed the
    /// branches give equals the closed form, and with Γ = 0 the restitution is Walton and
    /// Braun's (k_p/k_e)^{1/2}.
    #[test]
    fn impact_energy_balance_and_walton_braun_limit() {
        let l = simplified();
        let m = 1350.0 * 4.0 / 3.0 * PI * R.powi(3);
        let a0 = l.alpha_0();
        let am = 0.15e-6;
        // (A3.6) v_i² = k_p/m (α_max² − 2α_0α_max)
        let vi2 = KP / m * (am * am - 2.0 * a0 * am);
        let (_, out) = cycle(&l, am, 100_000);
        // Work of the force over the whole cycle (trapezoids): −½ m (v_r² − v_i²).
        let mut w_in = 0.0;
        let mut w_out = 0.0;
        let mut turned = false;
        for p in out.windows(2) {
            let dw = 0.5 * (p[0].1 + p[1].1) * (p[1].0 - p[0].0);
            if p[1].0 < p[0].0 {
                turned = true;
            }
            if turned {
                w_out += dw;
            } else {
                w_in += dw;
            }
        }
        assert!(close(w_in * 2.0 / m, vi2, 1e-6));
        // (A3.9) v_r² = F_max/m (α_max − α_p) − f_cp/m (α_p − α_fp)
        let b = l.branch(am);
        let fmax = KP * (am - a0);
        let vr2 = fmax / m * (am - b.alpha_p) - b.f_cp / m * (b.alpha_p - b.alpha_fp);
        assert!(
            close(-w_out * 2.0 / m, vr2, 1e-4),
            "{} {vr2}",
            -w_out * 2.0 / m
        );
        // Γ = 0: e = (k_p / k_e)^{1/2}, independent of the speed.
        let wb = Linear {
            f_ce: 0.0,
            version: Version::Simplified {
                k_cp: 0.0,
                f_0p: 0.0,
            },
            ..l
        };
        let b = wb.branch(am);
        let e2 = (KE * (am - b.alpha_p).powi(2)) / (KP * am * am);
        assert!(close(e2, KP / KE, 1e-12));
    }

    /// The stored energy is a potential of the force along the reversible branch.
    #[test]
    fn stored_energy_is_the_work_along_the_branch() {
        for l in [simplified(), full()] {
            let b = l.branch(0.2e-6);
            let n = 10_000;
            let (x0, x1) = (b.alpha_fp, 0.2e-6);
            let mut w = 0.0;
            for k in 0..n {
                let (a, c) = (
                    x0 + (x1 - x0) * k as f64 / n as f64,
                    x0 + (x1 - x0) * (k + 1) as f64 / n as f64,
                );
                w += 0.5 * (l.on_branch(&b, a).unwrap() + l.on_branch(&b, c).unwrap()) * (c - a);
            }
            assert!(close(l.stored(&b, x1), w, 1e-6), "{} {w}", l.stored(&b, x1));
        }
    }

    #[test]
    fn friction_limits_and_damping() {
        let l = simplified();
        let st = LinState {
            alpha_max: 0.2e-6,
            made: true,
        };
        let lim = l.friction_limit(0.3, 1e-5, 0.1e-6, &st);
        assert!(close(
            lim,
            0.3 * (1e-5 + KCP * 0.1e-6 + F0P - f_ce()),
            1e-12
        ));
        assert_eq!(l.friction_limit(0.3, -1e-3, 0.0, &st), 0.0);
        let lf = full();
        let lim = lf.friction_limit(0.3, 1e-5, 0.1e-6, &st);
        assert!(close(
            lim,
            0.3 * (1e-5 + lf.branch(0.2e-6).f_cp - f_ce()),
            1e-12
        ));
        // (4.25) against the damped oscillator: ζ = β/(2√(m k)), e = exp(−πζ/√(1−ζ²)).
        let (m, k, e) = (2e-6, 1e6, 0.5);
        let z = damping(e, m, k) / (2.0 * (m * k).sqrt());
        assert!(close((-PI * z / (1.0 - z * z).sqrt()).exp(), e, 1e-12));
    }
}
