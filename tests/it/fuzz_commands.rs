//! Random command files through the binary (one or two threads, every fourth with `--json`):
//! every command with extreme, odd or missing arguments (0, ±1e300, 1e-300, the smallest
//! subnormal, NaN, `x`, ...), in random order on
//! a small scene with walls, a region and cycles in between. Whatever the input, trubal must
//! not panic, abort (an allocation failure) or hang: each file either runs or gets its
//! errors. The seeds are fixed, so a failure names a file that can be replayed: the test
//! writes it to the temporary directory and prints its path.
//!
//! The bugs this found when it was written: a reach of the order of i64::MAX cells on
//! periodic axes (`LIQuid 1e308 …`, `SET TOL 1e99`) wrapped the search's span test, and an
//! AGEnerate step far below the particle size enumerated ~1e20 lattice sites.

use std::process::Stdio;
use std::time::{Duration, Instant};

/// A small deterministic generator (64-bit LCG, the high bits).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a>(&mut self, v: &[&'a str]) -> &'a str {
        v[self.below(v.len())]
    }
    fn unit(&mut self) -> f64 {
        self.next() as f64 / (1u64 << 31) as f64
    }
}

const EXTREME: &[&str] = &[
    "0",
    "-0",
    "1e-300",
    "1e-30",
    "1e-12",
    "1e-6",
    "1e-3",
    "0.5",
    "1",
    "10",
    "1e6",
    "1e12",
    "1e30",
    "1e300",
    "1.7976931348623157e308",
    "-1",
    "-1e-300",
    "-1e300",
    "4.9e-324",
    "nan",
    "inf",
    "-inf",
    "1e400",
    "4294967296",
    "x",
    "",
];

const BASE: &str = "start 0.01 0.01 0.01 10 400 6\nset open z\nrad 5e-4 1\nrad 3e-4 2\n\
    density 2500 1\ndensity 2500 2\nymd 1e7 1\nymd 1e7 2\npra 0.3 1\npra 0.3 2\nfriction 0.5 1\n\
    damping restitution 0.5\ngravity 0 0 -9.81\nfraction 0.2\ndwall p 0 0 1 0\n\
    agglomerate 1 0.005 0.005 0.005 0.003\nrgenerate 40 1 1 1\nrgenerate 20 2 1 0\n";

/// One random command.
fn command(g: &mut Lcg) -> String {
    let e = |g: &mut Lcg| g.pick(EXTREME).to_string();
    let p = |g: &mut Lcg| format!("{}", 0.01 * g.unit());
    // `n` of them, drawn in order, separated by spaces.
    let es = |g: &mut Lcg, n: usize| (0..n).map(|_| e(g)).collect::<Vec<_>>().join(" ");
    let ps = |g: &mut Lcg, n: usize| (0..n).map(|_| p(g)).collect::<Vec<_>>().join(" ");
    let mat = |g: &mut Lcg| g.pick(&["1", "2", "0", "9"]).to_string();
    match g.below(46) {
        0 => format!("create {} {} 1 1", ps(g, 3), es(g, 6)),
        1 => format!("rad {} {}", e(g), mat(g)),
        2 => format!(
            "rad 5e-4 1 {} {} {}",
            g.pick(&["normal", "uniform"]),
            e(g),
            e(g)
        ),
        3 => format!("density {} {}", e(g), mat(g)),
        4 => format!("ymd {} {}", e(g), mat(g)),
        5 => format!(
            "pra {} 1",
            g.pick(&["0", "0.49", "0.5", "-1", "-0.99", "nan"])
        ),
        6 => format!("friction {} {}", e(g), mat(g)),
        7 => format!("cohesion {} {}", e(g), mat(g)),
        8 => format!("damping restitution {} {}", e(g), mat(g)),
        9 => format!("damping {} {} 0 0 {}", e(g), e(g), g.pick(&["0", "1"])),
        10 => format!("gravity {}", es(g, 3)),
        11 => format!("fraction {}", e(g)),
        12 => format!("{} {}", g.pick(&["fmm", "vmu", "zero", "mode"]), e(g)),
        13 => format!(
            "liquid {} {} {} {}",
            e(g),
            e(g),
            g.pick(&["0", "10", "89", "90", "180", "-5"]),
            e(g)
        ),
        14 => format!(
            "set {} {}",
            g.pick(&[
                "tol",
                "xres",
                "smin",
                "genoverlap",
                "fragment",
                "snapshot",
                "history"
            ]),
            if g.below(4) == 0 {
                "default".into()
            } else {
                e(g)
            }
        ),
        15 => format!(
            "set {}",
            g.pick(&[
                "bridge fit",
                "bridge toroidal",
                "bridge laplace",
                "tangential md",
                "tangential noslip",
                "liquid lian",
                "liquid conserve",
                "goldman on",
                "wallbridges off",
                "open x",
                "open all",
                "periodic x",
                "periodic all",
                "view xz",
                "nonsense 3",
            ])
        ),
        16 => format!("dwall p {}", es(g, 4)),
        17 => format!("dwall sp {} {}", ps(g, 3), e(g)),
        18 => format!("dwall ob {} {} V {} M {}", ps(g, 3), e(g), es(g, 3), mat(g)),
        19 => format!("dwall p 0 0 -1 -0.009 V 0 0 {} SE {}", e(g), es(g, 3)),
        20 => format!(
            "awall {} {} {}",
            g.pick(&["1", "2", "0", "99"]),
            g.pick(&["V", "SP", "P", "M", "SE"]),
            es(g, 4)
        ),
        21 => format!("velocity {} {}", es(g, 3), g.pick(&["0", "1"])),
        22 => format!("cgravity {} {}", g.pick(&["1", "2", "0"]), e(g)),
        23 => format!("move {} {}", g.pick(&["1", "2"]), es(g, 3)),
        24 => format!(
            "agglomerate {} {} {}",
            g.pick(&["1", "2", "3"]),
            ps(g, 3),
            e(g)
        ),
        25 => format!(
            "agenerate 1 1 {} {} {}",
            g.pick(&["0", "1", "2"]),
            ps(g, 3),
            es(g, 3)
        ),
        26 => format!(
            "rgenerate {} {} 1 {}",
            g.pick(&["0", "1", "10", "100", "1e9", "-1"]),
            g.pick(&["1", "2", "5"]),
            g.pick(&["0", "1", "2"])
        ),
        27 => format!("fix 1 1 1 1 1 1 {}", g.pick(&["1", "5", "0", "999", "All"])),
        28 => format!("relax {} {} {}", e(g), e(g), g.pick(&["0", "100", "300"])),
        29 => g
            .pick(&[
                "fro",
                "reset",
                "2-d",
                "help",
                "help cycle",
                "iset 1 2",
                "rset 1 2",
            ])
            .into(),
        30 => format!("window {}", es(g, 6)),
        31 => format!(
            "print {}",
            g.pick(&[
                "balls",
                "bonds",
                "chist",
                "clusters",
                "contacts",
                "all",
                "gap",
                "energy",
                "entries",
                "grid",
                "history",
                "info",
                "map",
                "partitions",
                "settings",
                "stress",
                "walls",
                "nothing",
            ])
        ),
        32 => format!(
            "plot {}",
            g.pick(&[
                "ball", "disks", "bou", "grid", "cluster", "lcluster", "cnd", "lcnd", "couple",
                "forces", "lforces", "mforces", "rdisp", "rotation", "save", "velocity", "wall",
                "history",
            ])
        ),
        33 => format!("probe {}", g.pick(&["e11", "e22", "e12", "e1m2"])),
        34 => format!("grid {} 0 0 {} 0 0", e(g), e(g)),
        35 => format!("gain {} {}", e(g), e(g)),
        36 => format!(
            "cycle {} {} {}",
            g.below(60),
            g.pick(&["S11", "S0", "RING"]),
            e(g)
        ),
        37 => g
            .pick(&[
                "save a.sav",
                "new\nrestart a.sav",
                "restart nothing.sav",
                "save /",
            ])
            .into(),
        38 => format!("{} {} {}", g.pick(&["cycle", "start", "log"]), e(g), e(g)),
        39 => format!(
            "vtk {}",
            g.pick(&[
                "",
                "every 7",
                "every 0",
                "off",
                "every 3 file f",
                "file ../x",
                "every",
                "raw",
                "every 5 raw",
                "off raw",
                "arrays id radius velocity",
                "every 4 arrays vel",
                "arrays",
                "arrays colour",
                "arrays id id",
                "off arrays id",
                "arrays displacement cluster raw"
            ])
        ),
        40 => format!(
            "field {} {} {} {} {}",
            g.below(4),
            g.below(4),
            g.below(4),
            if g.below(3) == 0 {
                "bin".to_string()
            } else {
                e(g)
            },
            g.pick(&[
                "",
                "lucy",
                "file g",
                "file",
                "average 3 4",
                "csv average 1 2",
                "average 0 1",
                "average 5",
                "in 0 1e-3 0 1e-3 0 1e-3",
                "lucy in 0 1 0 1 0 1"
            ])
        ),
        41 => format!(
            "group {} {}{}",
            g.pick(&[
                "a",
                "b",
                "B.2",
                "9x",
                "all",
                "a-very-long-name-over-thirty-two-chars"
            ]),
            g.pick(&[
                "",
                "dynamic ",
                "forget",
                "history",
                "history off",
                "dyn group a "
            ]),
            range(g)
        ),
        42 => format!(
            "{} {}",
            g.pick(&[
                "fix 1 1 1 0 0 0",
                "delete",
                "velocity 0 0 -1",
                "property velocity 1 2 3",
                "property spin 1 2 3",
                "property material 2",
                "property material 7",
                "print group",
                "print range",
                "print group all",
                "plot ball"
            ]),
            range(g)
        ),
        // The programmable language (doc/language.md): expressions of extreme values, blocks
        // (some left open or closed twice), procedures, hooks and conditions of a Cycle.
        43 => format!(
            "let x = {}\n{}",
            e(g),
            g.pick(&[
                "let y = x * 1e300 + x",
                "show [x / (x - x)] [sqrt(x)] [log(x)] [x^x]",
                "rad [x] 1",
                "create [x] 0.005 0.005 0 0 x 0 0 0 1 1",
                "show [ball_vz(x)] [wall_fz(x)] [energy.kinetic] [sum(vz)] [avg(x, g)] [info.balls.1]",
                "if x > 1\nshow x\nelse\nshow 0\nend",
                "loop i 1 3\ncycle 2\nend",
                "loop i 3 1 x\nend",
                "while x < 1\nlet x = x + 0.5 + abs(x)\nend",
                "while 1\nbreak\nend",
                "end",
                "else",
                "break",
                "return x",
                "if x\nloop i 1 2",
                "define p a\nlet q = a * x\nreturn q\nend\ncall p x",
                "call p",
                "let = 3",
                "let x 3",
                "let time = 1",
                "show [((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((1]",
                "include nothing.tru",
                "save \"s_$x.sav\"",
            ])
        ),
        44 => format!(
            "define h\nlet c = c + 1\n{}\nend\nlet c = 0\ncycle {} {} {}",
            g.pick(&["awall 1 v 0 0 [c*1e-3]", "cycle 1", "stop", "let c = 1 / 0", "show c"]),
            g.below(60),
            g.pick(&["call h every", "until", "call h every 7 until", "call nope every"]),
            g.pick(&["1", "5", "0", "c > 3", "ball_z(1) < 0.005", "energy.kinetic > 1", "x", ""])
        ),
        _ => format!("cycle {}", 1 + g.below(80)),
    }
}

/// A random range (doc/groups.md), sometimes malformed.
fn range(g: &mut Lcg) -> String {
    let e = |g: &mut Lcg| g.pick(EXTREME).to_string();
    let p = |g: &mut Lcg| format!("{}", 0.01 * g.unit());
    let mut out = Vec::new();
    for k in 0..1 + g.below(3) {
        if k > 0 && g.below(3) == 0 {
            out.push("or".to_string());
        }
        if g.below(4) == 0 {
            out.push("not".to_string());
        }
        out.push(match g.below(9) {
            0 => format!("box 0 {} 0 {} 0 {}", p(g), p(g), p(g)),
            1 => format!("box {} {} {} {} {} {}", e(g), e(g), e(g), e(g), e(g), e(g)),
            2 => format!("sphere {} {} {} {}", p(g), p(g), p(g), e(g)),
            3 => format!("cylinder {} {} {} 0 0 {} {}", p(g), p(g), p(g), e(g), e(g)),
            4 => format!("id {} to {} {}", g.below(70), g.below(70), e(g)),
            5 => format!("material {}", g.pick(&["1", "2", "0", "65", "1 2"])),
            6 => format!("size {}", g.pick(&["1", "2", "x", "1 2 3"])),
            7 => format!("group {}", g.pick(&["a", "b", "b.2", "zz"])),
            _ => g.pick(&["", "or", "not", "to 3"]).to_string(),
        });
    }
    out.join(" ")
}

fn deck(seed: u64) -> String {
    let mut g = Lcg(seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0x5bd1e995);
    let mut d = BASE.to_string();
    for _ in 0..3 + g.below(12) {
        d += &command(&mut g);
        d.push('\n');
        if g.below(10) < 4 {
            d += &format!("cycle {}\n", 1 + g.below(100));
        }
    }
    d + "print info\ncycle 50\nprint energy\nsave b.sav\nplot ball\n"
}

/// Runs one file; `Err` with what went wrong (and where the file was left).
fn run(seed: u64, dir: &std::path::Path) -> Result<(), String> {
    let sub = dir.join(format!("s{seed}"));
    std::fs::create_dir_all(&sub).unwrap();
    let text = deck(seed);
    std::fs::write(sub.join("d.tru"), &text).unwrap();
    let threads = if seed.is_multiple_of(2) { "1" } else { "2" };
    // Every fourth file with machine-readable output.
    let json: &[&str] = if seed % 4 == 1 { &["--json"] } else { &[] };
    let mut child = crate::common::trubal()
        .args(["--threads", threads, "--keep-going"])
        .args(json)
        .arg("d.tru")
        .current_dir(&sub)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let limit = Duration::from_secs(120);
    loop {
        if let Some(_status) = child.try_wait().unwrap() {
            break;
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "seed {seed}: still running after {limit:?}: {}",
                sub.display()
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let bad = err.contains("panicked") || err.contains("memory allocation");
    // (Exit codes: 0 and the error codes; a signal gives none.)
    if bad || out.status.code().is_none_or(|c| c > 2) {
        let tail: String = err.lines().rev().take(6).collect::<Vec<_>>().join(" | ");
        return Err(format!(
            "seed {seed} ({threads} threads, {:?}): {tail}; file {}",
            out.status,
            sub.join("d.tru").display()
        ));
    }
    let _ = std::fs::remove_dir_all(&sub);
    Ok(())
}

#[test]
fn random_command_files_never_panic_abort_or_hang() {
    let dir = std::env::temp_dir().join(format!("trubal_fuzz_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Two at a time (the machine has two cores).
    let seeds: Vec<u64> = (0..160).collect();
    let failures: Vec<String> = std::thread::scope(|s| {
        let (a, b) = seeds.split_at(seeds.len() / 2);
        let ha = s.spawn(|| {
            a.iter()
                .filter_map(|&k| run(k, &dir).err())
                .collect::<Vec<_>>()
        });
        let hb = s.spawn(|| {
            b.iter()
                .filter_map(|&k| run(k, &dir).err())
                .collect::<Vec<_>>()
        });
        let mut f = ha.join().unwrap();
        f.extend(hb.join().unwrap());
        f
    });
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_files_are_the_same_for_a_seed_and_differ_between_seeds() {
    assert_eq!(deck(7), deck(7));
    assert_ne!(deck(7), deck(8));
    // Every kind of command is drawn within the seeds the test runs.
    let all: String = (0..160).map(deck).collect();
    for c in [
        "agenerate",
        "liquid",
        "dwall sp",
        "awall",
        "restart",
        "plot",
        "probe",
        "relax",
        "vtk",
        "field",
    ] {
        assert!(all.contains(c), "{c}");
    }
}
