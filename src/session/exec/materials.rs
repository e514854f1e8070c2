//! Size types and materials: RAdius, Density, YMD, PRA, FRiction, COHesion.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Radius { r, size, dist } => {
            if *size > MAX_SIZES {
                return Err(format!(
                    "size type {size} is beyond the limit of {MAX_SIZES}"
                ));
            }
            if *size > scene.sizes.len() {
                scene.sizes.resize(*size, 0.0);
                scene.size_dist.resize(*size, Default::default());
            }
            scene.sizes[size - 1] = *r;
            scene.size_dist[size - 1] = dist.clone();
            // Particles of a fixed size type change radius (and mass).
            let p = &mut scene.particles;
            for i in 0..p.len() {
                if *dist == SizeDist::Fixed && p.size[i] as usize == *size {
                    let rho = p.mass[i] / sphere_mass(1.0, p.radius[i]);
                    p.radius[i] = *r;
                    p.mass[i] = sphere_mass(rho, *r);
                }
            }
            scene.contacts.mark_stale();
            Ok(String::new())
        }
        Command::Density { rho, material } => {
            material_mut(scene, *material)?.density = *rho;
            refresh_masses(scene, *material);
            Ok(String::new())
        }
        Command::Ymd { e, material } => {
            material_mut(scene, *material)?.young = *e;
            Ok(String::new())
        }
        Command::Pra { nu, material } => {
            material_mut(scene, *material)?.poisson = *nu;
            Ok(String::new())
        }
        Command::Friction { mu, material } => {
            material_mut(scene, *material)?.friction = *mu;
            Ok(String::new())
        }
        Command::Cohesion {
            gamma,
            material,
            base,
        } => {
            existing_material(scene, *material)?;
            let m = material_mut(scene, *material)?;
            m.gamma = *gamma;
            m.gamma_base = base.unwrap_or(*gamma);
            scene.contacts.mark_stale();
            Ok(String::new())
        }
        other => Err(not_here(other)),
    }
}

/// Re-computes particle masses of a material after a density change.
fn refresh_masses(scene: &mut Scene, m: usize) {
    let rho = scene.materials[m - 1].density;
    let p = &mut scene.particles;
    for i in 0..p.len() {
        if p.material[i] as usize == m {
            p.mass[i] = sphere_mass(rho, p.radius[i]);
        }
    }
}
