//! The sweep's directory and what makes it resumable and safe.
//!
//! ```text
//! DIR/sweep.json          the manifest: the sweep's definition and its runs
//! DIR/FILE.tru            the command file as it was when the sweep started (the runs read this copy)
//! DIR/prepare/            the prepare step's directory (with DIR/PREPARE.tru, its copy)
//! DIR/runs/NAME/          one run: its working directory, output.jsonl (the --json output),
//!                         stderr.txt, status.json (written last: exit code, seconds, host)
//! DIR/results.csv, DIR/*.png   what --collect gathers
//! DIR/slurm/              the job scripts, the task lists, the submitted job ids, the task logs
//! ```
//!
//! A run is finished when its `status.json` says exit 0; a finished run is never run again and
//! nothing in its directory is written again. An unfinished run's directory (a failure, or a
//! run killed half-way) is cleared before the run starts again.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use super::expand::Run;

pub const MANIFEST: &str = "sweep.json";
const FORMAT: u32 = 1;
/// Files of a run directory written by the sweep, not by the command file.
pub const OUTPUT: &str = "output.jsonl";
pub const STDERR: &str = "stderr.txt";
pub const STATUS: &str = "status.json";

/// A command file kept in the sweep directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Script {
    /// Its file name in DIR (the original's name).
    pub name: String,
    /// Where it was read from (information only: the runs read the copy).
    pub source: String,
    pub text: String,
}

/// DIR/sweep.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: u32,
    pub script: Script,
    pub prepare: Option<Script>,
    pub sets: Vec<(String, String)>,
    pub lets: Vec<(String, String)>,
    pub params: Vec<String>,
    pub let_names: Vec<String>,
    /// Every run ever expanded into this directory, in order.
    pub runs: Vec<Run>,
    pub threads: usize,
    pub measures: Vec<String>,
    pub charts: Vec<String>,
    pub logx: bool,
}

impl Manifest {
    pub fn new(
        script: Script,
        prepare: Option<Script>,
        sets: Vec<(String, String)>,
        lets: Vec<(String, String)>,
        params: Vec<String>,
        let_names: Vec<String>,
        runs: Vec<Run>,
    ) -> Manifest {
        Manifest {
            format: FORMAT,
            script,
            prepare,
            sets,
            lets,
            params,
            let_names,
            runs,
            threads: 1,
            measures: Vec::new(),
            charts: Vec::new(),
            logx: false,
        }
    }

    /// What makes two sweeps different (the same run name would not give the same result):
    /// the command files' text, the `--set` values, the `--let` expressions, the parameters.
    /// Empty when they are the same sweep.
    pub fn differences(&self, other: &Manifest) -> Vec<String> {
        let mut d = Vec::new();
        if self.script.text != other.script.text {
            d.push(format!("the command file {} differs", self.script.name));
        }
        if self.prepare.as_ref().map(|p| &p.text) != other.prepare.as_ref().map(|p| &p.text) {
            d.push("the prepare file differs".into());
        }
        if self.sets != other.sets {
            d.push(format!(
                "the --set values differ ({} there, {} here)",
                show(&self.sets),
                show(&other.sets)
            ));
        }
        if self.lets != other.lets {
            d.push(format!(
                "the --let values differ ({} there, {} here)",
                show(&self.lets),
                show(&other.lets)
            ));
        }
        if self.params != other.params {
            d.push(format!(
                "the parameters differ ({} there, {} here)",
                self.params.join(","),
                other.params.join(",")
            ));
        }
        d
    }
}

fn show(kv: &[(String, String)]) -> String {
    if kv.is_empty() {
        return "none".into();
    }
    kv.iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes a file whole or not at all (a temporary file renamed).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let tmp = path.with_extension(format!(
        "{}.tmp{}",
        path.extension().and_then(|e| e.to_str()).unwrap_or(""),
        std::process::id()
    ));
    let r = fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|_| f.sync_all()))
        .and_then(|_| fs::rename(&tmp, path));
    r.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        format!("cannot write {}: {e}", path.display())
    })
}

/// The sweep directory.
#[derive(Clone, Debug)]
pub struct Store {
    pub dir: PathBuf,
}

/// How one run ended (status.json).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Status {
    /// The exit code; None when a signal ended it.
    pub exit: Option<i32>,
    pub wall_s: f64,
    pub host: String,
    /// Seconds since 1970 when it ended.
    pub ended: u64,
}

impl Status {
    pub fn ok(&self) -> bool {
        self.exit == Some(0)
    }
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Outcome {
    pub name: String,
    pub status: Status,
    /// The end of its standard error (for a failure).
    pub stderr_tail: String,
}

impl Store {
    pub fn new(dir: &Path) -> Store {
        Store {
            dir: dir.to_path_buf(),
        }
    }

    pub fn manifest_path(&self) -> PathBuf {
        self.dir.join(MANIFEST)
    }

    pub fn run_dir(&self, name: &str) -> PathBuf {
        self.dir.join("runs").join(name)
    }

    pub fn prepare_dir(&self) -> PathBuf {
        self.dir.join("prepare")
    }

    /// The manifest, if the directory holds a sweep.
    pub fn load(&self) -> Result<Option<Manifest>, String> {
        let p = self.manifest_path();
        let text = match fs::read_to_string(&p) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(format!("cannot read {}: {e}", p.display())),
        };
        let m: Manifest = serde_json::from_str(&text).map_err(|e| {
            format!(
                "{} is not a sweep manifest of this trubal: {e}",
                p.display()
            )
        })?;
        if m.format != FORMAT {
            return Err(format!(
                "{} has format {}; this trubal reads format {FORMAT}",
                p.display(),
                m.format
            ));
        }
        Ok(Some(m))
    }

    /// Opens the directory for this sweep: creates it, or checks that it holds the same
    /// sweep and adds the new runs. Refuses a directory holding another sweep or other files.
    pub fn open(&self, new: Manifest) -> Result<Manifest, String> {
        let merged = match self.load()? {
            Some(old) => {
                let d = old.differences(&new);
                if !d.is_empty() {
                    return Err(format!(
                        "{} holds another sweep: {}; choose another --out, or delete it to start again",
                        self.dir.display(),
                        d.join("; ")
                    ));
                }
                let mut m = old;
                for r in new.runs {
                    match m.runs.iter().find(|o| o.name == r.name) {
                        Some(o) if o.values != r.values => {
                            return Err(format!(
                                "{}: the run {} is there with other values; choose another --out",
                                self.dir.display(),
                                r.name
                            ));
                        }
                        Some(_) => {}
                        None => m.runs.push(r),
                    }
                }
                m.threads = new.threads;
                if !new.measures.is_empty() {
                    m.measures = new.measures;
                }
                if !new.charts.is_empty() {
                    m.charts = new.charts;
                    m.logx = new.logx;
                }
                m
            }
            None => {
                if let Ok(entries) = fs::read_dir(&self.dir)
                    && entries
                        .filter_map(|e| e.ok())
                        .any(|e| e.file_name() != ".lock")
                {
                    return Err(format!(
                        "{} is not empty and holds no sweep ({MANIFEST}); choose a new or empty directory",
                        self.dir.display()
                    ));
                }
                fs::create_dir_all(&self.dir)
                    .map_err(|e| format!("cannot create {}: {e}", self.dir.display()))?;
                new
            }
        };
        for s in std::iter::once(&merged.script).chain(merged.prepare.as_ref()) {
            let p = self.dir.join(&s.name);
            match fs::read_to_string(&p) {
                Ok(t) if t == s.text => {}
                Ok(_) => {
                    return Err(format!(
                        "{} differs from the sweep's command file: restore it or start a new sweep",
                        p.display()
                    ));
                }
                Err(_) => write_atomic(&p, s.text.as_bytes())?,
            }
        }
        self.save(&merged)?;
        Ok(merged)
    }

    pub fn save(&self, m: &Manifest) -> Result<(), String> {
        let text = serde_json::to_string_pretty(m).map_err(|e| e.to_string())?;
        write_atomic(&self.manifest_path(), text.as_bytes())
    }

    /// The status of a run directory (None: not finished, never ran, or killed).
    pub fn status_in(dir: &Path) -> Option<Status> {
        let t = fs::read_to_string(dir.join(STATUS)).ok()?;
        serde_json::from_str(&t).ok()
    }

    pub fn status(&self, name: &str) -> Option<Status> {
        Store::status_in(&self.run_dir(name))
    }

    pub fn finished(&self, name: &str) -> bool {
        self.status(name).is_some_and(|s| s.ok())
    }

    pub fn prepared(&self) -> bool {
        Store::status_in(&self.prepare_dir()).is_some_and(|s| s.ok())
    }

    /// The names of the runs not finished.
    pub fn missing<'a>(&self, runs: &'a [Run]) -> Vec<&'a Run> {
        runs.iter().filter(|r| !self.finished(&r.name)).collect()
    }

    /// The files the prepare step wrote (linked into every run's directory).
    fn prepared_files(&self) -> Vec<PathBuf> {
        let mut out: Vec<PathBuf> = fs::read_dir(self.prepare_dir())
            .map(|rd| {
                rd.filter_map(|e| e.ok())
                    .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
                    .map(|e| e.path())
                    .filter(|p| {
                        let n = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
                        ![OUTPUT, STDERR, STATUS].contains(&n)
                    })
                    .collect()
            })
            .unwrap_or_default();
        out.sort();
        out
    }

    /// Runs the prepare step (in DIR/prepare) unless it has finished.
    pub fn prepare(&self, m: &Manifest, exe: &Path) -> Result<Option<Outcome>, String> {
        let Some(p) = &m.prepare else {
            return Ok(None);
        };
        if self.prepared() {
            return Ok(None);
        }
        let o = self.execute(
            &self.prepare_dir(),
            "prepare",
            &self.dir.join(&p.name),
            &m.sets,
            m.threads,
            exe,
            &[],
        )?;
        Ok(Some(o))
    }

    /// Runs one run unless it has finished (None then).
    pub fn run(&self, m: &Manifest, run: &Run, exe: &Path) -> Result<Option<Outcome>, String> {
        if self.finished(&run.name) {
            return Ok(None);
        }
        let links = if m.prepare.is_some() {
            if !self.prepared() {
                return Err(format!(
                    "run {}: the prepare step has not finished ({})",
                    run.name,
                    self.prepare_dir().display()
                ));
            }
            self.prepared_files()
        } else {
            Vec::new()
        };
        self.execute(
            &self.run_dir(&run.name),
            &run.name,
            &self.dir.join(&m.script.name),
            &run.values,
            m.threads,
            exe,
            &links,
        )
        .map(Some)
    }

    /// `exe FILE --json --threads N --set k=v ...` in `dir` (cleared first: it holds no
    /// finished run), standard output to output.jsonl, standard error to stderr.txt, then
    /// status.json.
    #[allow(clippy::too_many_arguments)]
    fn execute(
        &self,
        dir: &Path,
        name: &str,
        file: &Path,
        values: &[(String, String)],
        threads: usize,
        exe: &Path,
        links: &[PathBuf],
    ) -> Result<Outcome, String> {
        if dir.exists() {
            fs::remove_dir_all(dir)
                .map_err(|e| format!("cannot clear {} for a new attempt: {e}", dir.display()))?;
        }
        fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        for src in links {
            let to = dir.join(src.file_name().unwrap_or_default());
            fs::hard_link(src, &to)
                .or_else(|_| fs::copy(src, &to).map(|_| ()))
                .map_err(|e| {
                    format!("cannot link {} into {}: {e}", src.display(), dir.display())
                })?;
        }
        let out = fs::File::create(dir.join(OUTPUT))
            .map_err(|e| format!("cannot write {}: {e}", dir.join(OUTPUT).display()))?;
        let err = fs::File::create(dir.join(STDERR))
            .map_err(|e| format!("cannot write {}: {e}", dir.join(STDERR).display()))?;
        let file = fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf());
        let mut cmd = Command::new(exe);
        cmd.arg(&file)
            .arg("--json")
            .arg("--threads")
            .arg(threads.to_string())
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(out)
            .stderr(err)
            .env_remove("RAYON_NUM_THREADS");
        for (k, v) in values {
            cmd.arg("--set").arg(format!("{k}={v}"));
        }
        let t0 = Instant::now();
        let exit = match cmd.status() {
            Ok(s) => s.code(),
            Err(e) => return Err(format!("cannot start {}: {e}", exe.display())),
        };
        let status = Status {
            exit,
            wall_s: (t0.elapsed().as_secs_f64() * 1000.0).round() / 1000.0,
            host: hostname(),
            ended: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0),
        };
        let text = serde_json::to_string(&status).map_err(|e| e.to_string())?;
        write_atomic(&dir.join(STATUS), text.as_bytes())?;
        Ok(Outcome {
            name: name.to_string(),
            stderr_tail: if status.ok() {
                String::new()
            } else {
                tail(&dir.join(STDERR), 12)
            },
            status,
        })
    }
}

/// The last `n` lines of a file.
pub fn tail(path: &Path, n: usize) -> String {
    let t = fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = t.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

pub fn hostname() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_default()
}

/// DIR/.lock: one `trubal sweep` at a time runs or collects in a directory.
pub struct Lock {
    path: PathBuf,
}

impl Lock {
    pub fn take(dir: &Path) -> Result<Lock, String> {
        let path = dir.join(".lock");
        for _ in 0..2 {
            match fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    let _ = write!(f, "{} {}", std::process::id(), hostname());
                    return Ok(Lock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let text = fs::read_to_string(&path).unwrap_or_default();
                    let mut w = text.split_whitespace();
                    let pid = w.next().unwrap_or("");
                    let host = w.next().unwrap_or("");
                    let alive = host == hostname()
                        && !pid.is_empty()
                        && Path::new("/proc").join(pid).exists();
                    if alive || (host != hostname() && !host.is_empty()) {
                        return Err(format!(
                            "{} is in use by another trubal sweep (process {pid} on {host}); if it is gone, delete {}",
                            dir.display(),
                            path.display()
                        ));
                    }
                    // A stale lock of a process that has gone.
                    let _ = fs::remove_file(&path);
                }
                Err(e) => return Err(format!("cannot write {}: {e}", path.display())),
            }
        }
        Err(format!("cannot take the lock {}", path.display()))
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.path);
    }
}
