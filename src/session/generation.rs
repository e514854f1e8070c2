//! The generation commands that can run long (`AGEnerate`, `RGEnerate`, `RGEnerate Seed`)
//! watched like a `Cycle`: the progress line on a terminal, and Ctrl-C stopping them. A
//! stopped command changes nothing (`sim::place`: the places are found first, then the
//! particles added), so the session is as before it and the command can be given again.

use std::cell::Cell;

use super::{Flow, Session, exec, interrupt, progress};
use crate::lang::command::Command;

impl Session {
    /// Runs a generation command under watch.
    pub(super) fn generate(&mut self, cmd: &Command) -> Result<Flow, String> {
        let mut progress = progress::Progress::new(0, self.json);
        let stopped = Cell::new(false);
        let scene = self.scene_mut()?;
        let mut watch = |a: &crate::sim::generate::Advance| {
            progress.tick_advance(a);
            if interrupt::requested() {
                stopped.set(true);
                return false;
            }
            true
        };
        let r = scene.booked_edit(false, |s| exec::apply_watched(s, cmd, &mut watch));
        progress.finish();
        if stopped.get() {
            interrupt::clear();
            let why = r.err().unwrap_or_default();
            self.emit_err(&format!("interrupted: {why}"));
            return Ok(Flow::Interrupted);
        }
        let text = r?;
        self.emit_command_text(&text);
        Ok(Flow::Continue)
    }

    /// A command's text: its `warning: ` lines to standard error with the other
    /// diagnostics, the rest to the output.
    pub(super) fn emit_command_text(&mut self, text: &str) {
        let mut out = String::new();
        for line in text.lines() {
            match line.strip_prefix("warning: ") {
                Some(w) => self.emit_err(&format!("warning: {w}")),
                None => {
                    out.push_str(line);
                    out.push('\n');
                }
            }
        }
        self.emit(&out);
    }
}
