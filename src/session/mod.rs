//! A session: reads lines (terminal, file, standard input, batch), parses them, applies them
//! to the simulation and writes the output. Data flows one way: text → command → scene →
//! output. A command that fails changes nothing.

pub mod arrays;
pub mod exec;
mod generation;
pub mod input;
pub mod interrupt;
mod problem;
pub mod progress;
pub mod script;
pub mod vars;
pub mod vtk;

use std::collections::HashMap;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::checkpoint;
use crate::lang::command::{Command, PlotItem, StressServo};
use crate::lang::{Parsed, parse_line_in};
use crate::output::print;
use crate::sim::cell::{Servo, StressTarget};
use crate::sim::{Scene, cycle, energy};

/// Where a line came from (for error messages).
#[derive(Clone, Debug)]
pub struct Source {
    pub name: String,
    pub line: usize,
}

/// A located error: byte span in the line and the message.
#[derive(Clone, Debug, PartialEq)]
pub struct LineError {
    pub start: usize,
    pub end: usize,
    pub message: String,
}

/// Result of running one line.
#[derive(Debug, PartialEq)]
pub enum Flow {
    Continue,
    Stop,
    /// Ctrl-C cut the command short (a `Cycle` or `RELax` stopped at the end of a step; the
    /// scene is as a shorter command would have left it). A command file stops here; the
    /// terminal session returns to the prompt.
    Interrupted,
}

pub struct Session {
    pub scene: Option<Scene>,
    pub json: bool,
    pub vars: HashMap<String, String>,
    out: Box<dyn Write + Send>,
    /// Diagnostics (errors, warnings): standard error unless a caller (a test) gives another.
    diag: Box<dyn Write + Send>,
    log: Option<File>,
    echo: bool,
    /// Working directory for relative file names (checkpoints, logs).
    pub dir: PathBuf,
    /// `VTk`'s series and schedule.
    vtk: vtk::VtkState,
    /// Variables, procedures, blocks being read (doc/language.md).
    pub script: script::Interp,
}

impl Session {
    pub fn new(out: Box<dyn Write + Send>, json: bool) -> Self {
        Session {
            scene: None,
            json,
            vars: HashMap::new(),
            out,
            diag: Box::new(std::io::stderr()),
            log: None,
            echo: false,
            dir: PathBuf::from("."),
            vtk: vtk::VtkState::default(),
            script: script::Interp::default(),
        }
    }

    /// Diagnostics go to `w` instead of standard error (tests keep them out of the test
    /// runner's output this way).
    pub fn with_diagnostics(mut self, w: Box<dyn Write + Send>) -> Self {
        self.diag = w;
        self
    }

    /// Writes output (and to the log file when one is open).
    pub fn emit(&mut self, text: &str) {
        if text.is_empty() {
            return;
        }
        let nl = if text.ends_with('\n') { "" } else { "\n" };
        let _ = write!(self.out, "{text}{nl}");
        if let Some(f) = &mut self.log {
            let _ = write!(f, "{text}{nl}");
        }
    }

    /// Diagnostics go to standard error (and the log). Write errors are ignored (a closed
    /// pipe must not panic, as `eprintln!` would).
    pub fn emit_err(&mut self, text: &str) {
        let _ = self.out.flush();
        let _ = writeln!(self.diag, "{text}");
        let _ = self.diag.flush();
        if let Some(f) = &mut self.log {
            let _ = writeln!(f, "{text}");
        }
    }

    pub fn flush(&mut self) {
        let _ = self.out.flush();
    }

    fn path(&self, name: &str) -> PathBuf {
        join(&self.dir, name)
    }

    /// Runs one line. Errors are returned located; the state is unchanged by a failing command
    /// (earlier complete commands of the same line stay done).
    pub fn run_line(&mut self, raw: &str) -> Result<Flow, LineError> {
        // `$name`: the --set value, else the variable's (script::Session::substituted).
        let line = self.substituted(raw)?;
        if self.echo
            && let Some(f) = &mut self.log
        {
            let _ = writeln!(f, "> {line}");
        }
        let parsed = parse_line_in(&line, &self.names()).map_err(|e| LineError {
            start: e.start,
            end: e.end,
            message: e.message,
        })?;
        for Parsed {
            command,
            start,
            end,
        } in parsed
        {
            let logging = self.echo && self.log.is_some();
            let r = self.execute(&command);
            // The command that opened the log (`STArt ... Log`, `Log ON`) is its first line.
            if !logging
                && self.echo
                && let Some(f) = &mut self.log
            {
                let _ = writeln!(f, "> {line}");
            }
            match r {
                // BREak or RETurn: the rest of the line is not run.
                Ok(Flow::Continue) if self.line_cut() => break,
                Ok(Flow::Continue) => {}
                Ok(flow) => return Ok(flow),
                Err(message) => {
                    if let Some(e) = self.take_span() {
                        return Err(e);
                    }
                    return Err(LineError {
                        start,
                        end,
                        message,
                    });
                }
            }
        }
        Ok(Flow::Continue)
    }

    /// Executes one command.
    pub fn execute(&mut self, cmd: &Command) -> Result<Flow, String> {
        // Only a CReate after another keeps the overlap index of the run (`exec::apply`);
        // dropped before any other command runs, so no snapshot or saved state carries it.
        if !matches!(cmd, Command::Create { .. })
            && let Some(s) = self.scene.as_mut()
        {
            s.end_create_run();
        }
        let r = self.execute_one(cmd);
        // Only an AGEnerate right after another joins its lattice (`sim::place::layer_order`).
        if r.is_ok()
            && !matches!(cmd, Command::Agenerate { .. })
            && let Some(s) = self.scene.as_mut()
        {
            s.end_lattice_run();
        }
        r
    }

    fn execute_one(&mut self, cmd: &Command) -> Result<Flow, String> {
        self.refuse_in_hook(cmd)?;
        match cmd {
            Command::Script(s) => return self.script_command(s),
            Command::Help { topic, item } => {
                let text = match topic {
                    None => crate::lang::doc::help_index(),
                    Some(t) => crate::lang::doc::help_for(t, item.as_deref())?,
                };
                self.emit(&crate::lang::doc::wrap(&text, terminal_width()));
                return Ok(Flow::Continue);
            }
            Command::Stop => return Ok(Flow::Stop),
            Command::Log { on, file } => {
                if *on {
                    let name = file.clone().unwrap_or_else(|| "TRUBAL.OUT".into());
                    if self.log.is_none() || file.is_some() {
                        let f = File::create(self.path(&name))
                            .map_err(|e| format!("cannot open log file {name}: {e}"))?;
                        self.log = Some(f);
                    }
                }
                self.echo = *on;
                return Ok(Flow::Continue);
            }
            Command::Iset | Command::Rset => {
                return Err(
                    "Iset/RSet poked TRUBAL's memory array, which does not exist here: use SET (e.g. `SET TOL 1e-6`, `SET XRES 2e-7`; `PRint SETtings` lists them)"
                        .into(),
                );
            }
            Command::New => {
                self.scene = None;
                return Ok(Flow::Continue);
            }
            _ => {}
        }
        if let Some(r) = self.problem(cmd) {
            return r;
        }
        match cmd {
            Command::Cycle { n, servo } => return self.cycle_servo(*n, servo),
            Command::Relax { kmax, fmax, nmax } => return self.relax(*kmax, *fmax, *nmax),
            Command::Agenerate { .. }
            | Command::Rgenerate { .. }
            | Command::RgenerateSeed { .. } => return self.generate(cmd),
            Command::Vtk {
                every,
                off,
                prefix,
                layout,
            } => {
                return self.vtk(*every, *off, prefix.as_deref(), *layout);
            }
            Command::Field {
                nodes,
                width,
                lucy,
                prefix,
                csv,
                average,
                bin,
                region,
            } => {
                let out = vtk::FieldOut {
                    prefix: prefix.clone(),
                    csv: *csv,
                };
                let kernel = crate::output::fields::Kernel::of(*bin, *lucy);
                return self.field(*nodes, *width, kernel, *region, out, *average);
            }
            _ => {}
        }
        // PLot HIStory: the histories of HIStory too (session::script::history).
        if let Command::Plot { items, mark } = cmd
            && items.contains(&PlotItem::History)
            && let Some(rest) = self.plot_histories(items)?
        {
            if rest.is_empty() {
                return Ok(Flow::Continue);
            }
            return self.scene_part(&Command::Plot {
                items: rest,
                mark: mark.clone(),
            });
        }
        self.scene_part(cmd)
    }

    /// A command that needs a scene, its output and warnings.
    fn scene_part(&mut self, cmd: &Command) -> Result<Flow, String> {
        let json = self.json;
        let dir = self.dir.clone();
        let Some(scene) = self.scene.as_mut() else {
            return Err("no problem is defined yet: give STArt (or RESTart) first".into());
        };
        let (text, warnings) = scene_command(scene, cmd, json, &dir, &self.script.state)?;
        for w in warnings {
            self.emit_err(&format!("warning: {w}"));
        }
        self.emit(&text);
        if let Command::Print { items, .. } = cmd
            && items.contains(&crate::lang::command::PrintItem::History)
        {
            let h = self.history_print();
            self.emit(&h);
        }
        Ok(Flow::Continue)
    }
}

impl Session {
    /// The scene, or the error of a command that needs one.
    fn scene_mut(&mut self) -> Result<&mut Scene, String> {
        self.scene
            .as_mut()
            .ok_or_else(|| "no problem is defined yet: give STArt (or RESTart) first".to_string())
    }

    /// Before a `Cycle` or `RELax`: the warnings about the scene, then everything printed so
    /// far out (on the screen or in the file before the long step).
    fn before_cycling(&mut self) -> Result<(), String> {
        for w in cycle::warnings(self.scene_mut()?) {
            self.emit_err(&format!("warning: {w}"));
        }
        self.flush();
        Ok(())
    }

    /// `Cycle n`: the warnings about the scene first, then the steps with a progress line on a
    /// terminal; Ctrl-C stops at the end of the current step.
    fn cycle(&mut self, n: u64) -> Result<Flow, String> {
        self.before_cycling()?;
        let mut progress = progress::Progress::new(n, self.json);
        let timing = std::env::var_os("TRUBAL_TIMING").is_some();
        let (t0, c0) = (
            std::time::Instant::now(),
            if timing { cpu_ns() } else { 0.0 },
        );
        self.scene_mut()?;
        let mut notes = Vec::new();
        let run = self.watched_frames(0, n, &mut progress, &mut notes);
        progress.finish();
        let scene = self.scene_mut()?;
        let balls = scene.particles().len();
        let at = scene.cycle();
        let ran = match run {
            Ok(ran) => ran,
            Err(b) => return Err(with_notes(b.message, &notes)),
        };
        for w in notes {
            self.emit_err(&format!("warning: {w}"));
        }
        if timing {
            // Benchmark hook (scripts/bench): wall-clock and CPU time of this Cycle, and
            // the pollers' changes and time asleep so far (`sim::parallel::awake`).
            let (changes, asleep) = crate::sim::parallel::awake::asleep_so_far();
            self.emit_err(&format!(
                "TRUBAL_TIMING cycles={n} balls={balls} cycle_wall_s={:.6} cycle_cpu_s={:.6} pollers_changed={changes} pollers_asleep_s={asleep:.3}",
                t0.elapsed().as_secs_f64(),
                (cpu_ns() - c0) * 1e-9
            ));
        }
        let stopped_by_hooks = self
            .script
            .hooks
            .as_ref()
            .is_some_and(|h| h.met || h.error.is_some());
        if ran < n && !stopped_by_hooks {
            interrupt::clear();
            self.emit_err(&format!(
                "interrupted: Cycle stopped after {ran} of {n} cycles, at cycle {at} (the state a `Cycle {ran}` would have left; `Cycle {}` runs the rest)",
                n - ran
            ));
            return Ok(Flow::Interrupted);
        }
        Ok(Flow::Continue)
    }

    /// `Cycle n S0 σ ...`: a Cycle with the periodic cell's stress servo (`sim::cell`).
    fn cycle_servo(&mut self, n: u64, servo: &[(StressServo, f64)]) -> Result<Flow, String> {
        if servo.is_empty() {
            return self.cycle(n);
        }
        let mut targets = Vec::new();
        for &(s, v) in servo {
            let t = match s {
                StressServo::S0 => StressTarget::Mean,
                StressServo::S1ms2 => StressTarget::Mean12,
                StressServo::S11 => StressTarget::Axis(0),
                StressServo::S22 => StressTarget::Axis(1),
                StressServo::S33 => StressTarget::Axis(2),
                StressServo::Ring => StressTarget::Ring,
            };
            if t == StressTarget::Ring {
                if !(v.is_finite() && (0.0..180.0).contains(&v)) {
                    return Err(format!(
                        "Cycle: RING takes the angle of the major principal stress in the x-y plane, in degrees from x towards y, 0 <= angle < 180; got {v}"
                    ));
                }
            } else if !(v.is_finite() && v > 0.0) {
                return Err(format!(
                    "Cycle: the servo's target stress must be a positive number (Pa, compression positive); got {v}"
                ));
            }
            targets.push((t, v));
        }
        let scene = self.scene_mut()?;
        // The servo the last Cycle ended with goes on, if it held these targets over the
        // same cell settings (`Scene::continued_servo`): it was checked when it began.
        if let Some(kept) = scene.continued_servo(&targets) {
            scene.set_servo(Some(kept));
            return self.cycle_ending_servo(n);
        }
        if scene.settings().two_d
            && let Some(&(t, _)) = targets
                .iter()
                .find(|(t, _)| matches!(t, StressTarget::Mean | StressTarget::Axis(2)))
        {
            return Err(format!(
                "Cycle: in a 2-D scene (`2-D`) the cell strains only in the x-y plane (GRID and PRObe refuse ed33 too): {} would strain z, and σ33 of a planar layer is not a stress it can reach; hold the in-plane mean with S1MS2 ((σ11+σ22)/2) or the axes with S11 and S22",
                if t == StressTarget::Mean {
                    "S0 holds (σ11+σ22+σ33)/3 and"
                } else {
                    "S33"
                }
            ));
        }
        let servo = Servo::new(scene.cell(), &targets);
        if let Some(&(t, _, _)) = servo.targets.iter().find(|&&(t, _, axes)| {
            matches!(t, StressTarget::Mean | StressTarget::Mean12) && axes == [false; 4]
        }) {
            let (name, held) = if t == StressTarget::Mean {
                ("S0", "S11, S22 and S33")
            } else {
                ("S1MS2", "S11 and S22")
            };
            return Err(format!(
                "Cycle: {name} has no axis left to adjust: {held} hold every axis it averages; give {name} alone, or drop one of the axis targets"
            ));
        }
        if servo
            .targets
            .iter()
            .any(|&(t, _, axes)| t == StressTarget::Ring && axes == [false; 4])
        {
            return Err("Cycle: RING has no strain rate to turn: GRID prescribes the shear rate ed12 and S11 and S22 hold ed11 and ed22; give up one of them (doc/cell.md, \"Ring shear\")".into());
        }
        scene.set_servo(Some(servo));
        self.cycle_ending_servo(n)
    }

    /// A Cycle with the servo set; the servo is kept for the next Cycle after it.
    fn cycle_ending_servo(&mut self, n: u64) -> Result<Flow, String> {
        let r = self.cycle(n);
        if let Ok(scene) = self.scene_mut() {
            scene.set_servo(None);
        }
        r
    }

    /// `RELax`: cycles in runs of 100 until the kinetic energy and the largest contact force
    /// are below their limits, or `nmax` cycles. Ctrl-C stops it like a `Cycle`.
    fn relax(&mut self, kmax: f64, fmax: f64, nmax: u64) -> Result<Flow, String> {
        self.before_cycling()?;
        let mut progress = progress::Progress::new(nmax, self.json);
        self.scene_mut()?;
        let mut notes = Vec::new();
        let mut done = 0;
        let mut interrupted = false;
        let (mut ke, mut fm) = (f64::INFINITY, f64::INFINITY);
        while done < nmax {
            let n = (nmax - done).min(100);
            let run = self.watched_frames(done, n, &mut progress, &mut notes);
            let ran = match run {
                Ok(ran) => ran,
                Err(b) => {
                    progress.finish();
                    return Err(with_notes(b.message, &notes));
                }
            };
            done += ran;
            let scene = self.scene_mut()?;
            let st = energy::stored(scene);
            ke = st.kinetic_translation + st.kinetic_rotation;
            fm = max_contact_force(scene);
            if ran < n {
                interrupted = true;
                break;
            }
            if ke < kmax && fm < fmax {
                break;
            }
        }
        progress.finish();
        let at = self.scene_mut()?.cycle();
        for w in notes {
            self.emit_err(&format!("warning: {w}"));
        }
        self.emit(&format!(
            "RELax: {} after {done} cycles: kinetic energy {ke:.4e} J (limit {kmax:.4e}), largest contact force {fm:.4e} N (limit {fmax:.4e})",
            if ke < kmax && fm < fmax {
                "relaxed"
            } else if interrupted {
                "interrupted"
            } else {
                "not relaxed"
            }
        ));
        if interrupted {
            interrupt::clear();
            self.emit_err(&format!(
                "interrupted: RELax stopped after {done} cycles, at cycle {at}"
            ));
            return Ok(Flow::Interrupted);
        }
        Ok(Flow::Continue)
    }
}

/// `n` steps watched by the session: the progress line drawn, and Ctrl-C making the step
/// about to run the last.
fn watched(
    scene: &mut Scene,
    n: u64,
    progress: &mut progress::Progress,
    until: &mut Option<script::Until>,
) -> Result<(crate::sim::params::Model, u64), cycle::Blowup> {
    let mut watch = |s: &Scene, done| {
        progress.tick(s.cycle(), s.time(), s.particles().len(), done);
        interrupt::requested()
    };
    match until {
        // `Cycle ... UNTIL`: the condition is read after every step (session::script).
        Some(u) => cycle::run_until(scene, n, &mut watch, Some(&mut |s: &Scene| u.reached(s))),
        None => cycle::run_watched(scene, n, &mut watch),
    }
}

/// CPU time of all the process's threads (the rayon workers included), in ns, from Linux's
/// /proc/self/task/*/schedstat (NaN elsewhere).
fn cpu_ns() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return f64::NAN;
    };
    tasks
        .flatten()
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum()
}

pub(crate) fn join(dir: &Path, name: &str) -> PathBuf {
    let p = Path::new(name);
    // Relative to the current directory: keep the name as given (messages show it so).
    if p.is_absolute() || dir == Path::new(".") {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

/// Largest contact force (solid normal force or bridge force) in the scene.
fn max_contact_force(scene: &Scene) -> f64 {
    // The net normal force of each pair or wall contact: solid (with its dashpot) plus
    // liquid bridge (static attraction and viscous force). A bridge at contact pulls with
    // its full static force, so solid and bridge forces must be added, not compared
    // separately (Lian ch. 6: "total contact force (bridge + Hertz) < 1 µN").
    fn net(s: &crate::sim::contacts::ContactState) -> f64 {
        let mut f = 0.0;
        if s.touching {
            f += s.normal_force + s.damp_force;
        }
        if let Some(b) = &s.bridge {
            f += b.f_visc - b.f_static;
        }
        f.abs()
    }
    let mut f: f64 = 0.0;
    for c in scene.contacts().iter() {
        f = f.max(net(c.s));
    }
    for c in scene.contacts().wall_pairs() {
        f = f.max(net(&c.s));
    }
    f
}

/// An error of a run that also had warnings: they follow the error's text (an error would
/// lose the warnings of its command).
fn with_notes(message: String, warnings: &[String]) -> String {
    let mut out = message;
    for w in warnings {
        out.push_str("\nwarning: ");
        out.push_str(w);
    }
    out
}

/// Runs a command that needs a scene; returns the output text and warnings.
fn scene_command(
    scene: &mut Scene,
    cmd: &Command,
    json: bool,
    dir: &Path,
    script: &script::ScriptState,
) -> Result<(String, Vec<String>), String> {
    let mut out = String::new();
    let mut warnings = Vec::new();
    match cmd {
        Command::Print { items, ranges } => {
            // The ranges first: a group not defined refuses the command before it prints.
            let mut ranged = Vec::new();
            for r in ranges {
                ranged.push(crate::output::groups::item(scene, r.as_ref())?);
            }
            let mut ranged = ranged.into_iter();
            for it in items {
                let (human, j) = match it {
                    crate::lang::command::PrintItem::Range => ranged
                        .next()
                        .ok_or("internal: PRint has fewer ranges than GROup/RANge items")?,
                    _ => print::item(scene, *it),
                };
                if json {
                    out.push_str(&j.to_string());
                    out.push('\n');
                } else {
                    out.push_str(&human);
                }
            }
        }
        Command::Save { file } => {
            let name = file.clone().unwrap_or_else(|| "save.new".into());
            if let Some(m) = crate::sim::cycle::behind_a_wall(scene) {
                return Err(format!(
                    "SAve refused: {m}; such a state cannot cycle (delete the particle with DELete, or move the wall with AWAll)"
                ));
            }
            checkpoint::save_with(scene, script, &join(dir, &name))?;
            out = format!("saved cycle {} to {name}", scene.cycle());
        }
        Command::Plot { items, mark } => {
            // The range first: an undefined group refuses the command before PLot SAVe.
            let marked = match mark {
                Some(r) => {
                    crate::plot::check_mark(items)?;
                    let members = scene.members(r)?;
                    let mut ids: Vec<u32> =
                        members.iter().map(|&i| scene.particles().id[i]).collect();
                    ids.sort_unstable();
                    let label = match r.groups_named().as_slice() {
                        [g] if r.text() == format!("GROup {g}") => g.to_string(),
                        _ => "range".to_string(),
                    };
                    Some(crate::plot::Marked { label, ids })
                }
                None => None,
            };
            let mut drawn: Vec<PlotItem> = Vec::new();
            for it in items {
                if *it == PlotItem::Save {
                    scene.take_reference();
                } else {
                    drawn.push(*it);
                }
            }
            if !drawn.is_empty() {
                let file = crate::plot::plot_marked(scene, &drawn, marked.as_ref())?;
                out = format!("plot written to {file}");
            }
        }
        Command::Probe { kind } => {
            // The progress line, and Ctrl-C stopping the probe (the scene put back).
            let total = crate::sim::probe::PROBE_CYCLES.iter().sum();
            let mut progress = progress::Progress::new(total, json);
            let r = exec::probe(scene, *kind, &mut |s, done| {
                progress.tick(s.cycle(), s.time(), s.particles().len(), done);
                interrupt::requested()
            });
            progress.finish();
            if interrupt::requested() {
                interrupt::clear();
            }
            let (text, j) = r?;
            out = if json { j.to_string() } else { text };
        }
        _ => {
            // exec::apply checks everything before it changes anything, so a failing
            // command changes nothing; the kinetic energy it adds or removes is booked
            // (`Scene::booked_edit`).
            let create = matches!(cmd, Command::Create { .. });
            let text = scene.booked_edit(create, |scene| exec::apply(scene, cmd))?;
            // Warnings go to standard error with the others.
            for line in text.lines() {
                match line.strip_prefix("warning: ") {
                    Some(w) => warnings.push(w.to_string()),
                    None => {
                        out.push_str(line);
                        out.push('\n');
                    }
                }
            }
        }
    }
    Ok((out, warnings))
}

/// Formats a located error with the line and a caret under the offending words.
pub fn format_error(src: &Source, line: &str, e: &LineError) -> String {
    let col = line[..e.start.min(line.len())].chars().count() + 1;
    let width = line
        .get(e.start.min(line.len())..e.end.min(line.len()))
        .map(|s| s.chars().count())
        .unwrap_or(1)
        .max(1);
    let chars: Vec<char> = line
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    // A long line is shown as an excerpt around the error (at most ~160 characters).
    const SHOW: usize = 160;
    let (from, to) = if chars.len() <= SHOW {
        (0, chars.len())
    } else {
        let from = (col - 1).saturating_sub(SHOW / 2).min(chars.len() - SHOW);
        (from, from + SHOW)
    };
    let lead = if from > 0 { "..." } else { "" };
    let tail = if to < chars.len() { "..." } else { "" };
    let shown: String = chars[from..to].iter().collect();
    let width = width.min(to.saturating_sub(col - 1).max(1));
    // A message that quotes a huge word (a binary file's line) quotes the word's ends; a
    // long message of ordinary words is shown whole.
    // The message quotes words of the line: their control characters (a binary file's NUL
    // and ESC bytes) are shown as `?` like the excerpt's, never written raw to the terminal.
    let message: String = e
        .message
        .chars()
        .map(|c| if c.is_control() && c != '\n' { '?' } else { c })
        .collect();
    let message = message
        .split(' ')
        .map(|w| {
            let m: Vec<char> = w.chars().collect();
            if m.len() > 200 {
                let head: String = m[..100].iter().collect();
                let tail: String = m[m.len() - 60..].iter().collect();
                format!("{head}...{tail}")
            } else {
                w.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" ");
    format!(
        "{}:{}:{}: error: {}\n  | {lead}{shown}{tail}\n  | {}{}",
        src.name,
        src.line,
        col,
        message,
        " ".repeat(col - 1 - from + lead.len()),
        "^".repeat(width)
    )
}

/// The width of the terminal standard output writes to; 80 when it is not a terminal.
fn terminal_width() -> usize {
    use std::io::IsTerminal;
    if !std::io::stdout().is_terminal() {
        return 80;
    }
    // SAFETY: TIOCGWINSZ writes one `winsize` into the struct given; nothing else is touched.
    let mut ws: libc::winsize = unsafe { std::mem::zeroed() };
    let ok = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut ws) } == 0;
    if ok && ws.ws_col > 0 {
        ws.ws_col as usize
    } else {
        80
    }
}
