//! `Cycle n [servo] [CALL name EVery k] [UNTIL cond]`: the procedure runs after every step
//! that ends at a cycle which is a multiple of k (the Cycle runs in pieces that end there, as
//! for `VTk EVery`: the same bits as one piece); the condition is read after every step, and
//! the first step after which it holds is the last. Both depend on the cycle count and the
//! state only, so a run saved and restarted between two Cycles goes on with the same bits.

use std::collections::BTreeMap;

use super::query::Names;
use crate::lang::command::StressServo;
use crate::lang::expr::{self, Expr};
use crate::session::{Flow, Session};
use crate::sim::Scene;

/// The hooks of the Cycle being run.
#[derive(Debug, Default)]
pub struct Hooks {
    pub call: Option<(String, u64)>,
    pub until: Option<Expr>,
    /// The condition held after the last step.
    pub met: bool,
    /// The error of the procedure or of the condition, which stopped the Cycle.
    pub error: Option<String>,
}

/// The condition of UNTIL as the step's watcher reads it: with the variables as they were
/// when the piece began (only the procedure changes them, between pieces).
pub struct Until {
    pub expr: Expr,
    pub vars: BTreeMap<String, f64>,
    pub met: bool,
    pub error: Option<String>,
}

impl Until {
    /// Whether the Cycle stops after this step.
    pub fn reached(&mut self, s: &Scene) -> bool {
        let names = Names {
            vars: &self.vars,
            scene: Some(s),
        };
        match expr::eval(&self.expr, &names) {
            Ok(v) => {
                self.met = v != 0.0;
                self.met
            }
            Err(e) => {
                self.error = Some(format!("UNTIL: {} (column {})", e.message, e.start + 1));
                true
            }
        }
    }
}

impl Session {
    /// A procedure called by a Cycle's CALL may not cycle.
    pub(in crate::session) fn refuse_in_hook(
        &self,
        cmd: &crate::lang::Command,
    ) -> Result<(), String> {
        use crate::lang::Command::{Cycle, Probe, Relax};
        if self.script.in_hook && matches!(cmd, Cycle { .. } | Relax { .. } | Probe { .. }) {
            return Err("a procedure called by a Cycle's CALL cannot cycle".into());
        }
        Ok(())
    }

    pub(super) fn cycle_scripted(
        &mut self,
        n: u64,
        servo: &[(StressServo, f64)],
        call: Option<&(String, u64)>,
        until: Option<&Expr>,
    ) -> Result<Flow, String> {
        if self.script.in_hook {
            return Err("a procedure called by a Cycle's CALL cannot cycle".into());
        }
        if let Some((name, _)) = call {
            match self.script.state.procs.get(name) {
                None => return Err(format!("no procedure `{name}`: DEFine it first")),
                Some(p) if !p.params.is_empty() => {
                    return Err(format!(
                        "{name} takes parameters ({}): a Cycle's CALL gives none; call a procedure without parameters",
                        p.params.join(" ")
                    ));
                }
                _ => {}
            }
        }
        let start = self.scene_mut()?.cycle();
        if let Some(u) = until {
            let now = expr::eval(u, &self.names())
                .map_err(|e| format!("UNTIL: {} (column {})", e.message, e.start + 1))?;
            if now != 0.0 {
                self.emit(&format!(
                    "Cycle: UNTIL already holds at cycle {start}: no cycles run"
                ));
                return Ok(Flow::Continue);
            }
        }
        self.script.hooks = Some(Hooks {
            call: call.cloned(),
            until: until.cloned(),
            met: false,
            error: None,
        });
        let r = if servo.is_empty() {
            self.cycle(n)
        } else {
            self.cycle_servo(n, servo)
        };
        let hooks = self.script.hooks.take().unwrap_or_default();
        if let Some(e) = hooks.error {
            let at = self.scene_mut()?.cycle();
            return Err(format!("{e}; the Cycle stopped at cycle {at}"));
        }
        let flow = r?;
        if hooks.met {
            let at = self.scene_mut()?.cycle();
            self.emit(&format!(
                "Cycle: UNTIL holds at cycle {at}, after {} of at most {n} cycles",
                at - start
            ));
        }
        Ok(flow)
    }

    /// The next piece of a Cycle ends at the next multiple of the CALL's k (or sooner).
    pub(in crate::session) fn hook_piece(&self, cycle: u64, m: u64) -> u64 {
        match self.script.hooks.as_ref().and_then(|h| h.call.as_ref()) {
            Some((_, k)) => m.min(k - cycle % k),
            None => m,
        }
    }

    /// The watcher's condition for the next piece, if the Cycle has one.
    pub(in crate::session) fn hook_until(&self) -> Option<Until> {
        let u = self.script.hooks.as_ref()?.until.as_ref()?;
        Some(Until {
            expr: u.clone(),
            vars: self.script.state.vars.clone(),
            met: false,
            error: None,
        })
    }

    /// After a piece: the condition's outcome kept; the procedure called when the piece
    /// ended at a multiple of k. False when the Cycle must stop.
    pub(in crate::session) fn after_piece(&mut self, until: Option<Until>, complete: bool) -> bool {
        let Some(h) = self.script.hooks.as_mut() else {
            return true;
        };
        if let Some(u) = until {
            h.met = u.met;
            if u.error.is_some() {
                h.error = u.error;
                return false;
            }
            if u.met {
                return false;
            }
        }
        if !complete {
            return false;
        }
        let Some((name, k)) = h.call.clone() else {
            return true;
        };
        let Some(cycle) = self.scene.as_ref().map(|s| s.cycle()) else {
            return false;
        };
        if !cycle.is_multiple_of(k) {
            return true;
        }
        self.script.in_hook = true;
        let r = self.call(&name, &[]);
        self.script.in_hook = false;
        // (Invariant: the hooks are set for the whole Cycle that calls this.)
        let h = self.script.hooks.as_mut().expect("set for the Cycle");
        match r {
            Ok(Flow::Continue) => true,
            Ok(Flow::Interrupted) => false,
            Ok(Flow::Stop) => {
                h.error = Some(format!(
                    "STOp in {name}, called by the Cycle: the Cycle stops"
                ));
                false
            }
            Err(e) => {
                h.error = Some(e);
                false
            }
        }
    }
}
