//! `SET TANgential HM`: the Hertz–Mindlin tangential law of EDEM and LIGGGHTS, Mindlin's
//! no-slip spring with a dashpot from the pair's restitution (`physics::dashpot::
//! tangential_coefficient`), on the Hertz pairs and on the Mindlin springs of `SET NORmal MJKR
//! EDEM` and `NGUYEN`. A sphere held on a wall at a fixed overlap, free to move along x only
//! (no spin), is a damped harmonic oscillator along x: spring `k_t = 8G*a`, mass `m`,
//! coefficient `C_t = ζ (2/3 m k_t)^{1/2}`; its displacement after a kick `v0` is
//! `(v0/ω_d) e^{−ξω_0 t} sin ω_d t` with `ξ = C_t/(2(k_t m)^{1/2})`. Without the dashpot
//! (`NOSLIP`) it swings undamped. The energy the dashpot takes is booked as contact damping
//! and the ledger closes; across SAve/Restart.

use crate::common::*;
use trubal::physics::restitution::zeta_for_restitution;

const R: f64 = 1e-3;
const ALPHA: f64 = 5e-6;
const V0: f64 = 1e-3;
const E: f64 = 0.8;
const FRAC: f64 = 0.01;

fn mass() -> f64 {
    2500.0 * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3)
}

/// G* of the sphere against a wall of its own material (E = 1e8, ν = 0.25).
fn g_star() -> f64 {
    let g = 1e8 / (2.0 * 1.25);
    g / (2.0 * (2.0 - 0.25))
}

/// The sphere on the wall at the overlap `ALPHA`, started at `V0` along x, held in the other
/// degrees of freedom by `fix` (the step `frac` of the Rayleigh step, if given).
fn scene(tang: &str, law: &str, cohesion: f64, mu: f64, fix: &str, frac: Option<f64>) -> String {
    let mut s = format!(
        "start 0.01 0.01 0.01 10 10 2\nset open all\nset tangential {tang}\nrad {R} 1\n\
         ymd 1e8 1\npra 0.25 1\ndensity 2500 1\nfriction {mu} 1\ndamping restitution {E} 1\n"
    );
    if let Some(f) = frac {
        s += &format!("fraction {f}\n");
    }
    if cohesion > 0.0 {
        s += &format!("cohesion {cohesion} 1\n");
    }
    s += &format!("set normal {law} 1\n");
    s += &format!("create 0.005 0.005 0.005 {V0} 0 0 0 0 0 1 1\nfix {fix} all\n");
    s += &format!("dwall p 0 0 1 {} m 1\n", 0.005 - R + ALPHA);
    s
}

/// The held sphere free along x only; 12 prints of the balls and the energy every 300
/// steps, saved and restarted half-way.
fn run(tang: &str, law: &str, cohesion: f64) -> Run {
    let mut s = scene(tang, law, cohesion, 1.0, "0 1 1 1 1 1", Some(FRAC));
    for k in 0..12 {
        s += "cycle 300\nprint balls energy\n";
        if k == 6 {
            s += "save hm.sav\nnew\nrestart hm.sav\n";
        }
    }
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    run
}

/// The printed (time, x − x0) and the energies, against the damped oscillator of stiffness
/// `k_t` and coefficient `c_t`.
fn check(run: &Run, k_t: f64, c_t: f64, what: &str) {
    let m = mass();
    let w0 = (k_t / m).sqrt();
    let xi = c_t / (2.0 * (k_t * m).sqrt());
    let wd = w0 * (1.0 - xi * xi).sqrt();
    let amp = V0 / w0;
    let balls = printed(run, "balls");
    let mut worst: f64 = 0.0;
    for b in &balls {
        let t = b["time"].as_f64().unwrap();
        let x = b["balls"][0]["pos"][0].as_f64().unwrap() - 0.005;
        let want = V0 / wd * (-xi * w0 * t).exp() * (wd * t).sin();
        worst = worst.max((x - want).abs() / amp);
    }
    assert!(
        worst < 0.015,
        "{what}: worst error {worst} of the amplitude"
    );
    let ens = printed(run, "energy");
    let last = ens.last().unwrap();
    let input = last["input"].as_f64().unwrap();
    let damping = last["dissipated"]["damping_contact"].as_f64().unwrap();
    let res = last["residual"].as_f64().unwrap() / input;
    assert!(res.abs() < 1e-3, "{what}: ledger residual {res}");
    // What the oscillator lost by now: ½ m v0² less its energy left, e^{−2ξω0 t} of it.
    let t = balls.last().unwrap()["time"].as_f64().unwrap();
    let lost = 0.5 * m * V0 * V0 * (1.0 - (-2.0 * xi * w0 * t).exp());
    if c_t > 0.0 {
        assert!(
            (damping / lost - 1.0).abs() < 0.05,
            "{what}: damping {damping}, lost {lost}"
        );
    } else {
        assert!(
            damping.abs() < 1e-6 * 0.5 * m * V0 * V0,
            "{what}: damping {damping}"
        );
    }
}

fn c_t(k_t: f64) -> f64 {
    zeta_for_restitution(E) * (2.0 / 3.0 * mass() * k_t).sqrt()
}

/// The oscillator under each law with its spring: Hertz's `8G*(R*α)^{1/2}`; EDEM's JKR
/// (`MJKR EDEM`) `8G*a` with the JKR contact radius (Pasha (3.42)); LIGGGHTS' (`NGUYEN`)
/// `8G*(R*α)^{1/2}`. Damped under `HM`, undamped under `NOSLIP`.
fn swings(cases: &[(&str, &str, f64)]) {
    let k_h = 8.0 * g_star() * (R * ALPHA).sqrt();
    let (a, _, _, _) = crate::pasha_laws::jkr_contact(R);
    for &(tang, law, cohesion) in cases {
        let k_t = if law == "mjkr edem" {
            8.0 * g_star() * a
        } else {
            k_h
        };
        let c = if tang == "hm" { c_t(k_t) } else { 0.0 };
        check(&run(tang, law, cohesion), k_t, c, &format!("{law}, {tang}"));
    }
}

#[test]
fn hertz_pair_swings_damped_with_hm_and_undamped_with_noslip() {
    swings(&[("hm", "hertz", 0.0), ("noslip", "hertz", 0.0)]);
}

#[test]
fn edem_and_liggghts_jkr_springs_take_the_dashpot_under_hm() {
    swings(&[
        ("hm", "mjkr edem", 0.25),
        ("noslip", "mjkr edem", 0.25),
        ("hm", "nguyen", 0.25),
    ]);
}

/// A sliding contact's force is the Coulomb cap alone, without the dashpot (LIGGGHTS'
/// `tangential history`: the damping only while the spring holds): the sphere dragged over
/// the wall at a constant speed, held at its overlap, feels μ times the Hertz force.
#[test]
fn a_sliding_contact_has_no_tangential_dashpot() {
    let mu = 0.3;
    let e_star = 1e8 / (2.0 * (1.0 - 0.25f64.powi(2)));
    let p = 4.0 / 3.0 * e_star * R.sqrt() * ALPHA.powf(1.5);
    let s = scene("hm", "hertz", 0.0, mu, "1 1 1 1 1 1", None) + "cycle 3000\nprint walls energy\n";
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let w = &printed(&run, "walls")[0]["walls"][0];
    let (ft, fz) = (
        w["force"][0].as_f64().unwrap(),
        w["normal_force"].as_f64().unwrap(),
    );
    assert!((fz / p - 1.0).abs() < 1e-9, "normal {fz}, Hertz {p}");
    assert!(
        (ft / (mu * p) - 1.0).abs() < 1e-9,
        "sliding {ft}, cap {}",
        mu * p
    );
}
