//! The time-step study behind the default FRAction (doc/performance.md, "Speed against
//! error"). Ignored in the suite: `cargo test --release --test it timestep_study:: -- --ignored
//! --nocapture` prints the tables.

use crate::common;
use common::*;

fn hertz_binary(fraction: f64) -> (f64, f64, f64, u64) {
    let mut sc = scene(&format!(
        "start 0.2 0.1 0.1 1000 10 2\nset open all\nrad 0.01 1\nymd 4.8e10 1\npra 0.2 1\ndensity 2800 1\n\
         fraction {fraction}\ncreate 0.09 0.05 0.05 10 0 0 0 0 0 1 1\ncreate 0.11 0.05 0.05 -10 0 0 0 0 0 1 1\n"
    ));
    let mut fmax: f64 = 0.0;
    let mut prev = 0.0;
    let mut started = false;
    let mut tc = f64::NAN;
    for _ in 0..100_000 {
        step(&mut sc);
        let c = &sc.contacts().pair(0).s;
        fmax = fmax.max(c.normal_force);
        let gap = -c.overlap;
        if gap < 0.0 {
            started = true;
        }
        if started && gap >= 0.0 {
            let dt = sc.time() / sc.cycle() as f64;
            tc = sc.time() - 2.0 * dt + (-prev / (gap - prev)) * dt;
            break;
        }
        prev = gap;
    }
    let e = (sc.particles().vel[1].x - sc.particles().vel[0].x) / 20.0;
    (e, tc, fmax, sc.cycle())
}

fn jkr_threshold(fraction: f64) -> f64 {
    // Bisection on the relative velocity at which two equal adhesive spheres rebound.
    let rebounds = |v: f64| {
        let mut sc = scene(&format!(
            "start 1e-3 1e-3 1e-3 100 10 2\nset open all\nrad 30e-6 1\nymd 70e9 1\npra 0.3 1\ndensity 2650 1\n\
             cohesion 0.4 1\nfraction {fraction}\ncreate 4e-4 5e-4 5e-4 {} 0 0 0 0 0 1 1\n\
             create 4.6e-4 5e-4 5e-4 {} 0 0 0 0 0 1 1\n",
            v / 2.0,
            -v / 2.0
        ));
        trubal::sim::cycle::run(&mut sc, (2000.0 / fraction) as u64).unwrap();
        !sc.contacts().iter().any(|c| c.s.touching)
    };
    let (mut lo, mut hi) = (0.01, 0.1);
    for _ in 0..14 {
        let mid = 0.5 * (lo + hi);
        if rebounds(mid) { hi = mid } else { lo = mid }
    }
    0.5 * (lo + hi)
}

#[test]
#[ignore]
fn print_timestep_tables() {
    let m = 2800.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    let e_star = 4.8e10 / (2.0 * 0.96);
    let m_star = m / 2.0;
    let r_star: f64 = 0.005;
    let a_max = (15.0 * m_star * 400.0 / (16.0 * e_star * r_star.sqrt())).powf(0.4);
    let f_th = 4.0 / 3.0 * e_star * r_star.sqrt() * a_max.powf(1.5);
    let t_th = 2.868 * (m_star * m_star / (r_star * e_star * e_star * 20.0)).powf(0.2);
    println!(
        "| FRAction | steps per contact | restitution error | contact time error | peak force error |"
    );
    println!("|---|---|---|---|---|");
    for f in [0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0] {
        let (e, tc, fmax, _) = hertz_binary(f);
        let dt_r = std::f64::consts::PI * 0.01 * (2800.0f64 / (4.8e10 / 2.4)).sqrt()
            / (0.1631 * 0.2 + 0.8766);
        println!(
            "| {f} | {:.1} | {:.2e} | {:+.2} % | {:+.2} % |",
            t_th / (f * dt_r),
            (e - 1.0).abs(),
            100.0 * (tc / t_th - 1.0),
            100.0 * (fmax / f_th - 1.0)
        );
    }
    // JKR sticking threshold vs the theory v_s = sqrt(2 W_p / m*).
    let pc = 3.0 * std::f64::consts::PI * 0.4 * 15e-6;
    let es = 70e9 / (2.0 * 0.91);
    let alpha_s = -(3.0 * pc * pc / (16.0 * es * es * 15e-6)).cbrt();
    let wp = -4.0 / 45.0 * (1.0 + 6.0 * 4f64.cbrt()) * pc * alpha_s;
    let mj = 2650.0 * 4.0 / 3.0 * std::f64::consts::PI * (30e-6f64).powi(3);
    let vs = (2.0 * wp / (mj / 2.0)).sqrt();
    println!("\n| FRAction | JKR sticking threshold error |\n|---|---|");
    for f in [0.05, 0.1, 0.2, 0.5, 1.0] {
        let v = jkr_threshold(f);
        println!("| {f} | {:+.2} % |", 100.0 * (v / vs - 1.0));
    }
}
