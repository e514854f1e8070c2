//! Helpers shared by the physics tests: build a scene from command lines and step it.

#![allow(dead_code)]

use trubal::session::Session;
use trubal::sim::{Scene, cycle};

/// Runs command lines in a session whose output is discarded; panics on an error.
pub fn session(lines: &str) -> Session {
    let mut s = Session::new(Box::new(std::io::sink()), false);
    for (k, l) in lines.lines().enumerate() {
        if let Err(e) = s.run_line(l) {
            panic!("line {}: `{l}`: {}", k + 1, e.message);
        }
    }
    s
}

pub fn scene(lines: &str) -> Scene {
    session(lines).scene.expect("a Start in the lines")
}

/// One step.
pub fn step(scene: &mut Scene) {
    cycle::run(scene, 1).unwrap_or_else(|b| panic!("{}", b.message));
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Sets a particle's velocity and books the change of kinetic energy as a command input (as
/// the session does for commands).
pub fn set_velocity(scene: &mut Scene, i: usize, v: trubal::sim::Vec3) {
    let before = trubal::sim::energy::stored(scene).total();
    scene.particles.vel[i] = v;
    scene.ledger.commands += trubal::sim::energy::stored(scene).total() - before;
}
