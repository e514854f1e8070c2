//! The average stress of the assembly (compression positive, Pa):
//! `σ = (1/V) [Σ_contacts f ⊗ l + Σ_particles m C ⊗ C]`, Shang 1998 (2.50)
//! (doc/spec/shang1998.md §2.7): the contact part (Cundall–Strack/Love, `f` the force on B of
//! the last step, `l` the branch vector A → B, each contact once) and the kinetic part
//! (`C` the velocity relative to the mean field, which is the stored velocity: `sim::cell`).
//! `σ[i][j]` pairs the force component i with the branch component j. `V` is the
//! work-space (cell) volume. Particle–wall contacts are not in the sum (in a cell closed by
//! walls the wall forces give the boundary stress instead: `PRint Walls`).
//!
//! [`in_box`] is the stress of a bin (a box, `PRint Stress` with a `Window`): the particles
//! whose centre lies in it with all their contacts, walls included (Pasha 2013 (5.1), Bagi).
use super::scene::{Scene, Vec3};
use super::walls::WallShape;

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

/// Adds `−f ⊗ l` to `sig` (`f` the force on a particle, `l` its centre → the contact point).
fn add_particle_term(sig: &mut [[f64; 3]; 3], f: &Vec3, l: &Vec3) {
    for (a, row) in sig.iter_mut().enumerate() {
        for (b, x) in row.iter_mut().enumerate() {
            *x -= f[a] * l[b];
        }
    }
}

/// The stress in a bin, the box `b` = [x1, x2, y1, y2, z1, z2] (Pa, compression positive),
/// and the number of particles in it. Pasha 2013 (5.1) (Bagi 1996; `doc/spec/pasha2013.md`
/// §5): `σ = −(1/V) Σ_{p in the bin} Σ_{contacts of p} F ⊗ (x_c − x_p)`, `F` the force on the
/// particle, `x_c` the contact point, summed over the particles whose centre lies in the box
/// (bounds included) and all of their contacts, particle–wall ones included; `V` is the box's
/// volume (a bin that an indenter or a wall cuts is not corrected: Pasha skips such bins).
/// The contact point is the middle of the overlap (of the gap for a bridge), on the line of
/// centres (on the wall's normal). Summed over a box that holds every particle, the
/// particle–particle terms give [`contact_part`]'s `Σ f ⊗ l` (the contact points cancel).
/// The kinetic part is `Σ m C ⊗ C / V` over the same particles.
pub fn in_box(scene: &Scene, b: &[f64; 6]) -> (Stress, usize) {
    let p = &scene.particles;
    let inside = |x: &Vec3| {
        b[0] <= x.x && x.x <= b[1] && b[2] <= x.y && x.y <= b[3] && b[4] <= x.z && x.z <= b[5]
    };
    let vol = (b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]);
    let mut sig = [[0.0; 3]; 3];
    let mut kin = [[0.0; 3]; 3];
    let is_in: Vec<bool> = p.pos.iter().map(inside).collect();
    let count = is_in.iter().filter(|&&x| x).count();
    if count == 0 || vol <= 0.0 {
        return (Stress::default(), count);
    }
    for c in scene.contacts.iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        if !is_in[i] && !is_in[j] {
            continue;
        }
        let Some((fb, arm_i, arm_j)) = pair_terms(scene, i, j, c.s) else {
            continue;
        };
        if is_in[i] {
            add_particle_term(&mut sig, &(-fb), &arm_i);
        }
        if is_in[j] {
            add_particle_term(&mut sig, &fb, &arm_j);
        }
    }
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    for c in &scene.contacts.wall_pairs {
        let i = c.i as usize;
        if !is_in[i] {
            continue;
        }
        if let Some((fw, arm)) = wall_term(scene, &shapes, c) {
            add_particle_term(&mut sig, &(-fw), &arm);
        }
    }
    for i in (0..p.len()).filter(|&i| is_in[i]) {
        let (m, v) = (p.mass[i], p.vel[i]);
        for (a, row) in kin.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x += m * v[a] * v[b];
            }
        }
    }
    for row in sig.iter_mut().chain(kin.iter_mut()) {
        for x in row.iter_mut() {
            *x /= vol;
        }
    }
    (
        Stress {
            contact: sig,
            kinetic: kin,
        },
        count,
    )
}

/// A pair contact's terms of [`in_box`]: the force on B and the arms from A's and from B's
/// centre to the contact point (the middle of the overlap, or of the gap: R − δ/2 from each
/// centre); `None` for a pair that carries no force or whose centres coincide.
fn pair_terms(
    scene: &Scene,
    i: usize,
    j: usize,
    s: &super::contacts::ContactState,
) -> Option<(Vec3, Vec3, Vec3)> {
    let p = &scene.particles;
    if !s.touching && s.damp_force == 0.0 && s.bridge.is_none() {
        return None;
    }
    let l = scene.branch(&p.pos[i], &p.pos[j]);
    let dist = l.norm();
    if dist == 0.0 {
        return None;
    }
    let u = l / dist;
    let fb = pair_force(s, &u);
    let half = 0.5 * (p.radius[i] + p.radius[j] - dist);
    Some((fb, u * (p.radius[i] - half), -u * (p.radius[j] - half)))
}

/// A particle–wall contact's terms of [`in_box`]: the force on the wall and the arm from the
/// particle's centre to the contact point (the middle of the overlap, on the wall's normal).
fn wall_term(
    scene: &Scene,
    shapes: &[WallShape],
    c: &super::contacts::WallPair,
) -> Option<(Vec3, Vec3)> {
    let p = &scene.particles;
    let i = c.i as usize;
    let s = &c.s;
    if !s.touching && s.damp_force == 0.0 && s.bridge.is_none() {
        return None;
    }
    let shape = shapes.get(c.wall as usize)?;
    // n: from the particle towards the wall (the wall is B).
    let (gap, n) = shape.gap(&p.pos[i], p.radius[i]);
    Some((pair_force(s, &n), n * (p.radius[i] + 0.5 * gap)))
}

/// Each particle's moment `−Σ_{contacts of p} F ⊗ (x_c − x_p)` (Pa m³), the terms [`in_box`]
/// sums over the particles of a bin (the same contacts, forces and contact points): the
/// box kernel of `FIEld … BIN` adds them up cell by cell.
pub fn particle_moments(scene: &Scene) -> Vec<[[f64; 3]; 3]> {
    let mut m = vec![[[0.0; 3]; 3]; scene.particles.len()];
    for c in scene.contacts.iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        if let Some((fb, arm_i, arm_j)) = pair_terms(scene, i, j, c.s) {
            add_particle_term(&mut m[i], &(-fb), &arm_i);
            add_particle_term(&mut m[j], &fb, &arm_j);
        }
    }
    let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
    for c in &scene.contacts.wall_pairs {
        if let Some((fw, arm)) = wall_term(scene, &shapes, c) {
            add_particle_term(&mut m[c.i as usize], &(-fw), &arm);
        }
    }
    m
}

/// The deviatoric stress of Pasha 2013 (5.3): `((σxx − σyy)² + (σxx − σzz)² + (σyy − σzz)²)/6`
/// to the power ½ (the normal components only, as he wrote it).
pub fn deviatoric_pasha(t: &[[f64; 3]; 3]) -> f64 {
    let (x, y, z) = (t[0][0], t[1][1], t[2][2]);
    (((x - y).powi(2) + (x - z).powi(2) + (y - z).powi(2)) / 6.0).sqrt()
}
