//! The force of one contact (particle–particle or particle–wall): normal law (Hertz or JKR),
//! contact damping, tangential law, and the liquid bridge. Lian §5.6.2 (with the sign
//! corrections of doc/spec/physics-lian1994.md §2.4) and §5.7.

use super::contacts::{BridgeState, ContactState, JkrRow, Rows, new_jkr_row};
use super::kinematics::reset_solid;
pub use super::kinematics::{Acc, Kin, Laws, Out};
use super::params::PairConst;
use super::scene::Vec3;
use crate::physics::bridge::{self, Bridge};
use crate::physics::hertz_edge::{EdgeIn, edge_step};
use crate::physics::jkr::{Jkr, LeapFrog, PathStart};
use crate::physics::jkr_branch::{t_of_a, taylor_start};
use crate::physics::mdr::MdrRow;
use crate::physics::tangential::{self, TangentialInput};
use crate::physics::walton::{self, WaltonInput};
use crate::physics::{dashpot, hertz};
use crate::sim::model::{TangentialChoice, bridge_model, smin_ratio, tangential_viscous};

/// Computes the contact force and updates the contact state.
///
/// The kernel is specialised per scene ("model only what a scene needs"): `ADH` false is for
/// scenes whose materials have no surface energy (contacts are Hertzian; a contact still
/// adhering from an earlier `Cycle` is handed to the adhesive kernel), `LIQ` false for scenes
/// without `LIQuid`. Each specialisation does exactly the arithmetic of the general kernel
/// for the contacts it handles, so results do not depend on the choice.
#[inline(always)]
pub fn interact<const ADH: bool, const LIQ: bool>(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    s: &mut ContactState,
    acc: &mut Acc,
) -> Out {
    interact_rows::<ADH, LIQ>(k, pc, laws, s, None, acc)
}

/// [`interact`] for a contact whose MDR spring row and JKR row are kept in `rows` (a
/// particle pair: the row lists of its block, `contacts::StateBlock`) rather than in its
/// `ext` (`None`).
#[inline(always)]
pub fn interact_rows<const ADH: bool, const LIQ: bool>(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    s: &mut ContactState,
    rows: Option<Rows<'_>>,
    acc: &mut Acc,
) -> Out {
    if !ADH && s.touching && s.needs_adhesive_kernel() {
        return interact_rows::<true, LIQ>(k, pc, laws, s, rows, acc);
    }
    let (rows, jkr_rows) = match rows {
        Some(r) => (Some(r.mdr), Some(r.jkr)),
        None => (None, None),
    };
    let alpha = -k.gap;
    let dt = laws.dt;
    let v_n = k.v_rel.dot(&k.n); // separation rate (positive = opening)
    let mut fn_b = 0.0; // normal force on B along n (positive = pushes B away)

    // Forces of the previous step: energy is booked as ½(F_old + F_new)·v Δt with the
    // velocity of the half step between them, which is exact for the leap-frog scheme
    // (the sum telescopes to Σ F_n·v̄_n Δt).
    let fd_prev = s.damp_force;
    let td_prev = s.tdamp;

    // ---- normal law -----------------------------------------------------------------
    let p_old = s.normal_force;
    let was_touching = s.touching;
    let (alpha_prev, v_prev) = (s.overlap, s.v_prev);
    // The laws of `SET NORmal` (sim::elastoplastic) or Hertz/JKR.
    let (gamma, kn, pcrit, lin_shear, jkr) = if ADH && pc.law != 0 {
        let o = super::elastoplastic::normal(k, pc, laws, s, acc, v_n);
        (o.gamma, o.kn, o.pcrit, o.linear, false)
    } else {
        let (g, kn, pcrit) = normal_law::<ADH>(k, pc, laws, (s, jkr_rows), acc, v_n);
        (g, kn, pcrit, None, ADH && g > 0.0 && s.touching)
    };

    // ---- liquid bridge: formation, rupture, capillary force ------------------------------
    // (Its viscous force is worked out with the other velocity-dependent forces below.)
    let (bridge_prev, bridge_static, bridge_c, sgap) = bridge_now::<LIQ>(k, laws, s, acc, v_n);

    // ---- velocity-dependent normal forces (physics::dashpot) ---------------------------------
    let (fd, fv) = viscous_normal::<ADH>(
        k,
        pc,
        laws,
        s,
        &Normal {
            alpha,
            v_n,
            p_old,
            was_touching,
            gamma,
            kn,
            linear: lin_shear.is_some(),
            jkr,
        },
        (fd_prev, bridge_prev, bridge_static, bridge_c),
    );

    if s.touching || fd != 0.0 || fd_prev != 0.0 {
        // Solid contact (or its approach): the dashpot's booking, the last step's second half
        // when it has ended.
        if s.touching {
            fn_b += s.normal_force;
        }
        // While priming (Δt = 0: states only, nothing moves) the forces of the last real
        // step are kept, since they are the ones the next booking must pair with.
        if dt > 0.0 {
            s.damp_force = fd;
        }
        acc.damping_contact += -0.5 * (fd + fd_prev) * v_n * dt;
        fn_b += fd;
    }
    if edges(pc, laws, s) {
        // An elastic contact: the corrections of its edges (`physics::hertz_edge`).
        let (d, keep) = edge_step(
            pc.e_star,
            k.r_star,
            &EdgeIn {
                alpha,
                alpha_prev,
                was_touching,
                v_n,
                v_prev,
                p_prev: p_old,
                m_star: k.m_star,
                dt,
            },
        );
        s.v_prev = keep;
        fn_b += d;
    }
    // ---- tangential law ---------------------------------------------------------------
    let mut ft_b = match lin_shear {
        // Pasha's linear laws: their own spring and limit (sim::elastoplastic).
        Some(ls) if ADH && laws.rotation => super::elastoplastic::shear(k, laws.dt, s, acc, ls),
        _ => shear(k, pc, laws, (s, rows), acc, (p_old, pcrit, td_prev, v_n)),
    };

    // ---- liquid bridge: viscous forces and booking -------------------------------------
    if let Some((fn_bridge, ft)) =
        bridge_forces::<LIQ>(k, laws, s, acc, v_n, (bridge_static, fv, sgap))
    {
        ft_b += ft;
        fn_b += fn_bridge;
    }

    Out {
        f: k.n * fn_b + ft_b,
        ft: ft_b,
    }
}

/// Whether a contact takes the corrections of its edges (`physics::hertz_edge`): in a step of
/// a scene without damping or liquid (`Laws::edges`), a Hertz contact without a dashpot,
/// friction, adhesion or another normal law. Why: where an elastic contact starts and ends
/// within a step the leap-frog impulses miss its strain energy by up to ±2.6e-3 of a
/// collision's energy at FRAction 0.2, with a mean that a gas adds up collision after
/// collision (issue 49 item 4; doc/limits.md, "Energy drift of an elastic gas"). The
/// contacts of the other scenes are as before, bit for bit.
#[inline(always)]
fn edges(pc: &PairConst, laws: &Laws, s: &ContactState) -> bool {
    laws.edges
        && pc.zeta == 0.0
        && pc.mu == 0.0
        && pc.gamma == 0.0
        && pc.gamma_base == 0.0
        && pc.law == 0
        && s.bridge.is_none()
}

/// What the normal law left for the velocity-dependent forces of one contact.
struct Normal {
    /// Overlap (negative: gap) and separation rate (positive: opening).
    alpha: f64,
    v_n: f64,
    /// The elastic normal force of the last step.
    p_old: f64,
    was_touching: bool,
    /// Surface energy of the contact (0: the dashpot never pulls).
    gamma: f64,
    /// Normal stiffness (Rayleigh's β k_n).
    kn: f64,
    /// One of Pasha's linear laws, with its own dashpot.
    linear: bool,
    /// A touching JKR contact: it keeps `v_prev` for its next path (`Jkr::leap_frog_force`).
    jkr: bool,
}

/// The velocity-dependent normal forces of one contact (`physics::dashpot`): the restitution
/// dashpot D (R*α)^{1/4} α' while touching, and while approaching within half a step's
/// travel (its share of the step in which the contact starts); Rayleigh's β k_n; the
/// bridge's viscous force (`bridge_c`). One implicit midpoint velocity for all of them.
/// Returns the dashpot's and the bridge's viscous force; `prev` = (the last step's dashpot
/// force, bridge force, the bridge's static force, its viscous coefficient).
#[inline(always)]
fn viscous_normal<const ADH: bool>(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    s: &mut ContactState,
    nl: &Normal,
    (fd_prev, bridge_prev, bridge_static, bridge_c): (f64, f64, f64, f64),
) -> (f64, f64) {
    let Normal {
        alpha,
        v_n,
        p_old,
        was_touching,
        gamma,
        kn,
        linear,
        jkr,
    } = *nl;
    let dt = laws.dt;
    let approaching = !s.touching && v_n < 0.0 && alpha - v_n * (0.5 * dt) > 0.0;
    let dashed = pc.zeta > 0.0 && (s.touching || approaching);
    let mut rayleigh = if laws.beta > 0.0 && s.touching {
        laws.beta * kn
    } else {
        0.0
    };
    if ADH && pc.law != 0 && linear {
        // The linear laws' dashpot β (Pasha 2013 (4.24)–(4.25)), a linear coefficient like
        // Rayleigh's β k_n (with which it is booked as contact damping).
        rayleigh += super::elastoplastic::linear_damping(laws, pc, kn, k.m_star);
    }
    let viscous = dashed || rayleigh > 0.0 || bridge_c > 0.0;
    let (mut fd, mut fv) = (0.0, 0.0);
    if viscous {
        // (While priming, Δt = 0, the step degenerates to the dashpot at α with v: the
        // forces shown, nothing integrated.)
        let inv_m = 1.0 / k.m_star;
        let drive = if dt > 0.0 {
            let f_prev = p_old + fd_prev + bridge_prev;
            let f_static = if s.touching { s.normal_force } else { 0.0 } - bridge_static;
            dashpot::drive(f_static, f_prev, v_n, s.v_prev, inv_m, 1.0 / dt)
        } else {
            0.0
        };
        let linear = rayleigh + bridge_c;
        let (coef, vn) = if dashed {
            // (R* α)^{1/2}: the Hertz contact radius.
            let a_h = (k.r_star * alpha).sqrt();
            dashpot::viscous_step(&dashpot::ViscousIn {
                alpha,
                v: v_n,
                drive,
                dash: pc.dash,
                scale: k.m_star * k.m_star * k.r_star,
                steady: was_touching && alpha > 0.0,
                point: (k.m_star * a_h).sqrt(),
                linear,
                inv_m,
                dt,
            })
        } else {
            // A linear coefficient alone (a bridge's, Rayleigh's): `viscous_step`'s implicit
            // step with the dashpot's coefficient 0, the same arithmetic without the means
            // of α^{1/4} it would multiply by 0 (four fourth roots).
            let h = 0.5 * dt;
            (0.0, (v_n + h * drive) / (1.0 + h * (0.0 + linear) * inv_m))
        };
        fd = 0.0 - coef * vn;
        if rayleigh > 0.0 {
            fd -= rayleigh * vn;
        }
        // The tension clamp of the restitution model: the dashpot never pulls a
        // non-adhesive contact (nor a pair that is only approaching), unless the pair's
        // dashpot form lets it (SET DASHpot LIGGGHTS, while touching).
        let p = if s.touching { s.normal_force } else { 0.0 };
        if gamma == 0.0 && !(pc.pull && s.touching) && p + fd < 0.0 {
            fd = -p;
        }
        fv = 0.0 - bridge_c * vn;
        if dt > 0.0 {
            s.v_prev = v_n;
        }
    } else if dt > 0.0 {
        s.v_prev = if jkr { v_n } else { f64::INFINITY };
    }
    (fd, fv)
}

/// The tangential force on B of a touching contact (`tangential_step`), or, for a contact
/// that has ended, the booking of its last tangential dashpot force's second half.
#[inline(always)]
fn shear(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    (s, rows): (&mut ContactState, Option<&mut Vec<MdrRow>>),
    acc: &mut Acc,
    (p_old, pcrit, td_prev, v_n): (f64, f64, Vec3, f64),
) -> Vec3 {
    let dt = laws.dt;
    if s.touching {
        if laws.rotation && (pc.mu > 0.0 || pcrit > 0.0) {
            return tangential_step(k, pc, laws, (s, rows), p_old, pcrit, acc);
        }
    } else if dt > 0.0 && td_prev != Vec3::zeros() {
        // The contact ended: book the second half of the last tangential dashpot force.
        let v_t = k.v_rel - k.n * v_n;
        acc.damping_contact += -0.5 * td_prev.dot(&v_t) * dt;
        s.tdamp = Vec3::zeros();
    }
    Vec3::zeros()
}

/// The normal law of a contact at this step: JKR (snap-in, the mean force over the step's
/// path on its curve, detachment at α_s, Lian 1994 (3.24), (3.29) corrected, (3.38),
/// (3.114)–(3.119); `Jkr::step_force`) or Hertz (3.14)–(3.15); books the peeling work W_p
/// lost at detachment. Returns the surface energy in use, the normal
/// stiffness (for Rayleigh's β k_n) and the pull-off force P_c (0 without adhesion).
/// `rows`: the JKR row list of a particle pair's block (`contacts::JkrRow`), where a touching
/// JKR pair keeps its γ, a_s and path end; `None` for a particle–wall contact (`ext`).
#[inline(always)]
fn normal_law<const ADH: bool>(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    (s, mut rows): (&mut ContactState, Option<&mut Vec<JkrRow>>),
    acc: &mut Acc,
    v_n: f64,
) -> (f64, f64, f64) {
    let alpha = -k.gap;
    let dt = laws.dt;
    let p_old = s.normal_force;
    let was_touching = s.touching;
    // A touching contact keeps its own γ; a new one takes the material value, or the base
    // value after an impact (`VELocity ... 1`, Lian App. B).
    let gamma = if !ADH {
        0.0
    } else if s.touching {
        match s.row.jkr().and_then(|r| rows.as_deref()?.get(r)) {
            Some(row) => row.gamma,
            None => s.gamma(),
        }
    } else if laws.impact {
        pc.gamma_base
    } else {
        pc.gamma
    };
    let mut kn = 0.0;
    let mut pcrit = 0.0;
    if gamma > 0.0 {
        let j = Jkr {
            e_star: pc.e_star,
            r_star: k.r_star,
            gamma,
        };
        if !s.touching && alpha >= 0.0 {
            snap_in(&j, (s, rows.as_deref_mut()), dt);
        }
        if s.touching {
            // The contact's separation radius and path end: its row's (a particle pair's),
            // or its extension's.
            let slot = s.row.jkr();
            let (a_s, path_end) = match slot.and_then(|r| rows.as_deref()?.get(r)) {
                Some(row) => (row.a_s, row.end),
                None => (s.ext().a_s, s.ext().end),
            };
            let b = j.branch(a_s);
            // The step's path starts at α_{n−1/2} = α + v Δt/2 (α itself while priming).
            let lo = alpha + 0.5 * v_n * dt;
            if was_touching && lo < b.alpha_s {
                // Detachment at α_s (3.38): the last step's path ended beyond it, at
                // E(α_s) = W_p, which is lost (3.119). (While priming: the energy it had.)
                acc.adhesion += if dt > 0.0 {
                    b.w_p
                } else {
                    super::energy::normal_strain(s, pc.e_star, k.r_star)
                };
                reset_solid(s, acc);
            } else {
                // (3.29) at α_n, started from the last step's root (at its overlap; a new
                // contact's at α = 0, a_0) by the inverse's Taylor polynomial.
                let t_old = t_of_a(b.a_s, s.a);
                let alpha_old = if was_touching { s.overlap } else { 0.0 };
                let t = j.solve_t(&b, alpha, taylor_start(t_old, (alpha - alpha_old) * b.c_d));
                s.a = b.radius(t);
                s.normal_force = b.force(t);
                if dt > 0.0 {
                    // The mean force over the step's path (`Jkr::leap_frog_force`).
                    let from = PathStart::of(s.v_prev == f64::NEG_INFINITY, was_touching);
                    let x = LeapFrog {
                        alpha,
                        lo,
                        v: v_n,
                        dt,
                        m_star: k.m_star,
                        p_old,
                        v_prev: s.v_prev,
                        f_damp: s.damp_force,
                        from,
                        end: path_end,
                    };
                    let (p, end) = j.leap_frog_force(&b, t, &x);
                    s.normal_force = p;
                    match slot.and_then(|r| rows?.get_mut(r)) {
                        Some(row) => row.end = end,
                        None => s.ext_mut().end = end,
                    }
                }
                if laws.beta > 0.0 {
                    kn = b.stiffness(t).abs();
                }
                pcrit = j.pc();
            }
        }
    } else if alpha > 0.0 {
        if !s.touching {
            s.touching = true;
            if let Some(e) = s.ext.as_deref_mut() {
                e.gamma = 0.0;
                e.laws = None;
            }
        }
        // Hertz (3.14)-(3.15): P = 4/3 E* a³/R* = 4/3 E* a α, k_n = 2 E* a.
        let (a, p) = hertz::radius_and_force(pc.e_star, k.r_star, alpha);
        s.a = a;
        s.normal_force = p;
        kn = 2.0 * pc.e_star * a;
    } else if s.touching {
        reset_solid(s, acc);
    }
    s.overlap = alpha;
    (gamma, kn, pcrit)
}

/// JKR snap-in at first touch: a = a0, P = −8/9 Pc (doc/spec/DECISIONS.md). The separation
/// radius a_s (3.117) is computed once here, and a particle pair gets its JKR row (`rows`).
#[inline(always)]
fn snap_in(j: &Jkr, (s, rows): (&mut ContactState, Option<&mut Vec<JkrRow>>), dt: f64) {
    s.touching = true;
    s.a = j.a0();
    let e = s.ext_mut();
    e.gamma = j.gamma;
    e.a_s = j.a_s();
    e.laws = None;
    e.end = None;
    let row = JkrRow::of(e);
    if let Some(rows) = rows {
        new_jkr_row(s, rows, row);
    }
    if dt == 0.0 {
        // Snapped in while priming: its force has not acted yet (`normal_law`).
        s.v_prev = f64::NEG_INFINITY;
    }
}

/// The liquid bridge at this step: formed on solid contact, ruptured beyond S_c (its work
/// booked, Lian 1994 §5.7), else its capillary force and viscous coefficient. Returns the
/// bridge's normal force of the last step, the capillary force now (attractive magnitude),
/// the viscous coefficient 6πηR*²/max(S, S_min) and the gap S used.
#[inline(always)]
fn bridge_now<const LIQ: bool>(
    k: &Kin,
    laws: &Laws,
    s: &mut ContactState,
    acc: &mut Acc,
    v_n: f64,
) -> (f64, f64, f64, f64) {
    let dt = laws.dt;
    let mut bridge_prev = 0.0; // the bridge's normal force of the last step
    let mut bridge_static = 0.0; // capillary force of this step (attractive magnitude)
    let mut bridge_c = 0.0; // viscous coefficient 6πηR*²/max(S, S_min)
    let mut sgap = 0.0;
    if let Some(liq) = laws.liquid.filter(|_| LIQ) {
        // Formation on solid contact (doc/spec/DECISIONS.md); touching within round-off counts.
        if s.bridge.is_none() && liq.pvol > 0.0 && k.gap <= 1e-6 * k.r1 {
            let (volume, share) = match laws.liquid_share {
                // Lian: the nominal volume, pvol % of the mean volume of the two spheres.
                None => (super::liquid::bridge_volume(liq.pvol, k.r1, k.r2), [0.0; 2]),
                // Conserving mode: each particle gives a share of its own liquid (the session
                // settles the draws after the step, see sim::liquid::settle).
                Some(f) => {
                    let d = super::liquid::share_request(f, liq.pvol, k.r1, k.r2);
                    (d[0] + d[1], d)
                }
            };
            s.bridge = Some(Box::new(BridgeState::new(
                bridge_model(laws.bridge),
                Bridge {
                    r1: k.r1,
                    r2: k.r2,
                    volume,
                    gamma: liq.gamma,
                    theta: liq.theta,
                },
                k.gap,
                share,
            )));
        }
        if let Some(bs) = s.bridge.as_deref_mut() {
            if bs.coeffs.model() != bridge_model(laws.bridge) {
                bs.rebuild(bridge_model(laws.bridge));
            }
            bridge_prev = bs.f_visc - bs.f_static;
            if k.gap > bs.s_c {
                // Rupture: the work done against the bridge is lost (Lian §5.7); book the
                // second half of the last step's forces.
                bs.work += 0.5 * bs.f_static * v_n * dt;
                acc.viscous += -0.5 * bs.f_visc * v_n * dt;
                acc.viscous += -0.5 * bs.f_tang.dot(&(k.v_rel - k.n * v_n)) * dt;
                acc.rupture += bs.work;
                if bs.share != [0.0; 2] {
                    s.ext_mut().released = bs.share;
                }
                s.bridge = None;
            } else {
                sgap = k.gap.max(0.0);
                bridge_static = bs.coeffs.force(sgap);
                if liq.eta > 0.0 {
                    bridge_c = bridge::viscous_normal_coefficient(
                        liq.eta,
                        k.r_star,
                        sgap,
                        laws.smin.unwrap_or(smin_ratio(laws.bridge) * k.r_star),
                    );
                }
            }
        }
    }
    (bridge_prev, bridge_static, bridge_c, sgap)
}

/// The bridge's forces of this step and their booking: the work against the capillary force
/// (stored until rupture) and the viscous loss as ½(F_old + F_new)·v_n Δt, Goldman's
/// tangential viscous force (4.76) (its moment (4.77) is not applied, doc/bridge.md).
/// Returns the bridge's net normal force on B (viscous − capillary) and its tangential
/// force, if the pair has a bridge.
#[inline(always)]
fn bridge_forces<const LIQ: bool>(
    k: &Kin,
    laws: &Laws,
    s: &mut ContactState,
    acc: &mut Acc,
    v_n: f64,
    (bridge_static, fv, sgap): (f64, f64, f64),
) -> Option<(f64, Vec3)> {
    let dt = laws.dt;
    let liq = laws.liquid.filter(|_| LIQ)?;
    let bs = s.bridge.as_deref_mut()?;
    // Work done against the attractive force while opening (stored) and the viscous
    // loss, booked as ½(F_old + F_new)·v_n Δt.
    let fs = bridge_static;
    bs.work += 0.5 * (fs + bs.f_static) * v_n * dt;
    acc.viscous += -0.5 * (fv + bs.f_visc) * v_n * dt;
    // Goldman's tangential viscous force (4.76), opposing the relative
    // tangential motion; its moment (4.77) is not applied (doc/bridge.md).
    let v_t = k.v_rel - k.n * v_n;
    let vt = if tangential_viscous(laws.goldman, laws.bridge) && liq.eta > 0.0 {
        v_t.norm()
    } else {
        0.0
    };
    let ft = if vt > 0.0 {
        let smin = laws.smin.unwrap_or(smin_ratio(laws.bridge) * k.r_star);
        let (t, _) = bridge::viscous_tangential(liq.eta, k.r_star, vt, sgap, smin);
        v_t * (t / vt)
    } else {
        Vec3::zeros()
    };
    acc.viscous += -0.5 * (ft + bs.f_tang).dot(&v_t) * dt;
    if dt > 0.0 {
        bs.f_static = fs;
        bs.f_visc = fv;
        bs.f_tang = ft;
    }
    bs.gap = k.gap;
    Some((fv - fs, ft))
}

/// Tangential force on B: rotate the history into the current contact plane, advance the
/// signed resultant displacement (Lian (5.22)–(5.26), corrected sign rule of
/// doc/spec/physics-lian1994.md §2.4 item 6) and apply the chosen law (Walton's law works on
/// the force vector itself, Shang 1998 (2.30)–(2.38)).
#[inline(always)]
fn tangential_step(
    k: &Kin,
    pc: &PairConst,
    laws: &Laws,
    (s, rows): (&mut ContactState, Option<&mut Vec<MdrRow>>),
    p_old: f64,
    pcrit: f64,
    acc: &mut Acc,
) -> Vec3 {
    let dt = laws.dt;
    let n = k.n;
    // Rotation of the contact plane (5.19)–(5.21): project the old vectors on the new plane
    // and keep their lengths.
    let rotate = |v: Vec3| Vec3::from(tangential::rotate_into_plane_lazy(v.into(), n.into()));
    s.tforce = rotate(s.tforce);
    let v_t = k.v_rel - n * k.v_rel.dot(&n);
    let dd = v_t * dt;
    let p_new = s.normal_force;
    let kt0 = 8.0 * pc.g_star * s.a;
    let mut slid = false;
    match laws.tangential {
        TangentialChoice::NoSlip | TangentialChoice::HertzMindlin => {
            // Mindlin no-slip spring k_t = 8 G* a with a Coulomb cap μ P_e (vector form).
            let pe = p_new + 2.0 * pcrit;
            let step = tangential::noslip_spring(s.tforce.into(), dd.into(), kt0, pc.mu, pe);
            slid = step.slid;
            // Energy: work done on the spring minus the change of its stored energy.
            acc.friction += step.work - (step.energy - s.tang_energy);
            s.tang_energy = step.energy;
            s.tforce = Vec3::from(step.force);
        }
        TangentialChoice::Mdr if pc.law == 0 && pcrit == 0.0 && s.gamma() == 0.0 => {
            // The MDR spring row of a Hertz contact (sim::mdr).
            super::mdr::shear(k, pc, s, rows, dd, acc);
        }
        TangentialChoice::Md | TangentialChoice::Mdr => {
            // (Under MDR: the pairs with a surface energy or a law of `SET NORmal`.)
            let t_old = s.tforce;
            let (a, tang_energy) = (s.a, s.tang_energy);
            let e = s.ext_mut();
            let old_vec = rotate(e.delta);
            let new_vec = old_vec + dd;
            let old_len = e.tdelta;
            let sign_old = if old_len < 0.0 { -1.0 } else { 1.0 };
            let dir = if old_vec.dot(&new_vec) < 0.0 {
                -1.0
            } else {
                1.0
            };
            let new_len = sign_old * dir * new_vec.norm();
            let inp = TangentialInput {
                g_star: pc.g_star,
                mu: pc.mu,
                a,
                p_old,
                p_new,
                pc: pcrit,
                e_star: pc.e_star,
                d_delta: new_len - old_len,
            };
            let out = tangential::mindlin_deresiewicz(&mut e.tang, &inp);
            e.tdelta = new_len;
            // Direction of the positive resultant: δ/δ_signed.
            let unit = if new_len != 0.0 {
                new_vec / new_len
            } else if t_old.norm() > 0.0 {
                -t_old / t_old.norm()
            } else {
                Vec3::zeros()
            };
            // The elastic force acts along δ on the contact; on B it opposes B's slip.
            let f = -unit * e.tang.t;
            let work = -0.5 * (t_old + f).dot(&dd);
            let e_new = tangential::stored_energy(&e.tang);
            let _ = out;
            e.delta = new_vec;
            acc.friction += work - (e_new - tang_energy);
            s.tang_energy = e_new;
            s.tforce = f;
        }
        TangentialChoice::Walton => {
            // Shang's friction bound: the Hertz part P_E of a JKR force, P for Hertz (§2.2.2).
            let f_n = if s.gamma() > 0.0 {
                walton::friction_normal_force(pc.e_star, k.r_star, s.a)
            } else {
                p_new
            };
            // Shang's T is the force on A (it grows along Δs, B's slip relative to A).
            let inp = WaltonInput {
                force: (-s.tforce).into(),
                ds: dd.into(),
                f_n,
                k0: walton::initial_stiffness(pc.g_star, s.a),
                mu: pc.mu,
            };
            let tang_energy = s.tang_energy;
            let e = s.ext_mut();
            let out = walton::step(&mut e.walton, &inp);
            let e_new = e.walton.stored;
            acc.friction += out.work - (e_new - tang_energy);
            s.tang_energy = e_new;
            s.tforce = -Vec3::from(out.force);
        }
    }
    let mut ft = s.tforce;
    // Rayleigh's β k_t, and under `SET TANgential HM` the Hertz–Mindlin dashpot of EDEM and
    // LIGGGHTS, ζ (2/3 m* k_t)^{1/2} (`dashpot::tangential_coefficient`), while the spring
    // holds (a sliding contact's force is the Coulomb cap alone, as LIGGGHTS has it).
    let mut c_t = laws.beta * kt0;
    if laws.tangential == TangentialChoice::HertzMindlin && !slid {
        c_t += dashpot::tangential_coefficient(pc.zeta, k.m_star, kt0);
    }
    let td = if c_t > 0.0 { -v_t * c_t } else { Vec3::zeros() };
    ft += td;
    acc.damping_contact += -0.5 * (td + s.tdamp).dot(&v_t) * dt;
    if dt > 0.0 {
        s.tdamp = td;
    }
    ft
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::contacts::ContactExt;

    fn laws() -> Laws<'static> {
        Laws::dry(1e-6, TangentialChoice::Md)
    }

    fn kin(gap: f64) -> Kin {
        Kin {
            n: Vec3::new(0.0, 0.0, 1.0),
            gap,
            v_rel: Vec3::new(0.1, 0.0, 0.0),
            r_star: 5e-4,
            m_star: 1e-5,
            r1: 1e-3,
            r2: 1e-3,
        }
    }

    /// The pair constants of the adhesion tests (E* = 1 GPa, G* = 0.4 GPa, μ = 0.3).
    fn adhesive_pair(gamma: f64) -> PairConst {
        PairConst {
            e_star: 1e9,
            g_star: 4e8,
            mu: 0.3,
            gamma,
            gamma_base: gamma,
            zeta: 0.0,
            dash: 0.0,
            law: 0,
            pull: false,
        }
    }

    /// Loads a contact with the Mindlin–Deresiewicz law (which keeps its displacement in the
    /// law-specific part), then separates it; returns the state after each.
    fn load_and_separate(gamma: f64) -> (ContactState, ContactState) {
        let pc = adhesive_pair(gamma);
        let mut s = ContactState::default();
        let mut acc = Acc::default();
        for _ in 0..3 {
            interact::<true, false>(&kin(-1e-7), &pc, &laws(), &mut s, &mut acc);
        }
        let loaded = s.clone();
        interact::<true, false>(&kin(1e-3), &pc, &laws(), &mut s, &mut acc);
        (loaded, s)
    }

    /// A Hertz contact that separates gives its law-specific part back: nothing in it
    /// differs from the defaults read for a contact without one, so it is freed (memory of a
    /// Mindlin–Deresiewicz bed), and reading it gives what it held, bit for bit.
    #[test]
    fn a_separated_hertz_contact_frees_its_law_specific_part() {
        let (loaded, s) = load_and_separate(0.0);
        assert!(loaded.touching && loaded.ext.is_some());
        assert!(loaded.ext().tdelta != 0.0, "the law kept a displacement");
        assert!(!s.touching);
        assert!(s.ext.is_none(), "{:?}", s.ext);
        assert_eq!(
            format!("{:?}", s.ext()),
            format!("{:?}", ContactExt::default())
        );
    }

    /// Walton's law (Shang 1998) bounds the friction of a JKR contact by the Hertz part of
    /// its force: at zero overlap (point A of doc/spec/shang1998.md Table 2.1, net force
    /// `−8/9 P_c`, `a = (2πΓR²/E*)^{1/3}`, `Γ = 2γ`) `P_E = 8πΓR/3 = 16/9 P_c`, so a contact
    /// that slides carries `μ 16/9 P_c` although it is in tension (Thornton's cap would be
    /// `μ (P + 2P_c) = μ 10/9 P_c`); the ledger books the loss.
    #[test]
    fn walton_friction_of_a_jkr_contact_is_bounded_by_the_hertz_part() {
        let gamma = 0.1;
        let pc = adhesive_pair(gamma);
        let laws = Laws {
            tangential: TangentialChoice::Walton,
            ..laws()
        };
        let k = kin(0.0);
        let mut s = ContactState::default();
        let mut acc = Acc::default();
        for _ in 0..2000 {
            interact::<true, false>(&k, &pc, &laws, &mut s, &mut acc);
        }
        let p_c = 3.0 * std::f64::consts::PI * gamma * k.r_star;
        assert!((s.normal_force + 8.0 / 9.0 * p_c).abs() < 1e-9 * p_c);
        let cap = pc.mu * 16.0 / 9.0 * p_c;
        assert!(
            (s.tforce.norm() - cap).abs() < 1e-9 * cap,
            "{} vs {cap}",
            s.tforce.norm()
        );
        assert!(s.tforce.x < 0.0, "the force on B opposes its slip");
        assert!(acc.friction > 0.0);
    }

    /// Under `SET TANgential MDR` a Hertz contact keeps the spring row (`physics::mdr`), a
    /// JKR contact the Mindlin–Deresiewicz state instead (the MDR of the adhesive contact
    /// is not derived); both give the row's or MD's force, and both free what they kept
    /// when they separate.
    #[test]
    fn mdr_rows_for_hertz_contacts_and_md_for_jkr_ones() {
        let laws = Laws {
            tangential: TangentialChoice::Mdr,
            ..laws()
        };
        for gamma in [0.0, 0.1] {
            let pc = adhesive_pair(gamma);
            let mut s = ContactState::default();
            let mut acc = Acc::default();
            for _ in 0..3 {
                interact::<true, false>(&kin(-1e-7), &pc, &laws, &mut s, &mut acc);
            }
            assert!(s.touching && s.tforce.x < 0.0, "{gamma}: {:?}", s.tforce);
            let e = s.ext();
            if gamma == 0.0 {
                let row = e.mdr.as_ref().expect("a row");
                // Three steps of 0.1 µm, five times the sliding displacement
                // μE*α/(4G*): the contact slides at μP.
                let t = pc.mu * s.normal_force;
                assert!((s.tforce.x + t).abs() < 1e-3 * t, "{} {t}", s.tforce.x);
                assert!(row.a_ref == s.a && e.tang.t == 0.0);
            } else {
                assert!(e.mdr.is_none() && e.tang.t != 0.0);
            }
            interact::<true, false>(&kin(1e-3), &pc, &laws, &mut s, &mut acc);
            assert!(!s.touching && s.ext().mdr.is_none());
        }
    }

    /// An adhesive contact keeps it after detachment: its surface energy and a_s stay.
    #[test]
    fn a_detached_jkr_contact_keeps_its_law_specific_part() {
        let (loaded, s) = load_and_separate(0.1);
        assert!(loaded.touching && loaded.ext().gamma == 0.1);
        assert!(!s.touching);
        let e = s.ext.as_ref().expect("kept");
        assert_eq!(e.gamma, 0.1);
        assert!(e.a_s > 0.0);
    }
}
