//! The average stress of the assembly (compression positive, Pa):
//! `σ = (1/V) [Σ_contacts f ⊗ l + Σ_particles m C ⊗ C]`, Shang 1998 (2.50)
//! (doc/spec/shang1998.md §2.7): the contact part (Cundall–Strack/Love, `f` the force on B of
//! the last step, `l` the branch vector A → B, each contact once) and the kinetic part
//! (`C` the velocity relative to the mean field, which is the stored velocity: `sim::cell`).
//! `σ[i][j]` pairs the force component i with the branch component j. `V` is the
//! work-space (cell) volume. Particle–wall contacts are not in the sum (in a cell closed by
//! walls the wall forces give the boundary stress instead: `PRint Walls`).
use super::scene::{Scene, Vec3};

/// The two parts of the average stress and their sum (Pa, compression positive).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stress {
    pub contact: [[f64; 3]; 3],
    pub kinetic: [[f64; 3]; 3],
}

impl Stress {
    pub fn total(&self) -> [[f64; 3]; 3] {
        let mut t = [[0.0; 3]; 3];
        for (a, row) in t.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x = self.contact[a][b] + self.kinetic[a][b];
            }
        }
        t
    }

    /// The mean stress (σ11 + σ22 + σ33)/3 of the total.
    pub fn mean(&self) -> f64 {
        let t = self.total();
        (t[0][0] + t[1][1] + t[2][2]) / 3.0
    }
}

/// The force on B of a particle pair's last step (the sum the step applied): the elastic and
/// dashpot normal forces, the tangential spring and dashpot, the bridge's static, viscous
/// and tangential forces. `n`: unit normal A → B.
pub fn pair_force(s: &super::contacts::ContactState, n: &Vec3) -> Vec3 {
    let mut fnorm = s.damp_force;
    let mut ft = Vec3::zeros();
    if s.touching {
        fnorm += s.normal_force;
        ft += s.tforce + s.tdamp;
    }
    if let Some(b) = &s.bridge {
        fnorm += b.f_visc - b.f_static;
        ft += b.f_tang;
    }
    n * fnorm + ft
}

/// The volume of the work-space (m³).
pub fn volume(scene: &Scene) -> f64 {
    scene.size[0] * scene.size[1] * scene.size[2]
}

/// The contact part of the average stress, Σ f ⊗ l / V.
pub fn contact_part(scene: &Scene) -> [[f64; 3]; 3] {
    let p = &scene.particles;
    let vol = volume(scene);
    let mut sig = [[0.0; 3]; 3];
    for c in scene.contacts.iter() {
        // (Most candidates carry no force: skipped before their branch vector.)
        let s = c.s;
        if !s.touching && s.damp_force == 0.0 && s.bridge.is_none() {
            continue;
        }
        let l = scene.branch(&p.pos[c.i as usize], &p.pos[c.j as usize]);
        let dist = l.norm();
        if dist == 0.0 {
            continue;
        }
        let f = pair_force(s, &(l / dist));
        for (a, row) in sig.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x += f[a] * l[b];
            }
        }
    }
    for row in sig.iter_mut() {
        for x in row.iter_mut() {
            *x /= vol;
        }
    }
    sig
}

/// The kinetic part Σ m C ⊗ C / V.
pub fn kinetic_part(scene: &Scene) -> [[f64; 3]; 3] {
    let p = &scene.particles;
    let vol = volume(scene);
    let mut sig = [[0.0; 3]; 3];
    for i in 0..p.len() {
        let (m, c) = (p.mass[i], p.vel[i]);
        for (a, row) in sig.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x += m * c[a] * c[b];
            }
        }
    }
    for row in sig.iter_mut() {
        for x in row.iter_mut() {
            *x /= vol;
        }
    }
    sig
}

/// Both parts.
pub fn of(scene: &Scene) -> Stress {
    Stress {
        contact: contact_part(scene),
        kinetic: kinetic_part(scene),
    }
}

/// The granular temperature ⟨C·C⟩/3 (m²/s²), the mean over particles (0 without any).
pub fn temperature(scene: &Scene) -> f64 {
    let p = &scene.particles;
    if p.is_empty() {
        return 0.0;
    }
    p.vel.iter().map(|c| c.norm_squared()).sum::<f64>() / (3.0 * p.len() as f64)
}
