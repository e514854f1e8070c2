//! What a library caller (the Python module, `src/python/`) changes from whole arrays:
//! positions and velocities. Each is one command to the session: checked whole before
//! anything changes (a refused array changes nothing), the kinetic energy it adds or removes
//! booked in the ledger as `VELocity`'s is, and it ends a run of `CReate`s or `AGEnerate`s
//! as any other command does.

use super::Session;

impl Session {
    /// Sets every particle's position (`Scene::set_positions`).
    pub fn set_positions(&mut self, pos: &[[f64; 3]]) -> Result<(), String> {
        self.array_edit(|s| s.set_positions(pos))
    }

    /// Sets every particle's velocity (`Scene::set_velocities`), booking the kinetic energy.
    pub fn set_velocities(&mut self, vel: &[[f64; 3]]) -> Result<(), String> {
        self.array_edit(|s| s.set_velocities(vel))
    }

    fn array_edit(
        &mut self,
        f: impl FnOnce(&mut crate::sim::Scene) -> Result<(), String>,
    ) -> Result<(), String> {
        let scene = self.scene_mut()?;
        scene.end_create_run();
        scene.booked_edit(false, f)?;
        scene.end_lattice_run();
        Ok(())
    }
}
