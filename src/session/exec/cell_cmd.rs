//! The periodic cell's strain control: GRID (strain rates), GAIN and Mode (the stress
//! servo of `Cycle n S0 σ`), `sim::cell`.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Grid { rates } => {
            if let Some(m) = crate::sim::cell::grid_refusal(rates, scene.settings.periodic) {
                return Err(m);
            }
            if !scene.walls.is_empty() && rates.iter().any(|&r| r != 0.0) {
                return Err(format!(
                    "GRID: the scene has {} wall(s), which would not follow the cell's deformation",
                    scene.walls.len()
                ));
            }
            scene.cell.rate = *rates;
            Ok(String::new())
        }
        Command::Gain { g, edmax } => {
            if !(g.is_finite() && *g > 0.0 && edmax.is_finite() && *edmax > 0.0) {
                return Err(format!(
                    "GAIN g edmax: both must be positive numbers (g in 1/(s Pa), edmax in 1/s); got {g} {edmax}"
                ));
            }
            scene.cell.gain = [*g, *edmax];
            Ok(String::new())
        }
        Command::Mode { n } => {
            if !(0..=1).contains(n) {
                return Err(format!(
                    "Mode {n}: the servo mode is 0 (velocity-increment control) or 1 (velocity control)"
                ));
            }
            scene.cell.mode = *n as u8;
            Ok(String::new())
        }
        other => Err(not_here(other)),
    }
}
