//! SLURM: a job-array script for the runs not finished (one array task per run), and its
//! submission with `sbatch`: a job for the prepare step before it (`afterok`), one that
//! collects the results after it (`afterany`). Every task runs `trubal sweep --task`, which
//! does what the local pool does for one run, so a task whose run has finished in the
//! meantime does nothing, and a resubmission runs only what is missing.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use super::expand::Run;
use super::spec::Slurm;
use super::store::{Manifest, Store, write_atomic};

/// `sbatch` can be run (checked before anything is written).
pub fn check_sbatch() -> Result<(), String> {
    match Command::new("sbatch").arg("--version").output() {
        Ok(o) if o.status.success() => Ok(()),
        Ok(o) => Err(format!(
            "sbatch --version failed: {}",
            String::from_utf8_lossy(&o.stderr).trim()
        )),
        Err(e) => Err(format!(
            "sbatch is missing ({e}): --submit needs SLURM's sbatch on the PATH; without --submit the script is written for you to submit"
        )),
    }
}

fn slurm_dir(store: &Store) -> PathBuf {
    store.dir.join("slurm")
}

/// Single quotes for the shell.
fn quote(p: &Path) -> String {
    format!("'{}'", p.display().to_string().replace('\'', r"'\''"))
}

/// The jobs this sweep submitted that SLURM still lists (queued or running). Without
/// `squeue` nothing is known to be active.
pub fn active_jobs(store: &Store) -> Vec<String> {
    let Ok(text) = fs::read_to_string(slurm_dir(store).join("jobs")) else {
        return Vec::new();
    };
    let mut active = Vec::new();
    for id in text.lines().filter_map(|l| l.split_whitespace().last()) {
        if let Ok(o) = Command::new("squeue")
            .args(["-h", "-o", "%i", "-j", id])
            .output()
            && o.status.success()
            && !String::from_utf8_lossy(&o.stdout).trim().is_empty()
        {
            active.push(id.to_string());
        }
    }
    active
}

/// The scripts written for one submission.
pub struct Written {
    pub number: usize,
    pub prepare: Option<PathBuf>,
    pub array: Option<PathBuf>,
    pub collect: PathBuf,
    pub tasks: usize,
}

fn header(name: &str, s: &Slurm, cpus: usize, log: &Path) -> String {
    let mut t = String::from("#!/bin/bash\n");
    t.push_str(&format!("#SBATCH --job-name={name}\n"));
    t.push_str(&format!("#SBATCH --cpus-per-task={cpus}\n"));
    if let Some(p) = &s.partition {
        t.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    if let Some(p) = &s.time {
        t.push_str(&format!("#SBATCH --time={p}\n"));
    }
    if let Some(p) = &s.mem {
        t.push_str(&format!("#SBATCH --mem={p}\n"));
    }
    t.push_str(&format!("#SBATCH --output={}\n", log.display()));
    for x in &s.extra {
        t.push_str(&format!("#SBATCH {x}\n"));
    }
    t
}

/// Writes DIR/slurm/{prepare,sweep,collect}.K.sh and tasks.K.txt for the runs `todo`.
pub fn write(
    store: &Store,
    m: &Manifest,
    todo: &[&Run],
    s: &Slurm,
    jobs: Option<usize>,
    exe: &Path,
) -> Result<Written, String> {
    let dir = slurm_dir(store);
    let logs = dir.join("logs");
    fs::create_dir_all(&logs).map_err(|e| format!("cannot create {}: {e}", logs.display()))?;
    // (Invariant: the search is unbounded; finitely many files exist.)
    let number = (1..)
        .find(|k| !dir.join(format!("collect.{k}.sh")).exists())
        .expect("a free number");
    let cpus = s.cpus.unwrap_or(m.threads);
    let out = quote(&store.dir);
    let exe_q = quote(exe);
    let base = store
        .dir
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("sweep")
        .to_string();
    let mut written = Written {
        number,
        prepare: None,
        array: None,
        collect: dir.join(format!("collect.{number}.sh")),
        tasks: todo.len(),
    };
    if m.prepare.is_some() && !store.prepared() {
        let p = dir.join(format!("prepare.{number}.sh"));
        let mut t = header(
            &format!("trubal-prepare-{base}"),
            s,
            cpus,
            &logs.join("prepare_%j.out"),
        );
        t.push_str("# The prepare step of the sweep (trubal sweep wrote this file).\n");
        t.push_str(&format!("exec {exe_q} sweep --task-prepare --out {out}\n"));
        write_atomic(&p, t.as_bytes())?;
        written.prepare = Some(p);
    }
    if !todo.is_empty() {
        let list = dir.join(format!("tasks.{number}.txt"));
        let names: String = todo.iter().map(|r| format!("{}\n", r.name)).collect();
        write_atomic(&list, names.as_bytes())?;
        let p = dir.join(format!("sweep.{number}.sh"));
        let mut t = header(&format!("trubal-{base}"), s, cpus, &logs.join("%A_%a.out"));
        let throttle = jobs.map(|j| format!("%{j}")).unwrap_or_default();
        t.push_str(&format!("#SBATCH --array=0-{}{throttle}\n", todo.len() - 1));
        t.push_str(&format!(
            "# {} runs of {}, one per array task: task k runs the run on line k+1 of\n# {} (trubal sweep wrote this file; a finished run is never run again).\n",
            todo.len(),
            m.script.name,
            list.display()
        ));
        t.push_str(&format!(
            "exec {exe_q} sweep --task --out {out} --list {}\n",
            quote(&list)
        ));
        write_atomic(&p, t.as_bytes())?;
        written.array = Some(p);
    }
    let mut t = header(
        &format!("trubal-collect-{base}"),
        &Slurm {
            cpus: None,
            ..s.clone()
        },
        1,
        &logs.join("collect_%j.out"),
    );
    t.push_str("# Gathers the runs' results into results.csv and the charts (trubal sweep wrote this file).\n");
    t.push_str(&format!("exec {exe_q} sweep --collect --out {out}\n"));
    write_atomic(&written.collect, t.as_bytes())?;
    Ok(written)
}

fn sbatch(args: &[String], script: &Path) -> Result<String, String> {
    let o = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .arg(script)
        .output()
        .map_err(|e| format!("cannot run sbatch: {e}"))?;
    if !o.status.success() {
        return Err(format!(
            "sbatch {} failed: {}",
            script.display(),
            String::from_utf8_lossy(&o.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&o.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() {
        return Err(format!("sbatch {} printed no job id", script.display()));
    }
    Ok(id)
}

/// Submits the scripts in order with their dependencies; records the job ids in
/// DIR/slurm/jobs. Returns (what, id) pairs.
pub fn submit(store: &Store, w: &Written) -> Result<Vec<(String, String)>, String> {
    let mut ids = Vec::new();
    let mut after: Option<String> = None;
    let record = |what: &str, id: &str| -> Result<(), String> {
        use std::io::Write;
        let path = slurm_dir(store).join("jobs");
        fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .and_then(|mut f| writeln!(f, "{} {what} {id}", w.number))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    if let Some(p) = &w.prepare {
        let id = sbatch(&[], p)?;
        record("prepare", &id)?;
        ids.push(("prepare".to_string(), id.clone()));
        after = Some(id);
    }
    if let Some(a) = &w.array {
        let dep: Vec<String> = after
            .iter()
            .map(|id| format!("--dependency=afterok:{id}"))
            .collect();
        let id = sbatch(&dep, a)?;
        record("array", &id)?;
        ids.push(("array".to_string(), id.clone()));
        after = Some(id);
    }
    let dep: Vec<String> = after
        .iter()
        .map(|id| format!("--dependency=afterany:{id}"))
        .collect();
    let id = sbatch(&dep, &w.collect)?;
    record("collect", &id)?;
    ids.push(("collect".to_string(), id));
    Ok(ids)
}

/// The run of this array task: line `SLURM_ARRAY_TASK_ID` + 1 of the list.
pub fn task_run<'a>(m: &'a Manifest, list: &Path) -> Result<&'a Run, String> {
    let id = std::env::var("SLURM_ARRAY_TASK_ID").map_err(|_| {
        "--task runs inside a SLURM array task (SLURM_ARRAY_TASK_ID is not set)".to_string()
    })?;
    let k: usize = id
        .trim()
        .parse()
        .map_err(|_| format!("SLURM_ARRAY_TASK_ID = `{id}` is not a task number"))?;
    let text =
        fs::read_to_string(list).map_err(|e| format!("cannot read {}: {e}", list.display()))?;
    let name = text
        .lines()
        .nth(k)
        .ok_or_else(|| format!("{} has no line {}", list.display(), k + 1))?;
    m.runs
        .iter()
        .find(|r| r.name == name)
        .ok_or_else(|| format!("the run {name} of {} is not in the sweep", list.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_quoting() {
        assert_eq!(quote(Path::new("/a b/c")), "'/a b/c'");
        assert_eq!(quote(Path::new("/it's")), r"'/it'\''s'");
    }

    #[test]
    fn header_lines() {
        let s = Slurm {
            partition: Some("short".into()),
            time: Some("0:10:00".into()),
            mem: Some("1G".into()),
            cpus: Some(2),
            extra: vec!["--account=abc".into()],
        };
        let h = header("trubal-x", &s, 2, Path::new("/d/%A_%a.out"));
        assert_eq!(
            h,
            "#!/bin/bash\n#SBATCH --job-name=trubal-x\n#SBATCH --cpus-per-task=2\n#SBATCH --partition=short\n\
             #SBATCH --time=0:10:00\n#SBATCH --mem=1G\n#SBATCH --output=/d/%A_%a.out\n#SBATCH --account=abc\n"
        );
    }
}
