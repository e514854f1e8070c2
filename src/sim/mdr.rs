//! The tangential force of a Hertz contact under `MDR` (the default, `SET TANgential MDR`):
//! its spring row (`physics::mdr`) turned into the contact plane, moved by the step's slip,
//! and booked.

use super::contacts::{ContactState, row_in};
use super::kinematics::{Acc, Kin};
use super::params::PairConst;
use super::scene::Vec3;
use crate::physics::mdr::{self, MdrInput, MdrRow};

/// One step of the MDR row of a touching Hertz contact: `dd` is the step's tangential
/// displacement of B relative to A in the contact plane, `s.tforce` the last force on B
/// already turned into it. Sets the new force on B and the stored energy; the work of the
/// force less the change of the springs' energy is booked as friction.
///
/// `rows`: the row list of the pair's block (`contacts::StateBlock`), where a particle pair
/// keeps its row; `None` for a particle–wall contact, which keeps it in `ext.mdr`.
#[inline(always)]
pub(super) fn shear(
    k: &Kin,
    pc: &PairConst,
    s: &mut ContactState,
    rows: Option<&mut Vec<MdrRow>>,
    dd: Vec3,
    acc: &mut Acc,
) {
    let n: [f64; 3] = k.n.into();
    let t_old = s.tforce;
    let inp = MdrInput {
        g_star: pc.g_star,
        e_star: pc.e_star,
        mu: pc.mu,
        r_star: k.r_star,
        a: s.a,
        dd: [0.0; 2],
    };
    let tang_energy = s.tang_energy;
    let make = || {
        // A contact that comes to this law while it touches keeps its force.
        let (e1, e2) = mdr::frame([0.0; 3], n);
        let t = [-t_old.dot(&Vec3::from(e1)), -t_old.dot(&Vec3::from(e2))];
        MdrRow::holding(t, e1, &inp)
    };
    let row = match rows {
        Some(rows) => row_in(s, rows, make),
        None => s.ext_mut().mdr.get_or_insert_with(|| Box::new(make())),
    };
    let (e1, e2) = mdr::frame(row.e1, n);
    row.e1 = e1;
    let (e1, e2) = (Vec3::from(e1), Vec3::from(e2));
    let step = row.step(&MdrInput {
        dd: [dd.dot(&e1), dd.dot(&e2)],
        ..inp
    });
    // The springs follow B's slip; their force on B opposes it.
    let f = -(e1 * step.force[0] + e2 * step.force[1]);
    let work = -0.5 * (t_old + f).dot(&dd);
    acc.friction += work - (step.energy - tang_energy);
    s.tang_energy = step.energy;
    s.tforce = f;
}
