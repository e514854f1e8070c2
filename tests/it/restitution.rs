//! The restitution dashpot at the default step, through the binary (issue 38, item 1): a
//! sphere (R = 10 mm, E = 1e8 Pa, ν = 0.3, ρ = 2500) against a wall and against a like
//! sphere, `DAmping REStitution e` for e = 0.1 … 0.9, impact speeds 0.1, 1 and 10 m/s, at
//! FRAction 0.2 (9–27 steps per contact), first touch at three places within a step. The
//! rebound must give e within 1.1 % (0.0015 absolute for e = 0.1): the reference is the set
//! e itself (the dashpot is calibrated to give it exactly in continuous time,
//! `physics::restitution`). Before the second-order dashpot (`physics::dashpot`) e = 0.1
//! came out 0.082 (wall) and 0.074 (sphere) at 1 m/s.

use crate::common;
use common::*;

const MATERIAL: &str = "rad 0.01 1\nymd 1e8 1\npra 0.3 1\ndensity 2500 1\n";

/// The rebound's e of one impact; `gap` the initial gap (m), `v` the impact speed.
fn rebound(wall: bool, e: f64, v: f64, gap: f64, cycles: u64) -> f64 {
    rebound_with("", wall, e, v, gap, cycles)
}

/// The same with `extra` command lines after the material (e.g. `set dashpot liggghts`).
fn rebound_with(extra: &str, wall: bool, e: f64, v: f64, gap: f64, cycles: u64) -> f64 {
    let run = if wall {
        trubal_json(
            &format!(
                "start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{extra}damping restitution {e}\n\
                 dwall p 0 0 1 0.02\ncreate 0.05 0.05 {} 0 0 -{v} 0 0 0 1 1\ncycle {cycles}\nprint balls\n",
                0.03 + gap
            ),
            &[],
        )
    } else {
        trubal_json(
            &format!(
                "start 0.2 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{extra}damping restitution {e}\n\
                 create 0.07 0.05 0.05 {} 0 0 0 0 0 1 1\ncreate {} 0.05 0.05 -{} 0 0 0 0 0 1 1\n\
                 cycle {cycles}\nprint balls\n",
                v / 2.0,
                0.09 + gap,
                v / 2.0
            ),
            &[],
        )
    };
    assert!(run.ok, "{}", run.stderr);
    let b = printed(&run, "balls");
    let balls = b.last().unwrap()["balls"].as_array().unwrap();
    let vel = |k: usize, c: usize| balls[k]["vel"][c].as_f64().unwrap();
    if wall {
        vel(0, 2) / v
    } else {
        (vel(1, 0) - vel(0, 0)) / v
    }
}

#[test]
fn restitution_holds_at_the_default_step() {
    // The step at FRAction 0.2 (Rayleigh, doc/spec/DECISIONS.md).
    let g: f64 = 1e8 / 2.6;
    let dt = 0.2 * std::f64::consts::PI * 0.01 * (2500.0f64 / g).sqrt() / (0.1631 * 0.3 + 0.8766);
    let mut worst: f64 = 0.0;
    for wall in [true, false] {
        for e in [0.1, 0.3, 0.5, 0.7, 0.9] {
            for v in [0.1, 1.0, 10.0] {
                for phase in [0.0, 0.37, 0.71] {
                    // 1 mm plus a fraction of a step's travel.
                    let gap = 1e-3 + phase * v * dt;
                    let cycles = (gap / (v * dt)) as u64 + 80;
                    let got = rebound(wall, e, v, gap, cycles);
                    let tol = (0.011 * e).max(0.0015);
                    assert!(
                        (got - e).abs() < tol,
                        "{} e = {e}, {v} m/s, phase {phase}: rebound {got}",
                        if wall { "wall" } else { "sphere" }
                    );
                    worst = worst.max((got / e - 1.0).abs());
                }
            }
        }
    }
    eprintln!("worst relative error {worst:.4}");
}

/// A heavy dashpot, e = 0.05 (issue 49 item 8), at the default step: the scene's default
/// FRAction is shortened for it to `0.2 ζ(0.2)/ζ(0.05)` (`physics::dashpot::heavy_step_share`,
/// 0.0752: ζ(0.2)/ζ(0.05) = 1.635/4.350 of the calibrated dashpot, which the RK4 of the
/// contact's equation gives too), and the rebound holds e within 1 % against the wall and against a like sphere at
/// 1, 10 and 30 m/s, first touch at six places within a step (the reference is the set e,
/// exact for the calibrated dashpot in continuous time). At FRAction 0.2 the same impacts
/// came out −0.25 … −2.7 % (doc/limits.md). `PRint INFo` says why the step is shorter; a
/// FRAction given keeps its step, and e = 0.1 keeps the default step.
#[test]
fn a_heavy_dashpot_holds_its_restitution_at_the_default_step() {
    let g: f64 = 1e8 / 2.6;
    let dt_r = std::f64::consts::PI * 0.01 * (2500.0f64 / g).sqrt() / (0.1631 * 0.3 + 0.8766);
    let zeta = trubal::physics::restitution::zeta_for_restitution;
    let share = zeta(0.2) / zeta(0.05);
    assert!((share - 0.3759).abs() < 1e-4, "{share}");
    let dt = 0.2 * share * dt_r;
    let mut worst: f64 = 0.0;
    for wall in [true, false] {
        for v in [1.0, 10.0, 30.0] {
            for phase in [0.0, 0.2, 0.37, 0.5, 0.71, 0.9] {
                let gap = 1e-3 + phase * v * dt;
                let cycles = (gap / (v * dt)) as u64 + 200;
                let got = rebound(wall, 0.05, v, gap, cycles);
                let err = got / 0.05 - 1.0;
                assert!(
                    err.abs() < 0.01,
                    "{} {v} m/s, phase {phase}: rebound {got}",
                    if wall { "wall" } else { "sphere" }
                );
                worst = worst.max(err.abs());
            }
        }
    }
    eprintln!("e = 0.05: worst relative error {worst:.4}");
    // The step in use, and why.
    let info = |e: f64, extra: &str| {
        let s = session(&format!(
            "start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{extra}damping restitution {e}\n\
             create 0.05 0.05 0.05 0 0 0 0 0 0 1 1\n"
        ));
        let (text, j) = trubal::output::print::item(
            s.scene.as_ref().unwrap(),
            trubal::lang::command::PrintItem::Info,
        );
        (j["dt"].as_f64().unwrap(), text)
    };
    let (heavy, text) = info(0.05, "");
    assert!((heavy / dt - 1.0).abs() < 1e-6, "{heavy} {dt}");
    assert!(text.contains("restitution is below 0.1"), "{text}");
    let (light, text) = info(0.1, "");
    assert!((light / (0.2 * dt_r) - 1.0).abs() < 1e-6, "{light}");
    assert!(!text.contains("restitution is below"), "{text}");
    let (given, _) = info(0.05, "fraction 0.2\n");
    assert_eq!(given, light);
}

/// A scene that dissipates nothing (Hertz, no restitution, friction, adhesion, liquid or
/// damping) takes FRAction 0.1 by default, half the step of the same scene with any of them
/// (issue 49 item 4: the elastic gas holds 1e-3 over 10⁷ steps at 0.1, not at 0.2;
/// doc/limits.md), and `PRint INFo` says why; a FRAction given, or AUTO, keeps its own rule.
#[test]
fn a_scene_without_dissipation_takes_the_elastic_default_step() {
    let g: f64 = 1e8 / 2.6;
    let dt_r = std::f64::consts::PI * 0.01 * (2500.0f64 / g).sqrt() / (0.1631 * 0.3 + 0.8766);
    let info = |extra: &str| {
        let s = session(&format!(
            "start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}{extra}\
             create 0.05 0.05 0.05 0 0 0 0 0 0 1 1\n"
        ));
        let (text, j) = trubal::output::print::item(
            s.scene.as_ref().unwrap(),
            trubal::lang::command::PrintItem::Info,
        );
        (j["dt"].as_f64().unwrap(), text)
    };
    let (elastic, text) = info("");
    assert!(
        (elastic / (0.1 * dt_r) - 1.0).abs() < 1e-6,
        "{elastic} {dt_r}"
    );
    assert!(text.contains("dissipates nothing"), "{text}");
    for dissipative in [
        "fric 0.3 1\n",
        "damping restitution 0.9\n",
        "damping 0.01 100 0 0 0\n",
    ] {
        let (dt, text) = info(dissipative);
        assert!(
            (dt / (0.2 * dt_r) - 1.0).abs() < 1e-6,
            "{dissipative}: {dt}"
        );
        assert!(!text.contains("dissipates nothing"), "{text}");
    }
    let (given, _) = info("fraction 0.2\n");
    assert!((given / (0.2 * dt_r) - 1.0).abs() < 1e-6, "{given}");
}

/// The head-on impact of the test sphere's contact (E* = 1e8/(2(1 − 0.3²)), R* and m* of two
/// like spheres, or of a sphere on a wall: R* = R, m* = m) with LIGGGHTS' dashpot, integrated
/// here by RK4 independently of the program: `m* α'' = −(4/3)E* sqrt(R*) α^{3/2} − γ_n α'`,
/// `γ_n = 2 sqrt(5/6) |β| sqrt(S_n m*)`, `β = ln e / sqrt(ln² e + π²)`, `S_n = 2E* sqrt(R* α)`
/// (LIGGGHTS' `hertz` and EDEM's Hertz–Mindlin), from α = 0 at the speed v. Without `limit`
/// the contact ends when α returns to 0 (the force may pull: LIGGGHTS' `limitForce off`),
/// with it when the total force first reaches zero (it then stays zero: `limitForce on`).
/// Returns the coefficient of restitution.
fn liggghts_rebound_ode(e: f64, wall: bool, v: f64, limit: bool) -> f64 {
    let (r, rho) = (0.01f64, 2500.0f64);
    let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let (r_star, m_star) = if wall { (r, m) } else { (r / 2.0, m / 2.0) };
    let e_star = 1e8 / (2.0 * (1.0 - 0.09));
    let l = e.ln();
    let beta = l / (l * l + std::f64::consts::PI.powi(2)).sqrt();
    let force = |a: f64, w: f64| {
        let a = a.max(0.0);
        let sn = 2.0 * e_star * (r_star * a).sqrt();
        let gn = 2.0 * (5.0f64 / 6.0).sqrt() * beta.abs() * (sn * m_star).sqrt();
        4.0 / 3.0 * e_star * r_star.sqrt() * a.powf(1.5) + gn * w
    };
    // α' = w (closing positive); contact time ~ 2.87 (m*²/(R* E*² v))^{1/5}.
    let tc = 2.87 * (m_star * m_star / (r_star * e_star * e_star * v)).powf(0.2);
    let h = tc / 2e5;
    let (mut a, mut w) = (0.0f64, v);
    let acc = |a: f64, w: f64| -force(a, w) / m_star;
    loop {
        let (k1a, k1w) = (w, acc(a, w));
        let (k2a, k2w) = (w + 0.5 * h * k1w, acc(a + 0.5 * h * k1a, w + 0.5 * h * k1w));
        let (k3a, k3w) = (w + 0.5 * h * k2w, acc(a + 0.5 * h * k2a, w + 0.5 * h * k2w));
        let (k4a, k4w) = (w + h * k3w, acc(a + h * k3a, w + h * k3w));
        let (na, nw) = (
            a + h / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a),
            w + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w),
        );
        if na <= 0.0 && nw < 0.0 {
            // Back at α = 0: the velocity there (linear in the last step).
            let f = a / (a - na);
            return -(w + f * (nw - w)) / v;
        }
        if limit && nw < 0.0 && force(na, nw) <= 0.0 {
            return -nw / v;
        }
        (a, w) = (na, nw);
    }
}

/// LIGGGHTS' (and EDEM's) dashpot, `SET DASHpot LIGGGHTS`: with the force free to pull, the
/// rebound is the e set (Tsuji et al.'s relation is exact for this form, the independent RK4
/// shows it); with the force kept compressive (`LIMITFORCE`, LIGGGHTS' `limitForce on`) the
/// same dashpot is livelier: e = 0.25 rebounds at 0.361, the "his 0.25 behaves like our
/// 0.361" of issue 53. trubal's default gives e with the force kept compressive. Through
/// the binary, sphere on sphere and on a wall, 1 m/s, FRAction 0.2 (9–27 steps per contact):
/// within 1.1 % of the RK4 figure kept compressive, 3.5 % free to pull.
#[test]
fn liggghts_dashpot_forms_rebound_as_their_closed_forms() {
    let g: f64 = 1e8 / 2.6;
    let dt = 0.2 * std::f64::consts::PI * 0.01 * (2500.0f64 / g).sqrt() / (0.1631 * 0.3 + 0.8766);
    // The reference figures first, from the RK4 alone.
    for e in [0.1, 0.25, 0.5, 0.9] {
        let free = liggghts_rebound_ode(e, false, 1.0, false);
        assert!(
            (free - e).abs() < 2e-4 * e.max(0.1),
            "e = {e}: free RK4 {free}"
        );
    }
    let limited = liggghts_rebound_ode(0.25, false, 1.0, true);
    assert!(
        (limited - 0.361).abs() < 1e-3,
        "LIMITFORCE at e = 0.25: {limited}"
    );
    // Speed-independent, as the Hertzian dashpot is (the RK4 at 0.1 and 10 m/s).
    for v in [0.1, 10.0] {
        let x = liggghts_rebound_ode(0.25, true, v, true);
        assert!((x - limited).abs() < 1e-3, "{v} m/s: {x}");
    }
    for wall in [false, true] {
        for e in [0.25, 0.5, 0.9] {
            let gap = 1e-3 + 0.37 * dt;
            let cycles = (gap / dt) as u64 + 80;
            for (form, limit) in [("liggghts", false), ("edem", false), ("limitforce", true)] {
                let want = liggghts_rebound_ode(e, wall, 1.0, limit);
                let got = rebound_with(&format!("set dashpot {form}\n"), wall, e, 1.0, gap, cycles);
                // The pulling form's last step (the dashpot's pull as the overlap crosses
                // zero) is resolved less well: up to 3 % at this step and phase, measured
                // (0.4 % at FRAction 0.2 in another phase, 0.02 % at 0.1).
                let tol = if limit { 0.011 } else { 0.035 };
                assert!(
                    (got - want).abs() < tol * want,
                    "{form} wall {wall} e {e}: rebound {got}, RK4 {want}"
                );
            }
            // trubal's own form still gives e.
            let got = rebound_with("set dashpot trubal\n", wall, e, 1.0, gap, cycles);
            assert!(
                (got - e).abs() < 0.011 * e,
                "trubal wall {wall} e {e}: {got}"
            );
        }
    }
}

/// The form is a choice per material pair: `SET DASHpot LIMITFORCE 1 2` changes the
/// particle–wall pair (material 2 the wall's) and leaves the particles' pair alone.
#[test]
fn dashpot_form_is_per_material_pair() {
    let deck = |form: &str| {
        format!(
            "start 0.2 0.1 0.1 100 10 2\nset open all\n{MATERIAL}ymd 1e8 2\npra 0.3 2\ndensity 2500 2\n\
             {form}damping restitution 0.25\ndwall p 0 0 1 0.02 m 2\n\
             create 0.05 0.05 0.0310 0 0 -1 0 0 0 1 1\n\
             create 0.12 0.05 0.06 0.5 0 0 0 0 0 1 1\ncreate 0.1410 0.05 0.06 -0.5 0 0 0 0 0 1 1\n\
             cycle 400\nprint balls\n"
        )
    };
    let run = |form: &str| {
        let r = trubal_json(&deck(form), &[]);
        assert!(r.ok, "{}", r.stderr);
        let b = printed(&r, "balls");
        let balls = b.last().unwrap()["balls"].as_array().unwrap().clone();
        let vel = |k: usize, c: usize| balls[k]["vel"][c].as_f64().unwrap();
        (vel(0, 2), vel(2, 0) - vel(1, 0))
    };
    let (wall0, pair0) = run("");
    let (wall1, pair1) = run("set dashpot limitforce 1 2\n");
    assert_eq!(pair0.to_bits(), pair1.to_bits(), "the 1-1 pair changed");
    assert!((wall0 - 0.25).abs() < 0.011 * 0.25, "wall, trubal: {wall0}");
    let want = liggghts_rebound_ode(0.25, true, 1.0, true);
    assert!(
        (wall1 - want).abs() < 0.011 * want,
        "wall, LIMITFORCE: {wall1} against {want}"
    );
}

/// Bad `SET DASHpot` input is refused with its place, and changes nothing: the form given
/// before still holds after the refusals (`--keep-going`).
#[test]
fn bad_dashpot_input_is_refused_with_its_place_and_changes_nothing() {
    let head = format!("start 0.1 0.1 0.1 100 10 2\nset open all\n{MATERIAL}");
    for (line, col, msg) in [
        ("set dashpot", 12, "TRUBAL, LIGGGHTS, EDEM or LIMITFORCE"),
        (
            "set dashpot tsuji",
            13,
            "TRUBAL, LIGGGHTS, EDEM or LIMITFORCE",
        ),
        (
            "set dashpot liggghts 9",
            1,
            "material type 9 is not defined",
        ),
        ("set dashpot liggghts 1 1 junk", 26, "junk"),
    ] {
        let run = trubal_json(&format!("{head}{line}\n"), &[]);
        let want = format!("<stdin>:7:{col}: error");
        assert!(
            run.stderr.contains(&want) && run.stderr.contains(msg),
            "{line}: {}",
            run.stderr
        );
    }
    let run = trubal_json(
        &format!(
            "{head}set dashpot limitforce\nset dashpot tsuji\nset dashpot trubal 9\n\
             damping restitution 0.25\ndwall p 0 0 1 0.02\n\
             create 0.05 0.05 0.0310 0 0 -1 0 0 0 1 1\ncycle 400\nprint balls\n"
        ),
        &["--keep-going"],
    );
    let b = &printed(&run, "balls")[0]["balls"][0];
    let e = b["vel"][2].as_f64().unwrap();
    let want = liggghts_rebound_ode(0.25, true, 1.0, true);
    assert!(
        (e - want).abs() < 0.011 * want,
        "{e} against {want}: {}",
        run.stderr
    );
}
