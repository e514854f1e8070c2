//! TRUBAL's `PRObe`: the moduli of a packing in the deforming periodic cell (`sim::cell`),
//! measured by cycling it (`sim::cycle`) through a small strain and putting it back.

use super::cycle::{self, Blowup};
use super::scene::Scene;
use super::stress;

/// The strain of a probe (`PRObe`): small enough to stay elastic in a Hertz packing
/// whose overlaps are ~1e-3 of the radius.
pub const PROBE_STRAIN: f64 = 1e-5;
/// TRUBAL's probe: cycles at zero strain, probing cycles, cycles at zero strain again.
pub const PROBE_CYCLES: [u64; 3] = [500, 250, 500];

/// TRUBAL's `PRObe`: from the current state, 500 cycles at zero strain rate, 250 cycles
/// straining along `dir` (rates proportional to `dir`, a total strain of
/// [`PROBE_STRAIN`] along it), 500 cycles at zero strain rate; returns the change of the
/// average stress per unit probe strain (Pa). The scene is then put back exactly as it was
/// (a clone: every bit, the contact states included).
pub fn probe(scene: &mut Scene, dir: [f64; 6]) -> Result<[[f64; 3]; 3], Blowup> {
    let kept = scene.clone();
    let r = probe_run(scene, dir);
    *scene = kept;
    r
}

fn probe_run(scene: &mut Scene, dir: [f64; 6]) -> Result<[[f64; 3]; 3], Blowup> {
    let [quiet, strain, settle] = PROBE_CYCLES;
    scene.cell.rate = [0.0; 6];
    let model = cycle::run(scene, quiet)?;
    let before = stress::of(scene).total();
    let rate = PROBE_STRAIN / (strain as f64 * model.dt);
    scene.cell.rate = dir.map(|d| d * rate);
    cycle::run(scene, strain)?;
    scene.cell.rate = [0.0; 6];
    cycle::run(scene, settle)?;
    let after = stress::of(scene).total();
    let mut m = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            m[a][b] = (after[a][b] - before[a][b]) / PROBE_STRAIN;
        }
    }
    Ok(m)
}
