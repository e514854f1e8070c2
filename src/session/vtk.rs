//! `VTk`: VTK frames now or on a schedule (`crate::output::vtk`; doc/output.md). A frame is
//! written by the session between steps, never inside the core: with `VTk EVery k` set, a
//! `Cycle` (or a `RELax` run) runs as consecutive watched runs that end at the cycles that
//! are multiples of k, and the frame is written after each, with the forces of its last
//! step kept as they are after any `Cycle` (a `Cycle` split in runs gives the same bits as
//! one: ARCHITECTURE.md, "Determinism").

use super::{Flow, Session, progress::Progress, watched};
use crate::output::vtk::{Series, write_frame};
use crate::sim::cycle::Blowup;

/// The VTK output of a session: the series frames go to, and the schedule.
#[derive(Debug, Default)]
pub struct VtkState {
    pub series: Option<Series>,
    pub every: Option<u64>,
}

/// The prefix of a series when `VTk FILe` names none.
pub const DEFAULT_PREFIX: &str = "trubal";

impl Session {
    /// `VTk [EVery k] [FILe prefix] | OFF`.
    pub(super) fn vtk(
        &mut self,
        every: Option<u64>,
        off: bool,
        prefix: Option<&str>,
    ) -> Result<Flow, String> {
        if off {
            self.vtk.every = None;
            self.emit("VTk: no more frames during cycling");
            return Ok(Flow::Continue);
        }
        let scene = self.scene.as_ref().ok_or_else(|| {
            "no problem is defined yet: give STArt (or RESTart) first".to_string()
        })?;
        // A new prefix starts a new series; the same one goes on.
        let mut series = match (&self.vtk.series, prefix) {
            (Some(s), None) => s.clone(),
            (Some(s), Some(p)) if s.prefix == p => s.clone(),
            (_, p) => Series::new(p.unwrap_or(DEFAULT_PREFIX)),
        };
        let files = write_frame(scene, &mut series)?;
        let text = format!(
            "VTk: frame at cycle {} written to {}{}",
            scene.cycle(),
            files[..4].join(", "),
            match every {
                Some(k) => format!("; then every {k} cycles during cycling"),
                None => String::new(),
            }
        );
        self.vtk.series = Some(series);
        if every.is_some() {
            self.vtk.every = every;
        }
        self.emit(&text);
        Ok(Flow::Continue)
    }

    /// `FIEld n1 n2 n3 w [LUCy] [FILe prefix]`: the fields printed, and with a prefix
    /// written as `.vti` (nothing is written when the grid is refused).
    pub(super) fn field(
        &mut self,
        nodes: [usize; 3],
        width: f64,
        lucy: bool,
        prefix: Option<&str>,
    ) -> Result<Flow, String> {
        use crate::output::fields;
        let scene = self.scene.as_ref().ok_or_else(|| {
            "no problem is defined yet: give STArt (or RESTart) first".to_string()
        })?;
        let spec = fields::Spec {
            nodes,
            width,
            kernel: if lucy {
                fields::Kernel::Lucy
            } else {
                fields::Kernel::Gauss
            },
        };
        fields::check(scene, &spec)?;
        let f = fields::compute(scene, &spec);
        let (mut text, j) = fields::report(scene, &spec, &f);
        if let Some(p) = prefix {
            let name = format!("{p}_field_c{:08}.vti", scene.cycle());
            let shown = crate::output::vtk::write_file(scene, &name, &fields::vti(scene, &f))?;
            text.push_str(&format!("field written to {shown}\n"));
        }
        let out = if self.json { j.to_string() } else { text };
        self.emit(&out);
        Ok(Flow::Continue)
    }

    /// `n` steps watched (progress, Ctrl-C), in runs that end where a frame is due, each
    /// frame written after its run. `base`: steps of the command done before (RELax).
    /// Returns the steps run (fewer than `n` when interrupted), and appends the notes of
    /// every run (`Scene::take_notes`) to `notes`. A frame that cannot be written is a warning and stops
    /// the schedule; the Cycle goes on.
    pub(super) fn watched_frames(
        &mut self,
        base: u64,
        n: u64,
        progress: &mut Progress,
        notes: &mut Vec<String>,
    ) -> Result<u64, Blowup> {
        let mut done = 0;
        let mut failed = None;
        let r = loop {
            let Some(scene) = self.scene.as_mut() else {
                break Ok(done);
            };
            if done >= n {
                break Ok(done);
            }
            let now = scene.cycle();
            let m = match self.vtk.every {
                Some(k) => (k - now % k).min(n - done),
                None => n - done,
            };
            // A Cycle's CALL ends a piece at its multiples too (session::script::cycle).
            let m = self.hook_piece(now, m);
            let m = self.history_piece(now, m);
            let mut until = self.hook_until();
            let Some(scene) = self.scene.as_mut() else {
                break Ok(done);
            };
            progress.set_offset(base + done);
            let run = watched(scene, m, progress, &mut until);
            notes.append(&mut scene.take_notes());
            let ran = match run {
                Ok((_, ran)) => ran,
                Err(b) => break Err(b),
            };
            done += ran;
            if let (Some(k), Some(series)) = (self.vtk.every, self.vtk.series.as_mut())
                && scene.cycle().is_multiple_of(k)
                && let Err(e) = write_frame(scene, series)
            {
                self.vtk.every = None;
                failed = Some(e);
            }
            self.history_record();
            let go = self.after_piece(until, ran == m);
            if ran < m || !go {
                break Ok(done);
            }
        };
        if let Some(e) = failed {
            self.emit_err(&format!(
                "warning: {e}; VTk EVery stopped (no more frames during cycling)"
            ));
        }
        r
    }
}
