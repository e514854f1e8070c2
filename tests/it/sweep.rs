//! `trubal sweep` on this machine: a small sweep with a prepare step runs, collects what the
//! runs printed, resumes after a partial failure without touching the finished runs; bad
//! input is refused before anything runs; the shipped sweeps of scripts/sweeps expand. The
//! SLURM path is in `slurm.rs`.

use std::fs;
use std::path::{Path, PathBuf};

/// A fresh temporary directory for one test.
pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trubal-sweep-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// The prepare step: the materials of two glass spheres (no particles yet), saved.
pub const PREPARE: &str = "start 0.2 0.1 0.1 1000 10 2\nset open all\nrad 0.01 1\nymd 4.8e10 1\n\
pra 0.2 1\ndensity 2800 1\nsave $state\n";

/// The run: two spheres 8 cm apart flying towards each other at $v for $n cycles (they do
/// not meet: 10 cycles of a few microseconds).
pub const RUN: &str = "; two spheres approach at $v each\nrestart \"$state\"\n\
create 0.05 0.05 0.05 $v 0 0 0 0 0 1 1\ncreate 0.15 0.05 0.05 -$v 0 0 0 0 0 1 1\ncycle $n\nprint info energy\n";

/// Kinetic energy of the two free spheres: 2 x m v^2 / 2, m = rho 4/3 pi R^3.
pub fn kinetic(v: f64) -> f64 {
    let m = 2800.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    m * v * v
}

pub struct Out {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

pub fn sweep(dir: &Path, args: &[&str]) -> Out {
    let o = crate::common::trubal()
        .arg("sweep")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    Out {
        code: o.status.code(),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

/// results.csv as rows of (column, value).
pub fn results(path: &Path) -> Vec<Vec<(String, String)>> {
    let text = fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

pub fn cell<'a>(row: &'a [(String, String)], col: &str) -> &'a str {
    row.iter()
        .find(|(k, _)| k == col)
        .map(|(_, v)| v.as_str())
        .unwrap_or_else(|| panic!("no column {col} in {row:?}"))
}

fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>, std::time::SystemTime)> {
    let mut out: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let meta = fs::metadata(&p).unwrap();
            (p.clone(), fs::read(&p).unwrap(), meta.modified().unwrap())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn a_local_sweep_runs_collects_and_resumes_after_a_partial_failure() {
    let d = tmp("local");
    fs::write(d.join("prep.tru"), PREPARE).unwrap();
    fs::write(d.join("pair.tru"), RUN).unwrap();
    // Run c restarts from a file that does not exist yet: it fails, the others go on.
    let late = d.join("late.sav");
    fs::write(
        d.join("rows.csv"),
        format!(
            "# three runs\nrun,v,state\na,0.5,prepared.sav\nb,1,prepared.sav\nc,2,{}\n",
            late.display()
        ),
    )
    .unwrap();
    let args = [
        "pair.tru",
        "--prepare",
        "prep.tru",
        "--rows",
        "rows.csv",
        "--set",
        "n=10",
        "--out",
        "out",
        "--jobs",
        "2",
        "--measure",
        "ke=energy.kinetic",
        "--measure",
        "balls=info.balls",
        "--chart",
        "ke:v",
    ];
    // `state` is a rows column and the prepare step reads $state: it gets only --set values.
    let bad = sweep(&d, &args);
    assert_eq!(bad.code, Some(2), "{}", bad.stderr);
    assert!(
        bad.stderr
            .contains("prep.tru:7:6: `$state`: the prepare file gets only the --set values"),
        "{}",
        bad.stderr
    );
    assert!(!d.join("out").exists());

    fs::write(
        d.join("prep.tru"),
        PREPARE.replace("$state", "prepared.sav"),
    )
    .unwrap();
    let first = sweep(&d, &args);
    assert_eq!(first.code, Some(1), "{}\n{}", first.stdout, first.stderr);
    assert!(
        first.stderr.contains("run c failed (exit 1)"),
        "{}",
        first.stderr
    );
    assert!(
        first.stderr.contains("late.sav"),
        "the failure shows its stderr: {}",
        first.stderr
    );
    let out = d.join("out");
    let rows = results(&out.join("results.csv"));
    assert_eq!(rows.len(), 3);
    for (row, v) in rows.iter().zip([0.5, 1.0]) {
        assert_eq!(cell(row, "status"), "ok");
        let ke: f64 = cell(row, "ke").parse().unwrap();
        assert!(
            (ke - kinetic(v)).abs() <= 1e-12 * kinetic(v),
            "{ke} against {}",
            kinetic(v)
        );
        assert_eq!(cell(row, "balls"), "2");
    }
    assert_eq!(cell(&rows[2], "status"), "failed (exit 1)");
    assert_eq!(cell(&rows[2], "ke"), "");
    // The prepared state is linked into every run's directory.
    assert!(out.join("runs/a/prepared.sav").exists());
    assert!(out.join("ke_vs_v.png").exists());

    // Fix the cause, and pretend run b was killed half-way (no status): only b and c run.
    fs::copy(out.join("prepare/prepared.sav"), &late).unwrap();
    fs::remove_file(out.join("runs/b/status.json")).unwrap();
    let a_before = snapshot(&out.join("runs/a"));
    let second = sweep(&d, &args);
    assert_eq!(second.code, Some(0), "{}\n{}", second.stdout, second.stderr);
    assert!(
        second.stderr.contains("3 runs, 1 finished, 2 to run"),
        "{}",
        second.stderr
    );
    assert!(
        !second.stderr.contains("prepare step"),
        "the prepare step ran again: {}",
        second.stderr
    );
    assert_eq!(
        snapshot(&out.join("runs/a")),
        a_before,
        "a finished run was written again"
    );
    let rows = results(&out.join("results.csv"));
    assert!(rows.iter().all(|r| cell(r, "status") == "ok"), "{rows:?}");
    let ke: f64 = cell(&rows[2], "ke").parse().unwrap();
    assert!((ke - kinetic(2.0)).abs() <= 1e-12 * kinetic(2.0));

    // Everything finished: nothing runs; --collect alone rebuilds the results.
    let third = sweep(&d, &args);
    assert_eq!(third.code, Some(0));
    assert!(
        third.stderr.contains("3 finished, 0 to run"),
        "{}",
        third.stderr
    );
    fs::remove_file(out.join("results.csv")).unwrap();
    let c = sweep(&d, &["--collect", "--out", "out"]);
    assert_eq!(c.code, Some(0), "{}", c.stderr);
    assert_eq!(results(&out.join("results.csv")), rows);
    let _ = fs::remove_dir_all(&d);
}

#[test]
fn grids_multiply_and_default_measures_take_every_number() {
    let d = tmp("grid");
    fs::write(d.join("prep.tru"), PREPARE).unwrap();
    fs::write(d.join("pair.tru"), RUN).unwrap();
    let o = sweep(
        &d,
        &[
            "pair.tru",
            "--prepare",
            "prep.tru",
            "--set",
            "state=p.sav",
            "--grid",
            "v=0.5,1",
            "--grid",
            "n=0,10",
            "--out",
            "g",
            "--jobs",
            "1",
        ],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let rows = results(&d.join("g/results.csv"));
    let names: Vec<&str> = rows.iter().map(|r| cell(r, "run")).collect();
    assert_eq!(names, ["v0.5_n0", "v0.5_n10", "v1_n0", "v1_n10"]);
    for r in &rows {
        let v: f64 = cell(r, "v").parse().unwrap();
        let ke: f64 = cell(r, "energy.kinetic").parse().unwrap();
        assert!((ke - kinetic(v)).abs() <= 1e-12 * kinetic(v));
        assert_eq!(cell(r, "energy.cycle"), cell(r, "n"));
        assert_eq!(cell(r, "info.balls"), "2");
    }
    // The same directory with other shared values is another sweep.
    let o = sweep(
        &d,
        &[
            "pair.tru",
            "--prepare",
            "prep.tru",
            "--set",
            "state=q.sav",
            "--grid",
            "v=0.5",
            "--grid",
            "n=0",
            "--out",
            "g",
        ],
    );
    assert_eq!(o.code, Some(2));
    assert!(
        o.stderr.contains(
            "holds another sweep: the --set values differ (state=p.sav there, state=q.sav here)"
        ),
        "{}",
        o.stderr
    );
    let _ = fs::remove_dir_all(&d);
}

#[test]
fn bad_input_is_refused_before_anything_runs() {
    let d = tmp("bad");
    fs::write(d.join("pair.tru"), RUN).unwrap();
    fs::create_dir_all(d.join("other")).unwrap();
    fs::write(d.join("other/notes.txt"), "mine").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "pair.tru",
                "--grid",
                "v=1",
                "--grid",
                "eta=0,0.01",
                "--set",
                "state=s",
                "--set",
                "n=1",
                "--out",
                "o",
            ],
            "--grid eta: pair.tru does not use `$eta`",
        ),
        (
            &[
                "pair.tru", "--grid", "v=1", "--set", "state=s", "--out", "o",
            ],
            "pair.tru:5:7: `$n` has no value in the sweep",
        ),
        (
            &[
                "pair.tru", "--grid", "v=", "--set", "state=s", "--set", "n=1", "--out", "o",
            ],
            "--grid v: the grid is empty",
        ),
        (
            &[
                "pair.tru", "--grid", "v=1,1", "--set", "state=s", "--set", "n=1", "--out", "o",
            ],
            "--grid v: `1` appears twice",
        ),
        (
            &[
                "pair.tru", "--grid", "v=1", "--set", "state=s", "--set", "n=1", "--out", "other",
            ],
            "other is not empty and holds no sweep",
        ),
        (
            &[
                "pair.tru", "--grid", "v=1", "--set", "state=s", "--set", "n=1", "--let", "w=2*v",
                "--out", "o",
            ],
            "--let w: pair.tru does not use `$w`",
        ),
        (
            &[
                "pair.tru", "--grid", "v=1", "--set", "state=s", "--set", "n=1", "--out", "o",
                "--chart", "ke:eta",
            ],
            "`eta` is not a parameter of the sweep",
        ),
        (
            &[
                "pair.tru",
                "--grid",
                "v=1",
                "--out",
                "o",
                "--dry-run",
                "--slurm",
            ],
            "give one",
        ),
        (
            &["nothere.tru", "--grid", "v=1", "--out", "o"],
            "cannot read the command file nothere.tru",
        ),
    ];
    for (args, want) in cases {
        let o = sweep(&d, args);
        assert_eq!(o.code, Some(2), "{args:?}: {}", o.stderr);
        assert!(
            o.stderr.contains(want),
            "{args:?}: wanted `{want}` in\n{}",
            o.stderr
        );
        assert!(!d.join("o").exists(), "{args:?} wrote the output directory");
    }
    assert_eq!(
        fs::read_to_string(d.join("other/notes.txt")).unwrap(),
        "mine"
    );
    // sbatch missing: refused before the directory is made.
    let o = crate::common::trubal()
        .args([
            "sweep", "pair.tru", "--grid", "v=1", "--set", "state=s", "--set", "n=1", "--out", "o",
            "--submit",
        ])
        .env("PATH", d.join("nothing-here"))
        .current_dir(&d)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("sbatch is missing"), "{err}");
    assert!(!d.join("o").exists());
    let _ = fs::remove_dir_all(&d);
}

#[test]
fn the_slurm_script_names_every_missing_run_once() {
    let d = tmp("script");
    fs::write(d.join("pair.tru"), RUN).unwrap();
    let o = sweep(
        &d,
        &[
            "pair.tru",
            "--grid",
            "v=0.5,1,2",
            "--set",
            "state=s.sav",
            "--set",
            "n=1",
            "--out",
            "s",
            "--slurm",
            "--partition",
            "short",
            "--time",
            "0:05:00",
            "--mem",
            "500M",
            "--cpus",
            "2",
            "--jobs",
            "2",
            "--sbatch=--account=abc",
        ],
    );
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    let s = d.join("s/slurm");
    let script = fs::read_to_string(s.join("sweep.1.sh")).unwrap();
    for line in [
        "#SBATCH --array=0-2%2",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --partition=short",
        "#SBATCH --time=0:05:00",
        "#SBATCH --mem=500M",
        "#SBATCH --account=abc",
        "sweep --task --out",
    ] {
        assert!(script.contains(line), "no `{line}` in\n{script}");
    }
    assert_eq!(
        fs::read_to_string(s.join("tasks.1.txt")).unwrap(),
        "v0.5\nv1\nv2\n"
    );
    let check = std::process::Command::new("bash")
        .arg("-n")
        .arg(s.join("sweep.1.sh"))
        .status()
        .unwrap();
    assert!(check.success());
    // The runs take 2 threads each (--cpus).
    let m: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(d.join("s/sweep.json")).unwrap()).unwrap();
    assert_eq!(m["threads"], 2);
    let _ = fs::remove_dir_all(&d);
}

#[test]
fn the_shipped_sweeps_expand() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let d = tmp("shipped");
    for (file, runs, params) in [
        ("lian6.sweep", 18, "v=2 eta=0.01 n=12500"),
        (
            "lian7.sweep",
            44,
            "v=2 theta=0 eta=0.1 gamma=0.025 n=50100 v1x=1 v1y=0 v2x=-1 v2y=0",
        ),
        ("timestep.sweep", 50, "tang=md frac=0.2 k=4 v=0.504 n=10016"),
        (
            "timestep_liquid.sweep",
            6,
            "bridge=laplace frac=0.05 n=40063",
        ),
        (
            "olsson_regime.sweep",
            16,
            "state=olsson_0.1.sav n=12500 v=5.2 smin=0.44e-6 law=nguyen",
        ),
    ] {
        let path = root.join("scripts/sweeps").join(file);
        let o = sweep(&d, &[path.to_str().unwrap(), "--out", "x", "--dry-run"]);
        assert_eq!(o.code, Some(0), "{file}: {}", o.stderr);
        assert!(
            o.stdout.contains(&format!("{runs} runs of")),
            "{file}: {}",
            o.stdout
        );
        let want: Vec<&str> = params.split(' ').collect();
        assert!(
            o.stdout
                .lines()
                .any(|l| want.iter().all(|w| l.split(' ').any(|x| x == *w))),
            "{file}: no run with {params} in\n{}",
            o.stdout
        );
        assert!(!d.join("x").exists());
    }
    let _ = fs::remove_dir_all(&d);
}
