//! Size types and materials: RAdius, Density, YMD, PRA, FRiction, COHesion.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Radius { r, size, dist } => {
            // A radius larger than the work-space is a typing slip, never a scene.
            let largest = match dist {
                SizeDist::Fixed => *r,
                SizeDist::Normal { sd } => r + 3.0 * sd,
                SizeDist::Uniform { max, .. } => max.max(*r),
                SizeDist::Table { radius, .. } => radius.iter().copied().fold(*r, f64::max),
            };
            let side = scene.size().into_iter().fold(0.0, f64::max);
            if !(largest <= side) {
                let num = |x: f64| {
                    if (1e-4..1e6).contains(&x.abs()) {
                        format!("{x}")
                    } else {
                        format!("{x:e}")
                    }
                };
                return Err(format!(
                    "a radius of {} m is larger than the work-space (its largest side is {side} m): accepted 0 < r <= {side} m",
                    num(largest)
                ));
            }
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
