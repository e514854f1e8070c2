//! Bitwise determinism across thread counts: the same command file run with 1 and 2 worker
//! threads prints exactly the same JSON (forces are summed in a fixed order, energy partial
//! sums per fixed chunk).

/// Runs trubal with `args` in folder `dir`; its standard output (it must succeed).
fn trubal(dir: &std::path::Path, args: &[&str]) -> String {
    trubal_regions(dir, args, None)
}

/// As [`trubal`], with the step in `regions` parallel regions (`TRUBAL_STEP_REGIONS`: 1, the
/// force step and the update together; 2, one after the other) whatever the cores.
fn trubal_regions(dir: &std::path::Path, args: &[&str], regions: Option<&str>) -> String {
    let mut cmd = crate::common::trubal();
    cmd.current_dir(dir).args(args);
    if let Some(r) = regions {
        cmd.env("TRUBAL_STEP_REGIONS", r);
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn run(threads: &str) -> String {
    let args = [
        "scripts/dry_agglomerate_impact.tru",
        "--json",
        "--threads",
        threads,
        "--set",
        "v=2",
        "--set",
        "n=300",
    ];
    trubal(std::path::Path::new(env!("CARGO_MANIFEST_DIR")), &args)
}

#[test]
fn one_and_two_threads_give_the_same_bits() {
    let a = run("1");
    let b = run("2");
    assert!(a.contains("\"damage_ratio\""), "{a}");
    assert_eq!(a, b);
}

/// A settling bed built by RGEnerate (Morton numbering, single-cell search), with walls,
/// friction and restitution damping, dry, moist and with a moving spherical indenter: the
/// whole saved state after 3000 steps is the same, byte for byte, with 1 thread, 2 (the
/// force step and the update in one parallel region, `cycle::fused`, and in two) and 3 (three
/// force tasks: one with a neighbour on each side; one region). Then a bed of 6000 spheres
/// (six chunks of the update: with two threads most are updated by their force task in the
/// force step's region), after 1000 steps.
#[test]
fn a_settling_bed_saves_the_same_bytes_with_one_and_two_threads() {
    let dir = std::env::temp_dir().join(format!("trubal_threads_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, w, n, extra, steps) in [
        ("dry", 0.02, 1500, "", 3000),
        ("moist", 0.02, 1500, "liquid 0.1 0.025 0 0.01\n", 3000),
        // JKR contacts, whose γ, a_s and path end the pair loop keeps in its blocks' JKR
        // rows (`contacts::JkrRow`) and the checkpoint in their extension.
        ("adhesive", 0.02, 1500, "cohesion 0.05 1\n", 3000),
        // A spherical indenter that moves down through the settling particles (the
        // update adds the wall forces of each chunk's particles with several threads).
        (
            "indenter",
            0.02,
            1500,
            "dwall ob 0.01 0.01 0.09 0.005 v 0 0 -1.2\n",
            3000,
        ),
        ("wide", 0.04, 6000, "", 1000),
        // Three force tasks in one region (one task with a neighbour on each side) on the
        // two cores: a task waits a while for one that has no core, so this one runs fewer
        // steps.
        ("three", 0.02, 1500, "", 300),
    ] {
        let deck = format!(
            "start {w} {w} 0.08 {cap} {cap} 6\nset open all\nrad 1e-3 1\ndensity 2500 1\nymd 1e7 1\npra 0.3 1\n\
             friction 0.5 1\ndamping restitution 0.5\ngravity 0 0 -9.81\nfraction 0.2\n\
             dwall p 1 0 0 0\ndwall p -1 0 0 -{w}\ndwall p 0 1 0 0\ndwall p 0 -1 0 -{w}\n\
             dwall p 0 0 1 0\nrgenerate {n} 1 1 0\nset tangential noslip\n{extra}cycle {steps}\n\
             print info\nsave $f\n",
            cap = 2 * n
        );
        std::fs::write(dir.join(format!("{name}.tru")), deck).unwrap();
        let mut saved = Vec::new();
        let runs: &[(&str, Option<&str>)] = if name == "three" {
            &[("1", None), ("3", Some("1"))]
        } else {
            &[("1", None), ("2", Some("1")), ("2", Some("2"))]
        };
        for &(t, regions) in runs {
            let f = format!("{name}_t{t}_{}.sav", regions.unwrap_or("-"));
            let deck = format!("{name}.tru");
            let set = format!("f={f}");
            let text = trubal_regions(&dir, &[&deck, "--threads", t, "--set", &set], regions);
            assert!(text.contains("particle-particle"), "{text}");
            saved.push(std::fs::read(dir.join(&f)).unwrap());
        }
        for (k, (t, regions)) in runs.iter().enumerate().skip(1) {
            assert!(
                saved[0] == saved[k],
                "{name}: the checkpoints differ (1 thread; {t} threads, regions {regions:?})"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The particle update's general path (Rayleigh damping with its mass term, fixed
/// particles), periodic sides, a spherical container (reaching beyond the work-space: the
/// particles generated outside it are deleted, `SET TUNnel DELETE`) and particles lost
/// through the open side: the same checkpoint bytes with 1 thread and with 2 in one and in
/// two regions.
#[test]
fn a_periodic_damped_bed_with_fixed_and_lost_particles_saves_the_same_bytes() {
    let dir = std::env::temp_dir().join(format!("trubal_threads_odd_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let deck = "start 0.04 0.04 0.06 12000 12000 2\nset open z\nrad 1e-3 1\ndensity 2500 1\n\
                ymd 1e7 1\npra 0.3 1\nfriction 0.5 1\ndamping 0.05 100 0 1 0\ngravity 0 0 -9.81\n\
                fraction 0.2\nset tunnel delete\ndwall p 0 0 1 0\ndwall sp 0.02 0.02 0.03 0.03\nrgenerate 6000 1 1 0\n\
                fix 1 1 1 0 0 0 5\nfix 1 1 1 0 0 0 3000\ncycle 1500\nprint info\nsave $f\n";
    std::fs::write(dir.join("odd.tru"), deck).unwrap();
    let mut saved = Vec::new();
    let runs = [("1", None), ("2", Some("1")), ("2", Some("2"))];
    for (t, regions) in runs {
        let f = format!("odd_t{t}_{}.sav", regions.unwrap_or("-"));
        let set = format!("f={f}");
        let text = trubal_regions(&dir, &["odd.tru", "--threads", t, "--set", &set], regions);
        assert!(text.contains("lost through open sides"), "{text}");
        assert!(
            !text.contains("lost through open sides or walls crossed 0)"),
            "some leave: {text}"
        );
        saved.push(std::fs::read(dir.join(&f)).unwrap());
    }
    for (k, (t, regions)) in runs.iter().enumerate().skip(1) {
        assert!(
            saved[0] == saved[k],
            "the checkpoints differ (1 thread; {t} threads, regions {regions:?})"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The pollers (`sim::parallel::awake`) put to sleep and woken every few steps, as on a busy
/// machine, at every phase of the step: the Cycle's thread then runs the step alone, on the
/// one-thread plan, and the split plan again when they wake. The saved state is the same
/// bytes as with one thread: a dry bed with the default law, and a moist one with NOSLIP,
/// both run until they rest on the floor (a step on the one-thread plan after a split one
/// must not read the split step's slots: the first form of the change added them to the
/// shared particles' forces once the particles touched, from about step 2000).
#[test]
fn pollers_put_to_sleep_and_woken_mid_cycle_change_no_bit() {
    let dir = std::env::temp_dir().join(format!("trubal_threads_pace_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let deck = |extra: &str, f: &std::path::Path| {
        format!(
            "start 0.02 0.02 0.08 3000 3000 6\nset open all\nrad 1e-3 1\ndensity 2500 1\n\
             ymd 1e7 1\npra 0.3 1\nfriction 0.5 1\ndamping restitution 0.5\ngravity 0 0 -9.81\n\
             fraction 0.2\ndwall p 1 0 0 0\ndwall p -1 0 0 -0.02\ndwall p 0 1 0 0\n\
             dwall p 0 -1 0 -0.02\ndwall p 0 0 1 0\nrgenerate 1500 1 1 0\n{extra}cycle 3000\n\
             save \"{}\"\n",
            f.display()
        )
    };
    let run = |threads: usize, extra: &str, f: &std::path::Path| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let lines = deck(extra, f);
        pool.install(|| drop(crate::common::session(&lines)));
        std::fs::read(f).unwrap()
    };
    for (name, extra) in [
        ("dry", ""),
        ("moist", "set tangential noslip\nliquid 0.1 0.025 0 0.01\n"),
    ] {
        let one = run(1, extra, &dir.join(format!("{name}_one.sav")));
        for every in [1, 7, 64] {
            let (before, _) = trubal::sim::parallel::awake::asleep_so_far();
            trubal::sim::parallel::awake::change_every(every);
            let two = run(2, extra, &dir.join(format!("{name}_two_{every}.sav")));
            trubal::sim::parallel::awake::change_every(0);
            let (after, _) = trubal::sim::parallel::awake::asleep_so_far();
            if trubal::sim::parallel::awake::cores() >= 2 {
                assert!(
                    after - before >= 3000 / every,
                    "{every}: {before} → {after}"
                );
            }
            assert!(
                one == two,
                "{name}: the checkpoints differ (pollers changed every {every} steps)"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
