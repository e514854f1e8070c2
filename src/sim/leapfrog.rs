//! The leap-frog update of plain particles, Lian (5.9)–(5.14), on component arrays.
//!
//! A particle is plain when it has no aggregate gravity, no fixed degree of freedom, no 2-D
//! constraint and the scene has no mass damping (α = 0): then every velocity and position
//! component is updated by the same few operations, independently of the others, and the
//! update runs as one loop over the x, y, z components of a run of particles (a `Vec<Vec3>`
//! is laid out as x0 y0 z0 x1 …), which the compiler vectorises. The arithmetic of each
//! component is exactly that of the general update in `cycle::move_all` (the same operations
//! in the same order, no fused multiply-add), and the work of gravity is summed per particle
//! in particle order as there, so both give bitwise the same state and ledger
//! (`tests` below and `tests/it/threads.rs`).
//!
//! Why two loops for one integration: the general update (`cycle::update`, `Mover::general`)
//! works particle by particle because its extra terms (aggregate gravity towards a centre,
//! held components and their work, the 2-D constraint, mass damping and its loss) mix the
//! components of a particle; this one has none of them, so it can run over the components
//! of a run as one flat loop that the compiler vectorises (the update of the S1 50k bed over
//! 5000 steps: 2.97 s particle by particle, 1.89 s so; doc/performance.md). What both compute
//! is written once: the velocity of a step is [`velocity`] in both.

use super::scene::Vec3;

/// The leap-frog velocity of a step, Lian (5.9)–(5.14) (`cycle`'s module comment) with the
/// mass damping folded into the factors: `v_old·damp + F·step` with damp =
/// (1 − α Δt/2)/(1 + α Δt/2) and step = Δt/m/(1 + α Δt/2) (for a spin: the moment and
/// Δt/I). For a component (`f64`, the plain update here) and for a vector (`Vec3`, the
/// general update in `cycle::update`, component by component): the same two products and one
/// sum, so both updates give the same bits.
#[inline(always)]
pub fn velocity<T>(v_old: T, damp: f64, f: T, step: f64) -> T
where
    T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
{
    v_old * damp + f * step
}

/// Particles per run of the component loops: their scratch arrays stay in L1.
const RUN: usize = 128;

/// What the update of a run of plain particles needs besides the particle arrays.
#[derive(Clone, Copy, Debug)]
pub struct Plain {
    /// Gravity g.
    pub g: [f64; 3],
    /// The body-force multiplier of the scene (`fmm`).
    pub fmm: f64,
    /// Velocity factor (1 − α Δt/2)/(1 + α Δt/2) (1 with α = 0).
    pub damp: f64,
    pub dt: f64,
    pub rotation: bool,
    /// Lower and upper bounds of the work-space per axis (±∞ along periodic axes).
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    /// All particles alike (`Model::uniform`): the body force m g fmm, Δt/m and Δt/I (each
    /// divided by 1 + α Δt/2) are the same for every particle, filled in once per call of
    /// [`update`] with the very operations of the per-particle path (so the same bits), and
    /// `Run::mass`, `step_v`, `step_w` are not read.
    pub uniform: Option<UniformSteps>,
}

/// The per-particle factors of a scene whose particles are all alike.
#[derive(Clone, Copy, Debug)]
pub struct UniformSteps {
    /// The common mass m.
    pub mass: f64,
    /// Δt/m·inv and Δt/I·inv, as `cycle::step_factors` computes them.
    pub step_v: f64,
    pub step_w: f64,
}

/// Sums of a run: the work of gravity, the largest displacement component since the last
/// rebuild, whether every position and velocity is finite, whether some particle is beyond
/// an open side, the largest |v|² (nalgebra's `norm_squared`; finite velocities only).
#[derive(Clone, Copy, Debug)]
pub struct RunSums {
    pub w_grav: f64,
    pub max_disp: f64,
    pub finite: bool,
    pub outside: bool,
    pub speed2: f64,
}

/// Particles per entry of [`Run::groups`] (the reach margins' groups, `cycle::EXT_GROUP`;
/// a run of [`RUN`] particles holds whole groups).
pub const GROUP: usize = 64;
const _: () = assert!(RUN.is_multiple_of(GROUP));

/// The particle arrays of a run, sliced alike (`step_v` = Δt/m, `step_w` = Δt/I, each
/// already divided by 1 + α Δt/2; `mass`, `step_v` and `step_w` may be empty when
/// `Plain::uniform` is set).
pub struct Run<'a> {
    pub mass: &'a [f64],
    pub step_v: &'a [f64],
    pub step_w: &'a [f64],
    pub force: &'a [Vec3],
    pub moment: &'a [Vec3],
    pub vel: &'a mut [Vec3],
    pub pos: &'a mut [Vec3],
    pub disp: &'a mut [Vec3],
    pub spin: &'a mut [Vec3],
    pub rot: &'a mut [Vec3],
    /// Out: the largest velocity component of each group of [`GROUP`] particles (the
    /// reach margins' table, `cycle::set_margins`), `vel.len().div_ceil(GROUP)` entries
    /// (finite velocities only).
    pub groups: &'a mut [f64],
}

/// Updates plain particles (the work of gravity summed particle by particle, from zero).
pub fn update(c: &Plain, r: Run<'_>) -> RunSums {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above); the same arithmetic in
            // wider registers (no FMA is enabled, so no operation is fused). Measured: the
            // update of the S1 50k bed over 5000 steps 2.97 s (per particle) → 1.89 s
            // (doc/performance.md).
            return unsafe { update_avx2(c, r) };
        }
    }
    update_impl(c, r)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn update_avx2(c: &Plain, r: Run<'_>) -> RunSums {
    update_impl(c, r)
}

#[inline(always)]
fn update_impl(c: &Plain, r: Run<'_>) -> RunSums {
    let n = r.vel.len();
    let mut sums = RunSums {
        w_grav: 0.0,
        max_disp: 0.0,
        finite: true,
        outside: false,
        speed2: 0.0,
    };
    let force: &[f64] = bytemuck::cast_slice(r.force);
    let moment: &[f64] = bytemuck::cast_slice(r.moment);
    let vel: &mut [f64] = bytemuck::cast_slice_mut(r.vel);
    let pos: &mut [f64] = bytemuck::cast_slice_mut(r.pos);
    let disp: &mut [f64] = bytemuck::cast_slice_mut(r.disp);
    let spin: &mut [f64] = bytemuck::cast_slice_mut(r.spin);
    let rot: &mut [f64] = bytemuck::cast_slice_mut(r.rot);
    // Per-component factors of a run: body force m g fmm, Δt/m; bounds of the work-space.
    let mut fb = [0.0; 3 * RUN];
    let mut sv = [0.0; 3 * RUN];
    let mut sw = [0.0; 3 * RUN];
    let mut lo = [0.0; 3 * RUN];
    let mut hi = [0.0; 3 * RUN];
    for l in 0..RUN {
        for k in 0..3 {
            lo[3 * l + k] = c.lo[k];
            hi[3 * l + k] = c.hi[k];
        }
    }
    let mut work = [0.0; 3 * RUN];
    // Alike particles: the factors once (the same operations as per particle below).
    if let Some(u) = c.uniform {
        let s = u.mass * c.fmm;
        for l in 0..RUN {
            for k in 0..3 {
                fb[3 * l + k] = c.g[k] * s;
                sv[3 * l + k] = u.step_v;
                sw[3 * l + k] = u.step_w;
            }
        }
    }
    let mut start = 0;
    while start < n {
        let m = (n - start).min(RUN);
        let (a, b) = (3 * start, 3 * (start + m));
        if c.uniform.is_none() {
            for l in 0..m {
                let s = r.mass[start + l] * c.fmm;
                for k in 0..3 {
                    fb[3 * l + k] = c.g[k] * s;
                    sv[3 * l + k] = r.step_v[start + l];
                    sw[3 * l + k] = r.step_w[start + l];
                }
            }
        }
        // Translation, component by component: v = v_old·damp + (F + m g fmm)·Δt/m,
        // x += v Δt (and the displacement since the last rebuild).
        let (f, v, x, d) = (
            &force[a..b],
            &mut vel[a..b],
            &mut pos[a..b],
            &mut disp[a..b],
        );
        let q = 3 * m;
        for (((((v, x), d), (f, fbq)), svq), w) in v
            .iter_mut()
            .zip(x.iter_mut())
            .zip(d.iter_mut())
            .zip(f.iter().zip(&fb[..q]))
            .zip(&sv[..q])
            .zip(&mut work[..q])
        {
            let v_old = *v;
            let vn = velocity(v_old, c.damp, f + fbq, *svq);
            *v = vn;
            *w = fbq * ((vn + v_old) * 0.5);
            let dx = vn * c.dt;
            *x += dx;
            *d += dx;
        }
        // The run's largest displacement component, finiteness, escape through an open side.
        let (dmax, zero, out) = run_checks(&d[..q], &x[..q], &v[..q], (&lo[..q], &hi[..q]));
        // Its fastest particles while they are in the cache (the passes over the velocities
        // that the margins and the check after the step would make).
        let s2 = run_speeds(&v[..q], &mut r.groups[start / GROUP..]);
        sums.speed2 = if s2 > sums.speed2 { s2 } else { sums.speed2 };
        // The work of gravity m g·v̄ Δt, particle by particle (the dot product summed as
        // nalgebra's: (x + y) + z).
        for l in 0..m {
            let w = &work[3 * l..3 * l + 3];
            sums.w_grav += (w[0] + w[1] + w[2]) * c.dt;
        }
        if c.rotation {
            let (mo, w, th) = (&moment[a..b], &mut spin[a..b], &mut rot[a..b]);
            for q in 0..3 * m {
                let wn = velocity(w[q], c.damp, mo[q], sw[q]);
                w[q] = wn;
                th[q] += wn * c.dt;
            }
        }
        for lane in 0..4 {
            sums.max_disp = sums.max_disp.max(dmax[lane]);
            sums.finite &= zero[lane] == 0.0;
            sums.outside |= out[lane];
        }
        start += m;
    }
    sums
}

/// The largest displacement component of a run of components, whether they are finite
/// (x·0 + v·0 is 0 for finite values, NaN otherwise), and whether one is beyond an open side
/// (`lo`/`hi`, ±∞ along periodic axes): four lanes, then the rest in lane 0.
#[inline(always)]
fn run_checks(
    d: &[f64],
    x: &[f64],
    v: &[f64],
    (lo, hi): (&[f64], &[f64]),
) -> ([f64; 4], [f64; 4], [bool; 4]) {
    let q = d.len();
    let mut dmax = [0.0f64; 4];
    let mut zero = [0.0f64; 4];
    let mut out = [false; 4];
    let full = q / 4 * 4;
    for (((d, x), v), (lo, hi)) in d[..full]
        .chunks_exact(4)
        .zip(x[..full].chunks_exact(4))
        .zip(v[..full].chunks_exact(4))
        .zip(lo[..full].chunks_exact(4).zip(hi[..full].chunks_exact(4)))
    {
        for k in 0..4 {
            let ad = d[k].abs();
            dmax[k] = if ad > dmax[k] { ad } else { dmax[k] };
            zero[k] += x[k] * 0.0 + v[k] * 0.0;
            out[k] |= (x[k] < lo[k]) | (x[k] > hi[k]);
        }
    }
    for k in full..q {
        let ad = d[k].abs();
        dmax[0] = if ad > dmax[0] { ad } else { dmax[0] };
        zero[0] += x[k] * 0.0 + v[k] * 0.0;
        out[0] |= (x[k] < lo[k]) | (x[k] > hi[k]);
    }
    (dmax, zero, out)
}

/// The largest `|v_k|` of each group of [`GROUP`] particles of a run (`v`: its components,
/// the run starting at a group's start) into `groups`, and the run's largest `|v|²`, summed
/// as nalgebra's `norm_squared` sums it (`0 + ((x·x + y·y) + z·z)`, the `0 +` changing
/// nothing). For finite velocities these are the largest of a set, whatever the order they
/// are taken in (the update's callers use them only then): those of the folds of
/// `cycle::set_margins` and `cycle::after_step`. Four lanes, then the rest in lane 0.
#[inline(always)]
fn run_speeds(v: &[f64], groups: &mut [f64]) -> f64 {
    let larger = |a: f64, m: f64| if a > m { a } else { m };
    let fold = |m: [f64; 4]| m.iter().fold(0.0f64, |a, &b| larger(b, a));
    for (g, e) in v.chunks(3 * GROUP).zip(groups.iter_mut()) {
        let mut m = [0.0f64; 4];
        let mut fours = g.chunks_exact(4);
        for c in &mut fours {
            for k in 0..4 {
                m[k] = larger(c[k].abs(), m[k]);
            }
        }
        for c in fours.remainder() {
            m[0] = larger(c.abs(), m[0]);
        }
        *e = fold(m);
    }
    let mut m = [0.0f64; 4];
    let mut fours = v.chunks_exact(12);
    for c in &mut fours {
        for k in 0..4 {
            let x = &c[3 * k..3 * k + 3];
            m[k] = larger(x[0] * x[0] + x[1] * x[1] + x[2] * x[2], m[k]);
        }
    }
    for x in fours.remainder().chunks_exact(3) {
        m[0] = larger(x[0] * x[0] + x[1] * x[1] + x[2] * x[2], m[0]);
    }
    fold(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The component update against the same formulas written per particle with nalgebra
    /// (the general path of `cycle::move_all`): bitwise equal state and work of gravity.
    #[test]
    fn matches_the_vector_update_bit_for_bit() {
        check_against_vector_update(false);
    }

    /// The same with alike particles and the factors given once (`Plain::uniform`), the
    /// per-particle arrays left empty.
    #[test]
    fn alike_particles_match_the_vector_update_bit_for_bit() {
        check_against_vector_update(true);
    }

    fn check_against_vector_update(alike: bool) {
        let n: usize = 301; // more than two runs, not a multiple of 4
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut v3 = |scale: f64| -> Vec<Vec3> {
            (0..n)
                .map(|_| Vec3::new(rnd() * scale, rnd() * scale, rnd() * scale))
                .collect()
        };
        let force = v3(1e-2);
        let moment = v3(1e-6);
        let vel0 = v3(0.3);
        let pos0 = v3(0.02);
        let disp0 = v3(1e-4);
        let spin0 = v3(10.0);
        let rot0 = v3(1.0);
        let mass: Vec<f64> = (0..n)
            .map(|i| 1e-5 * (1.0 + if alike { 0.3 } else { (i % 7) as f64 * 0.1 }))
            .collect();
        let step_v: Vec<f64> = mass.iter().map(|m| 1.7e-5 / m).collect();
        let step_w: Vec<f64> = mass.iter().map(|m| 1.7e-5 / (0.4 * m * 1e-6)).collect();
        let uniform = alike.then(|| UniformSteps {
            mass: mass[0],
            step_v: step_v[0],
            step_w: step_w[0],
        });
        let c = Plain {
            g: [0.1, -0.2, -9.81],
            fmm: 1.0,
            damp: 1.0,
            dt: 1.7e-5,
            rotation: true,
            lo: [0.0, f64::NEG_INFINITY, 0.0],
            hi: [0.04, f64::INFINITY, 0.05],
            uniform,
        };
        let (mut vel, mut pos, mut disp, mut spin, mut rot) = (
            vel0.clone(),
            pos0.clone(),
            disp0.clone(),
            spin0.clone(),
            rot0.clone(),
        );
        let per_particle = if alike { 0 } else { n };
        let mut groups = vec![f64::NAN; n.div_ceil(GROUP)];
        let got = update(
            &c,
            Run {
                mass: &mass[..per_particle],
                step_v: &step_v[..per_particle],
                step_w: &step_w[..per_particle],
                force: &force,
                moment: &moment,
                vel: &mut vel,
                pos: &mut pos,
                disp: &mut disp,
                spin: &mut spin,
                rot: &mut rot,
                groups: &mut groups,
            },
        );
        let g = Vec3::from(c.g);
        let mut w_grav = 0.0;
        let mut max_disp = 0.0f64;
        let mut outside = false;
        for i in 0..n {
            let fb = g * (mass[i] * c.fmm);
            let v = vel0[i] * c.damp + (force[i] + fb) * step_v[i];
            let vbar = (v + vel0[i]) * 0.5;
            w_grav += fb.dot(&vbar) * c.dt;
            let dx = v * c.dt;
            let x = pos0[i] + dx;
            let d = disp0[i] + dx;
            let w = spin0[i] * c.damp + moment[i] * step_w[i];
            let th = rot0[i] + w * c.dt;
            assert_eq!(
                (vel[i], pos[i], disp[i], spin[i], rot[i]),
                (v, x, d, w, th),
                "particle {i}"
            );
            max_disp = max_disp.max(d.amax());
            outside |= (0..3).any(|k| x[k] < c.lo[k] || x[k] > c.hi[k]);
        }
        assert_eq!(got.w_grav.to_bits(), w_grav.to_bits());
        assert_eq!(got.max_disp.to_bits(), max_disp.to_bits());
        assert!(got.finite);
        assert_eq!(got.outside, outside);
        assert!(outside, "the random positions leave the box on some side");
        // The fastest particles as the folds over the particles give them (the passes of
        // `cycle::set_margins` and `cycle::after_step`).
        let speed2 = vel.iter().fold(0.0f64, |m, v| m.max(v.norm_squared()));
        assert_eq!(got.speed2.to_bits(), speed2.to_bits());
        for (k, g) in vel.chunks(GROUP).enumerate() {
            let a = g.iter().fold(0.0f64, |m, v| m.max(v.amax()));
            assert_eq!(groups[k].to_bits(), a.to_bits(), "group {k}");
        }
    }

    #[test]
    fn reports_a_non_finite_velocity_and_an_escape() {
        let n = 9;
        let c = Plain {
            g: [0.0, 0.0, -9.81],
            fmm: 1.0,
            damp: 1.0,
            dt: 1e-3,
            rotation: false,
            lo: [0.0; 3],
            hi: [1.0; 3],
            uniform: None,
        };
        let run = |bad_force: bool, pos_x: f64| {
            let mut force = vec![Vec3::zeros(); n];
            if bad_force {
                force[5].y = f64::INFINITY;
            }
            let mut pos = vec![Vec3::new(0.5, 0.5, 0.5); n];
            pos[8].x = pos_x;
            let ones = vec![1.0; n];
            let mut z = vec![vec![Vec3::zeros(); n]; 4];
            let [vel, disp, spin, rot] = &mut z[..] else {
                unreachable!()
            };
            let mut groups = [0.0];
            update(
                &c,
                Run {
                    mass: &ones,
                    step_v: &ones,
                    step_w: &ones,
                    force: &force,
                    moment: &force,
                    vel,
                    pos: &mut pos,
                    disp,
                    spin,
                    rot,
                    groups: &mut groups,
                },
            )
        };
        let s = run(true, 0.5);
        assert!(!s.finite);
        let s = run(false, -1e-3);
        assert!(s.finite && s.outside, "x < 0 is outside");
        let s = run(false, 0.5);
        assert!(s.finite && !s.outside);
    }
}
