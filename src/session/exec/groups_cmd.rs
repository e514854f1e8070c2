//! Groups and ranges (doc/groups.md): GROup, PROPerty (and VELocity over a range), DELete
//! over a range. `Fix` over a range is in `motion.rs`.

use super::*;
use crate::sim::range::Range;

/// The particles in `range` now, or an error if there are none (the command changes
/// nothing).
pub(super) fn members_nonempty(scene: &Scene, range: &Range) -> Result<Vec<usize>, String> {
    let m = scene.members(range)?;
    if m.is_empty() {
        return Err(format!(
            "no particle is in the range `{}`: nothing changed",
            range.text()
        ));
    }
    Ok(m)
}

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Group { name, action } => match action {
            GroupAction::Define { range, dynamic } => scene.define_group(name, range, *dynamic),
            GroupAction::Forget => scene.forget_group(name),
            GroupAction::Record(on) => scene.record_group(name, *on),
        },
        Command::Property { what, range } => {
            if let Property::Material(m) = what {
                existing_material(scene, *m)?;
            }
            let m = members_nonempty(scene, range)?;
            let what = match what {
                Property::Velocity(v) => {
                    scene.set_velocity_of(&m, *v);
                    "velocity"
                }
                Property::Spin(w) => {
                    scene.set_spin_of(&m, *w);
                    "spin"
                }
                Property::Material(k) => {
                    scene.set_material_of(&m, *k);
                    "material"
                }
            };
            Ok(format!("{what} set for {} particles", m.len()))
        }
        Command::DeleteRange { range } => {
            let m = scene.members(range)?;
            place::delete_members(scene, &m, &format!("`{}`", range.text()))
        }
        other => Err(not_here(other)),
    }
}
