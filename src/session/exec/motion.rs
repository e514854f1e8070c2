//! Motion of the particles: Fix, FMM, FRO, GRAvity, CGRavity, VELocity, VMU, Zero, RESet.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Fix { flags, target } => {
            let bits = flags
                .iter()
                .enumerate()
                .fold(0u8, |b, (k, &f)| if f { b | (1 << k) } else { b });
            match target {
                FixTarget::All => scene.particles.fixed.iter_mut().for_each(|f| *f = bits),
                FixTarget::Particle(id) => {
                    let i = index_of(scene, *id)?;
                    scene.particles.fixed[i] = bits;
                }
            }
            Ok(String::new())
        }
        Command::Fmm { r } => {
            scene.fmm *= r;
            Ok(String::new())
        }
        Command::Fro => {
            scene
                .particles
                .spin
                .iter_mut()
                .for_each(|w| *w = Vec3::zeros());
            Ok(String::new())
        }
        Command::Gravity { g } => {
            scene.gravity = *g;
            Ok(String::new())
        }
        Command::Cgravity { nagg, g } => {
            if scene.regions[nagg - 1].is_none() {
                return Err(format!("agglomerate region {nagg} is not defined"));
            }
            scene.cgravity[nagg - 1] = *g;
            Ok(String::new())
        }
        Command::Velocity { v1, v2, ivd } => {
            let p = &mut scene.particles;
            let n1 = p.agg.iter().filter(|&&a| a == 1).count();
            if n1 == 0 {
                return Err("agglomerate 1 has no particles".into());
            }
            if v2.is_some() && p.agg.iter().all(|&a| a != 2) {
                return Err("agglomerate 2 has no particles".into());
            }
            for i in 0..p.len() {
                match p.agg[i] {
                    1 => p.vel[i] = Vec3::from(*v1),
                    2 => {
                        if let Some(v) = v2 {
                            p.vel[i] = Vec3::from(*v)
                        }
                    }
                    _ => {}
                }
            }
            scene.impact = *ivd;
            Ok(String::new())
        }
        Command::Vmu { r } => {
            let p = &mut scene.particles;
            for i in 0..p.len() {
                for k in 0..3 {
                    if p.fixed[i] & (1 << k) != 0 {
                        p.vel[i][k] *= r;
                    }
                    if p.fixed[i] & (8 << k) != 0 {
                        p.spin[i][k] *= r;
                    }
                }
            }
            Ok(String::new())
        }
        Command::Zero { always } => {
            scene
                .particles
                .vel
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            scene
                .particles
                .spin
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            scene.zero_always = *always;
            Ok(String::new())
        }
        Command::Reset => {
            scene
                .particles
                .rot
                .iter_mut()
                .for_each(|v| *v = Vec3::zeros());
            Ok(String::new())
        }
        other => Err(not_here(other)),
    }
}

fn index_of(scene: &Scene, id: usize) -> Result<usize, String> {
    scene
        .particles
        .id
        .iter()
        .position(|&x| x as usize == id)
        .ok_or_else(|| format!("particle {id} does not exist"))
}
