//! Continuation is exact: `Cycle N; SAve; (new session) RESTart; Cycle M` and `Cycle N; Cycle M`
//! give bitwise the same state as `Cycle N+M` (doc/spec/DECISIONS.md, "Output, determinism,
//! checkpoints"), for a dry frictional scene with walls, an adhesive (JKR) scene and a wet
//! (liquid bridge) scene. The split points are chosen so that some fall on a step after which
//! the candidate list is due for a rebuild (the case where a continuation used to re-evaluate
//! the contacts before its first step).

use std::path::PathBuf;

use trubal::checkpoint;
use trubal::session::Session;
use trubal::sim::Scene;

fn session_in(dir: &std::path::Path, lines: &str) -> Session {
    let mut s = crate::common::session_with(Box::new(std::io::sink()), false)
        .with_diagnostics(Box::new(std::io::sink()));
    s.dir = dir.to_path_buf();
    for (k, l) in lines.lines().enumerate() {
        if let Err(e) = s.run_line(l) {
            panic!("line {}: `{l}`: {}", k + 1, e.message);
        }
    }
    s
}

fn run(s: &mut Session, line: &str) {
    if let Err(e) = s.run_line(line) {
        panic!("`{line}`: {}", e.message);
    }
}

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trubal-cont-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Bitwise comparison with a readable message, then the whole serialised state.
fn assert_same(a: &Scene, b: &Scene, what: &str) {
    assert_eq!(a.cycle(), b.cycle(), "{what}: cycle");
    assert_eq!(a.time().to_bits(), b.time().to_bits(), "{what}: time");
    let (p, q) = (&a.particles(), &b.particles());
    assert_eq!(p.id, q.id, "{what}: particle ids");
    for i in 0..p.len() {
        for (name, x, y) in [
            ("position", &p.pos[i], &q.pos[i]),
            ("velocity", &p.vel[i], &q.vel[i]),
            ("spin", &p.spin[i], &q.spin[i]),
            ("rotation", &p.rot[i], &q.rot[i]),
            ("force", &p.force[i], &q.force[i]),
        ] {
            for k in 0..3 {
                assert_eq!(
                    x[k].to_bits(),
                    y[k].to_bits(),
                    "{what}: {name}[{k}] of particle {} differs: {} vs {}",
                    p.id[i],
                    x[k],
                    y[k]
                );
            }
        }
    }
    let (l, m) = (&a.ledger(), &b.ledger());
    for (name, x, y) in [
        ("commands", l.commands, m.commands),
        ("gravity", l.gravity, m.gravity),
        ("walls", l.walls, m.walls),
        ("friction", l.friction, m.friction),
        ("damping_mass", l.damping_mass, m.damping_mass),
        ("damping_contact", l.damping_contact, m.damping_contact),
        ("viscous", l.viscous, m.viscous),
        ("adhesion", l.adhesion, m.adhesion),
        ("rupture", l.rupture, m.rupture),
    ] {
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{what}: ledger {name} differs: {x} vs {y}"
        );
    }
    assert_eq!(
        a.contacts().iter().collect::<Vec<_>>(),
        b.contacts().iter().collect::<Vec<_>>(),
        "{what}: contact history"
    );
    assert_eq!(
        a.contacts().wall_pairs(),
        b.contacts().wall_pairs(),
        "{what}: wall contact history"
    );
    assert_eq!(a.walls(), b.walls(), "{what}: walls");
    // Everything else (rng, settings, reference, history, counters): the serialised state.
    assert!(
        checkpoint::to_bytes(a).unwrap() == checkpoint::to_bytes(b).unwrap(),
        "{what}: the serialised states differ"
    );
}

/// Runs the three variants for every split point; returns how many split points fell on a
/// step after which the candidate list was due for a rebuild.
fn check_continuation(tag: &str, setup: &str, total: u64, splits: &[u64]) -> usize {
    let dir = scratch(tag);
    let mut whole = session_in(&dir, setup);
    run(&mut whole, &format!("cycle {total}"));
    let whole = whole.scene.unwrap();
    let mut stale_splits = 0;
    for &n in splits {
        // Cycle N; Cycle M in one session.
        let mut two = session_in(&dir, setup);
        run(&mut two, &format!("cycle {n}"));
        if two.scene.as_ref().unwrap().contacts().needs_remap() {
            stale_splits += 1;
        }
        run(&mut two, &format!("cycle {}", total - n));
        assert_same(
            &whole,
            two.scene.as_ref().unwrap(),
            &format!("{tag}: cycle {n}; cycle {}", total - n),
        );

        // Cycle N; SAve; RESTart in a fresh session; Cycle M.
        let mut first = session_in(&dir, setup);
        run(&mut first, &format!("cycle {n}"));
        run(&mut first, &format!("save {tag}-{n}.sav"));
        let mut second = session_in(&dir, &format!("restart {tag}-{n}.sav"));
        assert_same(
            first.scene.as_ref().unwrap(),
            second.scene.as_ref().unwrap(),
            &format!("{tag}: state restarted at cycle {n}"),
        );
        run(&mut second, &format!("cycle {}", total - n));
        assert_same(
            &whole,
            second.scene.as_ref().unwrap(),
            &format!("{tag}: cycle {n}; save; restart; cycle {}", total - n),
        );

        // SAve; New; RESTart in the same session.
        run(&mut first, "new");
        run(&mut first, &format!("restart {tag}-{n}.sav"));
        run(&mut first, &format!("cycle {}", total - n));
        assert_same(
            &whole,
            first.scene.as_ref().unwrap(),
            &format!("{tag}: cycle {n}; save; new; restart; cycle {}", total - n),
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
    stale_splits
}

/// A small agglomerate of frictional, damped spheres falling under gravity onto a floor while
/// a side wall moves in; Rayleigh damping, a spinning particle, PLot SAve reference and history
/// recording, and random generation (the generator state is part of the checkpoint).
const DRY: &str = "start 0.1 0.1 0.1 1000 100 4
set open all
set history 50
rad 0.004 1
rad 0.003 2
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.3 1
damping restitution 0.6
damping 0.02 50 0 1 1
gravity 0 0 -9.81
agglomerate 1 0.05 0.05 0.03 0.02
rge 20 1 1 1
rge 10 2 1 1
velocity 0.1 0 -0.5 0
create 0.05 0.05 0.07 0 0 -0.3 5 0 0 1 1
dwall p 0 0 1 0.008
dwall p 1 0 0 0.01 v 0.01 0 0
plot save";

#[test]
fn dry_frictional_scene_with_walls_continues_bitwise() {
    // Under the `MD` law, whose trajectory the split points were chosen for (some fall right
    // after a re-mapping); the default law's: `mdr_scene_continues_bitwise`.
    let md = format!("{DRY}\nset tangential md");
    let stale = check_continuation("dry", &md, 4000, &[1, 777, 1500, 2345, 3001, 3999]);
    let mut more = 0;
    // Also every split of a short stretch, so that a split right after a re-mapping is met.
    let short = check_continuation(
        "dry-short",
        &format!("{md}\ncycle 2500"),
        150,
        &(1..150).step_by(2).collect::<Vec<_>>(),
    );
    more += short;
    assert!(
        stale + more > 0,
        "no split point fell on a step after which the candidate list was due for a re-mapping"
    );
}

/// JKR: a simple-cubic agglomerate of 27 touching adhesive, frictional spheres with a
/// restitution dashpot hits a floor at 0.5 m/s; bonds break (adhesion loss) and the rest
/// bounces off as a cluster.
const ADHESIVE: &str = "start 0.01 0.01 0.01 1000 100 2
set open all
rad 100e-6 1
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.3 1
cohesion 0.05 1
damping restitution 0.5
agglomerate 1 0.005 0.005 0.005 0.00045
agen 1 1 1 0 0 0 0.0002 0.0002 0.0002
velocity 0 0 -0.5 0
dwall p 0 0 1 0.00468";

#[test]
fn adhesive_scene_continues_bitwise() {
    let dir = scratch("adh-probe");
    let mut s = session_in(&dir, ADHESIVE);
    run(&mut s, "cycle 3000");
    let sc = s.scene.as_ref().unwrap();
    assert!(sc.ledger().adhesion > 0.0, "some bonds must break");
    assert!(
        sc.contacts()
            .iter()
            .any(|p| p.s.touching && p.s.gamma() > 0.0 && p.jkr.is_some_and(|r| r.end.is_some())),
        "the adhesive scene must have JKR contacts, with a JKR row and its path's end"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let stale = check_continuation("adh", ADHESIVE, 6000, &[1, 1234, 2999, 4500, 5999]);
    let short = check_continuation(
        "adh-short",
        &format!("{ADHESIVE}\ncycle 30"),
        150,
        &(1..150).collect::<Vec<_>>(),
    );
    assert!(
        stale + short > 0,
        "no split point fell on a step before a re-mapping"
    );
}

/// The adhesive agglomerate under the no-slip law (the benchmark's S2 has it): the JKR rows
/// (`contacts::JkrRow`, the γ, a_s and path end the pair loop reads) are all the law state
/// its pairs carry across SAve/RESTart.
#[test]
fn adhesive_noslip_scene_continues_bitwise() {
    let setup = format!("{ADHESIVE}\nset tangential noslip");
    check_continuation("adh-noslip", &setup, 3000, &[1, 1234, 2999]);
}

/// Walton's law (`SET TANgential WALTON`): the adhesive agglomerate, hitting the floor
/// obliquely, has JKR contacts with turning points and stored energy, which SAve/RESTart
/// must keep to the bit.
#[test]
fn walton_scene_continues_bitwise() {
    let setup = format!("{ADHESIVE}\nset tangential walton")
        .replace("velocity 0 0 -0.5 0", "velocity 0.3 0.1 -0.5 0");
    assert!(setup.contains("velocity 0.3"));
    let dir = scratch("walton-probe");
    let mut s = session_in(&dir, &setup);
    run(&mut s, "cycle 3000");
    let sc = s.scene.as_ref().unwrap();
    assert!(
        sc.contacts().iter().any(|p| p.s.touching
            && p.s.gamma() > 0.0
            && p.s.ext().walton.reversed
            && p.s.ext().walton.stored > 0.0),
        "the scene must have JKR contacts with a Walton history"
    );
    let _ = std::fs::remove_dir_all(&dir);
    check_continuation("walton", &setup, 6000, &[1, 2999, 4500, 5999]);
}

/// The default law (MDR, named here as the word does): the dry frictional scene, its Hertz
/// contacts with the spring rows of the MDR law (`physics::mdr`), whose 16 springs, frame
/// and largest contact radius SAve/RESTart must keep to the bit.
#[test]
fn mdr_scene_continues_bitwise() {
    let setup = format!("{DRY}\nset tangential mdr");
    let dir = scratch("mdr-probe");
    let mut s = session_in(&dir, &setup);
    run(&mut s, "cycle 1500");
    let sc = s.scene.as_ref().unwrap();
    assert!(
        sc.contacts().iter().any(|p| p.s.touching
            && p.row
                .is_some_and(|r| r.a_ref > 0.0 && r.u.iter().any(|u| u[0] != 0.0 && u[1] != 0.0)))
            && sc
                .contacts()
                .wall_pairs()
                .iter()
                .any(|p| p.s.ext().mdr.is_some()),
        "the scene must have pair and wall contacts with MDR rows"
    );
    let _ = std::fs::remove_dir_all(&dir);
    check_continuation("mdr", &setup, 4000, &[1, 1500, 2345, 3999]);
}

/// Wet: the same agglomerate with pendular bridges (water, 1 % volume, viscous) and gravity,
/// dropped onto a floor: bridges form, stretch and rupture.
const WET: &str = "start 0.01 0.01 0.01 1000 100 2
set open all
rad 100e-6 1
ymd 1e8 1
pra 0.3 1
density 2500 1
friction 0.3 1
liquid 1 0.072 20 0.001
gravity 0 0 -9.81
agglomerate 1 0.005 0.005 0.005 0.00045
agen 1 1 1 0 0 0 0.0002 0.0002 0.0002
velocity 0 0 -0.5 0
dwall p 0 0 1 0.00468";

#[test]
fn wet_scene_continues_bitwise() {
    let dir = scratch("wet-probe");
    let mut s = session_in(&dir, WET);
    run(&mut s, "cycle 3000");
    let sc = s.scene.as_ref().unwrap();
    assert!(sc.ledger().rupture > 0.0, "some bridges must rupture");
    assert!(
        sc.contacts().iter().any(|p| p.s.bridge.is_some()),
        "the wet scene must have liquid bridges"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let stale = check_continuation("wet", WET, 6000, &[1, 1234, 2999, 4500, 5999]);
    let short = check_continuation(
        "wet-short",
        &format!("{WET}\ncycle 100"),
        150,
        &(1..150).collect::<Vec<_>>(),
    );
    assert!(
        stale + short > 0,
        "no split point fell on a step before a re-mapping"
    );
}

#[test]
fn a_save_and_restart_between_two_agenerates_changes_nothing() {
    // The second AGEnerate of a BCC lattice numbers both halves together only right after
    // the first: a SAve in between ends that, so a RESTart in between gives the same.
    let dir = scratch("agen");
    let setup = "start 1e-3 1e-3 1e-3 1000 2000 0\nrad 30e-6 1\ndensity 2650 1\nymd 70e9 1\n\
        pra 0.3 1\nagglomerate 1 5e-4 5e-4 5e-4 200e-6\n\
        agen 1 1 1 0 0 0 6.9282032302755094e-05 6.9282032302755094e-05 6.9282032302755094e-05";
    let second = "agen 1 1 1 3.4641016151377547e-05 3.4641016151377547e-05 3.4641016151377547e-05 \
        6.9282032302755094e-05 6.9282032302755094e-05 6.9282032302755094e-05";
    let mut a = session_in(&dir, setup);
    run(&mut a, "save agen.sav");
    run(&mut a, second);
    let mut b = session_in(&dir, "restart agen.sav");
    run(&mut b, second);
    assert_same(
        a.scene.as_ref().unwrap(),
        b.scene.as_ref().unwrap(),
        "agen; save; agen against agen; save; restart; agen",
    );
    run(&mut a, "cycle 20");
    run(&mut b, "cycle 20");
    assert_same(
        a.scene.as_ref().unwrap(),
        b.scene.as_ref().unwrap(),
        "and 20 cycles on",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// With automatic TOL and XRES the rebuilds of a fast scene use a larger TOL (up to twice
/// the automatic one, cycle::rebuild_tol) and so happen less often; the forces, positions
/// and the ledger do not depend on it: the same bits as the fixed automatic TOL (`SEt XRES`
/// to a large value keeps TOL fixed and XRES at its limit, the search of earlier versions).
#[test]
fn a_grown_tol_changes_the_rebuilds_and_nothing_else() {
    let dir = scratch("tol");
    let mut grown = session_in(&dir, DRY);
    run(&mut grown, "cycle 3000");
    let mut fixed = session_in(&dir, &format!("{DRY}\nset xres 1"));
    run(&mut fixed, "cycle 3000");
    let (a, b) = (grown.scene.unwrap(), fixed.scene.unwrap());
    let (p, q) = (&a.particles(), &b.particles());
    assert_eq!(p.id, q.id);
    for i in 0..p.len() {
        for (x, y) in [
            (&p.pos[i], &q.pos[i]),
            (&p.vel[i], &q.vel[i]),
            (&p.spin[i], &q.spin[i]),
        ] {
            for k in 0..3 {
                assert_eq!(x[k].to_bits(), y[k].to_bits(), "particle {}", p.id[i]);
            }
        }
    }
    assert_eq!(a.ledger(), b.ledger());
    let base = b.contacts().tol();
    assert!(
        a.contacts().tol() > base && a.contacts().tol() <= 2.0 * base,
        "TOL {} (automatic {base})",
        a.contacts().tol()
    );
    assert!(
        a.contacts().rebuilds() < b.contacts().rebuilds(),
        "{} rebuilds with the grown TOL, {} without",
        a.contacts().rebuilds(),
        b.contacts().rebuilds()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The blow-up snapshot keeps only the pairs and wall pairs with a state and no
/// displacements since the last rebuild (`cycle::snapshot_of`); a scene restored from it
/// goes on bit for bit as the scene it was taken of (its first step searches anew), for the
/// dry, the adhesive and the wet scene.
#[test]
fn a_scene_restored_from_the_blow_up_snapshot_goes_on_as_the_original() {
    let mut leaner = 0;
    for (tag, setup, first) in [
        ("dry", DRY, 1750),
        ("adh", ADHESIVE, 2500),
        ("wet", WET, 2500),
    ] {
        let dir = scratch(&format!("snap-{tag}"));
        let mut s = session_in(&dir, setup);
        run(&mut s, &format!("cycle {first}"));
        let mut original = s.scene.take().unwrap();
        let snapshot = trubal::sim::cycle::snapshot_of(&mut original);
        // The snapshot is lean (candidate pairs without a state are left out, in the dry
        // scene at least), and the list must be searched again.
        leaner += usize::from(snapshot.contacts().len() < original.contacts().len());
        assert!(
            snapshot.contacts().len() <= original.contacts().len(),
            "{tag}: {} of {} pairs kept",
            snapshot.contacts().len(),
            original.contacts().len()
        );
        assert!(snapshot.particles().disp.is_empty(), "{tag}");
        let touching = |sc: &Scene| sc.contacts().iter().filter(|p| p.s.touching).count();
        assert!(touching(&original) > 0, "{tag}");
        assert_eq!(touching(&snapshot), touching(&original), "{tag}");
        let mut restored = original.clone();
        trubal::sim::cycle::restore(&mut restored, snapshot);
        assert!(restored.contacts().needs_remap(), "{tag}");
        for sc in [&mut original, &mut restored] {
            trubal::sim::cycle::run(sc, 1500).unwrap();
        }
        let (p, q) = (&original.particles(), &restored.particles());
        assert_eq!(p.id, q.id, "{tag}");
        for i in 0..p.len() {
            for (x, y) in [
                (&p.pos[i], &q.pos[i]),
                (&p.vel[i], &q.vel[i]),
                (&p.spin[i], &q.spin[i]),
                (&p.rot[i], &q.rot[i]),
                (&p.force[i], &q.force[i]),
            ] {
                for k in 0..3 {
                    assert_eq!(
                        x[k].to_bits(),
                        y[k].to_bits(),
                        "{tag}: particle {}",
                        p.id[i]
                    );
                }
            }
        }
        assert_eq!(original.ledger(), restored.ledger(), "{tag}");
        // The same contacts with the same states (the candidate lists may differ in pairs
        // that never came within reach).
        // (Particle pairs, then particle–wall pairs with the wall's number as the second id.)
        let live = |sc: &Scene| {
            let walls = sc
                .contacts()
                .wall_pairs()
                .iter()
                .map(|w| (w.id, u32::MAX - w.wall, &w.s));
            sc.contacts()
                .iter()
                .map(|p| (p.ida, p.idb, p.s))
                .chain(walls)
                .filter(|(_, _, s)| s.touching || s.bridge.is_some())
                .map(|(a, b, s)| (a, b, s.clone()))
                .collect::<Vec<_>>()
        };
        let live_now = live(&original);
        assert!(!live_now.is_empty(), "{tag}");
        assert_eq!(live_now, live(&restored), "{tag}");
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(leaner > 0, "no snapshot left a pair out");
}

/// FRAction AUTO: the step follows the fastest contact at every rebuild (a sphere thrown at
/// 30 m/s into the falling agglomerate of the dry scene changes it); Cycle N; Cycle M, and
/// Cycle N; SAve; RESTart; Cycle M, are bitwise Cycle N+M (the step in use is kept in the
/// checkpoint).
#[test]
fn fraction_auto_continues_bitwise() {
    let setup = format!("{DRY}\nfraction auto\ncreate 0.05 0.05 0.09 0 0 -30 0 0 0 1 1");
    check_continuation("auto", &setup, 1200, &[1, 300, 777]);
    // The step did change.
    let dir = scratch("auto-dt");
    let mut s = session_in(&dir, &setup);
    let first = trubal::sim::params::build(s.scene.as_ref().unwrap())
        .unwrap()
        .dt_base;
    run(&mut s, "cycle 1200");
    let sc = s.scene.as_ref().unwrap();
    let dt = sc.settings().auto_step.unwrap();
    assert!(
        dt > 0.0 && dt < first,
        "auto step {dt}, FRAction step {first}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An interrupt (Ctrl-C) makes the step about to run the Cycle's last: the state is that of
/// the shorter Cycle, bitwise, and it goes on as the uninterrupted run. Interrupts are put
/// on both sides of a snapshot (SNApshot 1000) and of a re-mapping.
#[test]
fn an_interrupted_cycle_is_a_shorter_cycle() {
    let dir = scratch("interrupt");
    for k in [1u64, 999, 1000, 1001, 2345] {
        let mut a = session_in(&dir, ADHESIVE);
        let sa = a.scene.as_mut().unwrap();
        let (_, ran) =
            trubal::sim::cycle::run_watched(sa, 1_000_000, &mut |_, done| done + 1 == k).unwrap();
        assert_eq!(ran, k);
        let mut b = session_in(&dir, ADHESIVE);
        run(&mut b, &format!("cycle {k}"));
        assert_same(
            a.scene.as_ref().unwrap(),
            b.scene.as_ref().unwrap(),
            &format!("interrupt at {k}"),
        );
        run(&mut a, "cycle 500");
        run(&mut b, "cycle 500");
        assert_same(
            a.scene.as_ref().unwrap(),
            b.scene.as_ref().unwrap(),
            &format!("after interrupt at {k}"),
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// 27 glass spheres in a spherical container that shrinks at 10 m/s onto them
/// (tests/it/hard_cases.rs), with friction: contacts and a moving wall in contact when a
/// command comes between two Cycles.
const SQUEEZE: &str = "start 1e-3 1e-3 1e-3 10 100 2
set open all
rad 30e-6 1
ymd 70e9 1
pra 0.3 1
density 2650 1
friction 0.3 1
aggl 1 5e-4 5e-4 5e-4 1.4e-4
age 1 1 1 4.4e-4 4.4e-4 4.4e-4 6e-5 6e-5 6e-5
dwall sp 5e-4 5e-4 5e-4 2.2e-4 v 0 0 0 -10";

/// A command between two Cycles books the same whether or not a SAve and a RESTart (in a
/// fresh session) came between: the work in flight at the first Cycle's end, the velocity
/// each wall moved with in its last step and the audit's reference are part of the state
/// (checkpoint format 14, `sim::scene::Carried`), so the books after the command are
/// bitwise those of the uninterrupted session (doc/spec/DECISIONS.md, "Output,
/// determinism, checkpoints"). The container is pressing the lattice when the command
/// comes; the command changes its speed, or puts a servo on it, or comes before the SAve.
#[test]
fn a_command_after_a_restart_books_as_without_it() {
    let dir = scratch("cmd-after-restart");
    let mut whole = session_in(&dir, SQUEEZE);
    run(&mut whole, "cycle 1400");
    let touching = whole.scene.as_ref().unwrap().touching_counts();
    assert!(touching.0 > 0 && touching.1 > 0, "in contact: {touching:?}");
    for (tag, before, after) in [
        ("speed", "", "awall 1 v 0 0 0 -5"),
        ("servo", "", "awall 1 se 1e-2 5 1e-2"),
        ("before", "awall 1 v 0 0 0 -5", ""),
    ] {
        let mut a = session_in(&dir, SQUEEZE);
        run(&mut a, "cycle 1400");
        if !before.is_empty() {
            run(&mut a, before);
        }
        run(&mut a, &format!("save cmd-{tag}.sav"));
        let mut b = session_in(&dir, &format!("restart cmd-{tag}.sav"));
        for s in [&mut a, &mut b] {
            if !after.is_empty() {
                run(s, after);
            }
            run(s, "cycle 100");
        }
        assert_same(
            a.scene.as_ref().unwrap(),
            b.scene.as_ref().unwrap(),
            &format!("cycle 1400; {before}; save; [restart;] {after}; cycle 100"),
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A loose gas of 100 spheres in a periodic cell pressed by the stress servo (mode 1): a
/// run split into Cycles, or across SAve and RESTart, is the run of one Cycle, to the bit —
/// the servo goes on with the axes it adjusts and its base rates (`Scene::continued_servo`).
/// With GRID prescribing ed11, S0 adjusts ed22 and ed33 only, in every part (a servo begun
/// afresh at the second Cycle, whose rates are then all non-zero, took ed11 over too); RING
/// in mode 1 turns ed12 from the first Cycle's rate, not from the one the first part left.
#[test]
fn a_servo_cycle_split_in_two_is_one_cycle() {
    let dir = scratch("servo-split");
    let base = "start 1e-3 1e-3 1e-3 100 1000 0\nrad 8e-5 1\ndensity 2600 1\nymd 1e8 1\n\
                pra 0.25 1\nfriction 0.3 1\ndamping restitution 0.2\nrge 100 1 1 0\n\
                gain 2e-2 600\nmode 1";
    for (tag, grid, targets) in [
        ("s0", "grid -50 0 0 0 0 0", "s0 2e4"),
        ("ring", "grid 0 0 0 0 0 0", "s0 2e4 ring 120"),
    ] {
        let setup = format!("{base}\n{grid}");
        let mut whole = session_in(&dir, &setup);
        run(&mut whole, &format!("cycle 3000 {targets}"));
        let mut two = session_in(&dir, &setup);
        run(&mut two, &format!("cycle 1700 {targets}"));
        run(&mut two, &format!("save servo-{tag}.sav"));
        run(&mut two, &format!("cycle 1300 {targets}"));
        assert_same(
            whole.scene.as_ref().unwrap(),
            two.scene.as_ref().unwrap(),
            &format!("{tag}: cycle 1700; cycle 1300"),
        );
        let mut restarted = session_in(&dir, &format!("restart servo-{tag}.sav"));
        run(&mut restarted, &format!("cycle 1300 {targets}"));
        assert_same(
            whole.scene.as_ref().unwrap(),
            restarted.scene.as_ref().unwrap(),
            &format!("{tag}: cycle 1700; save; restart; cycle 1300"),
        );
        let sc = whole.scene.as_ref().unwrap();
        if tag == "s0" {
            assert_eq!(sc.cell().rate[0], -50.0, "the prescribed rate stays");
        }
        assert!(
            sc.cell().rate[1] != 0.0 && sc.cell().rate[2] != 0.0,
            "the servo adjusted ed22 and ed33: {:?}",
            sc.cell().rate
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
