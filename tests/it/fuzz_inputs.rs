//! Mutational fuzzing in-process (issue 38, item 5): the command parser, the session applying
//! commands to a scene, and the checkpoint reader, on inputs mutated from a corpus
//! (`fuzz/corpus/commands/*.tru`: the golden and example command files and a few hard
//! scenes; the checkpoint fixtures of every format version in `tests/fixtures/`). Every
//! input must give a result or an error, never a panic. The generator is seeded, so a failure
//! names the target and the input number; the input is written to the temporary directory.
//!
//! CI runs `TRUBAL_FUZZ_INPUTS` inputs in all (default 100 000, about 3 s); the full run of
//! doc/limits.md: `TRUBAL_FUZZ_INPUTS=1000000 cargo test --release --test it fuzz_inputs:: --
//! --nocapture`. No coverage guidance (cargo-fuzz needs a nightly compiler, which this
//! project's machines do not have): the mutations are structured instead (numbers replaced
//! by extreme values, keywords and commands inserted, lines duplicated, spliced, cut; bytes
//! flipped in checkpoints, with the checksum recomputed so that the decoder sees them).
//! `tests/it/fuzz_commands.rs` keeps running random command files through the binary.

use std::panic::{AssertUnwindSafe, catch_unwind};

use trubal::checkpoint::{HEADER, fnv1a, from_bytes};
use trubal::lang::command::Command;
use trubal::lang::parse::parse_line;
use trubal::lang::script::ScriptCmd;

/// xorshift64*: small, seeded, fixed forever.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

const EXTREME: &[&str] = &[
    "0",
    "-0",
    "1e-300",
    "1e-30",
    "1e-12",
    "1e-6",
    "0.5",
    "1",
    "2",
    "3",
    "10",
    "1e6",
    "1e12",
    "1e300",
    "1.7976931348623157e308",
    "-1",
    "-1e300",
    "4.9e-324",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e400",
    "4294967296",
    "18446744073709551616",
    "1.d-3",
    "1e",
    ".",
    "-",
    "x",
    "$v",
    "#",
    ";",
    "(",
    ")",
    ",",
    "/",
    "\u{00e9}",
    "\u{feff}",
    "\t",
    "",
];

const WORDS: &[&str] = &[
    "cycle",
    "print",
    "plot",
    "set",
    "start",
    "create",
    "dwall",
    "awall",
    "rad",
    "ymd",
    "pra",
    "density",
    "friction",
    "cohesion",
    "liquid",
    "damping",
    "restitution",
    "gravity",
    "cgravity",
    "velocity",
    "fix",
    "fro",
    "zero",
    "always",
    "fraction",
    "auto",
    "agglomerate",
    "age",
    "rge",
    "seed",
    "relax",
    "move",
    "window",
    "help",
    "new",
    "reset",
    "tol",
    "xres",
    "smin",
    "tunnel",
    "delete",
    "stop",
    "open",
    "periodic",
    "all",
    "x",
    "y",
    "z",
    "p",
    "sp",
    "ob",
    "v",
    "m",
    "se",
    "info",
    "balls",
    "energy",
    "walls",
    "contacts",
    "bonds",
    "clusters",
    "history",
    "entries",
    "settings",
    "bridge",
    "laplace",
    "toroidal",
    "fit",
    "tangential",
    "md",
    "noslip",
    "conserve",
    "genoverlap",
    "snapshot",
    "goldman",
    "wallbridges",
    "on",
    "off",
    "grid",
    "gain",
    "mode",
    "probe",
    "vtk",
    "field",
    "raw",
    "csv",
    "average",
    "arrays",
    "velocity",
    "bin",
    "in",
    "iset",
    "rset",
    "vmu",
    "fmm",
    "twod",
    "group",
    "dynamic",
    "forget",
    "box",
    "sphere",
    "cylinder",
    "id",
    "to",
    "material",
    "size",
    "not",
    "or",
    "range",
    "property",
    "spin",
    "let",
    "x",
    "=",
    "if",
    "else",
    "end",
    "loop",
    "while",
    "define",
    "call",
    "return",
    "break",
    "include",
    "show",
    "until",
    "every",
    "[x*2]",
    "[1/0",
    "2*x",
    "-x",
    "[ball_vz(1)]",
    "[energy.kinetic]",
    "[sqrt(-1)]",
    "[((((((((1",
    "$x",
];

/// A mutated line or file from `seed`.
fn mutate_text(r: &mut Rng, seed: &str) -> String {
    let mut lines: Vec<String> = seed.lines().map(str::to_string).collect();
    if lines.is_empty() {
        lines.push(String::new());
    }
    for _ in 0..1 + r.below(4) {
        let k = r.below(lines.len());
        match r.below(9) {
            // A word replaced by an extreme value or a keyword.
            0 | 1 => {
                let mut words: Vec<String> =
                    lines[k].split_whitespace().map(str::to_string).collect();
                if !words.is_empty() {
                    let w = r.below(words.len());
                    words[w] = if r.below(2) == 0 {
                        r.pick(EXTREME).to_string()
                    } else {
                        r.pick(WORDS).to_string()
                    };
                }
                lines[k] = words.join(" ");
            }
            // A word inserted, or dropped.
            2 => {
                let mut words: Vec<String> =
                    lines[k].split_whitespace().map(str::to_string).collect();
                let at = r.below(words.len() + 1);
                let w = if r.below(2) == 0 {
                    *r.pick(EXTREME)
                } else {
                    *r.pick(WORDS)
                };
                words.insert(at, w.to_string());
                lines[k] = words.join(" ");
            }
            3 => {
                let mut words: Vec<&str> = lines[k].split_whitespace().collect();
                if !words.is_empty() {
                    let w = r.below(words.len());
                    words.remove(w);
                }
                lines[k] = words.join(" ");
            }
            // A line duplicated, dropped, or two joined.
            4 => {
                let l = lines[k].clone();
                lines.insert(r.below(lines.len() + 1), l);
            }
            5 => {
                lines.remove(k);
                if lines.is_empty() {
                    lines.push(String::new());
                }
            }
            6 => {
                let j = r.below(lines.len());
                let joined = format!("{} {}", lines[k], lines[j]);
                lines[k] = joined;
            }
            // A byte-level change within the line.
            7 => {
                let mut b = lines[k].clone().into_bytes();
                if !b.is_empty() {
                    let at = r.below(b.len());
                    b[at] = (r.next() & 0x7f) as u8;
                }
                lines[k] = String::from_utf8_lossy(&b).into_owned();
            }
            // A line cut short.
            _ => {
                let l = &lines[k];
                let cut = r.below(l.len() + 1);
                let cut = (0..=cut)
                    .rev()
                    .find(|&c| l.is_char_boundary(c))
                    .unwrap_or(0);
                lines[k] = l[..cut].to_string();
            }
        }
    }
    lines.join("\n")
}

/// Whether running `c` in-process would be slow or touch files (the binary-level fuzz test
/// and the checkpoint tests cover those): long cycles, large generations, file commands.
fn skipped(c: &Command) -> bool {
    match c {
        Command::Cycle { n, .. } => *n > 200,
        Command::Script(ScriptCmd::Cycle { n, .. }) => *n > 200,
        Command::Script(ScriptCmd::Include { .. }) => true,
        Command::Relax { nmax, .. } => *nmax > 200,
        Command::Start { nball, .. } => *nball > 2000,
        Command::Rgenerate { n, .. } => *n > 500,
        Command::RgenerateSeed { n } => *n > 100_000,
        Command::Save { .. }
        | Command::Restart { .. }
        | Command::Plot { .. }
        | Command::Vtk { .. }
        | Command::Field {
            prefix: Some(_), ..
        }
        | Command::Field { csv: true, .. }
        | Command::Log { .. }
        | Command::Set(trubal::lang::command::Setting::OutDir(_)) => true,
        _ => false,
    }
}

/// Runs a mutated command file in a session (each line parsed first; lines with a skipped
/// command are left out).
fn run_session(text: &str) {
    let mut s = crate::common::session_with(Box::new(std::io::sink()), false)
        .with_diagnostics(Box::new(std::io::sink()));
    s.vars.insert("v".into(), "1".into());
    for line in text.lines().take(60) {
        if let Ok(parsed) = parse_line(line)
            && parsed.iter().any(|p| skipped(&p.command))
        {
            continue;
        }
        let _ = s.run_line(line);
    }
}

fn inputs() -> usize {
    std::env::var("TRUBAL_FUZZ_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100_000)
}

fn corpus() -> Vec<String> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/commands");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let seeds: Vec<String> = files
        .iter()
        .map(|f| String::from_utf8_lossy(&std::fs::read(f).unwrap()).into_owned())
        .collect();
    assert!(seeds.len() >= 10, "the corpus is in {}", dir.display());
    seeds
}

fn report(target: &str, k: usize, input: &[u8]) -> String {
    let path = std::env::temp_dir().join(format!("trubal-fuzz-{target}-{k}"));
    let _ = std::fs::write(&path, input);
    format!(
        "{target}: input {k} panicked; written to {}",
        path.display()
    )
}

/// The parser and the session: lines and short files mutated from the corpus.
#[test]
fn mutated_command_files_never_panic() {
    let seeds = corpus();
    let n = inputs() * 6 / 10;
    let mut r = Rng(0x9e37_79b9_7f4a_7c15);
    let t0 = std::time::Instant::now();
    let mut sessions = 0;
    for k in 0..n {
        let seed = r.pick(&seeds);
        let text = mutate_text(&mut r, seed);
        // Most inputs through the parser alone (cheap), one in eight as a file in a session.
        let result = if k % 8 == 0 {
            sessions += 1;
            // (A short run: the first lines of a seed, mutated.)
            let short: String = text
                .lines()
                .take(4 + r.below(20))
                .collect::<Vec<_>>()
                .join("\n");
            catch_unwind(AssertUnwindSafe(|| run_session(&short)))
        } else {
            catch_unwind(AssertUnwindSafe(|| {
                for line in text.lines() {
                    let _ = parse_line(line);
                }
            }))
        };
        if result.is_err() {
            panic!("{}", report("commands", k, text.as_bytes()));
        }
    }
    eprintln!(
        "commands: {n} inputs ({sessions} run in a session) in {:.1} s, no panic",
        t0.elapsed().as_secs_f64()
    );
}

/// The checkpoint reader: the fixtures of every version with bytes flipped, inserted, cut
/// and duplicated, half of them with the header's length and checksum recomputed so that the
/// decoder reads the damage.
#[test]
fn damaged_checkpoints_never_panic() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let mut fixtures: Vec<Vec<u8>> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "sav"))
        .map(|p| std::fs::read(p).unwrap())
        .collect();
    fixtures.sort();
    assert!(fixtures.len() >= 3);
    let n = inputs() * 4 / 10;
    let mut r = Rng(0xd1b5_4a32_d192_ed03);
    let t0 = std::time::Instant::now();
    let mut loaded = 0;
    for k in 0..n {
        let mut d = r.pick(&fixtures).clone();
        for _ in 0..1 + r.below(3) {
            let len = d.len();
            match r.below(6) {
                0 | 1 => {
                    let at = r.below(len);
                    d[at] ^= 1 << r.below(8);
                }
                2 => {
                    let at = r.below(len);
                    d[at] = (r.next() & 0xff) as u8;
                }
                3 => {
                    let at = HEADER + r.below(len.saturating_sub(HEADER));
                    d.truncate(at);
                }
                4 => {
                    let at = r.below(len + 1);
                    d.insert(at.min(d.len()), (r.next() & 0xff) as u8);
                }
                _ => {
                    // Eight bytes of a float set to an extreme value.
                    let at = HEADER + r.below(len.saturating_sub(HEADER + 8));
                    let v =
                        *r.pick(&[f64::NAN, f64::INFINITY, -1.0, 0.0, 1e300, f64::MIN_POSITIVE]);
                    if at + 8 <= d.len() {
                        d[at..at + 8].copy_from_slice(&v.to_le_bytes());
                    }
                }
            }
        }
        if k % 2 == 0 && d.len() >= HEADER {
            // Recompute the length and checksum over what follows the header.
            let payload = d[HEADER..].to_vec();
            d[12..20].copy_from_slice(&(payload.len() as u64).to_le_bytes());
            d[20..28].copy_from_slice(&fnv1a(&payload).to_le_bytes());
        }
        match catch_unwind(AssertUnwindSafe(|| from_bytes(&d))) {
            Ok(Ok(sc)) => {
                loaded += 1;
                // What loads is consistent and can be cycled or is refused before cycling.
                let ok = catch_unwind(AssertUnwindSafe(|| {
                    let mut sc = sc;
                    if let Ok(model) = trubal::sim::params::build(&sc) {
                        assert!(model.dt.is_finite() || sc.particles().is_empty());
                    }
                    let _ = trubal::sim::cycle::run(&mut sc, 2);
                }));
                if ok.is_err() {
                    panic!("{}", report("checkpoint-cycle", k, &d));
                }
            }
            Ok(Err(e)) => assert!(!e.is_empty()),
            Err(_) => panic!("{}", report("checkpoint", k, &d)),
        }
    }
    eprintln!(
        "checkpoints: {n} inputs in {:.1} s, {loaded} loaded (damage within plausible values), no panic",
        t0.elapsed().as_secs_f64()
    );
}
