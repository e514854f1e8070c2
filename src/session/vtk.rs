//! `VTk`: VTK frames now or on a schedule (`crate::output::vtk`; doc/output.md), and
//! `FIEld`'s fields now or averaged over samples during cycling. A frame (or a sample) is
//! written by the session between steps, never inside the core: with `VTk EVery k` set, a
//! `Cycle` (or a `RELax` run) runs as consecutive watched runs that end at the cycles that
//! are multiples of k, and the frame is written after each, with the forces of its last
//! step kept as they are after any `Cycle` (a `Cycle` split in runs gives the same bits as
//! one: ARCHITECTURE.md, "Determinism").

use super::{Flow, Session, progress::Progress, watched};
use crate::lang::command::VtkLayout;
use crate::output::fields;
use crate::output::vtk::{Series, frame, resume, write_frame, xml::Encoding};
use crate::sim::Scene;
use crate::sim::cycle::Blowup;

/// Where `FIEld` writes besides its print: the `.vti` of `FILe prefix`, the CSV of `CSV`.
#[derive(Clone, Debug, Default)]
pub struct FieldOut {
    pub prefix: Option<String>,
    pub csv: bool,
}

/// A running `FIEld … AVerage k m`: the sums of the samples taken, and the next one's cycle.
#[derive(Debug)]
pub struct Average {
    spec: fields::Spec,
    out: FieldOut,
    every: u64,
    samples: u64,
    next: u64,
    sums: fields::Sums,
}

/// The fields' print (text, or JSON with `json`), after writing their files.
fn field_output(
    scene: &Scene,
    spec: &fields::Spec,
    out: &FieldOut,
    f: &fields::Fields,
    json: bool,
) -> Result<String, String> {
    let (mut text, j) = fields::report(scene, spec, f);
    let name = |ext: &str| {
        let p = out.prefix.as_deref().unwrap_or(DEFAULT_PREFIX);
        format!("{p}_field_c{:08}.{ext}", scene.cycle())
    };
    if out.prefix.is_some() {
        let shown = crate::output::vtk::write_file(scene, &name("vti"), &fields::vti(scene, f))?;
        text.push_str(&format!("field written to {shown}\n"));
    }
    if out.csv {
        let shown = crate::output::vtk::write_file(scene, &name("csv"), fields::csv(f).as_bytes())?;
        text.push_str(&format!("field written to {shown}\n"));
    }
    Ok(if json { j.to_string() } else { text })
}

/// The VTK output of a session: the series frames go to, and the schedule; `resume`: the
/// problem came from `RESTart`, so a series starts from its index on disk (a `STArt`
/// problem starts its series anew); the running `FIEld` average.
#[derive(Debug, Default)]
pub struct VtkState {
    pub series: Option<Series>,
    pub every: Option<u64>,
    pub resume: bool,
    pub average: Option<Average>,
}

/// The prefix of a series when `VTk FILe` names none.
pub const DEFAULT_PREFIX: &str = "trubal";

impl Session {
    /// `VTk [EVery k] [FILe prefix] [RAW] [SINgle] [ARRays name ...] [CONtacts name ...]
    /// | OFF`; `layout`: the arrays and encoding of this frame and the schedule's.
    pub(super) fn vtk(
        &mut self,
        every: Option<u64>,
        off: bool,
        prefix: Option<&str>,
        layout: VtkLayout,
    ) -> Result<Flow, String> {
        if off {
            self.vtk.every = None;
            self.emit("VTk: no more frames during cycling");
            return Ok(Flow::Continue);
        }
        let scene = self.scene.as_ref().ok_or_else(|| {
            "no problem is defined yet: give STArt (or RESTart) first".to_string()
        })?;
        // The same prefix goes on; another one starts, after a RESTart from its index on
        // disk if there is one.
        let mut series = match (&self.vtk.series, prefix) {
            (Some(s), None) => s.clone(),
            (Some(s), Some(p)) if s.prefix == p => s.clone(),
            (_, p) if self.vtk.resume => resume(scene, p.unwrap_or(DEFAULT_PREFIX)),
            (_, p) => Series::new(p.unwrap_or(DEFAULT_PREFIX)),
        };
        series.encoding = if layout.raw {
            Encoding::Raw
        } else {
            Encoding::Zlib
        };
        series.arrays = layout.arrays.unwrap_or(frame::ALL_ARRAYS);
        series.contacts = layout.contacts.unwrap_or(frame::ALL_CONTACT_ARRAYS);
        series.single = layout.single;
        let before = series.frames.iter().filter(|f| f.0 < scene.cycle()).count();
        let files = write_frame(scene, &mut series)?;
        let text = format!(
            "VTk: frame at cycle {} written to {}{}{}",
            scene.cycle(),
            files[..4].join(", "),
            if before > 0 {
                format!("; the series holds {before} earlier frames")
            } else {
                String::new()
            },
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

    /// `FIEld n1 n2 n3 (w [LUCy] | BIN [IN box]) [FILe prefix] [CSV] [AVerage k m]`: the fields printed and
    /// written; with `AVerage` the first of m samples taken, the output when the last is
    /// (nothing is written and no average starts when the grid is refused).
    pub(super) fn field(
        &mut self,
        nodes: [usize; 3],
        width: f64,
        kernel: fields::Kernel,
        region: Option<[f64; 6]>,
        out: FieldOut,
        average: Option<(u64, u64)>,
    ) -> Result<Flow, String> {
        let scene = self.scene.as_ref().ok_or_else(|| {
            "no problem is defined yet: give STArt (or RESTart) first".to_string()
        })?;
        let spec = fields::Spec {
            nodes,
            width,
            kernel,
            region,
        };
        fields::check(scene, &spec)?;
        let sums = fields::sample(scene, &spec);
        match average {
            Some((every, samples)) if samples > 1 => {
                let text = format!(
                    "FIEld: averaging {samples} states every {every} cycles, cycles {} to {} (the first taken){}",
                    scene.cycle(),
                    scene
                        .cycle()
                        .saturating_add(every.saturating_mul(samples - 1)),
                    if self.vtk.average.is_some() {
                        "; the average that was running is dropped"
                    } else {
                        ""
                    }
                );
                self.vtk.average = Some(Average {
                    spec,
                    out,
                    every,
                    samples,
                    next: scene.cycle().saturating_add(every),
                    sums,
                });
                self.emit(&text);
            }
            _ => {
                let text = field_output(scene, &spec, &out, &sums.finish(), self.json)?;
                self.emit(&text);
            }
        }
        Ok(Flow::Continue)
    }

    /// After a run: the running average's sample, if one is due, and its output when it is
    /// the last. A grid the cell has outgrown or an output that cannot be written is a
    /// warning that ends the average.
    fn field_due(&mut self) {
        let (Some(scene), Some(a)) = (self.scene.as_ref(), self.vtk.average.as_mut()) else {
            return;
        };
        if scene.cycle() < a.next {
            return;
        }
        let result = fields::check(scene, &a.spec).and_then(|()| {
            a.sums.add(&fields::sample(scene, &a.spec));
            a.next = scene.cycle().saturating_add(a.every);
            if (a.sums.samples as u64) < a.samples {
                return Ok(None);
            }
            field_output(scene, &a.spec, &a.out, &a.sums.finish(), self.json).map(Some)
        });
        match result {
            Ok(None) => {}
            Ok(Some(text)) => {
                self.vtk.average = None;
                self.emit(&text);
            }
            Err(e) => {
                self.vtk.average = None;
                self.emit_err(&format!("warning: {e}; FIEld AVerage stopped"));
            }
        }
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
            let mut m = match self.vtk.every {
                Some(k) => (k - now % k).min(n - done),
                None => n - done,
            };
            if let Some(a) = &self.vtk.average {
                m = m.min(a.next.saturating_sub(now).max(1));
            }
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
            self.field_due();
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
