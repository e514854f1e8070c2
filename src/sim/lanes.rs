//! The steady Hertz contact with the no-slip tangential law, for many contacts at a time.
//!
//! In a dense dry bed almost every evaluated pair is a Hertzian contact that was touching in
//! the last step and still overlaps. For those the general kernel ([`super::interact`])
//! reduces to straight-line arithmetic: Hertz (3.14)–(3.15), the restitution dashpot, the
//! rotation of the shear force into the new contact plane (5.19)–(5.21) and the Mindlin
//! no-slip spring with its Coulomb cap. This module does that arithmetic on arrays of
//! contacts (structure of arrays, no branches: every choice is a select), so the compiler
//! can use the processor's vector units. Every operation is the one the scalar kernel does,
//! in the same order, so the results are bitwise those of [`super::interact`]; the energy
//! ledger's terms are returned per contact so the caller can add them in pair order.
//! Used by the pair loop and by the particle–wall contacts (a wall is the pair's other body
//! with R* and m* those of the wall contact).

use super::contacts::ContactState;
use super::kinematics::Kin;
use super::params::PairConst;
use super::scene::Vec3;
use crate::physics::{dashpot, hertz, tangential};

/// Contacts per batch.
pub const SUB: usize = 32;
const _: () = assert!(
    SUB.is_multiple_of(4),
    "the kernel pads batches to whole 4-lane vectors"
);

/// One batch of steady contacts: inputs (geometry, constants, the state of the last step)
/// and, after [`hertz_noslip`], the new state and the forces.
#[derive(Clone)]
pub struct Batch {
    pub len: usize,
    // geometry: normal A → B, relative velocity of B's contact point, gap
    pub nx: [f64; SUB],
    pub ny: [f64; SUB],
    pub nz: [f64; SUB],
    pub vx: [f64; SUB],
    pub vy: [f64; SUB],
    pub vz: [f64; SUB],
    pub gap: [f64; SUB],
    pub r_star: [f64; SUB],
    pub m_star: [f64; SUB],
    // pair constants
    pub e_star: [f64; SUB],
    pub g_star: [f64; SUB],
    pub mu: [f64; SUB],
    /// The dashpot's constant ζ sqrt(4/3 E*) (`PairConst::dash`).
    pub zeta: [f64; SUB],
    // state in and out
    pub damp: [f64; SUB],
    pub v_prev: [f64; SUB],
    pub tfx: [f64; SUB],
    pub tfy: [f64; SUB],
    pub tfz: [f64; SUB],
    pub tdx: [f64; SUB],
    pub tdy: [f64; SUB],
    pub tdz: [f64; SUB],
    pub tang_energy: [f64; SUB],
    // state out (`normal`: in, the last step's)
    pub a: [f64; SUB],
    pub normal: [f64; SUB],
    // force on B and moment per unit radius
    pub fx: [f64; SUB],
    pub fy: [f64; SUB],
    pub fz: [f64; SUB],
    pub mx: [f64; SUB],
    pub my: [f64; SUB],
    pub mz: [f64; SUB],
    // ledger terms: normal dashpot, friction, tangential dashpot
    pub e_damp_n: [f64; SUB],
    pub e_friction: [f64; SUB],
    pub e_damp_t: [f64; SUB],
}

impl Default for Batch {
    fn default() -> Self {
        Self::new()
    }
}

impl Batch {
    pub fn new() -> Batch {
        let z = [0.0; SUB];
        Batch {
            len: 0,
            nx: z,
            ny: z,
            nz: z,
            vx: z,
            vy: z,
            vz: z,
            gap: z,
            r_star: z,
            m_star: z,
            e_star: z,
            g_star: z,
            mu: z,
            zeta: z,
            damp: z,
            v_prev: z,
            tfx: z,
            tfy: z,
            tfz: z,
            tdx: z,
            tdy: z,
            tdz: z,
            tang_energy: z,
            a: z,
            normal: z,
            fx: z,
            fy: z,
            fz: z,
            mx: z,
            my: z,
            mz: z,
            e_damp_n: z,
            e_friction: z,
            e_damp_t: z,
        }
    }
}

impl Batch {
    /// The pair's contact is steady (it can take the batch): a Hertz contact without a bridge,
    /// touching in the last step and overlapping now, with a dashpot and friction.
    #[inline(always)]
    pub fn takes(kin: &Kin, pc: &PairConst, s: &ContactState) -> bool {
        s.touching
            && s.ext.is_none()
            && s.bridge.is_none()
            && kin.gap < 0.0
            && pc.zeta > 0.0
            && pc.mu > 0.0
            && !pc.pull
    }

    /// Appends a contact; returns its lane.
    #[inline(always)]
    pub fn push(&mut self, kin: &Kin, pc: &PairConst, s: &ContactState) -> usize {
        let l = self.len;
        self.nx[l] = kin.n.x;
        self.ny[l] = kin.n.y;
        self.nz[l] = kin.n.z;
        self.vx[l] = kin.v_rel.x;
        self.vy[l] = kin.v_rel.y;
        self.vz[l] = kin.v_rel.z;
        self.gap[l] = kin.gap;
        self.r_star[l] = kin.r_star;
        self.m_star[l] = kin.m_star;
        self.e_star[l] = pc.e_star;
        self.g_star[l] = pc.g_star;
        self.mu[l] = pc.mu;
        self.zeta[l] = pc.dash;
        self.damp[l] = s.damp_force;
        self.v_prev[l] = s.v_prev;
        self.normal[l] = s.normal_force;
        self.tfx[l] = s.tforce.x;
        self.tfy[l] = s.tforce.y;
        self.tfz[l] = s.tforce.z;
        self.tdx[l] = s.tdamp.x;
        self.tdy[l] = s.tdamp.y;
        self.tdz[l] = s.tdamp.z;
        self.tang_energy[l] = s.tang_energy;
        self.len += 1;
        l
    }

    /// Writes lane `l`'s new state into the contact's; returns its force on B and moment per
    /// unit radius.
    #[inline(always)]
    pub fn store(&self, l: usize, s: &mut ContactState) -> (Vec3, Vec3) {
        s.a = self.a[l];
        s.normal_force = self.normal[l];
        s.overlap = -self.gap[l];
        s.damp_force = self.damp[l];
        s.v_prev = self.v_prev[l];
        s.tforce = Vec3::new(self.tfx[l], self.tfy[l], self.tfz[l]);
        s.tang_energy = self.tang_energy[l];
        s.tdamp = Vec3::zeros();
        (
            Vec3::new(self.fx[l], self.fy[l], self.fz[l]),
            Vec3::new(self.mx[l], self.my[l], self.mz[l]),
        )
    }
}

#[inline(always)]
fn sel(c: bool, a: f64, b: f64) -> f64 {
    if c { a } else { b }
}

/// The steady Hertz + restitution dashpot + no-slip contact for the first `b.len` contacts
/// (touching in the last step, overlapping now, Rayleigh β = 0, Δt > 0). The same arithmetic
/// as `interact::<false, false>` with `tangential_step`, operation by operation.
pub fn hertz_noslip(b: &mut Batch, dt: f64) {
    #[cfg(target_arch = "x86_64")]
    {
        // Four lanes where the processor has them (measured: −10 % of the step on the
        // settled S1 bed against the two lanes of the baseline x86-64 build, same bits).
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above); the function is the
            // portable kernel compiled for it (no FMA contraction: Rust does not fuse).
            return unsafe { hertz_noslip_avx2(b, dt) };
        }
    }
    hertz_noslip_impl(b, dt)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn hertz_noslip_avx2(b: &mut Batch, dt: f64) {
    hertz_noslip_impl(b, dt)
}

#[inline(always)]
fn hertz_noslip_impl(b: &mut Batch, dt: f64) {
    // The contacts padded to whole 4-lane vectors (SUB is a multiple of 4): the lanes past
    // `len` compute on what the last batch left there (or zeros; NaN at worst, never read),
    // which costs less than the scalar remainder loop would (settled S1 10k, one thread:
    // −13 % of this kernel's instructions, its share of the samples 13.6–14.1 % → 11.0–12.4 %;
    // a batch holds ~6 contacts on average). The first `len` lanes are unchanged.
    let n = b.len.min(SUB).div_ceil(4) * 4;
    let inv_dt = 1.0 / dt;
    for l in 0..n.min(SUB) {
        let (nx, ny, nz) = (b.nx[l], b.ny[l], b.nz[l]);
        let (vx, vy, vz) = (b.vx[l], b.vy[l], b.vz[l]);
        let alpha = -b.gap[l];
        let v_n = vx * nx + vy * ny + vz * nz;
        let fd_prev = b.damp[l];
        let p_old = b.normal[l];
        let (e_star, r_star, m_star) = (b.e_star[l], b.r_star[l], b.m_star[l]);
        // Hertz (3.14)-(3.15).
        let (a, p) = hertz::radius_and_force(e_star, r_star, alpha);
        let fn0 = 0.0 + p;
        // Restitution dashpot D (R*α)^{1/4} α' over the step with the implicit midpoint
        // velocity (physics::dashpot), clamped so the total stays compressive.
        let f_prev = p_old + fd_prev + 0.0;
        let f_static = p - 0.0;
        let inv_m = 1.0 / m_star;
        let drive = dashpot::drive(f_static, f_prev, v_n, b.v_prev[l], inv_m, inv_dt);
        let (coef, vn) = dashpot::viscous_step(&dashpot::ViscousIn {
            alpha,
            v: v_n,
            drive,
            dash: b.zeta[l],
            scale: m_star * m_star * r_star,
            steady: true,
            point: (m_star * a).sqrt(),
            linear: 0.0 + 0.0,
            inv_m,
            dt,
        });
        let fd = 0.0 - coef * vn;
        let fd = sel(p + fd < 0.0, -p, fd);
        b.v_prev[l] = v_n;
        let e_damp_n = -0.5 * (fd + fd_prev) * v_n * dt;
        let fn_b = fn0 + fd;
        // Rotation of the shear force into the new contact plane, keeping its length.
        let [tx, ty, tz] =
            tangential::rotate_into_plane([b.tfx[l], b.tfy[l], b.tfz[l]], [nx, ny, nz]);
        // Tangential relative velocity and displacement increment.
        let vn2 = vx * nx + vy * ny + vz * nz;
        let (vtx, vty, vtz) = (vx - nx * vn2, vy - ny * vn2, vz - nz * vn2);
        let (ddx, ddy, ddz) = (vtx * dt, vty * dt, vtz * dt);
        let kt0 = 8.0 * b.g_star[l] * a;
        // No-slip spring k_t = 8 G* a with the Coulomb cap μ P.
        let pe = p + 2.0 * 0.0;
        let step = tangential::noslip_spring([tx, ty, tz], [ddx, ddy, ddz], kt0, b.mu[l], pe);
        let [fx, fy, fz] = step.force;
        let (work, e_new) = (step.work, step.energy);
        let e_friction = work - (e_new - b.tang_energy[l]);
        // Rayleigh tangential dashpot: zero (β = 0); the last step's is booked.
        let (ftx, fty, ftz) = (fx + 0.0, fy + 0.0, fz + 0.0);
        let (qx, qy, qz) = (0.0 + b.tdx[l], 0.0 + b.tdy[l], 0.0 + b.tdz[l]);
        let e_damp_t = -0.5 * (qx * vtx + qy * vty + qz * vtz) * dt;
        // Force on B, n F_n + F_t, and the moment per unit radius −n × F_t.
        b.fx[l] = nx * fn_b + ftx;
        b.fy[l] = ny * fn_b + fty;
        b.fz[l] = nz * fn_b + ftz;
        b.mx[l] = -(ny * ftz - nz * fty);
        b.my[l] = -(nz * ftx - nx * ftz);
        b.mz[l] = -(nx * fty - ny * ftx);
        b.a[l] = a;
        b.normal[l] = p;
        b.damp[l] = fd;
        b.tfx[l] = fx;
        b.tfy[l] = fy;
        b.tfz[l] = fz;
        b.tang_energy[l] = e_new;
        b.e_damp_n[l] = e_damp_n;
        b.e_friction[l] = e_friction;
        b.e_damp_t[l] = e_damp_t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::contacts::ContactState;
    use crate::sim::interact::{Acc, Kin, Laws, interact};
    use crate::sim::model::TangentialChoice;
    use crate::sim::params::PairConst;
    use crate::sim::rng::Rng;
    use crate::sim::scene::Vec3;

    fn unit(r: &mut Rng) -> Vec3 {
        let v = Vec3::new(r.normal(), r.normal(), r.normal());
        v / v.norm()
    }

    /// The batch kernel against the general kernel on random steady contacts, covering the
    /// cases its selects stand for: sticking and sliding, a shear force that is zero or
    /// normal to the new plane, the dashpot clamp, and overlaps down to round-off. Every
    /// state field, force and ledger term must agree bit for bit.
    #[test]
    fn batch_kernel_is_the_general_kernel_bit_for_bit() {
        let mut r = Rng::new(7);
        let dt = 1.7e-5;
        let laws = Laws::dry(dt, TangentialChoice::NoSlip);
        let mut cases = 0;
        let mut seen = [0usize; 5]; // sliding, sticking, zero shear, shear along n, clamped
        for _ in 0..200 {
            let mut b = Batch::new();
            let mut kins = Vec::new();
            let mut states = Vec::new();
            let mut pcs = Vec::new();
            for l in 0..SUB {
                let n = unit(&mut r);
                let ri = 1e-3 * (0.5 + r.uniform());
                let rj = 1e-3 * (0.5 + r.uniform());
                let alpha = match l % 4 {
                    0 => 1e-6 * r.uniform(),
                    1 => 1e-18 * r.uniform(),
                    _ => 1e-5 * r.uniform() + 1e-300,
                };
                let speed = [1e-4, 1.0, 100.0][l % 3];
                let v_rel = Vec3::new(r.normal(), r.normal(), r.normal()) * speed;
                let kin = Kin {
                    n,
                    gap: -alpha,
                    v_rel,
                    r_star: ri * rj / (ri + rj),
                    m_star: 1e-5 * (0.2 + r.uniform()),
                    r1: ri,
                    r2: rj,
                };
                let pc = PairConst {
                    e_star: 1e7 * (0.5 + r.uniform()),
                    g_star: 4e6 * (0.5 + r.uniform()),
                    mu: 0.5 * r.uniform() + 1e-3,
                    gamma: 0.0,
                    gamma_base: 0.0,
                    zeta: 0.3 * r.uniform() + 1e-3,
                    dash: 0.0,
                    law: 0,
                    pull: false,
                };
                let pc = PairConst {
                    dash: pc.zeta * (4.0 / 3.0 * pc.e_star).sqrt(),
                    ..pc
                };
                let tf = match l % 5 {
                    0 => Vec3::zeros(),
                    1 => n * 1e-3,
                    _ => Vec3::new(r.normal(), r.normal(), r.normal()) * 1e-3,
                };
                let s = ContactState {
                    touching: true,
                    overlap: alpha * 0.9,
                    normal_force: 1e-3,
                    damp_force: 1e-4 * r.normal(),
                    // No history, a history, and one far from the current rate.
                    v_prev: match l % 3 {
                        0 => f64::INFINITY,
                        1 => v_rel.dot(&n) * (1.0 + 1e-3 * r.normal()),
                        _ => speed * r.normal(),
                    },
                    tang_energy: 1e-9 * r.uniform(),
                    a: 1e-5,
                    tforce: tf,
                    tdamp: if l % 7 == 0 {
                        Vec3::new(1e-6, -2e-6, 3e-6)
                    } else {
                        Vec3::zeros()
                    },
                    ext: None,
                    bridge: None,
                    row: crate::sim::contacts::RowSlot::NONE,
                };
                assert!(Batch::takes(&kin, &pc, &s));
                assert_eq!(b.push(&kin, &pc, &s), l);
                kins.push(kin);
                states.push(s);
                pcs.push(pc);
            }
            // The portable build of the kernel (two lanes on x86-64 without AVX2) gives the
            // same bits as the one the processor runs.
            let mut portable = b.clone();
            hertz_noslip_impl(&mut portable, dt);
            hertz_noslip(&mut b, dt);
            let fields = |b: &Batch| {
                let mut v = Vec::new();
                for a in [
                    &b.fx, &b.fy, &b.fz, &b.mx, &b.my, &b.mz, &b.a, &b.normal, &b.damp, &b.v_prev,
                ] {
                    v.extend(a.iter().map(|x| x.to_bits()));
                }
                for a in [
                    &b.tfx,
                    &b.tfy,
                    &b.tfz,
                    &b.tang_energy,
                    &b.e_damp_n,
                    &b.e_friction,
                ] {
                    v.extend(a.iter().map(|x| x.to_bits()));
                }
                v.extend(b.e_damp_t.iter().map(|x| x.to_bits()));
                v
            };
            assert_eq!(fields(&portable), fields(&b));
            for l in 0..SUB {
                let s = &mut states[l];
                let tf_old = s.tforce;
                let mut acc = Acc::default();
                let out = interact::<false, false>(&kins[l], &pcs[l], &laws, s, &mut acc);
                let m = -kins[l].n.cross(&out.ft);
                let bits = |x: f64| x.to_bits();
                let same = |a: Vec3, x: f64, y: f64, z: f64| {
                    bits(a.x) == bits(x) && bits(a.y) == bits(y) && bits(a.z) == bits(z)
                };
                assert!(same(out.f, b.fx[l], b.fy[l], b.fz[l]), "force, lane {l}");
                assert!(same(m, b.mx[l], b.my[l], b.mz[l]), "moment, lane {l}");
                assert!(
                    same(s.tforce, b.tfx[l], b.tfy[l], b.tfz[l]),
                    "shear, lane {l}"
                );
                assert_eq!(bits(s.a), bits(b.a[l]));
                assert_eq!(bits(s.normal_force), bits(b.normal[l]));
                assert_eq!(bits(s.damp_force), bits(b.damp[l]));
                assert_eq!(bits(s.v_prev), bits(b.v_prev[l]));
                assert_eq!(bits(s.tang_energy), bits(b.tang_energy[l]));
                assert_eq!(s.tdamp, Vec3::zeros());
                // The general kernel adds its terms to a zero ledger: the sums are the terms.
                assert_eq!(bits(acc.friction), bits(0.0 + b.e_friction[l]));
                assert_eq!(
                    bits(acc.damping_contact),
                    bits(0.0 + b.e_damp_n[l] + b.e_damp_t[l])
                );
                let cap = pcs[l].mu * s.normal_force;
                let t = s.tforce.norm();
                seen[0] += (t > 0.0 && (t - cap).abs() <= 1e-12 * cap) as usize;
                seen[1] += (t < 0.999 * cap) as usize;
                seen[2] += (tf_old == Vec3::zeros()) as usize;
                seen[3] += (l % 5 == 1) as usize;
                seen[4] += (s.damp_force == -s.normal_force) as usize;
                cases += 1;
            }
        }
        assert_eq!(cases, 200 * SUB);
        assert!(
            seen.iter().all(|&k| k > 50),
            "cases not all covered: {seen:?}"
        );
    }
}
