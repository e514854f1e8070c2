//! The periodic cell's strain control: GRID (strain rates), GAIN and Mode (the stress
//! servo of `Cycle n S0 σ`), PRObe; `sim::cell`.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Grid { rates } => {
            if let Some(m) = crate::sim::cell::grid_refusal(rates, scene.settings().periodic) {
                return Err(m);
            }
            if !scene.walls().is_empty() && rates.iter().any(|&r| r != 0.0) {
                return Err(format!(
                    "GRID: the scene has {} wall(s), which would not follow the cell's deformation",
                    scene.walls().len()
                ));
            }
            scene.set_strain_rates(*rates);
            Ok(String::new())
        }
        Command::Gain { g, edmax } => {
            if !(g.is_finite() && *g > 0.0 && edmax.is_finite() && *edmax > 0.0) {
                return Err(format!(
                    "GAIN g edmax: both must be positive numbers (g in 1/(s Pa), edmax in 1/s); got {g} {edmax}"
                ));
            }
            scene.set_servo_gain(*g, *edmax);
            Ok(String::new())
        }
        Command::Mode { n } => {
            if !(0..=1).contains(n) {
                return Err(format!(
                    "Mode {n}: the servo mode is 0 (velocity-increment control) or 1 (velocity control)"
                ));
            }
            scene.set_servo_mode(*n as u8);
            Ok(String::new())
        }
        other => Err(not_here(other)),
    }
}

/// `PRObe E11 ...` (`sim::probe::probe`): the modulus of the named strain, the state put back
/// bitwise.
pub fn probe(
    scene: &mut Scene,
    kind: crate::lang::command::ProbeKind,
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
) -> Result<(String, serde_json::Value), String> {
    use crate::lang::command::ProbeKind as P;
    // The rates' direction, and the modulus reported: −Δσ_ab/ε, or for E1M2 ...
    // −(Δσ_aa − Δσ_bb)/2ε (stress compression positive, strain extension positive: a stable
    // packing has a positive modulus).
    let (name, dir, a, b, half) = match kind {
        P::E11 => ("E11", [1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0, 0, false),
        P::E22 => ("E22", [0.0, 1.0, 0.0, 0.0, 0.0, 0.0], 1, 1, false),
        P::E33 => ("E33", [0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 2, 2, false),
        P::E12 => ("E12", [0.0, 0.0, 0.0, 1.0, 0.0, 0.0], 0, 1, false),
        P::E1m2 => ("E1M2", [1.0, -1.0, 0.0, 0.0, 0.0, 0.0], 0, 1, true),
        P::E2m3 => ("E2M3", [0.0, 1.0, -1.0, 0.0, 0.0, 0.0], 1, 2, true),
        P::E3m1 => ("E3M1", [-1.0, 0.0, 1.0, 0.0, 0.0, 0.0], 2, 0, true),
        P::E23 | P::E31 => {
            return Err("PRObe E23/E31: the cell shears only in x-y (ed12; ed23 and ed31 are not used, as in TRUBAL); probe E12".into());
        }
    };
    if scene.particles().is_empty() {
        return Err("PRObe: no particles to probe".into());
    }
    if !scene.walls().is_empty() {
        return Err(
            "PRObe: the scene has walls, which would not follow the cell's deformation".into(),
        );
    }
    if let Some(m) = crate::sim::cell::grid_refusal(&dir, scene.settings().periodic) {
        return Err(format!("PRObe {name}: {m}"));
    }
    let Some(m) = crate::sim::probe::probe_watched(scene, dir, watch).map_err(|e| e.message)?
    else {
        return Err(format!(
            "interrupted: PRObe {name} stopped at Ctrl-C; the state is as before, nothing measured"
        ));
    };
    let modulus = if half {
        -(m[a][a] - m[b][b]) / 2.0
    } else {
        -m[a][b]
    };
    let [c0, c1, c2] = crate::sim::probe::PROBE_CYCLES;
    let text = format!(
        "PRObe {name}: strain {:e} over {c1} cycles between {c0} and {c2} at zero strain rate; state restored\n  modulus {modulus:.6e} Pa\n  dsigma/strain (Pa) {:.6e} {:.6e} {:.6e} / {:.6e} {:.6e} {:.6e} / {:.6e} {:.6e} {:.6e}\n",
        crate::sim::probe::PROBE_STRAIN,
        m[0][0],
        m[0][1],
        m[0][2],
        m[1][0],
        m[1][1],
        m[1][2],
        m[2][0],
        m[2][1],
        m[2][2]
    );
    let j = serde_json::json!({"print": "probe", "probe": name, "modulus": modulus,
        "dstress_per_strain": m, "strain": crate::sim::probe::PROBE_STRAIN, "cycle": scene.cycle()});
    Ok((text, j))
}
