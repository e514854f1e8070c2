//! Size types and materials: RAdius, Density, YMD, PRA, FRiction, COHesion.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Radius { r, size, dist } => {
            scene.set_size_type(*size, *r, dist.clone())?;
            Ok(String::new())
        }
        Command::Density { rho, material } => {
            scene.set_density(*material, *rho)?;
            Ok(String::new())
        }
        Command::Ymd { e, material } => {
            scene.set_young(*material, *e)?;
            Ok(String::new())
        }
        Command::Pra { nu, material } => {
            scene.set_poisson(*material, *nu)?;
            Ok(String::new())
        }
        Command::Friction { mu, material } => {
            scene.set_friction(*material, *mu)?;
            Ok(String::new())
        }
        Command::Cohesion {
            gamma,
            material,
            base,
        } => {
            existing_material(scene, *material)?;
            scene.set_cohesion(*material, *gamma, base.unwrap_or(*gamma))?;
            Ok(String::new())
        }
        other => Err(not_here(other)),
    }
}
