//! The update half of a step: the leap-frog central-difference update of velocities and
//! positions with global damping, Lian (5.9)–(5.14), fixed components, the ledger's
//! damping, gravity and constraint work, and the removal of particles that left through an
//! open side.

use super::*;
use crate::sim::cell::{self, Servo};
use crate::sim::stress;

/// Step 2 of a cycle: wall forces and motion, then the particle update.
pub(super) fn move_all(
    scene: &mut Scene,
    model: &Model,
    xres: f64,
    acc: Acc,
    keep: bool,
) -> Result<(), Blowup> {
    let wall_work = move_walls(scene, model.dt);
    let mv = Mover::of(scene, model);
    let deferred = std::mem::take(&mut scene.contacts.step.deferred);
    let contacts = &scene.contacts;
    let left = deferred.then_some(Left {
        scatter: split_step(model).then_some((
            &contacts.step.scatter,
            &contacts.step.hot,
            &contacts.step.out,
        )),
        walls: &contacts.step.wall_out.pieces,
        roll: (!contacts.step.roll.is_empty()).then_some(&contacts.step.roll[..]),
    });
    let p = &mut scene.particles;
    let fixed_arrays = (&p.mass[..], &p.agg[..], &p.fixed[..], &p.radius[..]);
    // Parallel over fixed chunks of particles; the partial sums are added in chunk order,
    // so the ledger does not depend on the number of threads.
    let parts: Vec<ChunkSums> = p
        .vel
        .par_chunks_mut(CHUNK)
        .zip(p.pos.par_chunks_mut(CHUNK))
        .zip(p.disp.par_chunks_mut(CHUNK))
        .zip(p.spin.par_chunks_mut(CHUNK))
        .zip(p.rot.par_chunks_mut(CHUNK))
        .zip(p.force.par_chunks_mut(CHUNK))
        .zip(p.moment.par_chunks_mut(CHUNK))
        .enumerate()
        .map(
            |(chunk, ((((((vel, pos), disp), spin), rot), force), moment))| {
                let sums = mv.chunk(
                    chunk,
                    ChunkArrays {
                        vel,
                        pos,
                        disp,
                        spin,
                        rot,
                        force: &mut *force,
                        moment: &mut *moment,
                    },
                    fixed_arrays,
                    left,
                );
                // Cleared while the chunk is in the cache, for the next step's sums (a
                // particle with a non-finite state keeps its force for the message).
                if !keep && sums.bad.is_none() {
                    force.fill(Vec3::zeros());
                    moment.fill(Vec3::zeros());
                }
                sums
            },
        )
        .collect();
    finish_move(scene, (xres, keep), acc, wall_work, &parts, model.dt)
}

/// One chunk's sums of the update, added over the chunks in chunk order.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ChunkSums {
    /// Work of gravity m g·v̄ Δt.
    pub(super) w_grav: f64,
    /// Loss to the mass-proportional damping.
    pub(super) d_mass: f64,
    /// Largest displacement component since the last rebuild.
    pub(super) max_disp: f64,
    /// The first particle with a non-finite state.
    pub(super) bad: Option<usize>,
    /// Some particle is beyond an open side.
    pub(super) outside: bool,
    /// Work of the velocity constraints (`Fix`, 2-D).
    pub(super) w_fix: f64,
    /// The largest |v|² and, per group of [`EXT_GROUP`] particles, the largest velocity
    /// component after the update ([`Speeds`]; finite velocities only).
    pub(super) speed2: f64,
    pub(super) groups: [f64; CHUNK / EXT_GROUP],
}

/// A chunk's particle arrays.
/// The arrays the update of a chunk moves: velocity, position, displacement, spin, rotation.
type Moving<'a> = (
    &'a mut [Vec3],
    &'a mut [Vec3],
    &'a mut [Vec3],
    &'a mut [Vec3],
    &'a mut [Vec3],
);

pub(super) struct ChunkArrays<'a> {
    pub(super) vel: &'a mut [Vec3],
    pub(super) pos: &'a mut [Vec3],
    pub(super) disp: &'a mut [Vec3],
    pub(super) spin: &'a mut [Vec3],
    pub(super) rot: &'a mut [Vec3],
    pub(super) force: &'a mut [Vec3],
    pub(super) moment: &'a mut [Vec3],
}

/// What the force step left to the update (see [`finish_chunk`]): the shared particles'
/// pairs and slots (none with one thread), the wall forces.
#[derive(Clone, Copy)]
pub(super) struct Left<'a> {
    pub(super) scatter: Option<(&'a Incidence, &'a [HotPair], &'a [PairForce])>,
    pub(super) walls: &'a [WallPiece],
    /// The rolling moments per particle (`sim::rolling`), if the scene has rolling friction.
    pub(super) roll: Option<&'a [Vec3]>,
}

/// The constants of the particle update of a step, Lian (5.9)–(5.14).
#[derive(Clone, Copy)]
pub(super) struct Mover {
    pub(super) dt: f64,
    pub(super) g: Vec3,
    pub(super) two_d: bool,
    pub(super) alpha: f64,
    pub(super) damp: f64,
    pub(super) inv: f64,
    pub(super) cg: [f64; 2],
    pub(super) centres: [Option<Vec3>; 2],
    pub(super) fmm: f64,
    pub(super) rotation: bool,
    pub(super) size: [f64; 3],
    pub(super) periodic: [bool; 3],
    pub(super) plain: Option<leapfrog::Plain>,
}

impl Mover {
    pub(super) fn of(scene: &Scene, model: &Model) -> Mover {
        let dt = model.dt;
        let g = Vec3::from(scene.gravity);
        let two_d = scene.settings.two_d;
        let alpha = scene.damping_pp.alpha;
        let damp = (1.0 - 0.5 * alpha * dt) / (1.0 + 0.5 * alpha * dt);
        let inv = 1.0 / (1.0 + 0.5 * alpha * dt);
        let cg = scene.cgravity;
        let centres = scene.regions.map(|r| r.map(|r| Vec3::from(r.centre)));
        let fmm = scene.fmm;
        let rotation = model.rotation;
        let (size, periodic) = (scene.size, scene.settings.periodic);
        let plain = (!two_d && alpha == 0.0).then(|| {
            let mut c = leapfrog::Plain {
                g: scene.gravity,
                fmm,
                damp,
                dt,
                rotation,
                lo: [f64::NEG_INFINITY; 3],
                hi: [f64::INFINITY; 3],
                uniform: model.uniform.map(|u| {
                    let (mut sv, mut sw) = ([0.0], [0.0]);
                    step_factors(&[u.mass], &[u.radius], dt, inv, &mut sv, &mut sw);
                    leapfrog::UniformSteps {
                        mass: u.mass,
                        step_v: sv[0],
                        step_w: sw[0],
                    }
                }),
            };
            for k in 0..3 {
                if !periodic[k] {
                    (c.lo[k], c.hi[k]) = (0.0, size[k]);
                }
            }
            c
        });
        Mover {
            dt,
            g,
            two_d,
            alpha,
            damp,
            inv,
            cg,
            centres,
            fmm,
            rotation,
            size,
            periodic,
            plain,
        }
    }

    /// Moves the particles of chunk `chunk` (after adding what the force step `left`).
    pub(super) fn chunk(
        &self,
        chunk: usize,
        a: ChunkArrays<'_>,
        (mass, agg, fixed, radius): (&[f64], &[u8], &[u8], &[f64]),
        left: Option<Left<'_>>,
    ) -> ChunkSums {
        let Mover {
            dt,
            inv,
            cg,
            rotation,
            plain,
            ..
        } = *self;
        let ChunkArrays {
            vel,
            pos,
            disp,
            spin,
            rot,
            force,
            moment,
        } = a;
        // First what the force step left (`finish_chunk`): with several threads the shared
        // particles' sums; the moments times the radius; the wall forces.
        if let Some(left) = left {
            finish_chunk(left, chunk, (&mut *force, &mut *moment), radius, rotation);
        }
        let (force, moment) = (&*force, &*moment);
        let mut bad: Option<usize> = None;
        let lo = chunk * CHUNK;
        let hi = lo + vel.len();
        let n = vel.len();
        // Plain particles (no aggregate gravity, nothing fixed, no 2-D constraint, no
        // mass damping): the component update, bitwise the same as the loop below. A chunk
        // without aggregates and fixed components is plain: that first, as an OR over the
        // bytes (which the compiler vectorises), then the test per particle.
        let bits = |b: &[u8]| b.iter().fold(0u8, |m, &x| m | x);
        let plain_chunk = plain.is_some()
            && ((bits(&agg[lo..hi]) == 0 && bits(&fixed[lo..hi]) & 0x3f == 0)
                || agg[lo..hi].iter().zip(&fixed[lo..hi]).all(|(&a, &fx)| {
                    fx & 0x3f == 0 && (a == 0 || cg.get(a as usize - 1).is_none_or(|&g| !(g > 0.0)))
                }));
        // The step factors Δt/m and Δt/I of the chunk first, in a loop of their own that
        // the compiler vectorises (the divisions then do not stall the update below); not
        // needed by the plain update of alike particles (`Plain::uniform`), which then
        // does not clear their arrays either (16 KB a chunk).
        let alike = plain_chunk && plain.is_some_and(|c| c.uniform.is_some());
        let mut factors = None;
        let mut step_v;
        let mut step_w;
        if !alike {
            step_v = [0.0; CHUNK];
            step_w = [0.0; CHUNK];
            step_factors(
                &mass[lo..hi],
                &radius[lo..hi],
                dt,
                inv,
                &mut step_v,
                &mut step_w,
            );
            factors = Some((&step_v, &step_w));
        }
        if let (Some(c), true) = (&plain, plain_chunk) {
            let mut groups = [0.0; CHUNK / EXT_GROUP];
            let (mass, step_v, step_w) = match factors {
                None => (&[][..], &[][..], &[][..]),
                Some((v, w)) => (&mass[lo..hi], &v[..n], &w[..n]),
            };
            let s = leapfrog::update(
                c,
                leapfrog::Run {
                    mass,
                    step_v,
                    step_w,
                    force,
                    moment,
                    vel: &mut *vel,
                    pos: &mut *pos,
                    disp: &mut *disp,
                    spin: &mut *spin,
                    rot: &mut *rot,
                    groups: &mut groups[..n.div_ceil(EXT_GROUP)],
                },
            );
            if !s.finite {
                bad = (0..n)
                    .find(|&l| !all_finite(&pos[l], &vel[l]))
                    .map(|l| lo + l);
            }
            return ChunkSums {
                w_grav: s.w_grav,
                d_mass: 0.0,
                max_disp: s.max_disp,
                bad,
                outside: s.outside,
                w_fix: 0.0,
                speed2: s.speed2,
                groups,
            };
        }
        let Some(factors) = factors else {
            unreachable!("a chunk of alike particles is plain")
        };
        self.general(
            chunk,
            (vel, pos, disp, spin, rot),
            (force, moment),
            (mass, agg, fixed, radius),
            factors,
        )
    }

    /// The per-particle update of a chunk: aggregate gravity, fixed components, 2-D, mass
    /// damping and their work, Lian (5.9)–(5.14).
    ///
    /// The plain particles of a chunk take `leapfrog::update` instead: the same integration
    /// without these terms, as a flat loop over components that the compiler vectorises
    /// (this loop's terms mix a particle's components, so it stays per particle; the
    /// module comment of `leapfrog` has the figures). Both take the velocity from
    /// [`leapfrog::velocity`]; `leapfrog`'s tests hold the two to the same bits.
    #[inline(always)]
    fn general(
        &self,
        chunk: usize,
        (vel, pos, disp, spin, rot): Moving<'_>,
        (force, moment): (&[Vec3], &[Vec3]),
        (mass, agg, fixed, radius): (&[f64], &[u8], &[u8], &[f64]),
        (step_v, step_w): (&[f64; CHUNK], &[f64; CHUNK]),
    ) -> ChunkSums {
        let Mover {
            dt,
            g,
            two_d,
            alpha,
            damp,
            cg,
            centres,
            fmm,
            rotation,
            size,
            periodic,
            ..
        } = *self;
        let mut w_grav = 0.0;
        let mut d_mass = 0.0;
        let mut w_fix = 0.0;
        let mut max_disp = 0.0f64;
        let mut bad: Option<usize> = None;
        let mut outside = false;
        for l in 0..vel.len() {
            let i = chunk * CHUNK + l;
            let m = mass[i];
            let mut body = g;
            let a = agg[i] as usize;
            if a > 0
                && cg[a - 1] > 0.0
                && let Some(c) = centres[a - 1]
            {
                let e = c - pos[l];
                let len = e.norm();
                if len > 0.0 {
                    body += e * (cg[a - 1] / len);
                }
            }
            let fb = body * (m * fmm);
            let f = force[l] + fb;
            let v_old = vel[l];
            let mut v = leapfrog::velocity(v_old, damp, f, step_v[l]);
            let fx = fixed[i];
            keep_fixed(&mut v, &v_old, fx);
            if two_d {
                v.z = 0.0;
            }
            if fx & 7 != 0 || two_d {
                w_fix += constraint_work(m, &v_old, &v, &f, alpha, dt, fx & 7, two_d);
            }
            let vbar = (v + v_old) * 0.5;
            w_grav += fb.dot(&vbar) * dt;
            if alpha != 0.0 {
                // (With α = 0 the term is +0 and adding it changes nothing.)
                d_mass += alpha * m * vbar.norm_squared() * dt;
            }
            vel[l] = v;
            let dx = v * dt;
            pos[l] += dx;
            disp[l] += dx;
            let x = pos[l];
            outside |= outside_open_side(&x, &size, &periodic);
            max_disp = max_disp.max(disp[l].amax());
            if rotation {
                let inertia = 0.4 * m * radius[i] * radius[i];
                let w_old = spin[l];
                let mut w = leapfrog::velocity(w_old, damp, moment[l], step_w[l]);
                keep_fixed(&mut w, &w_old, fx >> 3);
                if two_d {
                    w.x = 0.0;
                    w.y = 0.0;
                }
                if (fx >> 3) & 7 != 0 || two_d {
                    // (In 2-D the spin keeps only its z component: x and y are held.)
                    let held = ((fx >> 3) & 7) | if two_d { 0b011 } else { 0 };
                    w_fix +=
                        constraint_work(inertia, &w_old, &w, &moment[l], alpha, dt, held, false);
                }
                if alpha != 0.0 {
                    let wbar = (w + w_old) * 0.5;
                    d_mass += alpha * inertia * wbar.norm_squared() * dt;
                }
                spin[l] = w;
                rot[l] += w * dt;
            }
            if !all_finite(&pos[l], &v) && bad.is_none() {
                bad = Some(i);
            }
        }
        let mut groups = [0.0; CHUNK / EXT_GROUP];
        for (g, e) in vel.chunks(EXT_GROUP).zip(groups.iter_mut()) {
            *e = largest_component(g);
        }
        ChunkSums {
            w_grav,
            d_mass,
            max_disp,
            bad,
            outside,
            w_fix,
            speed2: largest_norm_squared(vel),
            groups,
        }
    }
}

/// The work a velocity constraint did in one step on the components it held (bit k of
/// `held`: component k; `flat`: the z component, held at 0 in 2-D): the change of their
/// kinetic energy less the work booked for them (the force `f` with v̄ Δt, the mass damping
/// α m v̄² Δt), so that the ledger closes when a user drives particles with `Fix`.
#[allow(clippy::too_many_arguments)]
pub(super) fn constraint_work(
    m: f64,
    v_old: &Vec3,
    v: &Vec3,
    f: &Vec3,
    alpha: f64,
    dt: f64,
    held: u8,
    flat: bool,
) -> f64 {
    let mut w = 0.0;
    for k in 0..3 {
        if held & (1 << k) != 0 || (flat && k == 2) {
            let vbar = 0.5 * (v[k] + v_old[k]);
            let kinetic = 0.5 * m * (v[k] * v[k] - v_old[k] * v_old[k]);
            w += kinetic - (f[k] * vbar * dt - alpha * m * vbar * vbar * dt);
        }
    }
    w
}

/// The end of a step: the chunks' sums (in chunk order), whether the update cleared the
/// forces (not with `keep`), blow-up check, periodic wrap, the rebuild flag and the ledger.
pub(super) fn finish_move(
    scene: &mut Scene,
    (xres, keep): (f64, bool),
    acc: Acc,
    wall_work: f64,
    parts: &[ChunkSums],
    dt: f64,
) -> Result<(), Blowup> {
    scene.contacts.step.zeroed = !keep && parts.iter().all(|s| s.bad.is_none());
    scene.derived.speeds.fresh = false;
    let mut w_grav = 0.0;
    let mut d_mass = 0.0;
    let mut max_disp = 0.0f64;
    let mut bad: Option<usize> = None;
    let mut outside = false;
    let mut w_fix = 0.0;
    for c in parts {
        outside |= c.outside;
        w_grav += c.w_grav;
        d_mass += c.d_mass;
        max_disp = max_disp.max(c.max_disp);
        bad = bad.or(c.bad);
        w_fix += c.w_fix;
    }
    scene.derived.maybe_outside = outside;
    let p = &mut scene.particles;
    if let Some(i) = bad {
        return Err(Blowup {
            cycle: scene.cycle + 1,
            message: format!(
                "numerical blow-up at cycle {}: particle {} has a non-finite position or velocity (force {:?}). \
                 Hint: reduce FRAction, check for deep initial overlaps, very stiff dashpots or servo gains",
                scene.cycle + 1,
                p.id[i],
                [p.force[i].x, p.force[i].y, p.force[i].z]
            ),
        });
    }
    let mut servo = std::mem::take(&mut scene.derived.servo);
    // The deforming cell (`sim::cell`): its work, the mean field's share of the motion with
    // the wrap, and the stress servo.
    let wrapped = (scene.cell.needs_stress() || servo.is_some())
        && cell_end_step(scene, servo.as_mut(), &acc.stress, dt);
    let hunting = servo
        .as_ref()
        .is_some_and(|s| s.flips >= cell::HUNTING_STEPS);
    scene.derived.servo = servo;
    if hunting {
        return Err(Blowup {
            cycle: scene.cycle + 1,
            message: format!(
                "the stress servo hunts: its strain rates jumped between +edmax and -edmax for {} steps up to cycle {} (the packing it made is too stiff, or too damped, for GAIN {:e}); reduce GAIN (doc/cell.md, \"Choosing the servo gain\")",
                cell::HUNTING_STEPS,
                scene.cycle + 1,
                scene.cell.gain[0]
            ),
        });
    }
    if !wrapped {
        // Wrap periodic coordinates (across a sheared side at the image).
        cell::wrap(scene);
    }
    let p = &mut scene.particles;
    if scene.zero_always {
        // The kinetic energy taken out leaves the books as a command's change.
        let mut taken = 0.0;
        for i in 0..p.len() {
            taken += 0.5 * p.mass[i] * p.vel[i].norm_squared()
                + 0.5 * p.inertia(i) * p.spin[i].norm_squared();
            p.vel[i] = Vec3::zeros();
            p.spin[i] = Vec3::zeros();
        }
        scene.ledger.commands -= taken;
    }
    // A wall that moved more than XRES since the last rebuild is re-mapped like a particle
    // (its travel closes a gap as much as a particle's displacement).
    scene.contacts.step.max_disp = Some(max_disp);
    // (In a deforming cell a pair also closes by the mean field's share, `Cell::travel`.)
    if max_disp + scene.cell.travel > xres || scene.walls.iter().any(|w| w.travel > xres) {
        scene.contacts.request_remap();
    }

    let l = &mut scene.ledger;
    // The work of velocity constraints (Fix, 2-D) is put in by a command, as its kinetic
    // energy is.
    l.commands += w_fix;
    l.gravity += w_grav;
    l.walls += wall_work;
    l.damping_mass += d_mass;
    l.friction += acc.friction;
    l.damping_contact += acc.damping_contact;
    l.viscous += acc.viscous;
    l.adhesion += acc.adhesion;
    l.rupture += acc.rupture;
    scene.cycle += 1;
    scene.time += dt;
    // The velocities' largest values as the update left them (unless the cell or
    // `zero_always` changed the velocities since): for the check after the step and the
    // next step's margins.
    if !scene.zero_always && !scene.cell.needs_stress() && scene.derived.servo.is_none() {
        scene.derived.speeds.set(parts, scene.particles.len());
    }
    Ok(())
}

/// The periodic cell's share of the end of a step ([`finish_move`]; `sim::cell`): its work
/// with the stress of this step's forces, the deformation ([`cell::deform`], which also wraps the
/// particles) and the servo's new rates. `fl`: Σ f ⊗ l of this step's particle pairs
/// (row-major), summed by the pair loop for the components 11, 22, 33 and 12 (those that
/// the work `σ:G` and the servo read; the others are 0). Returns whether the particles
/// were wrapped.
fn cell_end_step(scene: &mut Scene, servo: Option<&mut Servo>, fl: &[f64; 9], dt: f64) -> bool {
    let v = stress::volume(scene);
    let active = scene.cell.is_active();
    // Σ m C ⊗ C of the velocities of this step (before the field's share of it).
    let kin = if active {
        cell::deform(scene, dt)
    } else {
        cell::kinetic_sum(&scene.particles)
    };
    let mut s = stress::Stress::default();
    for a in 0..3 {
        for b in 0..3 {
            s.contact[a][b] = fl[3 * a + b] / v;
            s.kinetic[a][b] = kin[a][b] / v;
        }
    }
    let total = s.total();
    let dot = |h: &[[f64; 3]; 3]| -> f64 {
        let mut w = 0.0;
        for a in 0..3 {
            for b in 0..3 {
                w += total[a][b] * h[a][b];
            }
        }
        w
    };
    // The last step's deformation, now that the forces at its end are known.
    let c = &mut scene.cell;
    c.work += c.pending + dot(&c.half);
    c.half = [[0.0; 3]; 3];
    c.pending = 0.0;
    if active {
        let g = c.gradient();
        for a in 0..3 {
            for b in 0..3 {
                c.half[a][b] = -0.5 * v * g[a][b] * dt;
            }
        }
        c.pending = dot(&c.half);
    }
    if let Some(servo) = servo {
        cell::servo_step(&mut scene.cell, servo, &total);
    }
    active
}

/// Δt/m·inv and Δt/I·inv (I = 0.4 m R², a solid sphere) for a chunk of particles, as the
/// update computes them (Lian (5.9)–(5.10) with the mass-damping factor `inv`).
pub(super) fn step_factors(
    mass: &[f64],
    radius: &[f64],
    dt: f64,
    inv: f64,
    sv: &mut [f64],
    sw: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above); same arithmetic, no FMA.
            return unsafe { step_factors_avx2(mass, radius, dt, inv, sv, sw) };
        }
    }
    step_factors_impl(mass, radius, dt, inv, sv, sw)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) fn step_factors_avx2(
    mass: &[f64],
    radius: &[f64],
    dt: f64,
    inv: f64,
    sv: &mut [f64],
    sw: &mut [f64],
) {
    step_factors_impl(mass, radius, dt, inv, sv, sw)
}

#[inline(always)]
pub(super) fn step_factors_impl(
    mass: &[f64],
    radius: &[f64],
    dt: f64,
    inv: f64,
    sv: &mut [f64],
    sw: &mut [f64],
) {
    for (((&m, &r), v), w) in mass
        .iter()
        .zip(radius)
        .zip(sv.iter_mut())
        .zip(sw.iter_mut())
    {
        *v = dt / m * inv;
        let inertia = 0.4 * m * r * r;
        *w = dt / inertia * inv;
    }
}

/// Every component of the two vectors is finite (without a branch per component: x·0 is
/// ±0 for finite x and NaN otherwise, and a sum of zeros is zero).
#[inline(always)]
pub(super) fn all_finite(a: &Vec3, b: &Vec3) -> bool {
    (a.x * 0.0 + a.y * 0.0 + a.z * 0.0 + b.x * 0.0 + b.y * 0.0 + b.z * 0.0) == 0.0
}

/// Fixed degrees of freedom (`Fix`): components whose bit is set in `mask` (bit k for
/// component k) keep their old velocity.
#[inline]
pub(super) fn keep_fixed(v: &mut Vec3, old: &Vec3, mask: u8) {
    if mask & 7 != 0 {
        for k in 0..3 {
            if mask & (1 << k) != 0 {
                v[k] = old[k];
            }
        }
    }
}

/// The position is beyond a non-periodic side of the work-space.
#[inline]
pub(super) fn outside_open_side(x: &Vec3, size: &[f64; 3], periodic: &[bool; 3]) -> bool {
    (0..3).any(|k| !periodic[k] && (x[k] < 0.0 || x[k] > size[k]))
}

/// Removes particles that left through an open side (counted in `lost`); returns whether
/// any was.
pub(super) fn remove_lost(scene: &mut Scene) -> bool {
    if !scene.derived.maybe_outside {
        return false;
    }
    let (size, periodic) = (scene.size, scene.settings.periodic);
    let out: Vec<bool> = scene
        .particles
        .pos
        .iter()
        .map(|x| outside_open_side(x, &size, &periodic))
        .collect();
    if !out.contains(&true) {
        return false;
    }
    // Their kinetic energy leaves the books with them.
    for (i, _) in out.iter().enumerate().filter(|(_, o)| **o) {
        let p = &scene.particles;
        let e = 0.5 * p.mass[i] * p.vel[i].norm_squared()
            + 0.5 * p.inertia(i) * p.spin[i].norm_squared();
        scene.ledger.commands -= e;
        scene.lost += 1;
    }
    remove_where(scene, &out);
    true
}

/// Deletes the particles marked in `gone` (`DELete`, `SET TUNnel DELETE`) and returns how
/// many. The stored energy of their contacts (strain, bridge stretch) leaves the books with
/// them, as work of commands; their kinetic energy is the caller's to book (the session books
/// it around every command, `Scene::booked_edit`).
pub fn delete_marked(scene: &mut Scene, gone: &[bool]) -> u64 {
    let n = gone.iter().filter(|g| **g).count() as u64;
    if n == 0 {
        return 0;
    }
    let held = |s: &Scene| {
        let st = crate::sim::energy::stored(s);
        st.total() - st.kinetic_translation - st.kinetic_rotation
    };
    let before = held(scene);
    remove_where(scene, gone);
    scene.ledger.commands += held(scene) - before;
    n
}

/// Removes the particles marked in `gone`, with their pairs and wall pairs (the indices of
/// the others re-mapped).
pub(super) fn remove_where(scene: &mut Scene, gone: &[bool]) {
    let mut i = 0;
    let mut k = 0;
    while i < scene.particles.len() {
        if gone[k] {
            scene.particles.remove(i);
        } else {
            i += 1;
        }
        k += 1;
    }
    // Indices changed: drop pairs of removed particles and re-index.
    let ids = &scene.particles.id;
    let mut index = std::collections::HashMap::new();
    for (k, &id) in ids.iter().enumerate() {
        index.insert(id, k as u32);
    }
    scene
        .contacts
        .retain_pairs(|c| match (index.get(&c.ida), index.get(&c.idb)) {
            (Some(&a), Some(&b)) => {
                c.i = a;
                c.j = b;
                true
            }
            _ => false,
        });
    scene
        .contacts
        .wall_pairs
        .retain_mut(|c| match index.get(&c.id) {
            Some(&a) => {
                c.i = a;
                true
            }
            None => false,
        });
    scene.contacts.clear_derived();
    scene.derived.speeds.fresh = false;
}
