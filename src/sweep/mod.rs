//! `trubal sweep`: a command file with `$name` parameters and a table of values (grids,
//! rows of a CSV file, shared and computed values) → runs with stable names, run on a local
//! pool or as a SLURM job array, resumable, with what they printed gathered into a CSV file
//! and a chart. doc/sweeps.md describes the design and the file formats.
//!
//! - [`spec`]: the options, from the command line and from a sweep file;
//! - [`expand`]: the runs and every check of the parameters against the command file;
//! - [`expr`]: the arithmetic of `--let`;
//! - [`store`]: the sweep directory (manifest, run directories, status, lock): resumability;
//! - [`pool`]: the local pool with its progress line; [`slurm`]: job scripts and `sbatch`;
//! - [`collect`]: results.csv; [`chart`]: the PNG chart.
//!
//! Nothing here is part of the simulation: each run is the `trubal` binary itself, started
//! with `--json --set NAME=VALUE ...` in the run's directory.

pub mod chart;
pub mod collect;
pub mod expand;
pub mod expr;
pub mod pool;
pub mod slurm;
pub mod spec;
pub mod store;

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use collect::{ChartSpec, Measure};
use expand::{Inputs, Plan, Text};
use spec::{Mode, Spec, USAGE};
use store::{Lock, Manifest, Script, Store};

macro_rules! say {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}
macro_rules! complain {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stderr(), $($t)*);
    }};
}

/// `trubal sweep ARGS`.
pub fn main(args: &[String]) -> ExitCode {
    if args.iter().any(|a| a == "--help" || a == "-h") {
        say!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let spec = match Spec::from_args(args) {
        Ok(s) => s,
        Err(errors) => {
            for e in errors {
                complain!("trubal sweep: {e}");
            }
            complain!("(trubal sweep --help shows the options)");
            return ExitCode::from(2);
        }
    };
    let r = match spec.mode {
        Mode::Task | Mode::TaskPrepare => task(&spec),
        Mode::Collect if spec.file.is_none() => collect_only(&spec),
        _ => sweep(&spec),
    };
    match r {
        Ok(code) => code,
        Err(errors) => {
            for e in errors {
                complain!("trubal sweep: {e}");
            }
            ExitCode::from(2)
        }
    }
}

fn one<T>(r: Result<T, String>) -> Result<T, Vec<String>> {
    r.map_err(|e| vec![e])
}

fn read_text(path: &Path, what: &str) -> Result<Text, String> {
    std::fs::read_to_string(path)
        .map(|text| Text {
            shown: path.display().to_string(),
            text,
        })
        .map_err(|e| format!("cannot read the {what} {}: {e}", path.display()))
}

fn script_of(path: &Path, text: &Text) -> Script {
    Script {
        name: path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep.tru".into()),
        source: std::fs::canonicalize(path)
            .unwrap_or_else(|_| path.to_path_buf())
            .display()
            .to_string(),
        text: text.text.clone(),
    }
}

/// Reads the files, expands the runs, checks the measures and charts: everything that can be
/// wrong is found here, before anything is written or run.
fn plan(spec: &Spec) -> Result<(Plan, Manifest), Vec<String>> {
    // (Invariant: `Spec::from_args` refuses a sweep without a command file; only the
    // internal task and collect modes have none, and they do not plan.)
    let file = spec.file.as_ref().expect("a command file");
    let mut errors = Vec::new();
    let script = read_text(file, "command file")
        .map_err(|e| errors.push(e))
        .ok();
    let prepare = spec.prepare.as_ref().and_then(|p| {
        read_text(&p.value, "prepare file")
            .map_err(|e| errors.push(e))
            .ok()
    });
    let rows = spec.rows.as_ref().and_then(|p| {
        read_text(&p.value, "rows file")
            .map_err(|e| errors.push(e))
            .ok()
    });
    let Some(script) = script else {
        return Err(errors);
    };
    if let (Some(p), Some(pt)) = (&spec.prepare, &prepare)
        && p.value.file_name() == file.file_name()
    {
        errors.push(format!(
            "the prepare file {} and the command file have the same name: rename one",
            pt.shown
        ));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let inputs = Inputs {
        script: script.clone(),
        prepare: prepare.clone(),
        rows,
    };
    let plan = expand::expand(spec, &inputs)?;
    let mut measures = Vec::new();
    for m in &spec.measures {
        match Measure::parse(&m.value) {
            Ok(x) => measures.push(x),
            Err(e) => errors.push(format!("{}: {e}", m.origin)),
        }
    }
    for c in &spec.charts {
        match ChartSpec::parse(&c.value) {
            Ok(ch) => {
                let known = |n: &str| plan.params.iter().chain(&plan.lets).any(|p| p == n);
                for axis in std::iter::once(&ch.x).chain(ch.group.as_ref()) {
                    if !known(axis) {
                        errors.push(format!(
                            "{}: --chart {}: `{axis}` is not a parameter of the sweep ({})",
                            c.origin,
                            c.value,
                            plan.params
                                .iter()
                                .chain(&plan.lets)
                                .cloned()
                                .collect::<Vec<_>>()
                                .join(", ")
                        ));
                    }
                }
                if known(&ch.x)
                    && let Some(r) = plan.runs.iter().find(|r| {
                        crate::lang::lexer::parse_real(r.get(&ch.x).unwrap_or("")).is_none()
                    })
                {
                    errors.push(format!(
                        "{}: --chart {}: `{}` = `{}` (run {}) is not a number",
                        c.origin,
                        c.value,
                        ch.x,
                        r.get(&ch.x).unwrap_or(""),
                        r.name
                    ));
                }
                if !measures.is_empty()
                    && !measures.iter().any(|m| m.column == ch.y)
                    && !known(&ch.y)
                    && ch.y != "wall_s"
                {
                    errors.push(format!(
                        "{}: --chart {}: `{}` is not one of the --measure columns ({})",
                        c.origin,
                        c.value,
                        ch.y,
                        measures
                            .iter()
                            .map(|m| m.column.clone())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
            }
            Err(e) => errors.push(format!("{}: {e}", c.origin)),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut m = Manifest::new(
        script_of(file, &script),
        spec.prepare
            .as_ref()
            .zip(prepare.as_ref())
            .map(|(p, t)| script_of(&p.value, t)),
        spec.sets.iter().map(|s| s.value.clone()).collect(),
        spec.lets.iter().map(|s| s.value.clone()).collect(),
        plan.params.clone(),
        plan.lets.clone(),
        plan.runs.clone(),
    );
    m.threads = spec.run_threads();
    m.measures = spec.measures.iter().map(|x| x.value.clone()).collect();
    m.charts = spec.charts.iter().map(|x| x.value.clone()).collect();
    m.logx = spec.logx;
    Ok((plan, m))
}

fn exe() -> Result<PathBuf, String> {
    std::env::current_exe()
        .and_then(std::fs::canonicalize)
        .map_err(|e| format!("cannot find the trubal binary itself: {e}"))
}

/// The checks of a directory that need no writing: another sweep, or other files.
fn check_dir(store: &Store, new: &Manifest) -> Result<Option<Manifest>, String> {
    match store.load()? {
        Some(old) => {
            let d = old.differences(new);
            if d.is_empty() {
                Ok(Some(old))
            } else {
                Err(format!(
                    "{} holds another sweep: {}; choose another --out, or delete it to start again",
                    store.dir.display(),
                    d.join("; ")
                ))
            }
        }
        None => match std::fs::read_dir(&store.dir).map(|e| e.count()) {
            Ok(n) if n > 0 => Err(format!(
                "{} is not empty and holds no sweep ({}); choose a new or empty directory",
                store.dir.display(),
                store::MANIFEST
            )),
            Ok(_) => Ok(None),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("cannot read {}: {e}", store.dir.display())),
        },
    }
}

fn sweep(spec: &Spec) -> Result<ExitCode, Vec<String>> {
    let (plan, manifest) = plan(spec)?;
    // (Invariant: `Spec::from_args` refuses a sweep without --out.)
    let out = spec.out.clone().expect("checked");
    let store = Store::new(&out);
    let existing = one(check_dir(&store, &manifest))?;
    if let Mode::Slurm { submit: true } = spec.mode {
        one(slurm::check_sbatch())?;
    }
    if spec.mode == Mode::DryRun {
        dry_run(&plan, &manifest, &store, existing.is_some());
        return Ok(ExitCode::SUCCESS);
    }
    let exe = one(exe())?;
    one(std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display())))?;
    let out = one(std::fs::canonicalize(&out).map_err(|e| format!("{}: {e}", out.display())))?;
    let store = Store::new(&out);
    let _lock = one(Lock::take(&store.dir))?;
    let active = slurm::active_jobs(&store);
    if !active.is_empty() && spec.mode != Mode::Collect {
        return Err(vec![format!(
            "the SLURM jobs {} of this sweep are still queued or running: wait for them (squeue) or cancel them (scancel) first",
            active.join(", ")
        )]);
    }
    let m = one(store.open(manifest))?;
    let todo: Vec<&expand::Run> = store.missing(&plan.runs);
    match spec.mode {
        Mode::Collect => Ok(report_collect(&store, &m)),
        Mode::Slurm { submit } => run_slurm(spec, &plan, &store, &m, &todo, &exe, submit),
        _ => run_local(spec, &plan, &store, &m, &todo, &exe),
    }
}

/// `--dry-run`: the runs and their values, which are finished.
fn dry_run(plan: &Plan, manifest: &Manifest, store: &Store, existing: bool) {
    let finished = |name: &str| existing && store.finished(name);
    let mut n_done = 0;
    for r in &plan.runs {
        let done = finished(&r.name);
        n_done += done as usize;
        let values: Vec<String> = r.values.iter().map(|(k, v)| format!("{k}={v}")).collect();
        say!(
            "{}  {}{}",
            r.name,
            values.join(" "),
            if done { "  (finished)" } else { "" }
        );
    }
    say!(
        "{} runs of {}, {} finished, {} to run{}",
        plan.runs.len(),
        manifest.script.name,
        n_done,
        plan.runs.len() - n_done,
        if manifest.prepare.is_some() {
            " (after the prepare step)"
        } else {
            ""
        }
    );
}

/// `--slurm`: the job-array scripts written for the runs still to do, and submitted with
/// `--submit`.
fn run_slurm(
    spec: &Spec,
    plan: &Plan,
    store: &Store,
    m: &Manifest,
    todo: &[&expand::Run],
    exe: &std::path::Path,
    submit: bool,
) -> Result<ExitCode, Vec<String>> {
    let w = one(slurm::write(store, m, todo, &spec.slurm, spec.jobs, exe))?;
    let mut lines = Vec::new();
    for p in [&w.prepare, &w.array].into_iter().flatten() {
        lines.push(p.display().to_string());
    }
    lines.push(w.collect.display().to_string());
    say!(
        "{} runs, {} finished, {} to run; wrote {}",
        plan.runs.len(),
        plan.runs.len() - todo.len(),
        w.tasks,
        lines.join(", ")
    );
    if submit {
        let ids = one(slurm::submit(store, &w))?;
        for (what, id) in ids {
            say!("submitted {what}: job {id}");
        }
        say!(
            "results: {} (when the collect job has run)",
            store.dir.join("results.csv").display()
        );
    } else {
        say!(
            "submit with: sbatch PREPARE (if written), then sbatch --dependency=afterok:ID ARRAY, then sbatch --dependency=afterany:ID COLLECT; or run trubal sweep again with --submit"
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The local pool: the prepare step if any, then the runs still to do, `--jobs` at a time;
/// failures reported with their standard error, the others collected.
fn run_local(
    spec: &Spec,
    plan: &Plan,
    store: &Store,
    m: &Manifest,
    todo: &[&expand::Run],
    exe: &std::path::Path,
) -> Result<ExitCode, Vec<String>> {
    let terminal = std::io::stderr().is_terminal();
    if m.prepare.is_some() && !store.prepared() {
        complain!(
            "sweep: the prepare step ({}) ...",
            m.prepare.as_ref().map(|p| p.name.as_str()).unwrap_or("")
        );
        match store.prepare(m, exe) {
            Ok(Some(o)) if !o.status.ok() => {
                return Err(vec![format!(
                    "the prepare step failed ({}); no run started. Its standard error ({}):\n{}",
                    o.status
                        .exit
                        .map(|c| format!("exit {c}"))
                        .unwrap_or("killed".into()),
                    store.prepare_dir().join(store::STDERR).display(),
                    o.stderr_tail
                )]);
            }
            Ok(_) => {}
            Err(e) => return Err(vec![e]),
        }
    }
    let jobs = spec.jobs.unwrap_or_else(|| {
        let cores = std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1);
        (cores / m.threads).max(1)
    });
    complain!(
        "sweep: {} runs, {} finished, {} to run, {} at a time ({} thread{} each)",
        plan.runs.len(),
        plan.runs.len() - todo.len(),
        todo.len(),
        jobs.min(todo.len().max(1)),
        m.threads,
        if m.threads == 1 { "" } else { "s" }
    );
    let sum = pool::run(store, m, todo, jobs, exe, terminal);
    let code = report_collect(store, m);
    let failures = sum.failed.len() + sum.errors.len();
    for o in &sum.failed {
        complain!(
            "\nrun {} failed ({}); {}:\n{}",
            o.name,
            o.status
                .exit
                .map(|c| format!("exit {c}"))
                .unwrap_or("killed by a signal".into()),
            store.run_dir(&o.name).join(store::STDERR).display(),
            o.stderr_tail
        );
    }
    for (name, e) in &sum.errors {
        complain!("\nrun {name} could not run: {e}");
    }
    if failures > 0 {
        complain!(
            "\nsweep: {failures} of {} runs failed; the others are finished. Run the same command again to retry only the failed ones.",
            todo.len()
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(code)
}

/// Collects and says what was written.
fn report_collect(store: &Store, m: &Manifest) -> ExitCode {
    match collect::collect(store, m) {
        Ok(c) => {
            for n in &c.notes {
                complain!("sweep: {n}");
            }
            say!("{} runs, {} finished: {}", c.rows, c.ok, c.files.join(", "));
            ExitCode::SUCCESS
        }
        Err(e) => {
            complain!("trubal sweep: collecting failed: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The sweep already in `--out DIR`, as its manifest describes it.
fn existing_sweep(spec: &Spec) -> Result<(Store, Manifest), Vec<String>> {
    // (Invariant: `Spec::from_args` refuses a sweep without --out.)
    let out = spec.out.clone().expect("checked");
    let store = Store::new(&out);
    match one(store.load())? {
        Some(m) => Ok((store, m)),
        None => Err(vec![format!(
            "{} holds no sweep ({})",
            out.display(),
            store::MANIFEST
        )]),
    }
}

/// `--collect --out DIR` without a file: the sweep in DIR as its manifest describes it.
fn collect_only(spec: &Spec) -> Result<ExitCode, Vec<String>> {
    let (store, m) = existing_sweep(spec)?;
    let _lock = one(Lock::take(&store.dir))?;
    Ok(report_collect(&store, &m))
}

/// One SLURM array task, or the prepare job.
fn task(spec: &Spec) -> Result<ExitCode, Vec<String>> {
    let (store, m) = existing_sweep(spec)?;
    let exe = one(exe())?;
    let (name, r) = if spec.mode == Mode::TaskPrepare {
        ("prepare".to_string(), store.prepare(&m, &exe))
    } else {
        let list = spec
            .list
            .clone()
            .ok_or_else(|| vec!["--task needs --list FILE".to_string()])?;
        let run = one(slurm::task_run(&m, &list))?;
        (run.name.clone(), store.run(&m, run, &exe))
    };
    match one(r)? {
        None => {
            say!("{name}: already finished");
            Ok(ExitCode::SUCCESS)
        }
        Some(o) if o.status.ok() => {
            say!(
                "{name}: finished in {} s on {}",
                o.status.wall_s,
                o.status.host
            );
            Ok(ExitCode::SUCCESS)
        }
        Some(o) => {
            complain!(
                "{name}: failed ({}) on {}:\n{}",
                o.status
                    .exit
                    .map(|c| format!("exit {c}"))
                    .unwrap_or("killed".into()),
                o.status.host,
                o.stderr_tail
            );
            Ok(ExitCode::FAILURE)
        }
    }
}
