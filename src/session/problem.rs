//! `STArt` and `RESTart`: a new problem, or one read from a checkpoint together with the
//! command language's state (its variables, procedures and histories join the session's).

use super::*;

impl Session {
    /// `STArt` / `RESTart`; `None` for any other command.
    pub(super) fn problem(&mut self, cmd: &Command) -> Option<Result<Flow, String>> {
        match cmd {
            Command::Start { .. } | Command::Restart { .. } => Some(self.problem_now(cmd)),
            _ => None,
        }
    }

    fn problem_now(&mut self, cmd: &Command) -> Result<Flow, String> {
        match cmd {
            Command::Start {
                size,
                nbox,
                nball,
                nwall,
                log,
            } => {
                if self.scene.is_some() {
                    return Err("a problem is already defined: give New first, then STArt".into());
                }
                self.scene = Some(Scene::new(*size, *nbox, *nball, *nwall));
                // A new problem starts its VTK series anew (doc/output.md).
                self.vtk.series = None;
                self.vtk.resume = false;
                self.vtk.average = None;
                if *log {
                    self.execute(&Command::Log {
                        on: true,
                        file: None,
                    })?;
                }
                return Ok(Flow::Continue);
            }
            Command::Restart { file } => {
                if self.scene.is_some() {
                    return Err("a problem is already defined: give New first, then RESTart".into());
                }
                let name = file.clone().unwrap_or_else(|| "save.old".into());
                let (scene, state) = checkpoint::load_with(&self.path(&name))?;
                // The file's variables and procedures join the session's (a name in both
                // takes the file's).
                self.script.state.vars.extend(state.vars);
                self.script.state.procs.extend(state.procs);
                let hs = &mut self.script.state.histories;
                hs.retain(|h| state.histories.iter().all(|g| g.name != h.name));
                hs.extend(state.histories);
                self.emit(&format!("restarted from {name} at cycle {}", scene.cycle()));
                self.scene = Some(scene);
                // The series goes on from its index on disk (`output::vtk::resume`).
                self.vtk.series = None;
                self.vtk.resume = true;
                self.vtk.average = None;
                return Ok(Flow::Continue);
            }
            _ => {}
        }
        Ok(Flow::Continue)
    }
}
