//! TRUBAL's `PRObe`: the moduli of a packing in the deforming periodic cell (`sim::cell`),
//! measured by cycling it (`sim::cycle`) through a small strain and putting it back.

use super::cycle::{self, Blowup};
use super::params::Model;
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
    let m = probe_watched(scene, dir, &mut |_, _| false)?;
    // (Invariant: the watcher never stops the probe, so it runs to its end.)
    Ok(m.expect("a probe no watcher stops runs to its end"))
}

/// [`probe`] with a watcher, called before each of its steps with the scene and the steps
/// done so far (of the 1250): when it answers `true` the probe stops and the scene is put
/// back as it was; `None` then (nothing measured).
pub fn probe_watched(
    scene: &mut Scene,
    dir: [f64; 6],
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
) -> Result<Option<[[f64; 3]; 3]>, Blowup> {
    let kept = scene.clone();
    let r = probe_run(scene, dir, watch);
    *scene = kept;
    r
}

/// The three runs of a probe; `None` if the watcher stopped one.
fn probe_run(
    scene: &mut Scene,
    dir: [f64; 6],
    watch: &mut (dyn FnMut(&Scene, u64) -> bool + Send),
) -> Result<Option<[[f64; 3]; 3]>, Blowup> {
    let [quiet, strain, settle] = PROBE_CYCLES;
    let mut done = 0;
    // One of the three runs, watched with the probe's count of steps; false if stopped.
    let mut run = |scene: &mut Scene, n: u64| -> Result<(Model, bool), Blowup> {
        let start = done;
        let (model, ran) = cycle::run_watched(scene, n, &mut |s, k| watch(s, start + k))?;
        done += ran;
        Ok((model, ran == n))
    };
    scene.cell.rate = [0.0; 6];
    let (model, whole) = run(scene, quiet)?;
    if !whole {
        return Ok(None);
    }
    let before = stress::of(scene).total();
    let rate = PROBE_STRAIN / (strain as f64 * model.dt);
    scene.cell.rate = dir.map(|d| d * rate);
    if !run(scene, strain)?.1 {
        return Ok(None);
    }
    scene.cell.rate = [0.0; 6];
    if !run(scene, settle)?.1 {
        return Ok(None);
    }
    let after = stress::of(scene).total();
    let mut m = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            m[a][b] = (after[a][b] - before[a][b]) / PROBE_STRAIN;
        }
    }
    Ok(Some(m))
}
