//! One contact's normal force under the laws of `SET NORmal` other than Hertz/JKR (modified
//! JKR, Thornton–Ning, Pasha's linear laws, LIGGGHTS' JKR of Nguyen et al.; the laws
//! themselves are in `physics`), with
//! their booking: the work the contact force did over the step, `−½(P_old + P_new) v_n Δt`
//! (the form that is exact for the leap-frog update, as for the dashpot), minus the change
//! of the energy the contact stores on its current reversible branch, is the energy lost to
//! plasticity and adhesion hysteresis (`Acc::adhesion`, the ledger's "adhesion" term), so
//! the ledger closes by construction; the stored energy is the law's
//! (`ContactExt::normal`, booked as normal strain).

use super::contacts::{ContactState, NormalHistory};
use super::kinematics::{Acc, Kin, Laws};
use super::params::{PairConst, PairLaw};
use super::scene::Vec3;
use crate::physics::jkr::Jkr;
use crate::physics::jkr_nguyen::NguyenJkr;
use crate::physics::pasha_linear::{self, Lin, Linear, Version};
use crate::physics::thornton_ning::{ThorntonNing, Tn};
use crate::physics::{dashpot, tangential, walton};
use crate::physics::{modified_jkr, pasha_linear::LinState, thornton_ning::TnState};
use crate::sim::model::{NormalLaw, TangentialChoice};

/// What the normal law of one step gives the rest of the contact: the surface energy in use
/// (per surface), the normal stiffness (Rayleigh's β k_n and the linear laws' dashpot), the
/// pull-off force of the tangential laws' limit `P + 2P_c` (JKR-type laws), and, for the
/// linear laws, their own friction limit (Pasha 2013 (4.27)–(4.28)) and tangential stiffness.
pub struct NormalOut {
    pub gamma: f64,
    pub kn: f64,
    pub pcrit: f64,
    pub linear: Option<LinearShear>,
}

/// The tangential spring of a linear-law or Nguyen-JKR contact: stiffness and the limit of
/// its force.
#[derive(Clone, Copy)]
pub struct LinearShear {
    pub k_t: f64,
    pub limit: f64,
    /// The tangential dashpot's coefficient (N·s/m): EDEM's and LIGGGHTS' for `MJKR EDEM`
    /// and `NGUYEN` pairs under `SET TANgential HM`, else 0 (Pasha's linear laws have none).
    pub damp: f64,
}

/// The pair's law (a `PairConst::law` above 0).
#[inline]
pub fn pair_law<'a>(laws: &'a Laws, pc: &PairConst) -> &'a PairLaw {
    &laws.pair_laws[pc.law as usize - 1]
}

/// The linear law of a pair, for a contact of effective radius `r_star`.
fn linear_of(law: &NormalLaw, pc: &PairConst, r_star: f64) -> Option<(Linear, f64)> {
    // f_ce = 3/2 πΓR* (4.1) with Γ = 2γ.
    let f_ce = 3.0 * std::f64::consts::PI * pc.gamma * r_star;
    match *law {
        NormalLaw::PashaFull { k_e, k_p, k_t } => Some((
            Linear {
                k_e,
                k_p,
                f_ce,
                version: Version::Full {
                    r_star,
                    big_gamma: 2.0 * pc.gamma,
                },
            },
            k_t,
        )),
        NormalLaw::PashaSimplified {
            k_e,
            k_p,
            k_cp,
            f_0p,
            k_t,
        } => Some((
            Linear {
                k_e,
                k_p,
                f_ce,
                version: Version::Simplified { k_cp, f_0p },
            },
            k_t,
        )),
        _ => None,
    }
}

/// The normal force of a contact under the pair's law of `SET NORmal`; updates the state
/// (`touching`, `normal_force`, `a`, `overlap`, the law's history) and books the loss.
/// (Out of line: the Hertz and JKR kernels, into which it would otherwise be inlined, keep
/// their code as it was.)
#[inline(never)]
pub fn normal(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    s: &mut ContactState,
    acc: &mut Acc,
    v_n: f64,
) -> NormalOut {
    let alpha = -k.gap;
    let dt = laws.dt;
    let pl = pair_law(laws, pc);
    let was_touching = s.touching;
    let p_old = if was_touching { s.normal_force } else { 0.0 };
    let primed = s.v_prev == f64::NEG_INFINITY;
    let u_old = s.ext().laws().normal.stored();
    let gamma = pc.gamma;
    let mut out = NormalOut {
        gamma,
        kn: 0.0,
        pcrit: 0.0,
        linear: None,
    };
    let hist = s.ext().laws().normal;
    let (now, history) = match pl.law {
        NormalLaw::ModifiedJkr => modified_jkr_step(k, pc, alpha, s.a, &mut out),
        NormalLaw::ModifiedJkrEdem { .. } => {
            let step = modified_jkr_step(k, pc, alpha, s.a, &mut out);
            if let Some((_, a, _)) = step.0 {
                // EDEM's friction: Mindlin's no-slip spring 8G*a capped at μ times the
                // Hertzian part 4E*a³/(3R*) of the force (doc/contact_laws.md).
                out.linear = Some(LinearShear {
                    k_t: 8.0 * pc.g_star * a,
                    limit: pc.mu * walton::friction_normal_force(pc.e_star, k.r_star, a),
                    damp: 0.0,
                });
            }
            step
        }
        NormalLaw::ThorntonNing { p_y } => {
            thornton_ning_step(k, pc, p_y, (alpha, was_touching, s.a), hist, &mut out)
        }
        NormalLaw::Nguyen => nguyen_step(k, pc, pl.wall, alpha, s.a, &mut out),
        ref law => linear_step(k, pc, law, (alpha, was_touching), hist, &mut out),
    };
    if laws.tangential == TangentialChoice::HertzMindlin
        && matches!(
            pl.law,
            NormalLaw::ModifiedJkrEdem { .. } | NormalLaw::Nguyen
        )
        && let Some(ls) = out.linear.as_mut()
    {
        // EDEM's and LIGGGHTS' tangential dashpot on Mindlin's spring.
        ls.damp = dashpot::tangential_coefficient(pc.zeta, k.m_star, ls.k_t);
    }
    match now {
        Some((f, a, _)) => {
            if !was_touching && dt == 0.0 {
                // Made while priming: its force acts from the next step on (see the JKR
                // snap-in in `interact`).
                s.v_prev = f64::NEG_INFINITY;
            }
            s.touching = true;
            s.normal_force = f;
            s.a = a;
        }
        None => {
            if was_touching {
                s.touching = false;
                s.normal_force = 0.0;
                s.a = 0.0;
            }
        }
    }
    let u_new = history.stored();
    if !history.is_none() || s.ext.as_ref().is_some_and(|e| e.laws.is_some()) {
        s.ext_mut().laws_mut().normal = history;
    }
    if dt > 0.0 {
        let p_acted = if primed { 0.0 } else { p_old };
        let p_new = if s.touching { s.normal_force } else { 0.0 };
        let work = -0.5 * (p_acted + p_new) * v_n * dt;
        acc.adhesion += work - (u_new - u_old);
    }
    if was_touching && !s.touching {
        super::kinematics::reset_solid(s, acc);
    }
    s.overlap = alpha;
    out
}

/// One law's step: (force, contact radius, stored energy) while in contact, and the
/// history the contact keeps.
type LawStep = (Option<(f64, f64, f64)>, NormalHistory);

/// The modified JKR of EDEM (`physics::modified_jkr`) at overlap `alpha`, contact radius
/// `a_old` of the last step.
#[inline(always)]
fn modified_jkr_step(
    k: &Kin,
    pc: &PairConst,
    alpha: f64,
    a_old: f64,
    out: &mut NormalOut,
) -> LawStep {
    let j = Jkr {
        e_star: pc.e_star,
        r_star: k.r_star,
        gamma: out.gamma,
    };
    let now =
        modified_jkr::force(&j, alpha, a_old).map(|(f, a)| (f, a, modified_jkr::stored(&j, a)));
    let history = match now {
        Some((_, _, stored)) => NormalHistory::ModifiedJkr { stored },
        None => NormalHistory::None,
    };
    if let Some((_, a, _)) = now {
        out.kn = j.stiffness_of_a(a).abs();
        out.pcrit = j.pc();
    }
    (now, history)
}

/// Thornton–Ning's elasto-plastic adhesive law (`physics::thornton_ning`) with yield
/// pressure `p_y`; `(alpha, was_touching, a_old)` as in [`normal`].
#[inline(always)]
fn thornton_ning_step(
    k: &Kin,
    pc: &PairConst,
    p_y: f64,
    (alpha, was_touching, a_old): (f64, bool, f64),
    hist: NormalHistory,
    out: &mut NormalOut,
) -> LawStep {
    let gamma = out.gamma;
    let t = ThorntonNing {
        e_star: pc.e_star,
        r_star: k.r_star,
        gamma,
        p_y,
    };
    let mut st = match hist {
        NormalHistory::ThorntonNing { st, .. } => st,
        _ => TnState::default(),
    };
    let r = t.step(&mut st, alpha, was_touching, a_old);
    let now = match r {
        Tn::Contact { force, a, stored } => Some((force, a, stored)),
        Tn::Apart => None,
    };
    let history = NormalHistory::ThorntonNing {
        st,
        stored: now.map_or(0.0, |x| x.2),
    };
    if let Some((_, a, _)) = now {
        let j = Jkr {
            e_star: pc.e_star,
            r_star: st.r_p,
            gamma,
        };
        out.kn = j.stiffness_of_a(a).abs();
        out.pcrit = t.f_cp(&st);
    }
    (now, history)
}

/// LIGGGHTS' JKR (Nguyen et al. 2014; `physics::jkr_nguyen`): the JKR curve above α_s (at a
/// wall, `wall`, above 0), approaching and separating alike; the energy on the curve, zero
/// where the force vanishes (`Jkr::energy_of_a`: U(a_s) = 0; at a wall U(a) − U(a_0), as
/// the modified JKR). Its own tangential spring: Mindlin's 8G*sqrt(R*α) capped at μ F_Hertz(α),
/// none in the neck (α ≤ 0).
#[inline(always)]
fn nguyen_step(
    k: &Kin,
    pc: &PairConst,
    wall: bool,
    alpha: f64,
    a_old: f64,
    out: &mut NormalOut,
) -> LawStep {
    let law = NguyenJkr {
        jkr: Jkr {
            e_star: pc.e_star,
            r_star: k.r_star,
            gamma: out.gamma,
        },
        wall,
    };
    let now = law.contact(alpha, a_old);
    let history = match now {
        Some((_, _, stored)) => NormalHistory::Nguyen { stored },
        None => NormalHistory::None,
    };
    if let Some((_, a, _)) = now {
        out.kn = law.jkr.stiffness_of_a(a).abs();
        out.pcrit = law.jkr.pc();
        out.linear = Some(LinearShear {
            k_t: law.tangential_stiffness(pc.g_star, alpha),
            limit: law.friction_bound(pc.mu, alpha),
            damp: 0.0,
        });
    }
    (now, history)
}

/// Pasha's linear elasto-plastic adhesive laws (`physics::pasha_linear`), with their own
/// tangential spring and limit (`out.linear`).
#[inline(always)]
fn linear_step(
    k: &Kin,
    pc: &PairConst,
    law: &NormalLaw,
    (alpha, was_touching): (f64, bool),
    hist: NormalHistory,
    out: &mut NormalOut,
) -> LawStep {
    // (Invariant: only Pasha's linear laws come here: the others have arms of their own in
    // `normal`, and Hertz has law index 0, which never calls it, `params`.)
    let (l, k_t) = linear_of(law, pc, k.r_star).expect("a linear law");
    let mut st = match hist {
        NormalHistory::Linear { st, .. } => st,
        _ => LinState::default(),
    };
    let r = l.step(&mut st, alpha, was_touching);
    let mut stored = 0.0;
    let now = match r {
        Lin::Contact {
            force,
            k_n,
            stored: u,
        } => {
            out.kn = k_n;
            stored = u;
            out.linear = Some(LinearShear {
                k_t,
                limit: l.friction_limit(pc.mu, force, alpha, &st),
                damp: 0.0,
            });
            Some((force, 0.0, u))
        }
        Lin::Apart => None,
    };
    (now, NormalHistory::Linear { st, stored })
}

/// The tangential force on B of a linear-law contact: the spring `F_t = k_t α_t` (4.26)
/// with the limit (4.27)–(4.28) (`tangential::noslip_spring` with stiffness `k_t`), the
/// friction booked as work minus the change of the stored energy; the tangential dashpot
/// `−ls.damp v_t` while the spring holds, booked as contact damping (none for Pasha's laws:
/// the thesis gives none; then the last step's Rayleigh force, if any, gets its second half).
#[inline(never)]
pub fn shear(k: &Kin, dt: f64, s: &mut ContactState, acc: &mut Acc, ls: LinearShear) -> Vec3 {
    let n = k.n;
    // The last force rotated into the contact plane, as for the other laws.
    s.tforce = Vec3::from(tangential::rotate_into_plane_lazy(
        s.tforce.into(),
        n.into(),
    ));
    let v_t = k.v_rel - n * k.v_rel.dot(&n);
    let dd = v_t * dt;
    let step = tangential::noslip_spring(s.tforce.into(), dd.into(), ls.k_t, 1.0, ls.limit);
    acc.friction += step.work - (step.energy - s.tang_energy);
    s.tang_energy = step.energy;
    s.tforce = Vec3::from(step.force);
    // The dashpot while the spring holds (a sliding contact's force is the cap alone).
    let damped = ls.damp > 0.0 && !step.slid;
    let td = if damped {
        -v_t * ls.damp
    } else {
        Vec3::zeros()
    };
    acc.damping_contact += -0.5 * (td + s.tdamp).dot(&v_t) * dt;
    if dt > 0.0 {
        s.tdamp = td;
    }
    if damped { s.tforce + td } else { s.tforce }
}

/// The dashpot coefficient of a linear-law contact, Pasha 2013 (4.24)–(4.25), with the
/// stiffness of the branch in use; 0 without a restitution coefficient.
#[inline]
pub fn linear_damping(laws: &Laws, pc: &PairConst, kn: f64, m_star: f64) -> f64 {
    let e = pair_law(laws, pc).restitution;
    if e > 0.0 && e < 1.0 {
        pasha_linear::damping(e, m_star, kn)
    } else {
        0.0
    }
}
