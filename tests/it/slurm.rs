//! `trubal sweep --submit` through a real SLURM: tests/slurm/cluster.sh installs Debian's
//! slurm-wlm and munge (when missing) and starts a one-node cluster on this machine with a
//! configuration of its own in a temporary directory; a small sweep with a prepare step is
//! submitted as a job array, waited for, and its results.csv checked; then one run is
//! "lost" and the resubmission runs only that one.
//!
//! Runs when the tests run as root with apt-get (as CI does); elsewhere it says why it is
//! skipped.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::sweep::{PREPARE, RUN, cell, kinetic, results, tmp};

fn root_dir() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Stops the cluster's daemons however the test ends.
struct Cluster {
    dir: PathBuf,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(root_dir().join("tests/slurm/cluster.sh"))
            .arg("stop")
            .arg(&self.dir)
            .status();
    }
}

fn is_root() -> bool {
    fs::read_to_string("/proc/self/status")
        .map(|s| {
            s.lines()
                .find(|l| l.starts_with("Uid:"))
                .and_then(|l| l.split_whitespace().nth(1).map(|u| u == "0"))
                .unwrap_or(false)
        })
        .unwrap_or(false)
}

/// The job ids a `--submit` printed (`submitted array: job 12`).
fn job_ids(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter_map(|l| l.strip_prefix("submitted "))
        .filter_map(|l| l.split_whitespace().last().map(String::from))
        .collect()
}

/// Waits until SLURM no longer lists the jobs.
fn wait(conf: &Path, ids: &[String], cluster: &Path) {
    let t0 = Instant::now();
    loop {
        let o = Command::new("squeue")
            .env("SLURM_CONF", conf)
            .args(["-h", "-o", "%i %T", "-j", &ids.join(",")])
            .output()
            .unwrap();
        let listed = String::from_utf8_lossy(&o.stdout).trim().to_string();
        if o.status.success() && listed.is_empty() {
            return;
        }
        if t0.elapsed() > Duration::from_secs(120) {
            let logs = Command::new("sh")
                .arg("-c")
                .arg(format!("tail -n 30 {}/log/*.log", cluster.display()))
                .output()
                .unwrap();
            panic!(
                "the jobs {ids:?} did not end in 120 s: {listed}\n{}",
                String::from_utf8_lossy(&logs.stdout)
            );
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn submit(d: &Path, conf: &Path, args: &[&str]) -> (String, String) {
    let o = crate::common::trubal()
        .arg("sweep")
        .args(args)
        .env("SLURM_CONF", conf)
        .current_dir(d)
        .output()
        .unwrap();
    let (out, err) = (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    );
    assert!(o.status.success(), "{out}\n{err}");
    (out, err)
}

#[test]
fn a_sweep_runs_as_a_slurm_job_array_and_resubmits_only_what_is_missing() {
    if !is_root() {
        eprintln!(
            "slurm::a_sweep_runs_as_a_slurm_job_array: SKIPPED: not root (installing and starting SLURM needs root; CI runs as root)"
        );
        return;
    }
    let script = root_dir().join("tests/slurm/cluster.sh");
    let install = Command::new(&script).arg("install").output().unwrap();
    if install.status.code() == Some(3) {
        eprintln!(
            "slurm::a_sweep_runs_as_a_slurm_job_array: SKIPPED: {}",
            String::from_utf8_lossy(&install.stderr).trim()
        );
        return;
    }
    assert!(
        install.status.success(),
        "installing SLURM failed: {}",
        String::from_utf8_lossy(&install.stderr)
    );
    let d = tmp("slurm");
    let cdir = d.join("cluster");
    let start = Command::new(&script)
        .arg("start")
        .arg(&cdir)
        .output()
        .unwrap();
    let _cluster = Cluster { dir: cdir.clone() };
    assert!(
        start.status.success(),
        "the one-node cluster did not start: {}",
        String::from_utf8_lossy(&start.stderr)
    );
    let conf = cdir.join("slurm.conf");

    fs::write(d.join("prep.tru"), PREPARE).unwrap();
    fs::write(d.join("pair.tru"), RUN).unwrap();
    let args = [
        "pair.tru",
        "--prepare",
        "prep.tru",
        "--set",
        "state=prepared.sav",
        "--set",
        "n=10",
        "--grid",
        "v=0.5,1,2",
        "--out",
        "out",
        "--submit",
        "--time",
        "0:05:00",
        "--measure",
        "ke=energy.kinetic",
        "--chart",
        "ke:v",
    ];
    let (out, _) = submit(&d, &conf, &args);
    let ids = job_ids(&out);
    assert_eq!(ids.len(), 3, "prepare, array, collect: {out}");
    wait(&conf, &ids, &cdir);
    let o = d.join("out");
    let rows = results(&o.join("results.csv"));
    assert_eq!(rows.len(), 3);
    for (row, v) in rows.iter().zip([0.5, 1.0, 2.0]) {
        assert_eq!(cell(row, "status"), "ok", "{rows:?}");
        let ke: f64 = cell(row, "ke").parse().unwrap();
        assert!((ke - kinetic(v)).abs() <= 1e-12 * kinetic(v));
    }
    assert!(o.join("ke_vs_v.png").exists());
    let logs: Vec<_> = fs::read_dir(o.join("slurm/logs")).unwrap().collect();
    assert_eq!(logs.len(), 5, "prepare, three tasks, collect");

    // Half the array "crashed": run v1 left no status. The resubmission runs only v1 (no
    // prepare job), and the finished runs stay as they were.
    fs::remove_file(o.join("runs/v1/status.json")).unwrap();
    fs::remove_file(o.join("results.csv")).unwrap();
    let before = fs::read(o.join("runs/v2/output.jsonl")).unwrap();
    let t_before = fs::metadata(o.join("runs/v2/status.json"))
        .unwrap()
        .modified()
        .unwrap();
    let (out, _) = submit(&d, &conf, &args);
    assert!(out.contains("3 runs, 2 finished, 1 to run"), "{out}");
    let ids = job_ids(&out);
    assert_eq!(ids.len(), 2, "array, collect: {out}");
    assert_eq!(
        fs::read_to_string(o.join("slurm/tasks.2.txt")).unwrap(),
        "v1\n"
    );
    wait(&conf, &ids, &cdir);
    let rows = results(&o.join("results.csv"));
    assert!(rows.iter().all(|r| cell(r, "status") == "ok"), "{rows:?}");
    assert_eq!(fs::read(o.join("runs/v2/output.jsonl")).unwrap(), before);
    assert_eq!(
        fs::metadata(o.join("runs/v2/status.json"))
            .unwrap()
            .modified()
            .unwrap(),
        t_before
    );
    drop(_cluster);
    let _ = fs::remove_dir_all(&d);
}
