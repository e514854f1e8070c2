//! Applies a command to the scene. Every function here either succeeds or returns an error
//! and leaves the scene as it was (the caller works on a copy for multi-step changes).

use crate::lang::command::*;
use crate::sim::generate::Watch;
use crate::sim::place;
use crate::sim::scene::{Rayleigh, Scene, Vec3, Wall};
use crate::sim::walls;

mod cell_cmd;
pub use cell_cmd::probe;
mod groups_cmd;
mod materials;
mod model;
mod motion;
mod walls_cmd;

fn existing_material(scene: &Scene, m: usize) -> Result<(), String> {
    if !scene.material_defined(m) {
        return Err(format!(
            "material type {m} is not defined: give it YMD, PRA and Density first"
        ));
    }
    Ok(())
}

/// Applies a scene command: the session's handlers by command group, and particle placement
/// through `sim::place`.
pub fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    apply_watched(scene, cmd, &mut |_| true)
}

/// [`apply`], with the session's watch over the generation commands that can run long
/// (`AGEnerate`, `RGEnerate`, `RGEnerate Seed`: progress line and Ctrl-C).
pub fn apply_watched(scene: &mut Scene, cmd: &Command, watch: Watch) -> Result<String, String> {
    match cmd {
        Command::Radius { .. }
        | Command::Density { .. }
        | Command::Ymd { .. }
        | Command::Pra { .. }
        | Command::Friction { .. }
        | Command::Cohesion { .. } => materials::apply(scene, cmd),
        Command::Agglomerate {
            nagg,
            centre,
            radius,
        } => place::define_region(scene, *nagg, *centre, *radius),
        Command::Create {
            pos,
            vel,
            spin,
            size,
            material,
        } => place::create(scene, *pos, *vel, *spin, *size, *material),
        Command::Agenerate {
            size,
            material,
            nagg,
            origin,
            step,
        } => place::lattice(scene, *size, *material, *nagg, *origin, *step, watch),
        Command::Rgenerate {
            n,
            size,
            material,
            nagg,
            walls,
        } => place::random(scene, (*n, *size, *material, *nagg), *walls, watch),
        Command::Move { nagg, d } => place::move_agglomerate(scene, *nagg, *d),
        Command::Delete { bounds } => place::delete_in_box(scene, *bounds),
        Command::RgenerateSeed { n } => place::discard_random(scene, *n, watch),
        Command::Dwall(_) | Command::Awall { .. } => walls_cmd::apply(scene, cmd),
        Command::Group { .. } | Command::Property { .. } | Command::DeleteRange { .. } => {
            groups_cmd::apply(scene, cmd)
        }
        Command::Grid { .. } | Command::Gain { .. } | Command::Mode { .. } => {
            cell_cmd::apply(scene, cmd)
        }
        Command::Damping(_)
        | Command::Fraction { .. }
        | Command::Liquid { .. }
        | Command::Window { .. }
        | Command::TwoD
        | Command::Set(_) => model::apply(scene, cmd),
        Command::Fix { .. }
        | Command::Fmm { .. }
        | Command::Fro
        | Command::Gravity { .. }
        | Command::Cgravity { .. }
        | Command::Velocity { .. }
        | Command::Vmu { .. }
        | Command::Zero { .. }
        | Command::Reset => motion::apply(scene, cmd),
        other => Err(not_here(other)),
    }
}

/// The error of a command that is not this handler's (the dispatch above is wrong).
fn not_here(cmd: &Command) -> String {
    format!(
        "internal: {} is not a scene command",
        crate::lang::parse::command_name(cmd)
    )
}
