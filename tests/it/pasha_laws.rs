//! The contact laws of Pasha (2013) through the binary (issue 36, item 3): the single-particle
//! impact of his Ch. 4 (§4.1.5, Tables 4.1–4.2; scripts/pasha_single.tru): an ammonium
//! fluorescein sphere (R = 2.45 µm) on a silicon wall, no damping, no friction. Pasha's
//! simplified linear law against its closed form (A3.6), (A3.9) evaluated here: restitution,
//! the minimum detachment speed (≈ 1.5 m/s; the thesis reads ≈ 1.6 m/s off its figure) and
//! the asymptote (k_p/k_e)^{1/2} = 0.374 (thesis ≈ 0.38); Thornton–Ning's restitution falling
//! at high speed; the energy ledger closing after each impact; rolling friction (`SET
//! ROLling`) against Newton's laws for a rolling sphere; bad `SET NORmal`/`ROLling` input.

use crate::common;
use common::*;

const SCRIPT: &str = include_str!("../../scripts/pasha_single.tru");
const R: f64 = 2.45e-6;
const KE: f64 = 1500.0;
const KP: f64 = 210.0;
const KCP: f64 = 20.0;
const F0P: f64 = 4.0e-6;

/// Restitution (0: stuck) and the ledger's residual relative to the input.
fn impact(law: &str, v: f64) -> (f64, f64) {
    let script = SCRIPT
        .replace("$law", law)
        .replace("$v", &v.to_string())
        .replace("$frac", "0.05")
        .replace("$n", "4000");
    let run = trubal_json(&script, &[]);
    assert!(run.ok, "{}", run.stderr);
    let balls = &printed(&run, "balls")[0]["balls"];
    let contacts = printed(&run, "contacts")[0]["contacts"]
        .as_array()
        .unwrap()
        .len();
    let en = &printed(&run, "energy")[0];
    let residual = en["residual"].as_f64().unwrap() / en["input"].as_f64().unwrap();
    let e = if contacts > 0 {
        0.0
    } else {
        balls[0]["vel"][2].as_f64().unwrap() / v
    };
    (e, residual)
}

/// The simplified law's restitution from its branches (doc/contact_laws.md), sphere on wall.
fn closed_form(v: f64) -> f64 {
    let m = 1350.0 * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
    closed_form_of(v, m, R)
}

/// The same for the effective mass `m` and radius `r_star`.
fn closed_form_of(v: f64, m: f64, r_star: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let f_ce = 1.5 * pi * r_star * 0.2;
    let a0 = 8.0 / 9.0 * f_ce / KP;
    let amax = a0 + (a0 * a0 + m * v * v / KP).sqrt();
    let fmax = KP * (amax - a0);
    let ap = amax - fmax / KE;
    let acp = (KE * ap - F0P) / (KE + KCP);
    let fcp = KCP * acp + F0P;
    let vr2 = (fmax * (amax - ap) - fcp * (ap - (2.0 * acp - ap))) / m;
    if vr2 > 0.0 { vr2.sqrt() / v } else { 0.0 }
}

#[test]
fn pasha_simplified_law_single_particle_impact() {
    let law = format!("pasha {KE} {KP} {KCP} {F0P}");
    for v in [1.4, 1.6, 2.0, 6.0, 25.0] {
        let (e, res) = impact(&law, v);
        let want = closed_form(v);
        assert!(
            (e - want).abs() < 0.005,
            "{v} m/s: e {e}, closed form {want}"
        );
        // (Once the contact has ended: while it lasts the kinetic energy of the half-step
        // velocities differs from the booked work by O(Δt).)
        if e > 0.0 {
            assert!(res.abs() < 1e-9, "{v} m/s: the ledger's residual {res}");
        }
    }
    // Stuck at 1.4 m/s, bounces at 1.6 m/s; the asymptote (k_p/k_e)^{1/2} ≈ 0.374.
    assert_eq!(closed_form(1.4), 0.0);
    assert!(closed_form(1.6) > 0.1);
    let e25 = closed_form(25.0);
    assert!(e25 > 0.36 && e25 < (KP / KE).sqrt());
}

/// Two like spheres (m* = m/2, R* = R/2) meeting at 4 m/s: the particle–particle contact
/// follows the same law.
#[test]
fn pasha_simplified_law_between_two_spheres() {
    let v = 4.0;
    let script = SCRIPT
        .replace("$law", &format!("pasha {KE} {KP} {KCP} {F0P}"))
        .replace("$frac", "0.05")
        .replace("$n", "4000")
        .replace("dwall p 0 0 1 5e-6 m 2\n", "")
        .replace(
            "create 1e-5 1e-5 7.451e-6 0 0 -$v 0 0 0 1 1",
            &format!(
                "create 1e-5 1e-5 5e-5 0 0 {} 0 0 0 1 1\ncreate 1e-5 1e-5 5.4901e-5 0 0 -{} 0 0 0 1 1",
                v / 2.0,
                v / 2.0
            ),
        );
    let run = trubal_json(&script, &[]);
    assert!(run.ok, "{}", run.stderr);
    let balls = &printed(&run, "balls")[0]["balls"];
    let vz = |k: usize| balls[k]["vel"][2].as_f64().unwrap();
    let e = (vz(1) - vz(0)) / v;
    let m = 1350.0 * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
    let want = closed_form_of(v, m / 2.0, R / 2.0);
    assert!(
        want > 0.2 && (e - want).abs() < 0.005,
        "e {e}, closed form {want}"
    );
}

#[test]
fn thornton_ning_restitution_falls_at_high_speed() {
    let (e5, r5) = impact("tning 35.3e6", 5.0);
    let (e10, _) = impact("tning 35.3e6", 10.0);
    let (e25, r25) = impact("tning 35.3e6", 25.0);
    assert!(e5 > e10 && e10 > e25 && e25 > 0.3, "{e5} {e10} {e25}");
    assert!(r5.abs() < 1e-9 && r25.abs() < 1e-9, "{r5} {r25}");
    // Adhesion wins at low speed: the sphere sticks.
    assert_eq!(impact("tning 35.3e6", 0.5).0, 0.0);
}

/// The modified JKR law keeps no hysteresis: without damping an impact is elastic (to the
/// step's error at the force jumps), and the ledger closes.
#[test]
fn modified_jkr_is_conservative() {
    let (e, res) = impact("mjkr", 5.0);
    assert!((e - 1.0).abs() < 0.01, "{e}");
    assert!(res.abs() < 1e-9, "{res}");
}

#[test]
fn bad_normal_law_input_is_refused() {
    for (line, msg) in [
        ("set normal pasha 100 200 1 1", "must not exceed"),
        ("set normal tning -1", "py"),
        ("set normal pasha 100 50 1", "f0p"),
        ("set normal hertz 9", "material type 9 is not defined"),
        ("set normal plastic", "normal law"),
        ("set rolling -0.1", "mur"),
        ("set rolling 0.1 1 7", "material type 7 is not defined"),
    ] {
        let run = trubal_json(
            &format!("start 1 1 1 10 10 2\nymd 1e9 1\npra 0.3 1\ndensity 1000 1\n{line}\n"),
            &[],
        );
        assert!(!run.ok || run.stderr.contains("error"), "{line}");
        assert!(run.stderr.contains(msg), "{line}: {}", run.stderr);
    }
}

/// `SET ROLling μ_r`: a sphere rolling on a plane under gravity decelerates at
/// `a = M R/(I + mR²) = 5/7 μ_r g` (the rolling moment at its limit `μ_r R F_n`, `F_n = mg`,
/// no slip: Newton's laws for a solid sphere), comes to rest, and stays there (the dashpot
/// of the rolling spring damps the rocking); the ledger closes once it rests.
#[test]
fn rolling_friction_decelerates_a_rolling_sphere() {
    let (v0, mu_r, g) = (0.1, 0.1, 9.81);
    let script = |cycles: u64| {
        format!(
            "start 0.1 0.02 0.02 10 10 2\nset open all\nrad 1e-3 1\nymd 1e8 1\npra 0.3 1\n\
             density 2500 1\nfriction 0.5 1\ndamping restitution 0.5\ngravity 0 0 -{g}\n\
             dwall p 0 0 1 0.002 m 1\nset rolling {mu_r}\n\
             create 0.01 0.01 0.002999875 {v0} 0 0 0 {} 0 1 1\ncycle {cycles}\n\
             print info balls energy\n",
            v0 / 1e-3
        )
    };
    let run = trubal_json(&script(9000), &[]);
    assert!(run.ok, "{}", run.stderr);
    let t = printed(&run, "balls")[0]["time"].as_f64().unwrap();
    let v = printed(&run, "balls")[0]["balls"][0]["vel"][0]
        .as_f64()
        .unwrap();
    let want = v0 - 5.0 / 7.0 * mu_r * g * t;
    assert!(
        (v - want).abs() < 1e-3 * v0,
        "v {v}, closed form {want} at t = {t}"
    );
    // Stops after v0/a = 0.143 s, and rests.
    let run = trubal_json(&script(36_000), &[]);
    let b = &printed(&run, "balls")[0]["balls"][0];
    let (v, w) = (
        b["vel"][0].as_f64().unwrap(),
        b["spin"][1].as_f64().unwrap(),
    );
    assert!(v.abs() < 1e-9 && (w * 1e-3).abs() < 1e-9, "{v} {w}");
    let en = &printed(&run, "energy")[0];
    let res = en["residual"].as_f64().unwrap() / en["input"].as_f64().unwrap();
    assert!(res.abs() < 1e-9, "{res}");
    // Without rolling friction it rolls on at v0.
    let run = trubal_json(
        &script(9000).replace(&format!("set rolling {mu_r}"), "set rolling 0"),
        &[],
    );
    let v = printed(&run, "balls")[0]["balls"][0]["vel"][0]
        .as_f64()
        .unwrap();
    assert!((v - v0).abs() < 1e-9, "{v}");
}

/// A sphere (R = 1 mm, E = 100 MPa, ν = 0.25, Γ = 2γ = 0.5 J/m²) held at an overlap of 5 µm
/// on a plane wall of its own material under the modified JKR, `law` (`mjkr` or `mjkr
/// edem`), created with the velocities `create`, then given the commands `extra` (FIX);
/// returns the script.
fn held_sphere(law: &str, extra: &str, create: &str, cycles: u32) -> String {
    held_sphere_on(law, extra, create, cycles, PLANE)
}

/// The plane wall 5 µm into the sphere, and an obstacle sphere of radius 2 mm as far in.
const PLANE: &str = "dwall p 0 0 1 0.004005 m 1";
const OBSTACLE: &str = "dwall ob 0.005 0.005 0.002005 0.002 m 1";

/// As [`held_sphere`] on the wall `wall`.
fn held_sphere_on(law: &str, extra: &str, create: &str, cycles: u32, wall: &str) -> String {
    format!(
        "start 0.01 0.01 0.01 10 10 2\nset open all\nset tangential noslip\nrad 1e-3 1\n\
         ymd 1e8 1\npra 0.25 1\ndensity 2500 1\ncohesion 0.25 1\nset normal {law} 1\n\
         create 0.005 0.005 0.005 {create} 1 1\n{extra}\n{wall}\n\
         cycle {cycles}\nsave held.sav\nnew\nrestart held.sav\ncycle {cycles}\nprint walls balls\n"
    )
}

/// The JKR contact of that sphere on the plane by its closed form, Pasha (3.41)–(3.42)
/// solved for a by bisection: (a, the Hertzian part 4E*a³/(3R*), the force P, the pull-off
/// force P_c).
fn held_sphere_jkr() -> (f64, f64, f64, f64) {
    jkr_contact(1e-3)
}

/// The same for the effective radius `r` (on the obstacle, R* = R r_o/(R + r_o)).
pub(crate) fn jkr_contact(r: f64) -> (f64, f64, f64, f64) {
    let pi = std::f64::consts::PI;
    let (e_star, big_gamma, alpha) = (1e8 / (2.0 * (1.0 - 0.25f64.powi(2))), 0.5, 5e-6);
    let f = |a: f64| a * a / r - (2.0 * pi * big_gamma * a / e_star).sqrt() - alpha;
    let (mut lo, mut hi) = (1e-9, 1e-3);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if f(m) > 0.0 { hi = m } else { lo = m }
    }
    let a = lo;
    let f_h = 4.0 * e_star * a.powi(3) / (3.0 * r);
    let p = f_h - (8.0 * pi * big_gamma * e_star * a.powi(3)).sqrt();
    (a, f_h, p, 1.5 * pi * r * big_gamma)
}

/// `SET NORmal MJKR EDEM [ROLling]`: the sliding force of a sphere dragged over a wall at a
/// fixed overlap saturates at μ times the Hertzian part of the JKR force, 4E*a³/(3R*) (EDEM's
/// "Hertz-Mindlin with JKR"), against μ(P + 2P_c) under plain MJKR; the normal force is the
/// JKR curve's in both; across SAve/Restart.
#[test]
fn edem_friction_limits_sliding_on_the_hertz_part() {
    let (_, f_h, p, p_c) = held_sphere_jkr();
    let mu = 0.3;
    for (law, limit) in [
        ("mjkr edem", mu * f_h),
        ("mjkr edem rolling", mu * f_h),
        ("mjkr", mu * (p + 2.0 * p_c)),
    ] {
        let extra = format!("friction {mu} 1\nfix 1 1 1 1 1 1 all");
        let run = trubal_json(&held_sphere(law, &extra, "1e-3 0 0 0 0 0", 1500), &[]);
        assert!(run.ok, "{}", run.stderr);
        let w = &printed(&run, "walls")[0]["walls"][0];
        let (ft, fz) = (
            w["force"][0].as_f64().unwrap(),
            w["normal_force"].as_f64().unwrap(),
        );
        assert!((fz / p - 1.0).abs() < 1e-9, "{law}: normal {fz}, JKR {p}");
        assert!(
            (ft / limit - 1.0).abs() < 1e-9,
            "{law}: sliding {ft}, limit {limit}"
        );
    }
}

/// `SET NORmal MJKR EDEM ROLling` with `SET ROLling μ_r`: a sphere held in place on a wall
/// spinning without sliding friction slows at I dω/dt = μ_r R F_n, with F_n the Hertzian part
/// of the force, or the force P (`MJKR EDEM`, plain MJKR), Newton's law for the sphere.
#[test]
fn edem_friction_limits_rolling_on_the_hertz_part() {
    let (_, f_h, p, _) = held_sphere_jkr();
    let (mu_r, w0, r): (f64, f64, f64) = (0.1, 1e4, 1e-3);
    let inertia = 0.4 * 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(5);
    // On the obstacle (R* = 2/3 mm) the moment arm is still R; P_H is that contact's.
    let (_, f_h_ob, _, _) = jkr_contact(1e-3 * 2e-3 / 3e-3);
    for (law, f_n, wall) in [
        ("mjkr edem rolling", f_h, PLANE),
        ("mjkr edem", p, PLANE),
        ("mjkr", p, PLANE),
        ("mjkr edem rolling", f_h_ob, OBSTACLE),
    ] {
        let extra = format!("friction 0 1\nset rolling {mu_r} 1\nfix 1 1 1 0 0 0 all");
        let create = format!("0 0 0 0 {w0} 0");
        let run = trubal_json(&held_sphere_on(law, &extra, &create, 500, wall), &[]);
        assert!(run.ok, "{}", run.stderr);
        let b = &printed(&run, "balls")[0];
        let t = b["time"].as_f64().unwrap();
        let w = b["balls"][0]["spin"][1].as_f64().unwrap();
        let want = w0 - mu_r * r * f_n * t / inertia;
        assert!(
            (w - want).abs() < 1e-9 * w0,
            "{law} ({wall}): spin {w}, Newton {want}"
        );
    }
}

#[test]
fn edem_option_belongs_to_mjkr_only() {
    for line in [
        "set normal tning 1e8 edem",
        "set normal hertz edem",
        "set normal mjkr rolling",
    ] {
        let run = trubal_json(
            &format!("start 1 1 1 10 10 2\nymd 1e9 1\npra 0.3 1\ndensity 1000 1\n{line}\n"),
            &[],
        );
        assert!(run.stderr.contains("error"), "{line}: {}", run.stderr);
    }
}

/// `PRint SETtings` lists the rules of `SET NORmal`, `SET ROLling`, `SET PAIr` and `SET
/// DASHpot` as the
/// commands that make them: given back to a new scene they give the same list.
#[test]
fn print_settings_lists_the_contact_rules_as_commands() {
    let head = "start 1 1 1 10 10 2\nymd 1e9 1\npra 0.3 1\ndensity 1000 1\nymd 1e9 2\npra 0.3 2\n\
                density 1000 2\n";
    let rules = "set normal mjkr edem rolling 1\nset rolling 0.1 1 1\nset pair 1 2 friction 0.35 \
                 restitution 0.3\nset normal nguyen 2\nset normal pasha 1500 210 20 4e-6 1 2\n\
                 set dashpot liggghts\nset dashpot limitforce 1 2\n";
    let listed = |script: &str| -> Vec<String> {
        let run = trubal_json(&format!("{head}{script}print settings\n"), &[]);
        assert!(run.ok, "{}", run.stderr);
        printed(&run, "settings")[0]["contact_rules"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_str().unwrap().to_string())
            .collect()
    };
    assert!(listed("").is_empty());
    let first = listed(rules);
    assert_eq!(
        first,
        [
            "SET NORmal MJKR EDEM ROLLING 1",
            "SET NORmal NGUYEN 2",
            "SET NORmal PASHA 1500 210 20 0.000004 KT 1500 1 2",
            "SET ROLling 0.1 1 1",
            "SET PAIr 1 2 FRIction 0.35 RESTitution 0.3",
            "SET DASHpot LIGGGHTS",
            "SET DASHpot LIMITFORCE 1 2"
        ]
    );
    assert_eq!(listed(&(first.join("\n") + "\n")), first);
}
