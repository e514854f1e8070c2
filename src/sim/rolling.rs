//! Rolling resistance of the contacts (`SET ROLling μ_r`, `physics::rolling`): a pass over
//! the touching contacts after the force step, in pair order, then the wall pairs in their
//! order. It needs the spins and the contact normal of both spheres, which the contact
//! kernels do not carry, and it puts opposite moments on the two spheres, which the kernels'
//! per-unit-radius moment sums cannot hold; so the moments go to a per-particle array that
//! the update adds (`cycle::finish_chunk`). A scene without rolling friction skips it.

use super::cell::nearest_image;
use super::contacts::ContactState;
use super::params::Model;
use super::scene::{Scene, Vec3};
use super::walls::WallShape;
use crate::physics::{hertz, rolling, tangential, walton};
use crate::sim::model::NormalLaw;

/// The normal stiffness of a touching contact, for the rolling stiffness: `k_e` of the
/// linear laws, else the Hertzian `2E*a`.
fn normal_stiffness(model: &Model, pc: &super::params::PairConst, s: &ContactState) -> f64 {
    if pc.law > 0 {
        match model.laws[pc.law as usize - 1].law {
            NormalLaw::PashaFull { k_e, .. } | NormalLaw::PashaSimplified { k_e, .. } => {
                return k_e;
            }
            _ => {}
        }
    }
    2.0 * pc.e_star * s.a
}

/// The normal force of a touching contact that bounds its rolling moment: the contact force
/// `P`, or under `SET NORmal MJKR EDEM ROLling` the Hertzian part `4E*a³/(3R*)` (`walton::
/// friction_normal_force`), as for its sliding; `r_star` gives the contact's R* (worked out
/// only then).
fn limit_force(
    model: &Model,
    pc: &super::params::PairConst,
    s: &ContactState,
    r_star: impl FnOnce() -> f64,
) -> f64 {
    if pc.law > 0 && model.laws[pc.law as usize - 1].law.hertz_rolling() {
        walton::friction_normal_force(pc.e_star, r_star(), s.a)
    } else {
        s.normal_force
    }
}

/// One contact's rolling spring and dashpot for the relative spin `w` of A with respect to
/// B, the normal `n`, the equivalent inertia `i_r` and the normal force `f_n` of its limit:
/// returns the moment on A and adds the losses (friction, damping) to `loss`.
fn contact(
    s: &mut ContactState,
    (w, n, r_r, mu_r, k_n, i_r, dt): (Vec3, Vec3, f64, f64, f64, f64, f64),
    f_n: f64,
    loss: &mut [f64; 2],
) -> Vec3 {
    let wt = w - n * w.dot(&n);
    let dtheta = wt * dt;
    let k_r = rolling::stiffness(k_n, mu_r, r_r);
    let cap = rolling::limit(mu_r, r_r, f_n);
    let e = s.ext_mut().laws_mut();
    let m_old = tangential::rotate_into_plane_lazy(e.roll.into(), n.into());
    let st = rolling::step(m_old, dtheta.into(), k_r, cap);
    loss[0] += st.work - (st.energy - e.roll_energy);
    e.roll = Vec3::from(st.moment);
    e.roll_energy = st.energy;
    // The dashpot while the spring holds (Ai et al.: off once the contact rolls).
    let md = if !st.rolling {
        -wt * rolling::damping(i_r, k_r)
    } else {
        Vec3::zeros()
    };
    let md_old = Vec3::from(tangential::rotate_into_plane_lazy(
        e.roll_damp.into(),
        n.into(),
    ));
    loss[1] += -0.5 * (md_old + md).dot(&dtheta);
    e.roll_damp = md;
    e.roll + md
}

/// The rolling moments of this step (into `ContactStore::step.roll`, per particle) and the
/// energy they dissipated: (rolling friction, rolling dashpot). Nothing is done without a
/// rolling friction (`Model::rolling`).
pub fn moments(scene: &mut Scene, model: &Model, dt: f64) -> [f64; 2] {
    let Some(table) = model.rolling.as_deref() else {
        scene.contacts.step.roll.clear();
        return [0.0; 2];
    };
    let nmat = model.nmat;
    let p = &scene.particles;
    let mut roll = std::mem::take(&mut scene.contacts.step.roll);
    roll.clear();
    roll.resize(p.len(), Vec3::zeros());
    let mut loss = [0.0; 2];
    let (size, periodic, shift) = (scene.size, scene.settings.periodic, scene.cell.shift);
    scene.contacts.for_each_state_mut(|pair, s| {
        if !s.touching {
            return;
        }
        let (i, j) = (pair.i as usize, pair.j as usize);
        let (mi, mj) = (p.material[i] as usize, p.material[j] as usize);
        let mu_r = table[(mi - 1) * nmat + (mj - 1)];
        if !(mu_r > 0.0) {
            return;
        }
        let d = nearest_image(p.pos[j] - p.pos[i], size, periodic, shift);
        let n = d / d.norm();
        let r_r = rolling::radius(p.radius[i], p.radius[j]);
        let pc = model.pair(mi, mj);
        let k_n = normal_stiffness(model, pc, s);
        let f_n = limit_force(model, pc, s, || hertz::r_star(p.radius[i], p.radius[j]));
        let i_r = rolling::inertia(p.mass[i], p.radius[i], p.mass[j], p.radius[j]);
        let m = contact(
            s,
            (p.spin[i] - p.spin[j], n, r_r, mu_r, k_n, i_r, dt),
            f_n,
            &mut loss,
        );
        roll[i] += m;
        roll[j] -= m;
    });
    for wp in scene.contacts.wall_pairs.iter_mut() {
        if !wp.s.touching {
            continue;
        }
        let i = wp.i as usize;
        let w = &scene.walls[wp.wall as usize];
        let mi = p.material[i] as usize;
        let mu_r = table[(mi - 1) * nmat + (w.material - 1)];
        if !(mu_r > 0.0) {
            continue;
        }
        let (_, n) = WallShape::of(&w.geom).gap(&p.pos[i], p.radius[i]);
        let pc = model.pair(mi, w.material);
        let k_n = normal_stiffness(model, pc, &wp.s);
        let r_r = rolling::radius(p.radius[i], f64::INFINITY);
        let f_n = limit_force(model, pc, &wp.s, || {
            super::walls::wall_r_star(&w.geom, p.radius[i])
        });
        let i_r = rolling::inertia(p.mass[i], p.radius[i], f64::INFINITY, 0.0);
        roll[i] += contact(
            &mut wp.s,
            (p.spin[i], n, r_r, mu_r, k_n, i_r, dt),
            f_n,
            &mut loss,
        );
    }
    scene.contacts.step.roll = roll;
    loss
}
