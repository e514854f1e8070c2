//! Particle–wall contacts of a step, and the walls' own motion (velocity or servo).

use super::*;

/// The particle–wall contacts of a stretch of wall pairs (whole blocks of [`WALL_BLOCK`]):
/// each evaluated pair's force and moment into `out`, in pair order, with the force on each
/// wall summed per block in pair order, and the entries grouped by the update's chunk of
/// their particle (`np` particles); returns the energy increments per block. The steady
/// no-slip contacts go through [`lanes::hertz_noslip`] in sub-batches of [`lanes::SUB`]
/// pairs (S1 10k, one thread: 5.5 % → 3.7 % of the samples in this function, same bits).
pub(super) fn wall_forces<const ADH: bool, const LIQ: bool>(
    wall_pairs: &mut [WallPair],
    out: &mut WallPiece,
    walls: (&[Wall], &[WallShape]),
    c: &PairCtx,
    np: usize,
) -> Vec<Acc> {
    use lanes::SUB;
    let nw = walls.0.len();
    out.forces.clear();
    out.sums.clear();
    // The steady Hertz contacts with the no-slip law go through the vectorised kernel, as
    // in the pair loop (`block_forces`): the same arithmetic, so the same bits.
    let laws = c.laws;
    let batched = batches_steady::<ADH, LIQ>(c);
    let mut batch = lanes::Batch::new();
    let mut kins = [Kin::ZERO; SUB];
    let mut idx = [0u8; SUB];
    let mut lane = [u8::MAX; SUB];
    let accs = wall_pairs
        .chunks_mut(WALL_BLOCK)
        .map(|pairs| {
            let mut acc = Acc::default();
            let base = out.sums.len();
            out.sums.resize(base + nw, [0.0; 3]);
            for sub in pairs.chunks_mut(SUB) {
                // The pairs evaluated, their geometry, and the steady ones into the batch.
                let mut m = 0;
                batch.len = 0;
                for (k, c2) in sub.iter().enumerate() {
                    let Some((kin, pc)) = wall_kin(c2, walls, c) else {
                        continue;
                    };
                    idx[m] = k as u8;
                    lane[m] = if batched && lanes::Batch::takes(&kin, pc, &c2.s) {
                        batch.push(&kin, pc, &c2.s) as u8
                    } else {
                        u8::MAX
                    };
                    // (Only the general kernel reads it back.)
                    if lane[m] == u8::MAX {
                        kins[m] = kin;
                    }
                    m += 1;
                }
                if batch.len > 0 {
                    lanes::hertz_noslip(&mut batch, laws.dt);
                }
                // In pair order: each force and the ledger's terms.
                for q in 0..m {
                    let c2 = &mut sub[idx[q] as usize];
                    let kin = &kins[q];
                    let i = c2.i as usize;
                    let ri = c.radius[i];
                    let (f, ft_moment) = if lane[q] != u8::MAX {
                        let l = lane[q] as usize;
                        let (f, m) = batch.store(l, &mut c2.s);
                        acc.damping_contact += batch.e_damp_n[l];
                        acc.friction += batch.e_friction[l];
                        acc.damping_contact += batch.e_damp_t[l];
                        (f, m * ri)
                    } else {
                        let w = &walls.0[c2.wall as usize];
                        let pc = c.model.pair(c.material[i] as usize, w.material);
                        let o = interact::<ADH, LIQ>(kin, pc, laws, &mut c2.s, &mut acc);
                        let m = if c.model.rotation {
                            -kin.n.cross(&o.ft) * ri
                        } else {
                            Vec3::zeros()
                        };
                        (o.f, m)
                    };
                    let o = WallForce {
                        f,
                        m: ft_moment,
                        i: c2.i,
                    };
                    let w = &mut out.sums[base + c2.wall as usize];
                    for (wk, fk) in w.iter_mut().zip(o.f.iter()) {
                        *wk += fk;
                    }
                    out.forces.push(o);
                }
            }
            acc
        })
        .collect();
    // A counting sort of the entries by chunk (stable: pair order within a chunk).
    let nchunks = np.div_ceil(CHUNK);
    out.start.clear();
    out.start.resize(nchunks + 2, 0);
    for o in &out.forces {
        out.start[o.i as usize / CHUNK + 2] += 1;
    }
    for c in 2..out.start.len() {
        out.start[c] += out.start[c - 1];
    }
    out.order.clear();
    out.order.resize(out.forces.len(), 0);
    for (e, o) in out.forces.iter().enumerate() {
        let at = &mut out.start[o.i as usize / CHUNK + 1];
        out.order[*at as usize] = e as u32;
        *at += 1;
    }
    out.start.pop();
    accs
}

/// The geometry of one particle–wall pair and the pair's constants (`None`: skipped, the
/// particle is out of reach with nothing to remember).
#[inline(always)]
pub(super) fn wall_kin<'m>(
    c: &WallPair,
    (walls, shapes): (&[Wall], &[WallShape]),
    ctx: &PairCtx<'m>,
) -> Option<(Kin, &'m crate::sim::params::PairConst)> {
    let i = c.i as usize;
    let w = &walls[c.wall as usize];
    let ri = ctx.radius[i];
    let (gap, n) = shapes[c.wall as usize].gap(&ctx.pos[i], ri);
    let far = gap > 1e-6 * ri && !c.s.live();
    // Beyond the dashpot's margin (the particle's and the fastest wall's travel in a step,
    // `ContactStore::margins`), or without a dashpot: not evaluated.
    let reach = match ctx.ext {
        Some(e) => 1e-6 * ri + e[i / EXT_GROUP] + ctx.laws.margin,
        None => 1e-6 * ri,
    };
    if far && !(gap <= reach) {
        return None;
    }
    let vw = surface_velocity(w, &n);
    let v_rel = vw - ctx.vel[i] - (ctx.spin[i] * ri).cross(&n);
    if far {
        // Only a pair approaching within half a step's travel gets the dashpot's share
        // (the kernel's own test, `interact`).
        let v_n = v_rel.dot(&n);
        if !(v_n < 0.0 && -gap - v_n * (0.5 * ctx.laws.dt) > 0.0) {
            return None;
        }
    }
    let r2 = match w.geom {
        WallGeom::Plane { .. } => f64::INFINITY,
        WallGeom::Sphere { radius, .. } => -radius,
        WallGeom::Obstacle { radius, .. } => radius,
        // (The bridge volume of a wall contact is the particle's: r2 only marks a wall.)
        WallGeom::Cylinder { .. } => f64::INFINITY,
    };
    let k = Kin {
        n,
        gap,
        v_rel,
        r_star: wall_r_star(&w.geom, ri),
        m_star: ctx.mass[i],
        r1: ri,
        r2: if r2 < 0.0 { f64::INFINITY } else { r2 },
    };
    Some((k, ctx.model.pair(ctx.material[i] as usize, w.material)))
}

/// The walls' measured forces and the work they put in; then their motion (servo,
/// advance). Returns the work of the walls on the particles in this step.
pub(super) fn move_walls(scene: &mut Scene, dt: f64) -> f64 {
    // The walls' measured forces: a plane's normal force, a sphere's or cylinder's radial one.
    let mut radial = vec![0.0; scene.walls.len()];
    for w in scene.walls.iter_mut() {
        let f = Vec3::from(w.force);
        w.normal_force = match w.geom {
            WallGeom::Plane { normal, .. } => -f.dot(&Vec3::from(normal).normalize()),
            _ => 0.0,
        };
    }
    let round = |w: &Wall| !matches!(w.geom, WallGeom::Plane { .. });
    let wall_pairs: &[WallPair] = if scene.walls.iter().any(round) {
        &scene.contacts.wall_pairs
    } else {
        &[]
    };
    for c in wall_pairs {
        let w = &mut scene.walls[c.wall as usize];
        if round(w) {
            let fn_ = c.s.normal_force
                + c.s.damp_force
                + c.s.bridge.as_ref().map_or(0.0, |b| b.f_visc - b.f_static);
            if c.s.touching || c.s.bridge.is_some() {
                w.normal_force += fn_;
                radial[c.wall as usize] += fn_;
            }
        }
    }
    // The servos set the velocities the walls move with until the next step; a wall's work
    // on the particles is its force times its displacement about this instant, the mean of
    // the velocity it came with and the one it goes on with (central in time, as the
    // particles' booking: exact for the scheme when a servo changes the speed every step,
    // and when a command changed it between steps: the velocity it came with is the one of
    // its last step, not the one the command gave it).
    let mut wall_work = 0.0;
    let last = &mut scene.carried.wall_last_vel;
    last.resize(scene.walls.len(), ([f64::NAN; 3], f64::NAN));
    for ((w, fr), came) in scene.walls.iter_mut().zip(&radial).zip(last.iter_mut()) {
        let (vel_old, vr_old) = if came.1.is_nan() {
            (Vec3::from(w.vel), w.vr)
        } else {
            (Vec3::from(came.0), came.1)
        };
        walls::servo(w);
        *came = (w.vel, w.vr);
        let vel = (vel_old + Vec3::from(w.vel)) * 0.5;
        let vr = 0.5 * (vr_old + w.vr);
        // Work done by a moving wall on the particles: −(force on wall)·v_w Δt.
        wall_work -= Vec3::from(w.force).dot(&vel) * dt;
        let sign = match w.geom {
            WallGeom::Sphere { .. } | WallGeom::Cylinder { .. } => 1.0,
            WallGeom::Obstacle { .. } => -1.0,
            WallGeom::Plane { .. } => 0.0,
        };
        if sign != 0.0 {
            wall_work -= sign * fr * vr * dt;
        }
        walls::advance(w, dt);
    }
    scene.carried.wall_step_work = wall_work;
    wall_work
}
