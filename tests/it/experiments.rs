//! The measures of the thesis experiments through a session (PRint BONds / CLUsters / ENErgy
//! as JSON) on hand-built cases with known answers, and a reduced moist wall impact (Lian ch. 6)
//! checked for its qualitative behaviour.

use crate::common;

use std::io::Write;
use std::sync::{Arc, Mutex};

use serde_json::Value;
use trubal::session::Session;
use trubal::sim::Vec3;

/// Output sink shared with the test.
#[derive(Clone, Default)]
struct Sink(Arc<Mutex<Vec<u8>>>);

impl Write for Sink {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.lock().expect("the sink's lock").extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

struct Run {
    s: Session,
    out: Sink,
}

impl Run {
    fn new(lines: &str) -> Run {
        let out = Sink::default();
        let mut s = crate::common::session_with(Box::new(out.clone()), true)
            .with_diagnostics(Box::new(std::io::sink()));
        let mut r = Run {
            s: crate::common::session_with(Box::new(std::io::sink()), true)
                .with_diagnostics(Box::new(std::io::sink())),
            out,
        };
        std::mem::swap(&mut r.s, &mut s);
        r.lines(lines);
        r
    }

    fn lines(&mut self, lines: &str) {
        for (k, l) in lines.lines().enumerate() {
            if let Err(e) = self.s.run_line(l) {
                panic!("line {}: `{l}`: {}", k + 1, e.message);
            }
        }
    }

    /// Runs one PRint line and returns its JSON objects by name.
    fn print(&mut self, items: &str) -> std::collections::HashMap<String, Value> {
        self.out.0.lock().expect("the sink's lock").clear();
        self.lines(&format!("print {items}"));
        self.s.flush();
        let text = String::from_utf8(self.out.0.lock().expect("the sink's lock").clone()).unwrap();
        text.lines()
            .filter(|l| l.starts_with('{'))
            .map(|l| {
                let v: Value = serde_json::from_str(l).unwrap();
                (v["print"].as_str().unwrap().to_string(), v)
            })
            .collect()
    }

    fn scene(&mut self) -> &mut trubal::sim::Scene {
        self.s.scene.as_mut().unwrap()
    }
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn u(v: &Value) -> u64 {
    v.as_u64().unwrap()
}

/// A chain of four touching R = 30 um spheres along x, silicone bridges, no viscosity.
const CHAIN: &str = "\
start 1e-3 1e-3 1e-3 1000 10 2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
cr 2e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
cr 2.6e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
cr 3.2e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
cr 3.8e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
liquid 0.1 0.025 0 0
set fragment 70e-6
cycle 1
plot save";

#[test]
fn chain_end_torn_off_breaks_one_bridge_of_three() {
    let mut r = Run::new(CHAIN);
    let p = r.print("bonds clusters energy");
    let b = &p["bonds"];
    assert_eq!(b["kind"], "bridges");
    assert_eq!(u(&b["initial"]), 3);
    assert_eq!(u(&b["broken"]), 0);
    assert_eq!(f(&b["damage_ratio"]), 0.0);
    assert_eq!(p["clusters"]["sizes"], serde_json::json!([4]));
    let e0 = f(&p["energy"]["dissipated"]["rupture"]);
    let bond_energy = f(&b["bond_energy"]);
    assert!(bond_energy > 0.0);

    // Throw the last particle away along +x at 1 m/s: its bridge stretches beyond
    // S_c = 4.84 um and ruptures; the other three stay bonded.
    let sc = r.scene();
    common::set_velocity(sc, 3, Vec3::new(1.0, 0.0, 0.0));
    r.lines("cycle 3000");
    let p = r.print("bonds clusters energy");
    let b = &p["bonds"];
    assert_eq!((u(&b["initial"]), u(&b["broken"]), u(&b["new"])), (3, 1, 0));
    assert!((f(&b["damage_ratio"]) - 1.0 / 3.0).abs() < 1e-15);
    // Bond probability (6.4) with the reference coordination Z = 2·3/4: Z/12 (1 − D_r + n_r).
    assert!((f(&b["bond_probability"]) - 1.5 / 12.0 * (2.0 / 3.0)).abs() < 1e-15);
    let c = &p["clusters"];
    assert_eq!(c["sizes"], serde_json::json!([3, 1]));
    assert_eq!(
        (u(&c["largest"]), u(&c["debris"]), u(&c["singlets"])),
        (3, 1, 1)
    );
    assert!((f(&c["coordination"]) - 1.0).abs() < 1e-15); // 2 bridges, 4 particles
    // DBSCAN (70 um, 3 points): the three bonded spheres are one fragment, the free one is
    // noise, so Olsson's total fragmentation is 1.
    assert_eq!(u(&c["fragmentation"]), 1);
    assert_eq!(c["fragments"], serde_json::json!([3]));
    // The rupture releases the work stored in that bridge: one third of the bond energy of
    // the three equal reference bridges (they sat at ~1 nm overlap).
    let rupture = f(&p["energy"]["dissipated"]["rupture"]) - e0;
    assert!(
        (rupture - bond_energy / 3.0).abs() < 1e-2 * bond_energy,
        "rupture {rupture:e} vs bond energy / 3 {:e}",
        bond_energy / 3.0
    );
    let e = &p["energy"];
    assert!(
        f(&e["residual"]).abs() < 1e-3 * f(&e["input"]),
        "residual {} input {}",
        e["residual"],
        e["input"]
    );
}

#[test]
fn a_new_bridge_is_counted_new_and_a_wall_bridge_captures() {
    // Two spheres 2 um apart (no bridge) and a wall 2 um under the first; they are pushed
    // together slowly enough to stick.
    let mut r = Run::new(
        "\
start 1e-3 1e-3 1e-3 1000 10 2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
cr 2e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
cr 2.62e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
dwall p 0 0 1 4.68e-4 m 1
liquid 0.1 0.025 0 0.01
cycle 1
plot save",
    );
    let p = r.print("bonds clusters");
    assert_eq!(u(&p["bonds"]["initial"]), 0);
    assert_eq!(p["clusters"]["sizes"], serde_json::json!([1, 1]));
    assert_eq!(f(&p["clusters"]["capture_ratio"]), 0.0);
    let sc = r.scene();
    common::set_velocity(sc, 1, Vec3::new(-0.1, 0.0, 0.0));
    common::set_velocity(sc, 0, Vec3::new(0.0, 0.0, -0.1));
    r.lines("cycle 6000");
    let p = r.print("bonds clusters");
    let b = &p["bonds"];
    assert_eq!((u(&b["initial"]), u(&b["broken"]), u(&b["new"])), (0, 0, 1));
    // No reference bonds: the ratios are reported as 0, not NaN.
    assert_eq!(f(&b["damage_ratio"]), 0.0);
    let c = &p["clusters"];
    assert_eq!(c["sizes"], serde_json::json!([2]));
    // Only the first sphere reached the wall.
    assert_eq!(f(&c["capture_ratio"]), 0.5);
}

#[test]
fn exactly_touching_lattice_pairs_all_get_bridges() {
    // Lian's BCC lattice (a = 4R/√3) of touching spheres: every touching pair gets its bridge
    // at the first cycle, although round-off puts half the distances an ulp beyond 2R.
    let mut r = Run::new(&lattice(250e-6));
    r.lines("liquid 0.1 0.025 0 0.1\ncycle 1");
    let info = &r.print("info")["info"];
    assert_eq!(u(&info["balls"]), 274);
    assert_eq!(u(&info["touching"]), 873, "{info}");
    assert_eq!(u(&info["bridges"]), u(&info["touching"]));
}

#[test]
fn dry_lattice_pairs_beyond_touching_are_not_evaluated() {
    // The same lattice without liquid or adhesion: the pairs that round-off puts beyond 2R get
    // no force from Hertz, so the pair loop does not evaluate them (no state, no refresh of
    // their gap at every step); those at or within 2R are evaluated as before. With liquid
    // (the test above) the round-off allowance stays, and all of them get bridges.
    let mut r = Run::new(&lattice(250e-6));
    r.lines("cycle 1");
    let sc = r.scene();
    let (mut beyond, mut evaluated) = (0, 0);
    for c in sc.contacts().iter() {
        let d = sc.branch(
            &sc.particles().pos[c.i as usize],
            &sc.particles().pos[c.j as usize],
        );
        let (ri, rj) = (
            sc.particles().radius[c.i as usize],
            sc.particles().radius[c.j as usize],
        );
        let near = d.norm() < 1.000001 * (ri + rj);
        let gap_beyond = d.norm_squared() > (ri + rj) * (ri + rj);
        if near && gap_beyond {
            beyond += 1;
            assert_eq!(c.s.overlap, 0.0, "a pair beyond touching was evaluated");
        } else if near {
            evaluated += 1;
        }
    }
    // Both kinds occur in this lattice (873 near pairs in all).
    assert!(
        beyond > 100 && evaluated > 100,
        "{beyond} beyond, {evaluated} at or within 2R"
    );
    assert_eq!(beyond + evaluated, 873);
}

#[test]
fn gravity_from_rest_is_not_a_runaway() {
    // All the kinetic energy comes from the field: the runaway check must count that input.
    let mut r = Run::new(
        "\
start 1e-3 1e-3 1e-3 1000 10 2
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
agglomerate 1 5e-4 5e-4 5e-4 1e-4
cr 5e-4 5e-4 5e-4 0 0 0 0 0 0 1 1
gravity 0 0 -1000
cycle 3000",
    );
    let e = &r.print("energy")["energy"];
    assert!(f(&e["kinetic"]) > 0.0);
    assert!(f(&e["residual"]).abs() < 1e-9 * f(&e["input"]));
}

/// Lian's BCC agglomerate (ch. 6) inside a region of radius `ra` (the region centre a/8 off a
/// lattice site along the diagonal).
fn lattice(ra: f64) -> String {
    format!(
        "\
start 2.2e-3 2.2e-3 2.2e-3 27000 5000 2
set open all
rad 30e-6 1
density 2650 1
ymd 70e9 1
pra 0.3 1
friction 0.3 1
agglomerate 1 1.0478907385791707e-3 1.0478907385791707e-3 1.0478907385791707e-3 {ra}
agen 1 1 1 0 0 0 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6
agen 1 1 1 34.641016151377545e-6 34.641016151377545e-6 34.641016151377545e-6 69.28203230275509e-6 69.28203230275509e-6 69.28203230275509e-6"
    )
}

/// The reduced wall impact: 274 particles, eta = 0.01 Pa s, relaxed with eta = 0.1 (as
/// scripts/lian_ch6_prepare.tru), then a wall 0.5 um below and the agglomerate at `v` m/s for
/// 128 us. Returns (damage ratio, |residual| / input, largest cluster share, relax message).
fn reduced_impact(base: &Session, v: f64) -> (f64, f64, f64) {
    let out = Sink::default();
    let mut s = crate::common::session_with(Box::new(out.clone()), true)
        .with_diagnostics(Box::new(std::io::sink()));
    s.scene = base.scene.clone();
    let mut r = Run { s, out };
    let h = {
        let p = &r.scene().particles();
        (0..p.len())
            .map(|i| p.pos[i].z - p.radius[i])
            .fold(f64::INFINITY, f64::min)
            - 0.5e-6
    };
    r.lines(&format!(
        "liquid 0.1 0.025 0 0.01\ndwall p 0 0 1 {h} m 1\nvelocity 0 0 -{v} 1\nplot save\ncycle 20000"
    ));
    let p = r.print("bonds clusters energy");
    let e = &p["energy"];
    (
        f(&p["bonds"]["damage_ratio"]),
        f(&e["residual"]).abs() / f(&e["input"]),
        f(&p["clusters"]["largest"]) / 274.0,
    )
}

#[test]
fn reduced_wall_impact_has_a_damage_threshold_and_closes_its_ledger() {
    let mut r = Run::new(&lattice(250e-6));
    r.out.0.lock().expect("the sink's lock").clear();
    r.lines("liquid 0.1 0.025 0 0.1\nrelax 1e-17 1e-6 10000");
    let msg = String::from_utf8(r.out.0.lock().expect("the sink's lock").clone()).unwrap();
    assert!(msg.contains("RELax: relaxed"), "{msg}");
    let base = r.s;

    // Far below Lian's thresholds (0.35-0.98 m/s): the bridges hold, nothing breaks away.
    let (dr, res, largest) = reduced_impact(&base, 0.1);
    assert!(dr < 1e-3, "damage ratio {dr} at 0.1 m/s");
    assert_eq!(largest, 1.0);
    assert!(res < 1e-3, "ledger residual {res} of the input at 0.1 m/s");
    // Well above: bridges rupture.
    let (dr, res, _) = reduced_impact(&base, 3.0);
    assert!(dr > 0.2, "damage ratio {dr} at 3 m/s");
    assert!(res < 1e-3, "ledger residual {res} of the input at 3 m/s");
}
