//! Motion of the particles: Fix, FMM, FRO, GRAvity, CGRavity, VELocity, VMU, Zero, RESet.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Fix { flags, target } => {
            let bits = flags
                .iter()
                .enumerate()
                .fold(0u8, |b, (k, &f)| if f { b | (1 << k) } else { b });
            if let FixTarget::Range(r) = target {
                // Over a dynamic group the Fix stands (doc/groups.md).
                if let Some(name) = r.single_group()
                    && scene.groups().get(name).is_some_and(|g| g.ids.is_none())
                {
                    return scene.fix_dynamic_group(name, bits);
                }
                let m = super::groups_cmd::members_nonempty(scene, r)?;
                scene.fix_members(bits, &m);
                return Ok(format!("fixed {} particles", m.len()));
            }
            let i = match target {
                FixTarget::All | FixTarget::Range(_) => None,
                FixTarget::Particle(id) => Some(
                    scene
                        .index_of(*id)
                        .ok_or_else(|| format!("particle {id} does not exist"))?,
                ),
            };
            scene.fix(bits, i);
        }
        Command::Fmm { r } => scene.scale_fmm(*r),
        Command::Fro => scene.stop_spins(),
        Command::Gravity { g } => scene.set_gravity(*g),
        Command::Cgravity { nagg, g } => scene.set_cgravity(*nagg, *g)?,
        Command::Velocity { v1, v2, ivd } => scene.set_agglomerate_velocity(*v1, *v2, *ivd)?,
        Command::Vmu { r } => scene.scale_fixed_velocities(*r),
        Command::Zero { always } => scene.zero_velocities(*always),
        Command::Reset => scene.reset_rotations(),
        other => return Err(not_here(other)),
    }
    Ok(String::new())
}
