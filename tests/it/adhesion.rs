//! JKR adhesion through the whole cycle (issue 4): quasi-static pull-off, loop loss,
//! sticking threshold of a head-on collision, oblique peeling/slip/sliding, singular points.
//! References are computed here from the closed forms of Lian 1994 ch. 3 (with the corrected
//! (3.29)), independently of src/physics/jkr.rs.

use crate::common;
use common::*;
use std::f64::consts::PI;
use trubal::sim::{Vec3, energy};

const R: f64 = 30e-6;
const E: f64 = 70e9;
const NU: f64 = 0.3;
const RHO: f64 = 2650.0;
const GAMMA: f64 = 0.4;

fn e_star() -> f64 {
    E / (2.0 * (1.0 - NU * NU))
}
fn r_star() -> f64 {
    R / 2.0
}
fn pc() -> f64 {
    3.0 * PI * GAMMA * r_star()
}
/// (3.38)
fn alpha_s() -> f64 {
    -(3.0 * pc() * pc() / (16.0 * e_star() * e_star() * r_star())).cbrt()
}
/// Corrected (3.29) and (3.24).
fn alpha_of_a(a: f64) -> f64 {
    a * a / r_star() - (4.0 * PI * GAMMA * a / e_star()).sqrt()
}
fn p_of_a(a: f64) -> f64 {
    4.0 * e_star() * a.powi(3) / (3.0 * r_star())
        - (16.0 * PI * GAMMA * e_star() * a.powi(3)).sqrt()
}
/// Stable branch a(α) by bisection (α ≥ α_s), a ≥ a_s (3.117).
fn a_of_alpha(alpha: f64) -> f64 {
    let a_s = (PI * GAMMA * r_star() * r_star() / (4.0 * e_star())).cbrt();
    let (mut lo, mut hi) = (a_s, a_s * 10.0);
    while alpha_of_a(hi) < alpha {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if alpha_of_a(mid) < alpha {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}
/// (3.119)
fn peel_work() -> f64 {
    -4.0 / 45.0 * (1.0 + 6.0 * 4f64.cbrt()) * pc() * alpha_s()
}

fn two_spheres(extra: &str, gap: f64, v: f64) -> trubal::sim::Scene {
    scene(&format!(
        "start 1e-3 1e-3 1e-3 100 10 2\nset open all\nrad {R} 1\nymd {E} 1\npra {NU} 1\ndensity {RHO} 1\n\
         cohesion {GAMMA} 1\n{extra}\ncreate 4e-4 5e-4 5e-4 0 0 0 0 0 0 1 1\n\
         create {} 5e-4 5e-4 {v} 0 0 0 0 0 1 1\n",
        4e-4 + 2.0 * R + gap
    ))
}

#[test]
fn quasi_static_pull_off() {
    // Sphere 1 held still, sphere 2 driven at a constant slow velocity (Fix keeps it):
    // approach to α = 2|α_s|, then withdraw until detachment.
    let v = 2e-5;
    let mut sc = two_spheres("fraction 0.2", 1e-9, -v);
    sc.unchecked().particles.fixed = vec![0b111111, 0b111111];
    let mut snap = None;
    let mut first_step = true;
    let mut samples = Vec::new();
    let mut pmin = f64::INFINITY;
    let mut detach = None;
    let mut reversed = false;
    for _ in 0..400_000 {
        let was = sc.contacts().iter().next().map(|c| c.s.clone());
        step(&mut sc);
        let c = &sc.contacts().pair(0).s;
        // The step of snap-in applies the mean force over its path, part of which lies
        // before the touch (`Jkr::step_force`); the next one is on the curve at α ≈ 0.
        if snap.is_none() && c.touching {
            if first_step {
                first_step = false;
            } else {
                snap = Some(c.normal_force);
            }
        }
        if c.touching {
            pmin = pmin.min(c.normal_force);
            samples.push((c.overlap, c.normal_force));
            if !reversed && c.overlap > -2.0 * alpha_s() {
                sc.unchecked().particles.vel[1].x = v;
                reversed = true;
            }
        } else if let Some(w) = was.filter(|w| w.touching && reversed) {
            detach = Some((w.overlap, w.normal_force));
            break;
        }
    }
    let snap = snap.expect("snap-in");
    assert!(
        rel(snap, -8.0 / 9.0 * pc()) < 1e-3,
        "snap-in {snap} vs {}",
        -8.0 / 9.0 * pc()
    );
    assert!(rel(pmin, -pc()) < 5e-3, "pull-off {pmin} vs {}", -pc());
    let (a_det, _) = detach.expect("detachment");
    let step_alpha = v * sc.time() / sc.cycle() as f64;
    assert!(
        (a_det - alpha_s()).abs() < 2.0 * step_alpha,
        "detach at {a_det} vs α_s {}",
        alpha_s()
    );
    // Just before detaching the force is on the closed-form curve, within a few steps of
    // its limit −5/9 Pc (the curve is vertical at α_s: dα/da = 0). (The last two steps
    // apply the mean force over a path that crosses α_s, zero beyond it: `Jkr::step_force`.)
    let (a_before, p_before) = samples[samples.len() - 3];
    assert!(
        rel(p_before, -5.0 / 9.0 * pc()) < 0.02,
        "force before detaching {p_before}"
    );
    assert!((p_before - p_of_a(a_of_alpha(a_before))).abs() < 1e-3 * pc());
    for &(_, p) in &samples[samples.len() - 2..] {
        assert!(p < 0.0 && p > -pc(), "force of the last steps {p}");
    }
    // Force-overlap curve against the closed form at 20 points (after the step of snap-in).
    let k = samples.len() / 20;
    for (alpha, p) in samples[1..].iter().step_by(k.max(1)).take(20) {
        let p_ref = p_of_a(a_of_alpha(*alpha));
        assert!(
            (p - p_ref).abs() < 1e-3 * pc(),
            "α {alpha}: P {p} vs {p_ref}"
        );
    }
    // The ledger: the loop lost the peeling work (3.119).
    assert!(
        rel(sc.ledger().adhesion, peel_work()) < 0.01,
        "{} vs {}",
        sc.ledger().adhesion,
        peel_work()
    );
}

#[test]
fn head_on_sticking_threshold() {
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);
    let m_star = m / 2.0;
    let v_s = (2.0 * peel_work() / m_star).sqrt();
    let outcome = |v_rel: f64| {
        // Each sphere moves at v_rel/2 toward the other, touching at t = 0.
        let mut sc = two_spheres("fraction 0.1", 0.0, -v_rel / 2.0);
        set_velocity(&mut sc, 0, Vec3::new(v_rel / 2.0, 0.0, 0.0));
        trubal::sim::cycle::run(&mut sc, 20_000).unwrap();
        let rebound = sc.particles().vel[1].x - sc.particles().vel[0].x;
        let apart = !sc.contacts().iter().any(|c| c.s.touching);
        // The ledger books each force as ½(F_old + F_new)·v Δt (exact for the leap-frog
        // scheme): the second half of the last step's force, ½ P v_{N+1/2} Δt, has already
        // moved the particles and is booked with the next step. While the spheres are
        // stuck and oscillate it is a few % of this small input: it is taken out here.
        let dt = sc.time() / sc.cycle() as f64;
        let pending = sc.contacts().iter().next().map_or(0.0, |c| {
            if c.s.touching {
                0.5 * (c.s.normal_force + c.s.damp_force) * rebound * dt
            } else {
                0.0
            }
        });
        (
            apart,
            rebound / v_rel,
            (energy::residual(&sc) - pending) / sc.ledger().input(),
        )
    };
    let (apart, _, res) = outcome(0.98 * v_s);
    assert!(!apart, "stuck below v_s");
    assert!(res.abs() < 1e-3, "residual {res}");
    let (apart, _, _) = outcome(1.02 * v_s);
    assert!(apart, "rebounds above v_s");
    // Above the threshold: e² = 1 − v_s²/v² (energy balance, only W_p lost).
    let v = 2.0 * v_s;
    let (apart, e, res) = outcome(v);
    assert!(apart);
    let e_th = (1.0 - (v_s / v).powi(2)).sqrt();
    assert!(rel(e, e_th) < 0.01, "e {e} vs {e_th}");
    // The JKR force jumps at snap-in (−8/9 Pc) and detachment (−5/9 Pc → 0): the explicit
    // scheme books those steps to O(Δt), 3.7e-3 of the input at FRAction 0.1.
    assert!(res.abs() < 5e-3, "residual {res}");
}

#[test]
fn oblique_peeling_then_sliding() {
    // Hold the normal overlap fixed (P > 0), then drive a tangential displacement: T grows with
    // the no-slip stiffness 8G*a until T_p (3.101), then micro-slip, then sliding at μ(P+2Pc).
    // μ = 0.9 puts the intersection P_2 of the peeling and sliding curves (3.106) at 0.3 Pc,
    // so a contact under P > P_2 peels smoothly into micro-slip.
    let mu = 0.9;
    let mut sc = two_spheres(&format!("friction {mu} 1\nfraction 0.2"), 1e-9, -1e-4);
    sc.unchecked().particles.fixed = vec![0b111111, 0b111111];
    while !(sc
        .contacts()
        .iter()
        .next()
        .is_some_and(|c| c.s.overlap > 2e-8))
    {
        step(&mut sc);
    }
    sc.unchecked().particles.vel[1] = Vec3::new(0.0, 1e-4, 0.0);
    let c0 = sc.contacts().pair(0).s.clone();
    let (a, p) = (c0.a, c0.normal_force);
    let g = E / (2.0 * (1.0 + NU));
    let g_star = 1.0 / (2.0 * (2.0 - NU) / g);
    let e_s = e_star();
    let t_p = 4.0 * (g_star / e_s * (p * pc() + pc() * pc())).sqrt();
    let slide = mu * (p + 2.0 * pc());
    let x = 4.0 * g_star / (mu * mu * e_s);
    let p2 = 2.0 * pc() * ((x - 1.0) + (x * (x - 1.0)).sqrt());
    assert!(p > p2, "P {p} must exceed P_2 {p2}");
    assert!(t_p < slide);
    let mut trace = Vec::new();
    for _ in 0..40_000 {
        step(&mut sc);
        let c = &sc.contacts().pair(0).s;
        trace.push((c.ext().delta.norm(), c.tforce.norm(), c.normal_force));
    }
    // Initial slope 8 G* a.
    let (d1, t1, _) = trace[5];
    assert!(
        rel(t1 / d1, 8.0 * g_star * a) < 0.02,
        "slope {} vs {}",
        t1 / d1,
        8.0 * g_star * a
    );
    // Linear up to T_p (< sliding limit here), then below the line, then the plateau.
    let tmax = trace.iter().map(|x| x.1).fold(0.0, f64::max);
    let p_end = trace.last().unwrap().2;
    assert!(
        rel(tmax, mu * (p_end + 2.0 * pc())) < 0.01,
        "plateau {tmax} vs {slide}"
    );
    let at_tp = trace
        .iter()
        .find(|x| x.1 >= t_p * 0.999)
        .expect("reaches T_p");
    assert!(
        rel(at_tp.1 / at_tp.0, 8.0 * g_star * a) < 0.02,
        "still linear at T_p"
    );
    let later = trace
        .iter()
        .find(|x| x.1 >= 0.5 * (t_p + slide))
        .expect("micro-slip");
    assert!(
        later.1 / later.0 < 0.98 * 8.0 * g_star * a,
        "softer after peeling"
    );
    assert!(sc.ledger().friction > 0.0);
}

#[test]
fn singular_points_stay_finite_with_huge_steps() {
    for f in [1.0, 3.0, 10.0] {
        let mut sc = two_spheres(&format!("fraction {f}"), 0.0, -0.05);
        for _ in 0..2000 {
            if trubal::sim::cycle::run(&mut sc, 1).is_err() {
                break;
            }
            for c in sc.contacts().iter() {
                assert!(c.s.normal_force.is_finite() && c.s.a.is_finite(), "FRA {f}");
            }
        }
    }
}

#[test]
fn impact_flag_uses_base_surface_energy() {
    let sc = scene(&format!(
        "start 1e-3 1e-3 1e-3 100 10 2\nset open all\nrad {R} 1\nymd {E} 1\npra {NU} 1\ndensity {RHO} 1\n\
         cohesion {GAMMA} 1 0.05\naggl 1 5e-4 5e-4 5e-4 2e-4\ncreate 4e-4 5e-4 5e-4 0 0 0 0 0 0 1 1\n\
         create 4.6e-4 5e-4 5e-4 -0.001 0 0 0 0 0 1 1\n"
    ));
    // Contacts made before/after the flag: the stored γ differs.
    for (flag, want) in [(false, GAMMA), (true, 0.05)] {
        let mut s2 = sc.clone();
        *s2.unchecked().impact = flag;
        trubal::sim::cycle::run(&mut s2, 5000).unwrap();
        let c = s2
            .contacts()
            .iter()
            .find(|c| c.s.touching)
            .expect("contact");
        assert!(
            (c.s.gamma() - want).abs() < 1e-12,
            "flag {flag}: γ {}",
            c.s.gamma()
        );
    }
}

#[test]
fn a_contact_keeps_its_surface_energy_when_the_material_loses_it() {
    // A JKR contact is made, then the material's surface energy is set to zero (as
    // `COHesion 0` would): the scene now runs the kernel without adhesion, which must hand
    // the still-adhering contact to the adhesive law. Pulled apart, it keeps its γ: the force
    // reaches −Pc and the contact detaches at α_s, not at α = 0 as a Hertz contact would.
    let v = 2e-5;
    let mut sc = two_spheres("fraction 0.2", 1e-9, -v);
    sc.unchecked().particles.fixed = vec![0b111111, 0b111111];
    while !sc
        .contacts()
        .iter()
        .next()
        .is_some_and(|c| c.s.overlap > -alpha_s())
    {
        step(&mut sc);
    }
    sc.unchecked().materials[0].gamma = 0.0;
    sc.unchecked().materials[0].gamma_base = 0.0;
    sc.unchecked().particles.vel[1].x = v;
    let mut pmin = f64::INFINITY;
    let mut last_touching = None;
    for _ in 0..400_000 {
        step(&mut sc);
        let c = sc.contacts().pair(0).s;
        if !c.touching {
            break;
        }
        pmin = pmin.min(c.normal_force);
        last_touching = Some(c.overlap);
    }
    assert!(rel(pmin, -pc()) < 5e-3, "pull-off {pmin} vs {}", -pc());
    let a_det = last_touching.expect("touching after the change");
    let step_alpha = v * sc.time() / sc.cycle() as f64;
    assert!(
        (a_det - alpha_s()).abs() < 2.0 * step_alpha,
        "detach at {a_det} vs α_s {}",
        alpha_s()
    );
    // New contacts of the changed material are Hertzian: no snap-in.
    let mut fresh = two_spheres("fraction 0.2", 1e-9, -v);
    fresh.unchecked().materials[0].gamma = 0.0;
    fresh.unchecked().materials[0].gamma_base = 0.0;
    fresh.unchecked().particles.fixed = vec![0b111111, 0b111111];
    let mut touched = false;
    for _ in 0..100_000 {
        step(&mut fresh);
        let c = fresh.contacts().pair(0).s;
        assert!(
            c.normal_force >= 0.0,
            "a Hertz contact never pulls: {}",
            c.normal_force
        );
        touched |= c.touching;
        if c.overlap > -alpha_s() {
            break;
        }
    }
    assert!(touched);
}

/// What one impact of the phase sweep gave.
struct Impact {
    /// Rebound / impact speed (normal), and its value from the energy balance with W_p lost,
    /// e² = 1 − 2W_p/(m* v²), the approach's kinetic energy; None if the pair stays stuck.
    e: Option<(f64, f64)>,
    /// Adhesion loss booked / W_p.
    loss: f64,
    /// Residual of the books / the input (rebounds) or / W_p (stuck, less the second half of
    /// the last force's work, ½ P v Δt, which has moved the particles and is booked with the
    /// next step).
    residual: f64,
}

/// One head-on impact of the phase sweep: two spheres (each at v/2) or a sphere against a
/// plane wall (at v), first touch at `phase` of a step's travel after three whole steps.
fn impact(wall: bool, v: f64, fraction: f64, phase: f64) -> Impact {
    let g = E / (2.0 * (1.0 + NU));
    let dt = fraction * PI * R * (RHO / g).sqrt() / (0.1631 * NU + 0.8766);
    let gap = (3.0 + phase) * v * dt;
    let r_star = if wall { R } else { R / 2.0 };
    let m = RHO * 4.0 / 3.0 * PI * R.powi(3);
    let m_star = if wall { m } else { m / 2.0 };
    let pc = 3.0 * PI * GAMMA * r_star;
    let es = e_star();
    let als = -(3.0 * pc * pc / (16.0 * es * es * r_star)).cbrt();
    let wp = -4.0 / 45.0 * (1.0 + 6.0 * 4f64.cbrt()) * pc * als;
    let mut sc = if wall {
        scene(&format!(
            "start 1e-3 1e-3 1e-3 100 10 2\nset open all\nrad {R} 1\nymd {E} 1\npra {NU} 1\n\
             density {RHO} 1\ncohesion {GAMMA} 1\nfraction {fraction}\ndwall p 1 0 0 4e-4\n\
             create {} 5e-4 5e-4 {} 0 0 0 0 0 1 1\n",
            4e-4 + R + gap,
            -v
        ))
    } else {
        let mut sc = two_spheres(&format!("fraction {fraction}"), gap, -v / 2.0);
        set_velocity(&mut sc, 0, Vec3::new(v / 2.0, 0.0, 0.0));
        sc
    };
    let rel_v = |sc: &trubal::sim::Scene| {
        let p = sc.particles();
        if wall {
            p.vel[0].x
        } else {
            p.vel[1].x - p.vel[0].x
        }
    };
    let state = |sc: &trubal::sim::Scene| {
        let c = sc.contacts();
        c.iter()
            .map(|c| c.s.clone())
            .chain(c.wall_pairs().iter().map(|c| c.s.clone()))
            .find(|s| s.touching)
    };
    let mut touched = false;
    let mut apart_for = 0;
    for _ in 0..20_000 {
        step(&mut sc);
        if state(&sc).is_some() {
            touched = true;
            apart_for = 0;
        } else if touched {
            apart_for += 1;
            if apart_for > 5 {
                break;
            }
        }
    }
    assert!(
        touched,
        "wall {wall} v {v} FRA {fraction} phase {phase}: no contact"
    );
    let loss = sc.ledger().adhesion / wp;
    match state(&sc) {
        None => Impact {
            e: Some((rel_v(&sc) / v, (1.0 - 2.0 * wp / (m_star * v * v)).sqrt())),
            loss,
            residual: energy::residual(&sc) / sc.ledger().input(),
        },
        Some(s) => Impact {
            e: None,
            loss,
            residual: (energy::residual(&sc) - 0.5 * s.normal_force * rel_v(&sc) * dt) / wp,
        },
    }
}

/// Issue 49 item 5: a JKR impact must not make energy wherever in a step the first touch
/// falls. Two 30 µm glass spheres (γ = 0.4 J/m²), and one against a wall, head on, no
/// damping: the loop's only loss is the peeling work W_p (3.119), so that e² = 1 −
/// 2W_p/(m* v²) whatever the step, and a pair below the sticking speed stays stuck without
/// detaching (no loss). At 20 m/s the adhesive zone (|α_s| ≈ 13 nm) is crossed in less than
/// a step. The sampled force gave e up to 1.00007 (FRAction 0.1) and 1.0011 (0.2), and an
/// adhesion loss from −737 to +869 W_p, depending on the phase.
#[test]
fn jkr_impact_never_creates_energy_at_any_phase() {
    let mut failures = Vec::new();
    for wall in [false, true] {
        for fraction in [0.1, 0.2] {
            for v in [0.01, 0.1, 1.0, 20.0] {
                let (mut emin, mut emax, mut dev) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
                let (mut lmin, mut lmax) = (f64::INFINITY, f64::NEG_INFINITY);
                let mut rmax: f64 = 0.0;
                let mut nstuck = 0;
                for k in 0..16 {
                    let phase = k as f64 / 16.0;
                    let r = impact(wall, v, fraction, phase);
                    match r.e {
                        Some((e, e_th)) => {
                            emin = emin.min(e);
                            emax = emax.max(e);
                            dev = dev.max((e - e_th).abs());
                            // The books close, and the loss is W_p.
                            if !(r.residual.abs() < 1e-9 && (r.loss - 1.0).abs() < 1e-9) {
                                failures.push(format!(
                                    "wall {wall} FRA {fraction} v {v} phase {phase}: residual {:e}, loss {} W_p",
                                    r.residual, r.loss
                                ));
                            }
                        }
                        None => {
                            nstuck += 1;
                            // Stuck: never detached, nothing lost; the books close to a
                            // small fraction of W_p (the pending work is taken out to first
                            // order in the step; its second order, k (vΔt)²/8, is left:
                            // 2e-4 W_p at FRAction 0.1, 5e-4 at 0.2).
                            if !(r.residual.abs() < 1e-3 && r.loss == 0.0) {
                                failures.push(format!(
                                    "wall {wall} FRA {fraction} v {v} phase {phase}: stuck, residual {:e} W_p, loss {} W_p",
                                    r.residual, r.loss
                                ));
                            }
                        }
                    }
                    lmin = lmin.min(r.loss);
                    lmax = lmax.max(r.loss);
                    rmax = rmax.max(r.residual.abs());
                }
                eprintln!(
                    "wall {wall:5} FRA {fraction} v {v:5}: e {emin:.7}..{emax:.7} |e − e_th| {dev:.1e} stuck {nstuck}/16 loss/W_p {lmin:.4}..{lmax:.4} |residual| {rmax:.1e}"
                );
                if emax > 1.0 || lmin < 0.0 || dev > 1e-9 {
                    failures.push(format!(
                        "wall {wall} FRA {fraction} v {v}: e {emin}..{emax} (|e − e_th| up to {dev:e}), adhesion loss {lmin}..{lmax} W_p"
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
