//! Ball indentation (Pasha 2013 ch. 5; issue 36): the cylindrical die, the indenter, the
//! piston servo, generation from a number-frequency table inside the die, and the bad input
//! around them (doc/indentation.md).

use crate::common::{printed, rel, scene, session, step, trubal_json};
use trubal::sim::energy;

/// Two materials: 1 the particles, 2 the walls.
const MATS: &str = "ymd 1e8 1\npra 0.25 1\ndensity 2500 1\nymd 2e8 2\npra 0.3 2\ndensity 7800 2\n";

/// E* of the particles (1) against the walls (2): (1 − ν1²)/E1 + (1 − ν2²)/E2 inverted.
fn e_star() -> f64 {
    1.0 / ((1.0 - 0.25 * 0.25) / 1e8 + (1.0 - 0.3 * 0.3) / 2e8)
}

/// A fixed sphere of radius R pressed δ into the inside of a die of radius 10 R whose axis is
/// oblique, (0, 0.6, 0.8): the force on the wall is Hertz's 4/3 E* √R_e δ^{3/2}, with the
/// equivalent radius of the two principal relative radii R' = R Rc/(Rc − R) (around the
/// axis) and R'' = R (along it), R_e = √(R' R''); outward along the radius.
#[test]
fn a_sphere_on_the_die_wall_gets_hertz_with_the_equivalent_radius() {
    let (r, rc, delta) = (4e-4f64, 4e-3, 2e-6f64);
    // The axis through (5, 5, 5) mm; the sphere 2 mm along the axis and Rc − R + δ off it
    // along x (x is perpendicular to the axis).
    let (px, py, pz) = (
        5e-3 + (rc - r + delta),
        5e-3 + 0.6 * 2e-3,
        5e-3 + 0.8 * 2e-3,
    );
    let mut sc = scene(&format!(
        "start 0.01 0.01 0.01 10 10 2\nset open all\nrad {r} 1\n{MATS}\
         dwall cylinder 5e-3 5e-3 5e-3 0 3 4 {rc} m 2\n\
         create {px} {py} {pz} 0 0 0 0 0 0 1 1\nfix 1 1 1 1 1 1 1\n"
    ));
    step(&mut sc);
    let r1 = r * rc / (rc - r);
    let r_e = (r1 * r).sqrt();
    let want = 4.0 / 3.0 * e_star() * r_e.sqrt() * delta.powf(1.5);
    let w = &sc.walls()[0];
    assert!(
        rel(w.normal_force, want) < 1e-9,
        "{} vs {want}",
        w.normal_force
    );
    assert!(rel(w.force[0], want) < 1e-9 && w.force[1].abs() < 1e-12 * want);
    // Not the plane's R nor the sphere container's R'.
    let plane = 4.0 / 3.0 * e_star() * r.sqrt() * delta.powf(1.5);
    assert!(rel(w.normal_force, plane) > 0.02);
}

/// A fixed sphere of radius R pressed δ onto an indenter of radius 8 R (particles outside):
/// R* = R Ro/(Ro + R) (doc/spec/DECISIONS.md), the force on the indenter pointing away from
/// the sphere.
#[test]
fn a_sphere_under_the_indenter_gets_hertz_with_the_convex_radius() {
    let (r, ro, delta) = (4e-4f64, 3.2e-3, 1e-6f64);
    let z = 5e-3 - (ro + r - delta);
    let mut sc = scene(&format!(
        "start 0.01 0.01 0.01 10 10 2\nset open all\nrad {r} 1\n{MATS}\
         create 5e-3 5e-3 {z} 0 0 0 0 0 0 1 1\nfix 1 1 1 1 1 1 1\n\
         dwall ob 5e-3 5e-3 5e-3 {ro} m 2\n"
    ));
    step(&mut sc);
    let r_star = r * ro / (ro + r);
    let want = 4.0 / 3.0 * e_star() * r_star.sqrt() * delta.powf(1.5);
    let w = &sc.walls()[0];
    // The particle below pushes the indenter up.
    assert!(rel(w.force[2], want) < 1e-9, "{:?} vs {want}", w.force);
    assert!(rel(w.normal_force, want) < 1e-9);
}

/// A small bed in a die (RAdius TABle, RGEnerate WAlls), pressed by a servo piston to
/// 10 kPa: the piston's force settles within 2 % of σ A; then the piston at constant speed
/// and an indenter at constant speed do work on the bed and the energy ledger closes.
#[test]
fn the_piston_servo_reaches_10_kpa_and_the_books_close_with_piston_and_indenter() {
    let rc = 4e-3;
    let area = std::f64::consts::PI * rc * rc;
    let target = 1e4 * area;
    let (vmax, gain) = (0.05, 0.05 / target);
    let mut s = session(&format!(
        "start 0.01 0.01 0.012 10 400 4\nset open all\nset tangential noslip\n\
         rad 5e-4 1 table 4e-4 1 5e-4 2 6e-4 1\n{MATS}friction 0.3 1\n\
         damping restitution 0.5 1\ndamping restitution 0.3 2\n\
         dwall cylinder 5e-3 5e-3 0 0 0 1 {rc} m 2\ndwall p 0 0 1 0 m 2\n\
         dwall p 0 0 -1 -0.005 m 2 se {target} {vmax} {gain}\nrge 120 1 1 0 walls\n\
         gravity 0 0 -9.81\n"
    ));
    let mut forces = Vec::new();
    for _ in 0..70 {
        s.run_line("cycle 500").unwrap();
        forces.push(s.scene.as_ref().unwrap().walls()[2].normal_force);
    }
    // The last 5000 steps: every record within 2 % of σ A.
    for f in &forces[60..] {
        assert!(rel(*f, target) < 0.02, "{f} vs {target}: {forces:?}");
    }
    // Now the piston pushes at constant speed (the servo's target out of reach, its speed
    // at vmax) and an indenter comes down; every joule the walls put in is booked.
    let sc = s.scene.as_mut().unwrap();
    let before = (energy::residual(sc), sc.ledger().input());
    let top = (0..sc.particles().len())
        .map(|i| sc.particles().pos[i].z + sc.particles().radius[i])
        .fold(0.0, f64::max);
    let z_ind = top + 1.5e-3 + 1e-4;
    s.run_line(&format!(
        "dwall ob 5e-3 5e-3 {z_ind} 1.5e-3 v 0 0 -0.05 m 2"
    ))
    .unwrap();
    s.run_line("cycle 4000").unwrap();
    let sc = s.scene.as_ref().unwrap();
    let input = sc.ledger().input() - before.1;
    let walls = sc.ledger().walls;
    let res = energy::residual(sc) - before.0;
    assert!(sc.walls()[3].force[2] > 0.0, "the indenter is in the bed");
    assert!(walls > 0.0, "the walls did work: {walls}");
    assert!(
        res.abs() < 2e-3 * input.abs().max(walls),
        "residual {res} of input {input} (walls {walls})"
    );
}

/// RAdius TABle with Pasha's Table 5.1 (diameters halved): the number fractions of 6000
/// generated particles match the table within four standard deviations of the binomial.
#[test]
fn table_sizes_come_out_in_the_table_frequencies() {
    let table = [
        (0.59, 0.33),
        (0.72, 3.84),
        (0.81, 11.24),
        (0.90, 21.00),
        (1.00, 27.75),
        (1.10, 20.85),
        (1.19, 10.95),
        (1.28, 3.74),
        (1.41, 0.29),
    ];
    let tab: Vec<String> = table
        .iter()
        .map(|(d, f)| format!("{:e} {f}", d * 0.5e-3))
        .collect();
    let n = 6000;
    let sc = scene(&format!(
        "start 0.1 0.1 0.1 10 {n} 0\nrad 5e-4 1 table {}\nrge {n} 1 1 0\n",
        tab.join(" ")
    ));
    assert_eq!(sc.particles().len(), n);
    let total: f64 = table.iter().map(|t| t.1).sum();
    for (d, f) in table {
        let k = sc
            .particles()
            .radius
            .iter()
            .filter(|&&r| r == d * 0.5e-3)
            .count();
        let p = f / total;
        let sd = (p * (1.0 - p) / n as f64).sqrt();
        let got = k as f64 / n as f64;
        assert!(
            (got - p).abs() < 4.0 * sd + 1e-9,
            "d = {d} mm: {got} vs {p}"
        );
    }
    // Every radius is one of the table's.
    assert!(
        sc.particles()
            .radius
            .iter()
            .all(|r| table.iter().any(|t| t.0 * 0.5e-3 == *r))
    );
}

/// RGEnerate WAlls places every particle wholly inside the die, above the floor and below
/// the lid; without WAlls, particles outside the die are counted in a warning.
#[test]
fn generation_inside_the_die_and_a_warning_outside_it() {
    let deck = |walls: &str| {
        format!(
            "start 0.02 0.02 0.02 10 2000 4\nset open all\nrad 5e-4 1 uniform 4e-4 6e-4\n{MATS}\
             dwall cylinder 0.01 0.01 0 0 0 1 0.005 m 2\ndwall p 0 0 1 0.001 m 2\n\
             dwall p 0 0 -1 -0.015 m 2\nrge 300 1 1 0 {walls}\nprint balls\n"
        )
    };
    let run = trubal_json(&deck("walls"), &[]);
    assert!(run.ok, "{}", run.stderr);
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    let balls = &printed(&run, "balls")[0]["balls"];
    assert_eq!(balls.as_array().unwrap().len(), 300);
    for b in balls.as_array().unwrap() {
        let x: Vec<f64> = (0..3).map(|k| b["pos"][k].as_f64().unwrap()).collect();
        let r = b["radius"].as_f64().unwrap();
        let rho = (x[0] - 0.01).hypot(x[1] - 0.01);
        assert!(
            rho + r <= 0.005 && x[2] - r >= 0.001 && x[2] + r <= 0.015,
            "{x:?} {r}"
        );
    }
    let run = trubal_json(&deck(""), &[]);
    assert!(run.ok, "{}", run.stderr);
    assert!(
        run.stderr.contains("warning: RGEnerate placed") && run.stderr.contains("WAlls"),
        "{}",
        run.stderr
    );
}

/// Bad input: each refused with a clear message and nothing changed, or warned about
/// before cycling.
#[test]
fn bad_dies_indenters_tables_and_servos() {
    let base = format!("start 0.02 0.02 0.02 10 100 4\nset open all\nrad 5e-4 1\n{MATS}");
    let mut s = session(&base);
    for (line, want) in [
        ("dwall cylinder 0.01 0.01 0 0 0 1 0", "positive"),
        ("dwall cylinder 0.01 0.01 0 0 0 1 -0.003", "positive"),
        ("dwall cylinder 0.01 0.01 0 0 0 0 0.003", "non-zero axis"),
        ("dwall cylinder 0.01 0.01 0 0 0 1", "r (radius)"),
        ("rad 1e-3 2 table", "pairs of numbers"),
        ("rad 1e-3 2 table 1e-3 0 2e-3 0", "at least one above 0"),
        ("rad 1e-3 2 table 1e-3 1 2e-3", "fk"),
        ("rad 1e-3 2 table 1e-3 -1", "fk"),
    ] {
        let e = s.run_line(line).expect_err(line);
        assert!(e.message.contains(want), "{line}: {}", e.message);
    }
    let sc = s.scene.as_ref().unwrap();
    assert!(sc.walls().is_empty(), "{:?}", sc.walls());
    assert_eq!(sc.sizes()[1], 0.0, "{:?}", sc.sizes());
    // A bed, then an indenter that starts inside it: refused (a particle's centre inside
    // the indenter), nothing changed; one that only cuts the top particles: a warning.
    s.run_line("create 0.01 0.01 0.0005 0 0 0 0 0 0 1 1")
        .unwrap();
    s.run_line("create 0.011 0.01 0.0005 0 0 0 0 0 0 1 1")
        .unwrap();
    let e = s
        .run_line("dwall ob 0.01 0.01 0.002 0.0018 m 2")
        .expect_err("indenter in the bed");
    assert!(
        e.message
            .contains("wall 1 would leave 1 particle(s) with the centre inside the obstacle"),
        "{}",
        e.message
    );
    assert!(s.scene.as_ref().unwrap().walls().is_empty());
    // The same die around particles outside it: refused.
    let e = s
        .run_line("dwall cylinder 0.0105 0.01 0 0 0 1 0.0004")
        .expect_err("die around nothing");
    assert!(
        e.message.contains("with the centre outside the die"),
        "{}",
        e.message
    );
    let run = trubal_json(
        &format!(
            "{base}create 0.01 0.01 0.0005 0 0 0 0 0 0 1 1\ndwall ob 0.01 0.01 0.0028 0.002 m 2\n"
        ),
        &[],
    );
    assert!(run.ok, "{}", run.stderr);
    assert!(
        run.stderr.contains("warning: wall 1 cuts 1 particle(s)"),
        "{}",
        run.stderr
    );
    // RGEnerate WAlls when the walls leave no room in the work-space.
    let mut s = session(&format!(
        "{base}dwall p 0 0 -1 -0.03\ndwall p 0 0 1 0.025\n"
    ));
    let e = s.run_line("rge 10 1 1 0 walls").expect_err("no room");
    assert!(e.message.contains("leave no room"), "{}", e.message);
    assert!(s.scene.as_ref().unwrap().particles().is_empty());
    // Servos that cannot reach their targets: warned about before the Cycle.
    let run = trubal_json(
        &format!(
            "{base}create 0.01 0.01 0.0005 0 0 0 0 0 0 1 1\n\
             dwall p 0 0 -1 -0.002 m 2 se 1 0 0\ndwall p 0 0 1 0 m 2 se -1 0.1 0.01\ncycle 1\n"
        ),
        &[],
    );
    assert!(run.ok, "{}", run.stderr);
    for want in [
        "servo of wall 1 cannot move (vmax = 0, g = 0)",
        "servo of wall 2 targets a pull (-1 N < 0)",
    ] {
        assert!(run.stderr.contains(want), "{want}: {}", run.stderr);
    }
}

/// A die with an indenter and table sizes goes through SAve and RESTart: the continued run
/// is the uninterrupted one to the bit.
#[test]
fn a_die_with_an_indenter_continues_bitwise_after_restart() {
    let run = trubal_json(
        &format!(
            "start 0.01 0.01 0.01 10 100 4\nset open all\nrad 5e-4 1 table 4e-4 1 6e-4 1\n{MATS}\
             damping restitution 0.5 1\ndwall cylinder 5e-3 5e-3 0 0 0 1 3e-3 v 0 0 0 -0.01 m 2\n\
             dwall p 0 0 1 0 m 2\ndwall p 0 0 -1 -0.004 m 2\nrge 40 1 1 0 walls\ngravity 0 0 -9.81\ncycle 2000\n\
             dwall ob 5e-3 5e-3 6e-3 1e-3 v 0 0 -0.2 m 2\ncycle 300\nsave a.sav\ncycle 300\n\
             print balls walls\nnew\nrestart a.sav\ncycle 300\nprint balls walls\n"
        ),
        &[],
    );
    assert!(run.ok, "{}", run.stderr);
    let (b, w) = (printed(&run, "balls"), printed(&run, "walls"));
    assert_eq!(b[0], b[1]);
    assert_eq!(w[0], w[1]);
    assert!(
        w[0]["walls"][0]["geometry"]["Cylinder"]["radius"]
            .as_f64()
            .unwrap()
            < 3e-3
    );
}

/// A piston still above the bed (no contacts yet) with a gain that will make it hunt through
/// the dashpots of the layer it is going to press: warned about before the first Cycle, with
/// the gain to use; a gain below that is not warned about.
#[test]
fn a_hunting_piston_is_warned_about_before_it_touches() {
    let deck = |g: f64| {
        format!(
            "start 0.01 0.01 0.001 10 200 4\nset open all\nrad 5e-4 1\n{MATS}\
             damping restitution 0.5 1\ndwall p 0 0 1 0 m 2\n\
             age 1 1 0 5e-4 5e-4 5e-4 1e-3 1e-3 1e-3\n\
             dwall p 0 0 -1 -0.003 m 2 se 5 0.1 {g}\ncycle 1\n"
        )
    };
    let run = trubal_json(&deck(1e3), &[]);
    let at = run
        .stderr
        .find("through the contacts' dashpots")
        .expect(&run.stderr);
    let tail = &run.stderr[at..];
    let g_max: f64 = tail[tail.find("use g below ").unwrap() + 12..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // The 100 particles of the layer count (with the candidate list of the moment, empty,
    // the estimate took one contact and allowed a gain about 100 times larger).
    let run = trubal_json(&deck(2.0 * g_max), &[]);
    assert!(
        run.stderr.contains("through the contacts' dashpots"),
        "{}",
        run.stderr
    );
    let run = trubal_json(&deck(0.5 * g_max), &[]);
    assert!(
        !run.stderr.contains("through the contacts' dashpots"),
        "{}",
        run.stderr
    );
}

/// The stress in bins (`PRint Stress` with a `Window`; Pasha 2013 (5.1)) in a column of five
/// equal spheres resting on the floor under gravity, settled. Each sphere is in equilibrium
/// with the weight w of those above it pressing on its top and w + m g on its bottom, so a
/// bin holding one sphere has σ_zz V = 2 R (w + m g / 2) — the weight above the bin's middle
/// times the sphere's height, computed here from the masses, not from the contact forces.
/// A bin holding the whole column gives ∫σ_zz dV = g Σ m z (the weight times the height of
/// the centre of mass), the floor's contact included. No horizontal stress without friction
/// or lateral neighbours, and no particle-less bin. (FRAction 0.2 given: the heavy dashpot
/// would shorten the default step, and the column settle in more cycles.)
#[test]
fn bin_stresses_in_a_settled_column_carry_the_weight_above() {
    let (r, n) = (5e-4f64, 5usize);
    let mut lines = format!(
        "start 0.004 0.004 0.008 10 10 2\nset open all\nrad {r} 1\n{MATS}\
         damping restitution 0.05 1\ndamping restitution 0.05 2\nfraction 0.2\ndwall p 0 0 1 0 m 2\ngravity 0 0 -9.81\n"
    );
    for k in 0..n {
        lines += &format!(
            "create 2e-3 2e-3 {} 0 0 0 0 0 0 1 1\n",
            r + 2.0 * r * k as f64 + 1e-9
        );
    }
    let mut s = session(&lines);
    s.run_line("cycle 40000").unwrap();
    let sc = s.scene.as_ref().unwrap();
    let g = 9.81;
    let m = sc.particles().mass[0];
    assert!(rel(m, 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3)) < 1e-12);
    // The column at rest: the kinetic energy a tiny part of the weight's work.
    let kin: f64 = (0..n)
        .map(|i| 0.5 * m * sc.particles().vel[i].norm_squared())
        .sum();
    assert!(kin < 1e-9 * m * g * r, "still moving: {kin}");
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| sc.particles().pos[a].z.total_cmp(&sc.particles().pos[b].z));
    let (lx, ly) = (1e-3, 1.5e-3);
    for (k, &i) in order.iter().enumerate() {
        let z = sc.particles().pos[i].z;
        let b = [
            2e-3 - lx / 2.0,
            2e-3 + lx / 2.0,
            2e-3 - ly / 2.0,
            2e-3 + ly / 2.0,
            z - r,
            z + r,
        ];
        let vol = lx * ly * 2.0 * r;
        let (st, count) = trubal::sim::stress::in_box(sc, &b);
        assert_eq!(count, 1, "bin {k}");
        let above = (n - 1 - k) as f64 * m * g;
        let want = 2.0 * r * (above + 0.5 * m * g) / vol;
        let t = st.total();
        assert!(rel(t[2][2], want) < 2e-3, "bin {k}: {} vs {want}", t[2][2]);
        for (a, row) in t.iter().enumerate() {
            for (c, x) in row.iter().enumerate() {
                if (a, c) != (2, 2) {
                    assert!(x.abs() < 1e-9 * want, "bin {k}: σ[{a}][{c}] = {x}");
                }
            }
        }
    }
    let all = [0.0, 0.004, 0.0, 0.004, 0.0, 0.008];
    let (st, count) = trubal::sim::stress::in_box(sc, &all);
    assert_eq!(count, n);
    let moment: f64 = (0..n).map(|i| m * g * sc.particles().pos[i].z).sum();
    let vol = 0.004 * 0.004 * 0.008;
    assert!(
        rel(st.total()[2][2] * vol, moment) < 2e-3,
        "{} vs {moment}",
        st.total()[2][2] * vol
    );
    let (st, count) = trubal::sim::stress::in_box(sc, &[0.0, 0.004, 0.0, 0.004, 0.007, 0.008]);
    assert_eq!((count, st), (0, Default::default()));
    // The same through PRint Stress with a Window (JSON: the bin beside the average).
    s.run_line(&format!("window 0 0.004 0 0.004 0 {}", 2.0 * r))
        .unwrap();
    let (_, j) = trubal::output::print::item(
        s.scene.as_ref().unwrap(),
        trubal::lang::command::PrintItem::Stress,
    );
    let w = &j["window"];
    assert_eq!(w["particles"], 1);
    let want = 2.0 * r * ((n as f64 - 0.5) * m * g) / (0.004 * 0.004 * 2.0 * r);
    assert!(rel(w["stress"][2][2].as_f64().unwrap(), want) < 2e-3, "{w}");
    assert!(rel(w["hydrostatic"].as_f64().unwrap(), want / 3.0) < 2e-3);
}

/// `AWAll n V ...` takes a servo off: the piston then moves at the velocity given (before,
/// the servo set its velocity again at the next step and the V was lost).
#[test]
fn awall_velocity_takes_the_servo_off() {
    let mut s = session(&format!(
        "start 0.01 0.01 0.01 10 10 4\nset open all\nrad 5e-4 1\n{MATS}\
         create 5e-3 5e-3 1e-3 0 0 0 0 0 0 1 1\n\
         dwall p 0 0 -1 -0.008 m 2 se 1.0 0.01 0.01\ncycle 10\n"
    ));
    let sc = s.scene.as_ref().unwrap();
    assert!(sc.walls()[0].servo.is_some());
    // The servo pushes down at vmax (no force on the piston yet).
    assert!(
        rel(sc.walls()[0].vel[2], -0.01) < 1e-12,
        "{:?}",
        sc.walls()[0].vel
    );
    s.run_line("awall 1 v 0 0 0.02").unwrap();
    let z0 = match s.scene.as_ref().unwrap().walls()[0].geom {
        trubal::sim::model::WallGeom::Plane { d, .. } => -d,
        _ => unreachable!(),
    };
    s.run_line("cycle 100").unwrap();
    let sc = s.scene.as_ref().unwrap();
    assert!(sc.walls()[0].servo.is_none());
    assert_eq!(sc.walls()[0].vel, [0.0, 0.0, 0.02]);
    let z1 = match sc.walls()[0].geom {
        trubal::sim::model::WallGeom::Plane { d, .. } => -d,
        _ => unreachable!(),
    };
    let dt = sc.time() / sc.cycle() as f64;
    assert!(
        rel(z1 - z0, 0.02 * 100.0 * dt) < 1e-6,
        "{} vs {}",
        z1 - z0,
        0.02 * 100.0 * dt
    );
    // SE again puts a servo on.
    s.run_line("awall 1 se 1.0 0.01 0.01").unwrap();
    assert!(s.scene.as_ref().unwrap().walls()[0].servo.is_some());
}
