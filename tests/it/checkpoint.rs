//! Checkpoints: the whole state round-trips; files of every format version kept under
//! `tests/fixtures/` still load (or are refused with a message naming both versions); bad
//! files (future version, truncated, flipped bytes, empty, not a checkpoint, impossible
//! content) are refused with a clear message and never panic; a failed RESTart changes
//! nothing; a failed SAve keeps the old file.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};
use trubal::checkpoint::{self, HEADER, OLDEST_READABLE, VERSION, fnv1a, from_bytes, to_bytes};
use trubal::session::Session;
use trubal::sim::{Scene, Vec3};

/// A small scene with a bit of everything: periodic x/y and open z, two size and material
/// types, restitution and Rayleigh damping, liquid bridges, gravity, a servo-controlled wall,
/// an agglomerate region, an advanced random generator, a PLot SAve reference, history rows,
/// a sliding particle pair (tangential history and a bridge) and a particle on the wall;
/// cycles with Walton's law (its history beside the Mindlin–Deresiewicz one); laws of
/// `SET NORmal` (a Thornton–Ning and a linear wall contact, a pair with LIGGGHTS' JKR held
/// across a gap), rolling friction and a pair's own friction and restitution (`SET PAIr`)
/// and dashpot form (`SET DASHpot`, format 10);
/// the last cycles with `MDR` (the spring row of the sliding pair, made from the force it
/// held; the Thornton–Ning wall contact keeps the MD law). (`SET TANgential HM`, the last
/// setting of the format-8 fixture, is a setting only: that fixture holds it.) A static
/// group recorded in the history and a dynamic one naming it (format 10), with a Fix
/// standing on the dynamic one (format 13).
const FIXTURE_SCRIPT: &str = "start 0.004 0.004 0.004 100 10 2
set open z
set tol 40e-6
set history 5
set snapshot 25
set view yz
rad 100e-6 1
rad 80e-6 2
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.3 1
ymd 2e8 2
pra 0.25 2
density 7800 2
friction 0.5 2
damping restitution 0.7 1
damping 0.05 1000 0 1 1
liquid 1 0.072 20 0.001
gravity 0 0 -9.81
agglomerate 1 0.002 0.002 0.002 0.0005
rge seed 3
create 0.0019 0.002 0.0011 0.01 0.05 0 0 0 0 1 1
create 0.0021000001 0.002 0.0011 -0.01 -0.05 0 0 0 0 1 1
create 0.003 0.001 0.00028 0.02 0 -0.01 0 0 300 2 1
create 0.001 0.003 0.0030 0 0 0 100 0 0 1 1
dwall p 0 0 1 0.0002 m 2 se -1e-4 0.001 1e-2
set normal tning 1e6 1 2
set rolling 0.1 1
plot save
ymd 1e8 3
pra 0.3 3
density 2500 3
friction 0.3 3
set normal pasha 1000 500 10 1e-7 3 2
create 0.003 0.003 0.00029999 0 0 -0.01 0 0 0 1 3
ymd 1e8 4
pra 0.3 4
density 2500 4
cohesion 0.05 4
set normal nguyen 4
set pair 1 2 friction 0.35 restitution 0.3
set dashpot liggghts 1 2
create 0.001 0.001 0.002 0 0 0 0 0 0 1 4
create 0.001 0.001 0.00220002 0 0 0 0 0 0 1 4
group low box 0 0.004 0 0.004 0 0.001
group wet dynamic material 1 not group low or id 6
group low history
fix 0 0 1 0 0 0 group wet
set tangential md
cycle 40
set tangential walton
cycle 5
set tangential mdr
cycle 5";

fn session(lines: &str) -> Session {
    let mut s = crate::common::session_with(Box::new(std::io::sink()), false)
        .with_diagnostics(Box::new(std::io::sink()));
    for (k, l) in lines.lines().enumerate() {
        if let Err(e) = s.run_line(l) {
            panic!("line {}: `{l}`: {}", k + 1, e.message);
        }
    }
    s
}

fn fixture_scene() -> Scene {
    let mut sc = session(FIXTURE_SCRIPT).scene.unwrap();
    // A periodic cell's state (format 4), set directly: at rest (the fixture has walls, which
    // a moving cell refuses), with its history.
    *sc.unchecked().cell = trubal::sim::cell::Cell {
        rate: [0.0; 6],
        strain: [-1e-3, 2e-3, 3e-4, 5e-2, 0.0, 0.0],
        shift: 0.0,
        gain: [2e-3, 40.0],
        mode: 1,
        travel: 3e-7,
        work: 4.5e-9,
        half: [[1e-12, 2e-12, 0.0], [0.0, -3e-12, 0.0], [0.0, 0.0, 4e-12]],
        pending: -2e-10,
    };
    // `SET WALlbridges OFF` (format 12), set directly: the command would also remove the
    // wall bridges, which the fixture keeps for the layout of their state.
    sc.unchecked().settings.wall_bridges = false;
    // What the last Cycle handed on (format 14): the Cycles of the script leave the audit's
    // reference, the work in flight and the wall's last velocity; a kept stress servo, set
    // directly (the fixture is not a periodic cell).
    use trubal::sim::cell::{Servo, StressTarget};
    sc.unchecked().carried.servo = Some(trubal::sim::scene::KeptServo {
        servo: Servo {
            targets: vec![
                (StressTarget::Axis(1), 2e4, [false, true, false, false]),
                (StressTarget::Ring, 105.0, [true, false, false, true]),
            ],
            base: [1e-3, 0.0, 0.0, 20.0, 0.0, 0.0],
            flips: 3,
        },
        rate: [-2e-3, 1e-3, 0.0, 20.0, 0.0, 0.0],
        gain: [2e-3, 40.0],
        mode: 1,
    });
    sc
}

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn fixture_path(version: u32, ext: &str) -> PathBuf {
    fixtures_dir().join(format!("checkpoint-v{version}.{ext}"))
}

// ---- facts: every part of the state, written field by field ---------------------------------

/// Floats as their shortest round-trip decimal: equal strings ⇔ equal bits.
fn f(x: f64) -> Value {
    json!(format!("{x:e}"))
}
fn fs(x: &[f64]) -> Value {
    Value::Array(x.iter().map(|&x| f(x)).collect())
}
fn v3(v: &Vec3) -> Value {
    fs(&[v.x, v.y, v.z])
}
fn v3s(v: &[Vec3]) -> Value {
    Value::Array(v.iter().map(v3).collect())
}

fn contact_facts(s: &trubal::sim::contacts::ContactState) -> Value {
    let e = s.ext();
    json!({
        "touching": s.touching, "overlap": f(s.overlap), "normal_force": f(s.normal_force),
        "damp_force": f(s.damp_force), "a_s": f(e.a_s), "tang_energy": f(s.tang_energy),
        "a": f(s.a), "gamma": f(e.gamma), "delta": v3(&e.delta), "tforce": v3(&s.tforce),
        "tdamp": v3(&s.tdamp), "tdelta": f(e.tdelta),
        "tang": {
            "t": f(e.tang.t), "tp": fs(&e.tang.tp), "n_tp": e.tang.n_tp, "sense": e.tang.sense,
            "peeled": e.tang.peeled, "stored": f(e.tang.stored),
        },
        "bridge": s.bridge.as_ref().map(|b| json!({
            "volume": f(b.volume), "s_c": f(b.s_c), "f_static": f(b.f_static),
            "f_visc": f(b.f_visc), "phi": f(b.phi()), "gap": f(b.gap), "work": f(b.work),
            "share": fs(&b.share), "fresh": b.fresh,
        })),
        "released": fs(&e.released),
        "walton": {
            "t_star": f(e.walton.t_star), "fn_prev": f(e.walton.fn_prev),
            "sense": e.walton.sense, "reversed": e.walton.reversed,
            "stored": f(e.walton.stored),
        },
        "normal": normal_facts(&e.laws().normal),
        "roll": v3(&e.laws().roll), "roll_energy": f(e.laws().roll_energy),
        "roll_damp": v3(&e.laws().roll_damp),
        "mdr": e.mdr.as_ref().map(|r| json!({
            "a_ref": f(r.a_ref), "e1": fs(&r.e1),
            "u": r.u.iter().map(|u| fs(u)).collect::<Vec<_>>(),
        })),
    })
}

fn normal_facts(h: &trubal::sim::contacts::NormalHistory) -> Value {
    use trubal::sim::contacts::NormalHistory as H;
    match *h {
        H::None => json!("none"),
        H::ModifiedJkr { stored } => json!({ "mjkr": f(stored) }),
        H::ThorntonNing { st, stored } => json!({ "tning": {
            "a_y": f(st.a_y), "alpha_max": f(st.alpha_max), "r_p": f(st.r_p),
            "alpha_p": f(st.alpha_p), "stored": f(stored),
        }}),
        H::Linear { st, stored } => json!({ "linear": {
            "alpha_max": f(st.alpha_max), "made": st.made, "stored": f(stored),
        }}),
        H::Nguyen { stored } => json!({ "nguyen": f(stored) }),
    }
}

/// Everything a checkpoint holds, field by field (not through serde, so that a future format
/// has to reproduce the values, not the layout).
fn facts(sc: &Scene) -> Value {
    let p = &sc.particles();
    let mut rng = sc.rng().clone();
    let rng_next: Vec<String> = (0..4).map(|_| rng.next_u64().to_string()).collect();
    let l = &sc.ledger();
    let st = &sc.settings();
    let mut v = json!({
        "size": fs(&sc.size()), "nbox": sc.nbox(), "nball": sc.nball(), "nwall": sc.nwall(),
        "sizes": fs(sc.sizes()),
        "materials": sc.materials().iter().map(|m| json!({
            "density": f(m.density), "young": f(m.young), "poisson": f(m.poisson),
            "friction": f(m.friction), "gamma": f(m.gamma), "restitution": m.restitution.map(f),
        })).collect::<Vec<_>>(),
        "regions": sc.regions().iter().map(|r| r.map(|r| json!({
            "centre": fs(&r.centre), "radius": f(r.radius)
        }))).collect::<Vec<_>>(),
        "particles": {
            "id": p.id, "pos": v3s(&p.pos), "vel": v3s(&p.vel), "spin": v3s(&p.spin),
            "rot": v3s(&p.rot), "force": v3s(&p.force), "moment": v3s(&p.moment),
            "radius": fs(&p.radius), "mass": fs(&p.mass), "size": p.size,
            "material": p.material, "agg": p.agg, "fixed": p.fixed, "disp": v3s(&p.disp),
        },
        "next_id": sc.next_id(),
        "walls": sc.walls().iter().map(|w| json!({
            "geom": format!("{:?}", w.geom), "vel": fs(&w.vel), "vr": f(w.vr),
            "material": w.material,
            "servo": w.servo.map(|s| fs(&[s.force, s.vmax, s.gain])),
            "force": fs(&w.force), "normal_force": f(w.normal_force), "disp": fs(&w.disp),
        })).collect::<Vec<_>>(),
        // (A pair's MDR row in `ext.mdr`, the checkpoint's shape: `saved_state`.)
        "pairs": sc.contacts().iter().enumerate().map(|(k, c)| json!({
            "i": c.i, "j": c.j, "ida": c.ida, "idb": c.idb,
            "s": contact_facts(&sc.contacts().saved_state(k)),
        })).collect::<Vec<_>>(),
        "wall_pairs": sc.contacts().wall_pairs().iter().map(|c| json!({
            "i": c.i, "id": c.id, "wall": c.wall, "s": contact_facts(&c.s),
        })).collect::<Vec<_>>(),
        "contacts": {
            "stale": sc.contacts().is_stale(), "remap": sc.contacts().needs_remap(), "tol": f(sc.contacts().tol()),
            "rebuilds": sc.contacts().rebuilds(),
        },
        "settings": {
            "tol": st.tol.map(f), "xres": st.xres.map(f), "smin": st.smin.map(f),
            "bridge": format!("{:?}", st.bridge), "tangential": format!("{:?}", st.tangential),
            "liquid_mode": format!("{:?}", st.liquid_mode), "periodic": st.periodic,
            "out_dir": st.out_dir, "view": format!("{:?}", st.view),
            "snapshot_every": st.snapshot_every, "history_every": st.history_every,
            "two_d": st.two_d, "fraction": st.fraction.map(f), "window": st.window.map(|w| fs(&w)),
            "wall_bridges": st.wall_bridges,
        },
        // (Format 5's facts wrote the whole ContactLaws; its fields since are facts of their own.)
        "laws": format!("ContactLaws {{ normal: {:?}, rolling: {:?} }}", sc.laws().normal, sc.laws().rolling),
        "pair_values": format!("{:?}", sc.laws().pair_values),
        "gravity": fs(&sc.gravity()), "cgravity": fs(&sc.cgravity()), "fmm": f(sc.fmm()),
        "zero_always": sc.zero_always(),
        "damping_pp": fs(&[sc.damping_pp().alpha, sc.damping_pp().beta]),
        "damping_pw": fs(&[sc.damping_pw().alpha, sc.damping_pw().beta]),
        "liquid": sc.liquid().map(|q| fs(&[q.pvol, q.gamma, q.theta, q.eta])),
        "impact": sc.impact(),
        "rng_next": rng_next,
        "cycle": sc.cycle(), "time": f(sc.time()),
        "ledger": {
            "commands": f(l.commands), "gravity": f(l.gravity), "walls": f(l.walls),
            "friction": f(l.friction), "damping_mass": f(l.damping_mass),
            "damping_contact": f(l.damping_contact), "viscous": f(l.viscous),
            "adhesion": f(l.adhesion), "rupture": f(l.rupture),
        },
        "lost": sc.lost(),
        "reference": sc.reference().as_ref().map(|r| json!({
            "cycle": r.cycle, "ids": r.ids,
            "pos": r.pos.iter().map(|x| fs(x)).collect::<Vec<_>>(),
            "rot": r.rot.iter().map(|x| fs(x)).collect::<Vec<_>>(),
            "contacts": r.contacts, "bridges": r.bridges,
        })),
        "history": sc.history().rows.iter().map(|r| fs(r)).collect::<Vec<_>>(),
        "cell": {
            "rate": fs(&sc.cell().rate), "strain": fs(&sc.cell().strain), "shift": f(sc.cell().shift),
            "gain": fs(&sc.cell().gain), "mode": sc.cell().mode, "travel": f(sc.cell().travel),
            "work": f(sc.cell().work), "half": sc.cell().half.iter().map(|r| fs(r)).collect::<Vec<_>>(),
            "pending": f(sc.cell().pending),
        },
    });
    // (Format 10: the named groups and the dashpot forms; outside the macro, which has
    // reached its recursion limit.)
    v["groups"] = json!(format!("{:?}", sc.groups()));
    v["dashpot"] = json!(format!("{:?}", sc.laws().dashpot));
    // (Format 14: what the last Cycle handed on.)
    v["carried"] = json!(format!("{:?}", sc.carried()));
    v
}

/// First difference between two JSON values, as a path. Keys of `b` that `a` lacks count
/// only when `strict`.
fn diff_in(a: &Value, b: &Value, path: &str, strict: bool) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                match y.get(k) {
                    None => return Some(format!("{path}.{k}: missing")),
                    Some(w) => {
                        if let Some(d) = diff_in(v, w, &format!("{path}.{k}"), strict) {
                            return Some(d);
                        }
                    }
                }
            }
            y.keys()
                .find(|k| strict && !x.contains_key(*k))
                .map(|k| format!("{path}.{k}: unexpected"))
        }
        (Value::Array(x), Value::Array(y)) => {
            if x.len() != y.len() {
                return Some(format!("{path}: length {} vs {}", x.len(), y.len()));
            }
            x.iter()
                .zip(y)
                .enumerate()
                .find_map(|(i, (v, w))| diff_in(v, w, &format!("{path}[{i}]"), strict))
        }
        _ if a == b => None,
        _ => Some(format!("{path}: {a} vs {b}")),
    }
}

fn diff(a: &Value, b: &Value, path: &str) -> Option<String> {
    diff_in(a, b, path, true)
}

// ---- the fixture ------------------------------------------------------------------------

/// Writes `tests/fixtures/checkpoint-v{VERSION}.sav` and its facts (`.json`). Run once per
/// format version: `cargo test --release --test it checkpoint::write_fixture -- --ignored`.
/// Refuses to overwrite an existing fixture: old fixtures are evidence, never regenerated.
#[test]
#[ignore]
fn write_fixture() {
    let sav = fixture_path(VERSION, "sav");
    assert!(
        !sav.exists(),
        "{} exists: fixtures are never regenerated",
        sav.display()
    );
    std::fs::create_dir_all(fixtures_dir()).unwrap();
    let sc = fixture_scene();
    checkpoint::save(&sc, &sav).unwrap();
    let facts = facts(&sc);
    std::fs::write(
        fixture_path(VERSION, "json"),
        serde_json::to_string_pretty(&facts).unwrap() + "\n",
    )
    .unwrap();
}

/// Facts a later format dropped deliberately, with the version that dropped them: the
/// contact normal of version 1 was written at every step and never read.
const DROPPED_CONTACT_FACTS: &[(&str, u32)] = &[("normal", 2)];

/// The recorded facts of a fixture of version `v` without those a later version dropped
/// (contact states are the objects with a `touching` fact).
fn without_dropped(mut facts: Value, v: u32) -> Value {
    fn strip(x: &mut Value, v: u32) {
        match x {
            Value::Object(m) => {
                if m.contains_key("touching") {
                    for (k, since) in DROPPED_CONTACT_FACTS {
                        if v < *since {
                            m.remove(*k);
                        }
                    }
                }
                m.values_mut().for_each(|y| strip(y, v));
            }
            Value::Array(a) => a.iter_mut().for_each(|y| strip(y, v)),
            _ => {}
        }
    }
    strip(&mut facts, v);
    facts
}

fn read_version(data: &[u8]) -> u32 {
    u32::from_le_bytes(data[8..12].try_into().unwrap())
}

/// Every fixture ever written still loads to the same facts, or (only if its version was
/// deliberately dropped) is refused with a message naming its version and ours.
#[test]
fn fixtures_of_every_version_still_load() {
    let mut versions = Vec::new();
    for e in std::fs::read_dir(fixtures_dir()).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("checkpoint-v") && name.ends_with(".sav")) {
            continue;
        }
        let data = std::fs::read(&path).unwrap();
        let v = read_version(&data);
        assert_eq!(
            name,
            format!("checkpoint-v{v}.sav"),
            "fixture name vs header"
        );
        versions.push(v);
        match from_bytes(&data) {
            Ok(sc) => {
                let want: Value = serde_json::from_str(
                    &std::fs::read_to_string(path.with_extension("json")).unwrap(),
                )
                .unwrap();
                // Values that did not exist in that version may be added to `facts` later:
                // compare the facts the fixture recorded.
                let mut got = facts(&sc);
                if v < 4 {
                    // Rows read from formats before 4 get the stress and temperature columns
                    // of format 4 as 0.
                    for row in got["history"].as_array_mut().into_iter().flatten() {
                        let a = row.as_array_mut().unwrap();
                        assert!(a[10..].iter().all(|x| x.as_str() == Some("0e0")), "{name}");
                        a.truncate(10);
                    }
                }
                if v < 13
                    && let Some(Value::String(g)) = got.get_mut("groups")
                {
                    // Groups read from formats 10 to 12 have no standing Fix (format 13).
                    *g = g.replace(", fix: None", "");
                }
                let want = without_dropped(want, v);
                if let Some(d) = diff_in(&want, &got, "", false) {
                    panic!("{name}: the loaded state differs from the recorded facts at {d}");
                }
                if v == VERSION {
                    assert!(
                        to_bytes(&sc).unwrap() == data,
                        "{name}: re-encoding the fixture gives different bytes: the layout of Scene \
                         changed without a version bump (see \"Format evolution\" in src/checkpoint.rs)"
                    );
                }
            }
            Err(e) => {
                if v == VERSION {
                    panic!(
                        "{name}: the fixture of the current format version no longer loads ({e}): \
                         the layout of Scene (or a type inside it) changed. Bump checkpoint::VERSION, \
                         add a reader for version {v} and a new fixture (see \"Format evolution\" in \
                         src/checkpoint.rs)"
                    );
                }
                assert!(
                    v < OLDEST_READABLE,
                    "{name}: version {v} should still be readable (OLDEST_READABLE = {OLDEST_READABLE}) but: {e}"
                );
                assert!(
                    e.contains(&format!("version {v}")) && e.contains(&format!("{VERSION}")),
                    "{name}: the refusal must name both versions: {e}"
                );
            }
        }
    }
    assert!(
        versions.contains(&VERSION),
        "no fixture for the current format version {VERSION}: run `cargo test --release --test it checkpoint::write_fixture -- --ignored`"
    );
}

#[test]
fn the_whole_state_round_trips() {
    let sc = fixture_scene();
    // The fixture scene exercises every part of the state.
    assert!(sc.particles().len() == 7 && sc.walls().len() == 1);
    // Format 6: a pair with LIGGGHTS' JKR (made across a gap), a pair's own friction and
    // restitution.
    let nguyen = sc
        .contacts()
        .iter()
        .map(|c| c.s)
        .find(|s| {
            matches!(
                s.ext().laws().normal,
                trubal::sim::contacts::NormalHistory::Nguyen { .. }
            )
        })
        .expect("a Nguyen contact");
    assert!(nguyen.touching && nguyen.normal_force != 0.0);
    assert_eq!(sc.laws().pair_values.len(), 1);
    // Format 5: a Thornton–Ning wall contact, a linear one, a rolling spring.
    use trubal::sim::contacts::NormalHistory;
    let hist = |k: usize| sc.contacts().wall_pairs()[k].s.ext().laws().normal;
    assert!(matches!(hist(0), NormalHistory::ThorntonNing { .. }));
    assert!(matches!(hist(1), NormalHistory::Linear { .. }));
    assert!(sc.contacts().wall_pairs()[0].s.ext().laws().roll.norm() > 0.0);
    assert!(sc.walls()[0].servo.is_some());
    let pair = sc.contacts().saved_state(0);
    assert!(pair.touching && pair.bridge.is_some() && pair.tforce.norm() > 0.0);
    assert!(pair.ext().tang.t != 0.0 && pair.ext().tang.stored > 0.0);
    // Format 9: the MDR row of the sliding pair; the Thornton–Ning wall contact has none.
    assert!(pair.ext().mdr.as_ref().is_some_and(|r| r.a_ref > 0.0));
    assert!(sc.contacts().wall_pairs()[0].s.ext().mdr.is_none());
    let w = &pair.ext().walton;
    assert!(w.fn_prev > 0.0 && w.sense != 0 && w.stored > 0.0);
    let wall = &sc.contacts().wall_pairs()[0].s;
    assert!(wall.touching && wall.bridge.is_some());
    assert!(sc.reference().as_ref().is_some_and(|r| r.ids.len() == 4));
    assert_eq!(sc.history().rows.len(), 10);
    assert_eq!(sc.settings().periodic, [true, true, false]);
    assert!(sc.settings().tol.is_some() && sc.liquid().is_some() && sc.regions()[0].is_some());
    assert!(sc.damping_pp().alpha > 0.0 && sc.materials()[0].restitution.is_some());
    assert!(
        *sc.rng() != trubal::sim::rng::Rng::new(0),
        "RGEnerate Seed advanced the generator"
    );
    let l = &sc.ledger();
    assert!(l.friction > 0.0 && l.damping_contact > 0.0 && l.damping_mass > 0.0);
    assert!(l.gravity != 0.0 && l.commands > 0.0);
    assert!(sc.particles().spin.iter().any(|w| w.norm() > 0.0));
    // Format 14: what the last Cycle handed on.
    let c = sc.carried();
    assert!(c.in_flight_end != 0.0 && c.audit_end != 0.0 && !c.wall_last_vel.is_empty());
    assert!(c.servo.is_some());

    let bytes = to_bytes(&sc).unwrap();
    let back = from_bytes(&bytes).unwrap();
    assert_eq!(diff(&facts(&sc), &facts(&back), ""), None);
    // Derived per-step buffers (forces, hot pair list, the outside-particle hint) are not
    // saved; compare without them.
    let mut sc = sc;
    sc.unchecked().contacts.clear_derived();
    sc.unchecked().derived.maybe_outside = true;
    // (What the last Cycle handed on — the audit's reference, the work in flight, the walls'
    // last velocities, the stress servo — is saved from format 14: `sim::scene::Carried`.)
    assert_eq!(format!("{sc:?}"), format!("{back:?}"));
    assert!(to_bytes(&back).unwrap() == bytes);
}

/// `save` (which encodes twice and writes through a buffer) writes the bytes `to_bytes`
/// gives, and `load` (which reads the file in two passes) gives what `from_bytes` gives; a
/// loaded scene's particle arrays hold no spare capacity (they grew by doubling while they
/// were decoded).
#[test]
fn save_and_load_are_to_bytes_and_from_bytes() {
    let sc = session(
        "start 0.04 0.04 0.04 100 45000 1\nrad 100e-6 1\nymd 1e8 1\npra 0.3 1\n\
         density 2500 1\nfriction 0.3 1\ngravity 0 0 -9.81\nrge 45000 1 1 0",
    )
    .scene
    .unwrap();
    // More than the 43,690 vectors serde reserves up front (1 MB): the arrays grow.
    assert_eq!(sc.particles().len(), 45000);
    let dir = std::env::temp_dir().join(format!("trubal-ckpt-same-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("state.sav");
    checkpoint::save(&sc, &path).unwrap();
    let bytes = to_bytes(&sc).unwrap();
    assert!(std::fs::read(&path).unwrap() == bytes);
    let a = checkpoint::load(&path).unwrap();
    let b = from_bytes(&bytes).unwrap();
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    let p = &a.particles();
    assert_eq!(p.len(), sc.particles().len());
    for (name, cap) in [
        ("id", p.id.capacity()),
        ("pos", p.pos.capacity()),
        ("vel", p.vel.capacity()),
        ("disp", p.disp.capacity()),
        ("radius", p.radius.capacity()),
        ("material", p.material.capacity()),
        ("fixed", p.fixed.capacity()),
        ("liquid", p.liquid.capacity()),
    ] {
        assert_eq!(cap, p.len(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- bad files --------------------------------------------------------------------------

fn current_fixture_bytes() -> Vec<u8> {
    to_bytes(&fixture_scene()).unwrap()
}

fn with_version(data: &[u8], v: u32) -> Vec<u8> {
    let mut d = data.to_vec();
    d[8..12].copy_from_slice(&v.to_le_bytes());
    d
}

/// The reason `from_bytes` refuses `data`; `checkpoint::load` (which reads a file in two
/// passes instead of holding it) must refuse the file of the same bytes for the same reason.
fn refused(data: &[u8]) -> String {
    let e = match std::panic::catch_unwind(|| from_bytes(data)) {
        Ok(Ok(_)) => panic!("a bad file was accepted"),
        Ok(Err(e)) => e,
        Err(_) => panic!("from_bytes panicked"),
    };
    let path = std::env::temp_dir().join(format!(
        "trubal-refused-{}-{:?}.sav",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::write(&path, data).unwrap();
    let from_file = match std::panic::catch_unwind(|| checkpoint::load(&path)) {
        Ok(Ok(_)) => panic!("a bad file was accepted by load"),
        Ok(Err(e)) => e,
        Err(_) => panic!("load panicked"),
    };
    let _ = std::fs::remove_file(&path);
    assert_eq!(from_file, format!("{}: {e}", path.display()));
    e
}

#[test]
fn a_file_from_the_future_is_refused_naming_both_versions() {
    let data = current_fixture_bytes();
    let e = refused(&with_version(&data, VERSION + 1));
    assert!(
        e.contains(&format!("version {}", VERSION + 1))
            && e.contains(&format!("version {VERSION}")),
        "{e}"
    );
    assert!(e.contains("newer"), "{e}");
    let e = refused(&with_version(&data, u32::MAX));
    assert!(e.contains("newer"), "{e}");
}

#[test]
fn a_version_below_the_oldest_readable_is_refused_naming_both_versions() {
    let data = current_fixture_bytes();
    let e = refused(&with_version(&data, OLDEST_READABLE - 1));
    assert!(
        e.contains(&format!("version {}", OLDEST_READABLE - 1))
            && e.contains(&format!("{VERSION}")),
        "{e}"
    );
}

#[test]
fn empty_and_foreign_files_are_refused() {
    assert!(refused(b"").contains("empty"));
    for foreign in [
        &b"start 1 1 1 10 10 1\ncycle 10\n"[..],
        b"TRUBALCX and more bytes than a header needs....",
        b"\x89PNG\r\n\x1a\n",
        b"x",
    ] {
        let e = refused(foreign);
        assert!(e.contains("not a trubal checkpoint"), "{e}");
    }
}

#[test]
fn truncated_files_are_refused() {
    let data = current_fixture_bytes();
    let mut cuts: Vec<usize> = (1..HEADER + 8).collect();
    cuts.extend([data.len() / 2, data.len() - 8, data.len() - 1]);
    for n in cuts {
        let e = refused(&data[..n]);
        assert!(e.contains("truncated"), "cut at {n}: {e}");
    }
    // Padded: bytes appended.
    let mut padded = data.clone();
    padded.extend_from_slice(b"junk");
    assert!(refused(&padded).contains("padded"));
}

/// Every single changed byte (header or payload) is refused, each with a message.
#[test]
fn flipped_bytes_are_refused() {
    let data = current_fixture_bytes();
    for k in 0..data.len() {
        for mask in [0x01u8, 0x80, 0xff] {
            let mut d = data.clone();
            d[k] ^= mask;
            let e = refused(&d);
            let ok = match k {
                0..8 => e.contains("not a trubal checkpoint"),
                // (A version this program reads, 6 to 8, has a layout without the ledger's
                // `unbooked`: the payload ends 8 bytes early for it.)
                8..12 => e.contains("version") || e.contains("trailing bytes"),
                12..20 => e.contains("truncated or padded"),
                _ => e.contains("checksum"),
            };
            assert!(ok, "byte {k} ^ {mask:#x}: {e}");
        }
    }
}

/// A payload that passes the checksum but is garbage (a bug or a crafted file) gives an
/// error or a consistent state, never a panic.
#[test]
fn garbage_with_a_valid_checksum_never_panics() {
    let data = current_fixture_bytes();
    let payload = &data[HEADER..];
    let reseal = |p: &[u8]| {
        let mut d = data[..8 + 4].to_vec();
        d.extend_from_slice(&(p.len() as u64).to_le_bytes());
        d.extend_from_slice(&fnv1a(p).to_le_bytes());
        d.extend_from_slice(p);
        d
    };
    let mut accepted = 0;
    for k in 0..payload.len() {
        for mask in [0x01u8, 0x40, 0xff] {
            let mut p = payload.to_vec();
            p[k] ^= mask;
            let d = reseal(&p);
            match std::panic::catch_unwind(|| from_bytes(&d)) {
                Ok(Ok(sc)) => {
                    accepted += 1;
                    sc.check_consistency().unwrap();
                    // What loads can cycle, or is refused before cycling with a reason: a
                    // finite step, no NaN (one damaged file used to load with `dt inf`).
                    if let Ok(model) = trubal::sim::params::build(&sc) {
                        assert!(
                            model.dt.is_finite() || sc.particles().is_empty(),
                            "byte {k} ^ {mask:#x}: dt {}",
                            model.dt
                        );
                    }
                }
                Ok(Err(e)) => assert!(!e.is_empty()),
                Err(_) => panic!("from_bytes panicked on payload byte {k} ^ {mask:#x}"),
            }
        }
        // Cut the payload short (header resealed): decoding runs out of bytes.
        if k % 7 == 0 {
            let d = reseal(&payload[..k]);
            let e = refused(&d);
            assert!(e.contains("corrupt") || e.contains("inconsistent"), "{e}");
        }
    }
    // Most single flips land in float bits and decode to a (different) valid state.
    assert!(accepted > 0);
}

#[test]
fn impossible_states_are_refused() {
    let good = fixture_scene();
    type Breaker = fn(&mut Scene);
    let breakers: &[(&str, Breaker)] = &[
        ("unequal", |s| {
            s.unchecked().particles.vel.pop();
        }),
        ("contact", |s| s.unchecked().contacts.pairs_mut()[0].j = 99),
        ("wall contact", |s| {
            s.unchecked().contacts.wall_pairs_mut()[0].wall = 5
        }),
        ("share an id", |s| {
            s.unchecked().particles.id[1] = s.particles().id[0]
        }),
        ("material", |s| s.unchecked().particles.material[0] = 9),
        ("material", |s| s.unchecked().walls[0].material = 0),
        ("reference", |s| {
            s.unchecked().reference.as_mut().unwrap().pos.pop();
        }),
        ("history", |s| {
            s.unchecked().history.rows[0].pop().map(|_| ()).unwrap()
        }),
        ("next id", |s| *s.unchecked().next_id = 2),
        // Numbers the program never writes (a damaged payload with a recomputed checksum).
        ("particle 1 has a non-finite velocity", |s| {
            s.unchecked().particles.vel[0].x = f64::NAN
        }),
        ("particle 2 has a non-finite position", |s| {
            s.unchecked().particles.pos[1].z = f64::INFINITY
        }),
        ("material type 1", |s| {
            s.unchecked().materials[0].poisson = 0.7
        }),
        ("material type 2", |s| {
            s.unchecked().materials[1].young = -1.0
        }),
        ("TOL", |s| s.unchecked().settings.tol = Some(f64::INFINITY)),
        ("wall 1", |s| s.unchecked().walls[0].vel[2] = f64::NAN),
        ("contact of particles 1 and 2", |s| {
            s.unchecked().contacts.state_mut(0).normal_force = f64::NAN
        }),
        ("contact of particle 3 and wall 1", |s| {
            s.unchecked().contacts.wall_pairs_mut()[0].s.tforce.x = f64::NAN
        }),
        ("ledger", |s| s.unchecked().ledger.friction = f64::NAN),
        ("time", |s| *s.unchecked().time = f64::INFINITY),
        ("liquid", |s| {
            s.unchecked().liquid.as_mut().unwrap().eta = -1.0
        }),
        // What the last Cycle handed on (format 14): a servo target on a fourth axis would
        // index past the stress tensor.
        ("work in flight", |s| {
            s.unchecked().carried.in_flight_end = f64::NAN
        }),
        ("walls' last velocities", |s| {
            s.unchecked().carried.wall_last_vel.push(([0.0; 3], 0.0))
        }),
        ("kept stress servo", |s| {
            let k = s.unchecked().carried.servo.as_mut().unwrap();
            k.servo.targets[0].0 = trubal::sim::cell::StressTarget::Axis(7)
        }),
    ];
    for (want, brk) in breakers {
        let mut sc = good.clone();
        brk(&mut sc);
        let e = refused(&to_bytes(&sc).unwrap());
        assert!(
            e.contains("inconsistent") && e.contains(want),
            "{want}: {e}"
        );
    }
}

// ---- through the binary -----------------------------------------------------------------

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trubal-ckpt-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs a command file in `dir` with --keep-going --json; returns (stdout, stderr).
fn trubal(dir: &Path, script: &str) -> (String, String) {
    std::fs::write(dir.join("run.tru"), script).unwrap();
    let out = crate::common::trubal()
        .args(["run.tru", "--keep-going", "--json"])
        .current_dir(dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "{err}");
    (String::from_utf8_lossy(&out.stdout).to_string(), err)
}

fn info_lines(out: &str) -> Vec<Value> {
    out.lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|v| v["print"] == "info")
        .collect()
}

#[test]
fn a_failed_restart_changes_nothing_and_the_session_goes_on() {
    let dir = scratch("restart");
    let good = current_fixture_bytes();
    std::fs::write(dir.join("good.sav"), &good).unwrap();
    let bad: Vec<(&str, Vec<u8>)> = vec![
        ("future.sav", with_version(&good, VERSION + 1)),
        ("truncated.sav", good[..good.len() / 3].to_vec()),
        ("flipped.sav", {
            let mut d = good.clone();
            d[HEADER + 100] ^= 0x10;
            d
        }),
        ("empty.sav", Vec::new()),
        ("foreign.sav", b"start 1 1 1 10 10 1\n".to_vec()),
    ];
    for (name, bytes) in &bad {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let expect = [
        "newer than this program",
        "truncated",
        "checksum",
        "empty",
        "not a trubal checkpoint",
    ];
    for ((name, _), want) in bad.iter().zip(expect) {
        // As the first command: refused, no scene afterwards; a valid RESTart then works.
        let (out, err) = trubal(
            &dir,
            &format!("restart {name}\nprint info\nrestart good.sav\nprint info\n"),
        );
        assert!(err.contains(want), "{name}: {err}");
        assert!(err.contains(name), "the message names the file: {err}");
        assert!(
            err.contains("give STArt (or RESTart) first"),
            "{name}: {err}"
        );
        let infos = info_lines(&out);
        assert_eq!(infos.len(), 1, "{out}");
        assert_eq!(infos[0]["cycle"], 50);
        assert_eq!(infos[0]["balls"], 7);

        // After New: still no scene after the failure; STArt works.
        let (out, err) = trubal(
            &dir,
            &format!(
                "restart good.sav\ncycle 5\nnew\nrestart {name}\ncycle 1\nstart 1 1 1 10 10 1\nprint info\n"
            ),
        );
        assert!(err.contains(want), "{name}: {err}");
        let infos = info_lines(&out);
        assert_eq!(infos.len(), 1, "{out}\n{err}");
        assert_eq!(infos[0]["balls"], 0);
        assert_eq!(infos[0]["cycle"], 0);
    }
    // RESTart with a problem defined is refused and the problem is kept.
    let (out, err) = trubal(
        &dir,
        "restart good.sav\ncycle 3\nrestart good.sav\nprint info\n",
    );
    assert!(err.contains("give New first"), "{err}");
    assert_eq!(info_lines(&out)[0]["cycle"], 53);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn default_file_names() {
    let dir = scratch("defaults");
    std::fs::write(dir.join("save.old"), current_fixture_bytes()).unwrap();
    let (out, err) = trubal(&dir, "restart\ncycle 2\nsave\nprint info\n");
    assert!(err.is_empty(), "{err}");
    assert!(out.contains("restarted from save.old at cycle 50"), "{out}");
    assert!(out.contains("saved cycle 52 to save.new"), "{out}");
    let sc = checkpoint::load(&dir.join("save.new")).unwrap();
    assert_eq!(sc.cycle(), 52);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Saving over an existing file never loses it: with the temporary file's path blocked (a
/// directory in its place) the save fails with a message and the old file is intact.
#[test]
fn a_failed_save_keeps_the_old_file() {
    let dir = scratch("atomic");
    let (_, err) = trubal(&dir, &format!("{FIXTURE_SCRIPT}\nsave state.sav\n"));
    assert!(!err.contains("error"), "{err}");
    let old = std::fs::read(dir.join("state.sav")).unwrap();
    std::fs::create_dir(dir.join("state.sav.tmp")).unwrap();
    let (out, err) = trubal(
        &dir,
        "restart state.sav\ncycle 10\nsave state.sav\nprint info\n",
    );
    assert!(err.contains("cannot save to state.sav"), "{err}");
    assert!(err.contains("state.sav.tmp"), "{err}");
    assert!(err.contains("untouched"), "{err}");
    assert_eq!(
        info_lines(&out)[0]["cycle"],
        60,
        "the session goes on after a failed save"
    );
    assert!(std::fs::read(dir.join("state.sav")).unwrap() == old);
    assert!(
        dir.join("state.sav.tmp").is_dir(),
        "the blocking directory is left alone"
    );
    // Without the obstacle the same save replaces the file and leaves no temporary file.
    std::fs::remove_dir(dir.join("state.sav.tmp")).unwrap();
    let (_, err) = trubal(&dir, "restart state.sav\ncycle 10\nsave state.sav\n");
    assert!(err.is_empty(), "{err}");
    assert_eq!(
        checkpoint::load(&dir.join("state.sav")).unwrap().cycle(),
        60
    );
    assert!(!dir.join("state.sav.tmp").exists());
    // A directory that does not exist (library API: `/` separates words in the language).
    let target = dir.join("no").join("such").join("x.sav");
    let e = checkpoint::save(&fixture_scene(), &target).unwrap_err();
    assert!(
        e.contains("cannot save to") && e.contains("x.sav.tmp"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A file that changes between `load`'s checksum pass and its decoding pass (another
/// program rewriting it) is refused with a reason, not decoded into a scene that matches
/// neither version: one bit of a particle's x coordinate flipped after the first pass still
/// decodes, and only the second pass's checksum can tell.
#[test]
fn a_checkpoint_that_changes_while_it_is_read_is_refused() {
    let sc = session(
        "start 1 1 1 10 10 0\nrad 0.01 1\nymd 1e7 1\npra 0.3 1\ndensity 2500 1\n\
         create 0.123456789 0.5 0.5 0 0 0 0 0 0 1 1\n",
    )
    .scene
    .unwrap();
    let dir = std::env::temp_dir().join(format!("trubal-ckpt-changed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("state.sav");
    checkpoint::save(&sc, &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let x = 0.123456789f64.to_le_bytes();
    let at = bytes
        .windows(8)
        .position(|w| w == x)
        .expect("the x coordinate's bytes are in the file");
    let mut changed = bytes.clone();
    changed[at] ^= 1;
    // The changed bytes differ from a valid checkpoint only in their checksum.
    assert!(
        from_bytes(&changed)
            .unwrap_err()
            .contains("checksum mismatch")
    );
    // Unchanged, it loads.
    assert!(checkpoint::load_between(&path, || {}).is_ok());
    let e =
        checkpoint::load_between(&path, || std::fs::write(&path, &changed).unwrap()).unwrap_err();
    assert!(
        e.contains("the checkpoint changed while it was read"),
        "{e}"
    );
    assert!(e.starts_with(&format!("{}: ", path.display())), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
