//! What a sweep is asked to do: the options of `trubal sweep`, from the command line and from a
//! sweep file (the same options, one per line, without the `--`).

use std::path::{Path, PathBuf};

/// What to do with the runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    /// Run the missing runs on this machine, then collect.
    Local,
    /// List the runs (and which are finished); write nothing.
    DryRun,
    /// Only gather what the runs printed into results.csv and the charts.
    Collect,
    /// Write a SLURM job-array script for the missing runs (and submit it with `sbatch`).
    Slurm { submit: bool },
    /// One array task (`--task`, in the script the sweep writes): the run named on line
    /// `SLURM_ARRAY_TASK_ID` of the list.
    Task,
    /// The prepare step as a job of its own (`--task-prepare`).
    TaskPrepare,
}

/// The `#SBATCH` settings of `--slurm`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Slurm {
    pub partition: Option<String>,
    pub time: Option<String>,
    pub mem: Option<String>,
    /// Cores per run (`--cpus-per-task`; also the run's `--threads` unless that is given).
    pub cpus: Option<usize>,
    /// Further `#SBATCH` lines, verbatim (`--sbatch=--account=abc`).
    pub extra: Vec<String>,
}

/// A value with where it was given (for error messages).
#[derive(Clone, Debug, PartialEq)]
pub struct Given<T> {
    pub value: T,
    pub origin: String,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// The command file with `$name` parameters.
    pub file: Option<PathBuf>,
    pub grids: Vec<Given<(String, Vec<String>)>>,
    pub rows: Option<Given<PathBuf>>,
    pub sets: Vec<Given<(String, String)>>,
    /// Derived parameters: name and expression (`--let v1x='v/2*cos(theta*pi/180)'`).
    pub lets: Vec<Given<(String, String)>>,
    /// A command file run once, before the runs, in DIR/prepare (with the `--set` values).
    pub prepare: Option<Given<PathBuf>>,
    pub out: Option<PathBuf>,
    pub jobs: Option<usize>,
    pub threads: Option<usize>,
    pub measures: Vec<Given<String>>,
    pub charts: Vec<Given<String>>,
    pub logx: bool,
    pub mode: Mode,
    pub slurm: Slurm,
    /// `--list FILE` of `--task`.
    pub list: Option<PathBuf>,
}

pub const USAGE: &str = "usage: trubal sweep (FILE.tru | FILE.sweep) --out DIR [options]
       trubal sweep --out DIR --collect
  FILE.tru             a command file with $name parameters
  FILE.sweep           a sweep file: these options one per line without `--` (`file FILE.tru` names
                       the command file; paths are relative to the sweep file); options given here
                       add to it (--set, --grid and --let of the same name replace its own)
  --out DIR            the sweep's directory: runs/NAME/ per run, results.csv, charts
  --grid NAME=V1,V2..  a parameter and its values; the runs are the product of all grids and rows
  --rows FILE.csv      explicit runs: a header of parameter names (a column `run` names the runs)
  --set NAME=VALUE     a value shared by every run
  --let NAME=EXPR      a value computed from the others (+ - * / ^, sin cos tan asin acos atan
                       sqrt exp ln log10 abs round floor ceil min max, pi), e.g. v1x=v/2*cos(theta*pi/180)
  --prepare FILE.tru   a command file run once before the runs, in DIR/prepare, with the --set
                       values; the files it writes are linked into every run's directory
  --jobs N             runs at once on this machine (default: the cores); with --slurm, at most
                       N array tasks at once
  --threads N          threads per run (default: the cores / --jobs, at least 1; --cpus with
                       --slurm)
  --measure [A=]KIND.FIELD[#K]  a column of results.csv: FIELD of the last (or K-th; -K from
                       the end) PRint KIND of each run (`bonds.damage_ratio`, `energy.dissipated.viscous`);
                       default: every number of the last PRint of each kind
  --chart Y:X[:GROUP]  DIR/Y_vs_X.png: measure Y against parameter X, one line per GROUP value
  --logx               logarithmic x axis in the charts
  --dry-run            list the runs and what is finished; run and write nothing
  --collect            only gather what the runs printed: DIR/results.csv and the charts
  --slurm              write a SLURM job-array script for the runs not yet finished (DIR/slurm/)
  --submit             ... and submit it with sbatch (a job for --prepare before, one that collects after)
  --partition P --time T --mem M --cpus N --sbatch ARG   #SBATCH settings (N cores per run)";

fn given<T>(value: T, origin: &str) -> Given<T> {
    Given {
        value,
        origin: origin.to_string(),
    }
}

/// Keys that take a value, as options (`--key VALUE`) and in sweep files (`key VALUE`).
const VALUED: &[&str] = &[
    "grid",
    "rows",
    "set",
    "let",
    "prepare",
    "jobs",
    "threads",
    "measure",
    "chart",
    "partition",
    "time",
    "mem",
    "cpus",
    "sbatch",
];

impl Spec {
    fn empty() -> Spec {
        Spec {
            file: None,
            grids: Vec::new(),
            rows: None,
            sets: Vec::new(),
            lets: Vec::new(),
            prepare: None,
            out: None,
            jobs: None,
            threads: None,
            measures: Vec::new(),
            charts: Vec::new(),
            logx: false,
            mode: Mode::Local,
            slurm: Slurm::default(),
            list: None,
        }
    }

    /// Reads the arguments after `trubal sweep`. Every error is returned (one per line).
    pub fn from_args(args: &[String]) -> Result<Spec, Vec<String>> {
        let mut spec = Spec::empty();
        let mut errors = Vec::new();
        let mut positional: Option<String> = None;
        let (mut dry, mut collect, mut slurm, mut submit, mut task, mut task_prep) =
            (false, false, false, false, false, false);
        // Options of the command line, applied after the sweep file's.
        let mut items: Vec<(String, String)> = Vec::new();
        let mut i = 0;
        while i < args.len() {
            let a = &args[i];
            i += 1;
            let Some(opt) = a.strip_prefix("--") else {
                if positional.is_some() {
                    errors.push(format!(
                        "only one command or sweep file may be given (`{a}`)"
                    ));
                } else {
                    positional = Some(a.clone());
                }
                continue;
            };
            let (key, inline) = match opt.split_once('=') {
                Some((k, v)) if VALUED.contains(&k) || k == "out" || k == "list" => {
                    (k, Some(v.to_string()))
                }
                _ => (opt, None),
            };
            match key {
                "dry-run" => dry = true,
                "collect" => collect = true,
                "slurm" => slurm = true,
                "submit" => submit = true,
                "logx" => spec.logx = true,
                "task" => task = true,
                "task-prepare" => task_prep = true,
                k if k == "out" || k == "list" || VALUED.contains(&k) => {
                    let v = match inline {
                        Some(v) => v,
                        None if i < args.len() => {
                            i += 1;
                            args[i - 1].clone()
                        }
                        None => {
                            errors.push(format!("--{key} needs a value"));
                            continue;
                        }
                    };
                    match key {
                        "out" => spec.out = Some(PathBuf::from(v)),
                        "list" => spec.list = Some(PathBuf::from(v)),
                        _ => items.push((key.to_string(), v)),
                    }
                }
                _ => errors.push(format!("unknown option --{key}")),
            }
        }
        spec.mode = match (dry, collect, slurm || submit, task, task_prep) {
            (false, false, false, false, false) => Mode::Local,
            (true, false, false, false, false) => Mode::DryRun,
            (false, true, false, false, false) => Mode::Collect,
            (false, false, true, false, false) => Mode::Slurm { submit },
            (false, false, false, true, false) => Mode::Task,
            (false, false, false, false, true) => Mode::TaskPrepare,
            _ => {
                errors.push(
                    "--dry-run, --collect and --slurm/--submit are different things: give one"
                        .into(),
                );
                Mode::Local
            }
        };
        if spec.out.is_none() {
            errors.push("--out DIR is missing: the directory of the sweep".into());
        }
        let internal = matches!(spec.mode, Mode::Task | Mode::TaskPrepare | Mode::Collect);
        match positional {
            Some(p) if p.ends_with(".sweep") => {
                let path = PathBuf::from(&p);
                match std::fs::read_to_string(&path) {
                    Ok(text) => spec.read_sweep_file(&path, &text, &mut errors),
                    Err(e) => errors.push(format!("cannot read the sweep file {p}: {e}")),
                }
            }
            Some(p) => spec.file = Some(PathBuf::from(p)),
            None if internal => {}
            None => {
                errors.push("no command file: trubal sweep FILE.tru ... (or FILE.sweep)".into())
            }
        }
        for (k, v) in items {
            spec.apply(&k, &v, "command line", None, true, &mut errors);
        }
        if errors.is_empty() {
            Ok(spec)
        } else {
            Err(errors)
        }
    }

    /// The lines of a sweep file: `key value` (the rest of the line is the value); `#` at the
    /// start of a line or after a blank starts a comment.
    fn read_sweep_file(&mut self, path: &Path, text: &str, errors: &mut Vec<String>) {
        let base = path.parent().unwrap_or(Path::new("")).to_path_buf();
        let shown = path.display().to_string();
        for (k, raw) in text.lines().enumerate() {
            // A comment starts at a `#` that begins the line or follows a blank (`#` inside
            // a word belongs to it: `--measure energy.kinetic#1`; `;` is a value, as in
            // `set liquid=;`, a command line that is a comment).
            let cut = raw
                .char_indices()
                .find(|&(i, c)| c == '#' && (i == 0 || raw[..i].ends_with([' ', '\t'])))
                .map(|(i, _)| i)
                .unwrap_or(raw.len());
            let line = raw[..cut].trim();
            if line.is_empty() {
                continue;
            }
            let origin = format!("{shown}:{}", k + 1);
            let (key, value) = match line.split_once(char::is_whitespace) {
                Some((k, v)) => (k, v.trim()),
                None => (line, ""),
            };
            match key {
                "file" if !value.is_empty() => {
                    if self.file.is_some() {
                        errors.push(format!("{origin}: `file` given twice"));
                    }
                    self.file = Some(base.join(value));
                }
                "logx" if value.is_empty() => self.logx = true,
                k if VALUED.contains(&k) && !value.is_empty() => {
                    self.apply(k, value, &origin, Some(&base), false, errors)
                }
                k if VALUED.contains(&k) || k == "file" => {
                    errors.push(format!("{origin}: `{k}` needs a value"))
                }
                k => errors.push(format!(
                    "{origin}: unknown key `{k}` (a sweep file holds the options of trubal sweep without `--`: file, {})",
                    VALUED.join(", ")
                )),
            }
        }
        if self.file.is_none() {
            errors.push(format!(
                "{shown}: no `file` line naming the command file of the sweep"
            ));
        }
    }

    /// One option. `base` resolves the paths of a sweep file; `replaces` lets a command-line
    /// `--set`/`--grid`/`--let` replace a sweep file's of the same name.
    fn apply(
        &mut self,
        key: &str,
        value: &str,
        origin: &str,
        base: Option<&Path>,
        replaces: bool,
        errors: &mut Vec<String>,
    ) {
        let path = |v: &str| match base {
            Some(b) => b.join(v),
            None => PathBuf::from(v),
        };
        let count = |v: &str, what: &str, errors: &mut Vec<String>| match v.parse::<usize>() {
            Ok(n) if n > 0 => Some(n),
            _ => {
                errors.push(format!(
                    "{origin}: {what} needs a positive whole number, not `{v}`"
                ));
                None
            }
        };
        match key {
            "grid" | "set" | "let" => {
                let Some((name, v)) = value.split_once('=') else {
                    errors.push(format!("{origin}: {key} needs NAME=VALUE, not `{value}`"));
                    return;
                };
                let name = name.trim().to_string();
                let v = v.trim();
                // The command line replaces a sweep file's grid, set or let of the same name
                // (`--set eta=0` narrows the file's `grid eta=...`); a name given twice
                // otherwise is an error, found when the names are checked.
                if replaces {
                    let keep = |g: &String, o: &String| !(*g == name && o != "command line");
                    self.grids.retain(|g| keep(&g.value.0, &g.origin));
                    self.sets.retain(|g| keep(&g.value.0, &g.origin));
                    self.lets.retain(|g| keep(&g.value.0, &g.origin));
                }
                match key {
                    "grid" => {
                        let values = if v.is_empty() {
                            Vec::new()
                        } else {
                            v.split(',').map(|s| s.trim().to_string()).collect()
                        };
                        self.grids.push(given((name, values), origin));
                    }
                    "set" => self.sets.push(given((name, v.to_string()), origin)),
                    _ => self.lets.push(given((name, v.to_string()), origin)),
                }
            }
            "rows" => {
                if self.rows.is_some() && !replaces {
                    errors.push(format!("{origin}: `rows` given twice"));
                }
                self.rows = Some(given(path(value), origin));
            }
            "prepare" => {
                if self.prepare.is_some() && !replaces {
                    errors.push(format!("{origin}: `prepare` given twice"));
                }
                self.prepare = Some(given(path(value), origin));
            }
            "jobs" => self.jobs = count(value, "jobs", errors).or(self.jobs),
            "threads" => self.threads = count(value, "threads", errors).or(self.threads),
            "cpus" => self.slurm.cpus = count(value, "cpus", errors).or(self.slurm.cpus),
            "measure" => self.measures.push(given(value.to_string(), origin)),
            "chart" => self.charts.push(given(value.to_string(), origin)),
            "partition" => self.slurm.partition = Some(value.to_string()),
            "time" => self.slurm.time = Some(value.to_string()),
            "mem" => self.slurm.mem = Some(value.to_string()),
            "sbatch" => self.slurm.extra.push(value.to_string()),
            _ => errors.push(format!("{origin}: unknown option {key}")),
        }
    }

    /// Threads per run: `--threads`, else `--cpus` (SLURM), else the cores shared among
    /// the `--jobs` run here at once (1 when `--jobs` is not given: as many runs as cores).
    pub fn run_threads(&self) -> usize {
        self.threads
            .or(self.slurm.cpus)
            .unwrap_or_else(|| match (self.mode, self.jobs) {
                (Mode::Local, Some(jobs)) => (crate::sim::parallel::awake::cores() / jobs).max(1),
                _ => 1,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn command_line_options() {
        let s = Spec::from_args(&args(
            "f.tru --grid v=0.5,1,2 --grid=eta=0,0.01 --set n=10 --out d --jobs 3 --chart x:v",
        ))
        .unwrap();
        assert_eq!(s.file, Some(PathBuf::from("f.tru")));
        assert_eq!(
            s.grids[0].value,
            ("v".into(), vec!["0.5".into(), "1".into(), "2".into()])
        );
        assert_eq!(s.grids[1].value.0, "eta");
        assert_eq!(s.sets[0].value, ("n".into(), "10".into()));
        assert_eq!(s.jobs, Some(3));
        assert_eq!(s.mode, Mode::Local);
        assert_eq!(s.out, Some(PathBuf::from("d")));
    }

    #[test]
    fn errors_are_all_reported() {
        let e = Spec::from_args(&args(
            "f.tru g.tru --jobs 0 --frob --set x --slurm --dry-run",
        ))
        .unwrap_err();
        assert_eq!(e.len(), 6, "{e:?}");
    }

    #[test]
    fn sweep_file_lines_and_command_line_replacement() {
        let mut s = Spec::empty();
        let mut errors = Vec::new();
        s.read_sweep_file(
            Path::new("scripts/sweeps/a.sweep"),
            "# comment\nfile ../x.tru\ngrid v = 1, 2 # comment\nset n=;\nmeasure e=energy.kinetic#1\nlogx\nrows t.csv\n",
            &mut errors,
        );
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(s.file, Some(PathBuf::from("scripts/sweeps/../x.tru")));
        assert_eq!(
            s.rows.as_ref().unwrap().value,
            PathBuf::from("scripts/sweeps/t.csv")
        );
        assert_eq!(s.grids[0].value.1, ["1", "2"]);
        assert_eq!(s.sets[0].value.1, ";");
        assert_eq!(s.measures[0].value, "e=energy.kinetic#1");
        assert!(s.logx);
        s.apply("set", "n=6", "command line", None, true, &mut errors);
        assert_eq!(s.sets.len(), 1);
        assert_eq!(s.sets[0].value.1, "6");
        s.apply("set", "v=1", "command line", None, true, &mut errors);
        assert!(s.grids.is_empty());
        s.read_sweep_file(Path::new("b.sweep"), "gird v=1\njobs\n", &mut errors);
        assert_eq!(errors.len(), 2, "{errors:?}");
    }

    #[test]
    fn threads_per_run_share_the_cores_among_the_jobs() {
        let cores = crate::sim::parallel::awake::cores();
        let threads = |line: &str| Spec::from_args(&args(line)).map(|s| s.run_threads());
        assert_eq!(threads("f.tru --out d"), Ok(1));
        assert_eq!(threads("f.tru --out d --jobs 1"), Ok(cores));
        assert_eq!(threads("f.tru --out d --jobs 1 --threads 3"), Ok(3));
        assert_eq!(
            threads(&format!("f.tru --out d --jobs {}", 2 * cores)),
            Ok(1)
        );
        assert_eq!(threads("f.tru --out d --jobs 1 --slurm"), Ok(1));
    }
}
