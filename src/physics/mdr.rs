//! The Hertz–Mindlin tangential contact by the method of dimensionality reduction (MDR;
//! Popov & Heß 2015, ch. 5–6), the default tangential law of Hertz pairs (`SET TANgential
//! MDR`): a row of independent springs that keeps
//! the traction field itself, so that it is exact for any history of the normal and
//! tangential displacement, where the Mindlin–Deresiewicz law (`physics::tangential`, which
//! keeps the force and its turning points) cannot tell a field proportional to the pressure
//! from a Cattaneo field of the same force (doc/contact_laws.md, "Oblique impacts").
//!
//! # The law
//! The Hertz contact of two spheres is the contact of the rigid 1-D profile `g(x) = x²/R*`
//! with a row of independent springs, each of normal stiffness `E* dx` and tangential
//! stiffness `4G* dx` (`G*` Lian's (3.95), `1/G* = (2 − ν₁)/G₁ + (2 − ν₂)/G₂`; Popov's `G*`
//! is `4G*`). At the overlap `α` the spring at `x` is pressed by `u_z(x) = α − x²/R*`
//! (`a = (R*α)^{1/2}`: the normal force `2∫₀^a E* u_z dx = 4E*a³/(3R*)` is Hertz's). Its
//! tangential displacement `u(x)` (a vector in the contact plane) enters the contact at zero,
//! follows the relative tangential displacement of the bodies, `u ← u + Δδ`, while
//! `4G*|u| ≤ μE* u_z` (stick), is held at that limit along its own direction otherwise
//! (slip: Coulomb's law per spring, the MDR form of Mindlin & Deresiewicz 1953), and is
//! cleared when it leaves the contact. The tangential force is
//! `T = 2∫₀^a 4G* u dx` (both halves of the symmetric row) and the stored energy
//! `2∫₀^a ½ 4G*|u|² dx`. For a constant normal force this is Cattaneo–Mindlin exactly:
//! monotonic loading `δ = 3μP/(16G*a)[1 − (1 − T/μP)^{2/3}]`, the Masing unloading branch,
//! sliding at `μP` (the unit tests); with a varying normal force it is the exact
//! Mindlin–Deresiewicz history, which needs no incremental rule.
//!
//! # Discretisation
//! [`NODES`] springs at `x_i = (i + ½) a_ref/NODES`, `a_ref` the largest contact radius of
//! the contact so far (a spring keeps its place while the contact shrinks). When `a` exceeds
//! `a_ref` the field is carried over to the new nodes by linear interpolation in `x`, falling
//! linearly to zero between the last node and the old `a_ref` (a spring at the old edge was
//! just entering) and zero beyond. The displacement is kept as two components in a frame of
//! the contact plane (`e1`, `n × e1`), and the frame is turned with the plane (`e1`
//! projected on the new plane) as the other laws turn their history vectors.
//!
//! With 16 nodes Chung & Ooi's test 6 at the default step is within 1.3 % (restitution) and
//! 3.8 % (spin) of the exact solution at 5° (the exact row of 2000 springs in the same time
//! stepping: 1.3 % and 3.7 %), and within 0.3 % from 10° on (tests/it/oblique_impact.rs).
//!
//! # Scope
//! The row is the elastic Hertz contact without adhesion: the MDR of the JKR contact
//! (Popov & Heß 2015 ch. 6 with a tangential part) is not derived here, and a plastic
//! contact has no Hertz profile. `sim::interact` uses the Mindlin–Deresiewicz law for the
//! pairs with a surface energy or a law of `SET NORmal` under `MDR`.

use serde::{Deserialize, Serialize};

/// Springs per (half) row.
pub const NODES: usize = 16;

/// The independent sums of [`MdrRow::step`] (a divisor of [`NODES`]; four are added in a
/// fixed order at the end of the step).
const LANES: usize = 4;
const _: () = assert!(LANES == 4 && NODES.is_multiple_of(LANES));

/// The springs' places in steps of `a_ref/NODES`: `i + ½`.
const MID: [f64; NODES] = {
    let mut m = [0.5; NODES];
    let mut i = 1;
    while i < NODES {
        m[i] = m[i - 1] + 1.0;
        i += 1;
    }
    m
};

/// The row of one contact (checkpoint format 9: `ContactExt::mdr`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MdrRow {
    /// The largest contact radius of the contact so far (m): spring `i` sits at
    /// `(i + ½) a_ref/NODES`.
    pub a_ref: f64,
    /// Unit vector of the contact plane along which the first component of each spring's
    /// displacement lies (the second is along `n × e1`); zero before the first step.
    pub e1: [f64; 3],
    /// Tangential displacement of each spring (m), in the frame `e1`, `n × e1`.
    pub u: [[f64; 2]; NODES],
}

/// What one step of the row needs.
#[derive(Clone, Copy, Debug)]
pub struct MdrInput {
    /// Lian's `G*` (3.95) and `E*` (3.16) of the pair (Pa), the friction coefficient.
    pub g_star: f64,
    pub e_star: f64,
    pub mu: f64,
    /// The effective radius `R*` (m) and the contact radius `a` of this step (m).
    pub r_star: f64,
    pub a: f64,
    /// The step's relative tangential displacement in the frame (m).
    pub dd: [f64; 2],
}

/// What one step of the row gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MdrStep {
    /// The tangential force of the row along its displacement, `T = 8G* dx Σu` (N), in the
    /// frame (the force on the body that moved by `+Δδ` is `−T`).
    pub force: [f64; 2],
    /// The elastic energy of the row `4G* dx Σ|u|²` (J).
    pub energy: f64,
}

impl MdrRow {
    /// A row holding the force `t` (in the frame, along the displacement) at the contact
    /// radius `a`, for a contact that comes to this law while it touches (`SET TANgential`
    /// changed): the traction proportional to the pressure, `u ∝ a² − x²` (the field of a
    /// contact loaded tangentially together with its normal force), capped at the Coulomb
    /// limit of every spring.
    pub fn holding(t: [f64; 2], e1: [f64; 3], inp: &MdrInput) -> MdrRow {
        let mut row = MdrRow {
            a_ref: inp.a,
            e1,
            u: [[0.0; 2]; NODES],
        };
        let tl = t[0].hypot(t[1]);
        if !(tl > 0.0 && inp.a > 0.0 && inp.g_star > 0.0) {
            return row;
        }
        let dx = inp.a / NODES as f64;
        let shape: f64 = row.xs().map(|x| inp.a * inp.a - x * x).sum();
        // u_i = c (a² − x_i²) along t, with 8G* dx c Σ(a² − x²) = |t|, c at most the limit's.
        let c_lim = inp.mu * inp.e_star / (4.0 * inp.g_star * inp.r_star);
        let c = (tl / (8.0 * inp.g_star * dx * shape)).min(c_lim);
        let xs: Vec<f64> = row.xs().collect();
        for (u, x) in row.u.iter_mut().zip(xs) {
            let m = c * (inp.a * inp.a - x * x) / tl;
            *u = [m * t[0], m * t[1]];
        }
        row
    }

    /// The springs' places.
    fn xs(&self) -> impl Iterator<Item = f64> + use<> {
        let h = self.a_ref / NODES as f64;
        (0..NODES).map(move |i| (i as f64 + 0.5) * h)
    }

    /// Carries the field over to the nodes of a larger `a_ref`: the fraction of the old
    /// edge's parabola that each spring holds, `u/(a_ref² − x²)`, interpolated linearly in
    /// `x` (constant before the first node and after the last), times that parabola; zero
    /// beyond the old `a_ref`. A field proportional to the pressure (the traction of a
    /// contact loaded tangentially with its normal force) is carried over exactly.
    fn remap(&mut self, a: f64) {
        let ao = self.a_ref;
        let n = NODES as f64;
        let w = |x: f64| ao * ao - x * x;
        let mut phi = [[0.0; 2]; NODES];
        for (j, (p, u)) in phi.iter_mut().zip(&self.u).enumerate() {
            let wj = w((j as f64 + 0.5) / n * ao);
            *p = [u[0] / wj, u[1] / wj];
        }
        for (i, u) in self.u.iter_mut().enumerate() {
            let x = (i as f64 + 0.5) / n * a;
            // The place of x among the old nodes: old node j at s = j.
            let s = x / ao * n - 0.5;
            let p = if !(ao > 0.0) || x >= ao {
                [0.0; 2]
            } else if s <= 0.0 {
                phi[0]
            } else if s < n - 1.0 {
                let j = s as usize;
                let f = s - j as f64;
                [
                    phi[j][0] + f * (phi[j + 1][0] - phi[j][0]),
                    phi[j][1] + f * (phi[j + 1][1] - phi[j][1]),
                ]
            } else {
                phi[NODES - 1]
            };
            let wx = if x < ao { w(x) } else { 0.0 };
            *u = [p[0] * wx, p[1] * wx];
        }
        self.a_ref = a;
    }

    /// One step: the row follows the contact radius `a` (grown: remapped; springs outside
    /// cleared), every spring in contact moves by `Δδ` and is held at its Coulomb limit
    /// `μE*(a² − x²)/(4G*R*)`; the force `T = 8G* dx Σu` and the energy `4G* dx Σ|u|²`.
    ///
    /// The springs go in [`LANES`] lanes (spring `i` in lane `i mod LANES`), each lane with
    /// its own sums, added in a fixed order at the end: the result does not depend on the
    /// threads, and the lanes' arithmetic is independent, so that it vectorises. The groups
    /// of [`LANES`] springs that lie wholly outside the contact (`x ≥ a`) are only cleared.
    pub fn step(&mut self, inp: &MdrInput) -> MdrStep {
        let a = inp.a;
        if a > self.a_ref {
            self.remap(a);
        }
        let a2 = a * a;
        let lim_c = if inp.g_star > 0.0 {
            inp.mu.max(0.0) * inp.e_star / (4.0 * inp.g_star * inp.r_star)
        } else {
            0.0
        };
        let h = self.a_ref / NODES as f64;
        // The groups whose first spring is in contact (`x < a`), and the first group (a row
        // of zero size: its limit is zero).
        let groups = 1
            + (1..NODES / LANES)
                .filter(|&g| MID[g * LANES] * h < a)
                .count();
        let (active, outside) = self.u.split_at_mut(groups * LANES);
        outside.fill([0.0; 2]);
        let [dx, dy] = inp.dd;
        let (mut sx, mut sy, mut s2) = ([0.0; LANES], [0.0; LANES], [0.0; LANES]);
        for (g, us) in active.chunks_exact_mut(LANES).enumerate() {
            // The group's components apart (lane by lane), so that the lanes vectorise.
            let ux: [f64; LANES] = std::array::from_fn(|l| us[l][0] + dx);
            let uy: [f64; LANES] = std::array::from_fn(|l| us[l][1] + dy);
            let l2: [f64; LANES] = std::array::from_fn(|l| ux[l] * ux[l] + uy[l] * uy[l]);
            // Branch-free, the root taken for every spring (a conditional root, or a
            // select, becomes a branch): over its limit a spring is scaled by
            // `lim/|u| < 1`; out of contact the limit is 0 and it is scaled to +0; a zero
            // displacement gives 0/0 (NaN, which `min` passes over) or lim/0, and `r = 1`.
            let r: [f64; LANES] = std::array::from_fn(|l| {
                let x = MID[g * LANES + l] * h;
                let lim = lim_c * (a2 - x * x).max(0.0);
                (lim / l2[l].sqrt()).min(1.0)
            });
            let ux: [f64; LANES] = std::array::from_fn(|l| ux[l] * r[l] + 0.0);
            let uy: [f64; LANES] = std::array::from_fn(|l| uy[l] * r[l] + 0.0);
            for l in 0..LANES {
                sx[l] += ux[l];
                sy[l] += uy[l];
                s2[l] += l2[l] * (r[l] * r[l]);
                us[l] = [ux[l], uy[l]];
            }
        }
        let sum = |s: [f64; LANES]| (s[0] + s[1]) + (s[2] + s[3]);
        let k = 8.0 * inp.g_star * h;
        MdrStep {
            force: [k * sum(sx), k * sum(sy)],
            energy: 0.5 * k * sum(s2),
        }
    }
}

/// The frame of the contact plane of normal `n` (unit): `e1` turned into the plane (projected
/// and made unit), or, for a new row or an `e1` along `n`, a unit vector perpendicular to `n`
/// built from `n` alone; and `e2 = n × e1`.
pub fn frame(e1: [f64; 3], n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |v: [f64; 3]| {
        let l = dot(v, v).sqrt();
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let nd = dot(e1, n);
    let w = [e1[0] - n[0] * nd, e1[1] - n[1] * nd, e1[2] - n[2] * nd];
    let e = if dot(w, w) > 1e-12 {
        unit(w)
    } else {
        // The axis least along n, crossed with n.
        let ax = if n[0].abs() <= n[1].abs() && n[0].abs() <= n[2].abs() {
            [1.0, 0.0, 0.0]
        } else if n[1].abs() <= n[2].abs() {
            [0.0, 1.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        unit(cross(n, ax))
    };
    (e, cross(n, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    // A steel-like contact: E* = 100 GPa, G* = 20 GPa, μ = 0.3, R* = 1 mm, α = 1 µm.
    const E: f64 = 1e11;
    const G: f64 = 2e10;
    const MU: f64 = 0.3;
    const R: f64 = 1e-3;
    const ALPHA: f64 = 1e-6;

    fn a() -> f64 {
        (R * ALPHA).sqrt()
    }
    fn p() -> f64 {
        4.0 / 3.0 * E * a().powi(3) / R
    }
    fn inp(a: f64, dd: f64) -> MdrInput {
        MdrInput {
            g_star: G,
            e_star: E,
            mu: MU,
            r_star: R,
            a,
            dd: [dd, 0.0],
        }
    }
    /// Displacement at full sliding, `3μP/(16G*a)` (Mindlin 1949).
    fn delta_s() -> f64 {
        3.0 * MU * p() / (16.0 * G * a())
    }

    /// The constant of the Cattaneo–Mindlin displacement: at a constant normal force the
    /// row slides entirely at `δ_s = 3μP/(16G*a) = μE*α/(4G*)`, the centre spring's limit.
    #[test]
    fn sliding_displacement_is_the_centre_springs_limit() {
        assert!((delta_s() - MU * E * ALPHA / (4.0 * G)).abs() < 1e-12 * delta_s());
    }

    /// Monotonic loading at constant `P` follows Mindlin's `T = μP[1 − (1 − δ/δ_s)^{3/2}]`
    /// (the inverse of `δ = 3μP/(16G*a)[1 − (1 − T/μP)^{2/3}]`); the initial stiffness is
    /// `8G*a`; beyond `δ_s` the row slides at `μP`.
    #[test]
    fn monotonic_loading_at_constant_normal_force_is_mindlin() {
        let mut row = MdrRow::default();
        row.step(&inp(a(), 0.0));
        let n = 1000;
        let dd = 1.2 * delta_s() / n as f64;
        let mut worst: f64 = 0.0;
        for k in 1..=n {
            let t = row.step(&inp(a(), dd)).force[0];
            let d = k as f64 * dd;
            let want = MU * p() * (1.0 - (1.0 - (d / delta_s()).min(1.0)).powf(1.5));
            worst = worst.max((t - want).abs() / (MU * p()));
            if k == 1 {
                let kt = t / dd;
                assert!((kt / (8.0 * G * a()) - 1.0).abs() < 1e-9, "{kt}");
            }
        }
        assert!(worst < 6e-3, "{worst}");
        let t = row.step(&inp(a(), dd)).force[0];
        assert!(
            (t / (MU * p()) - 1.0).abs() < 1e-3,
            "sliding: {}",
            t / (MU * p())
        );
    }

    /// Unloading from `T*` follows Mindlin's Masing branch
    /// `T = T* − 2μP[1 − (1 − (δ* − δ)/(2δ_s))^{3/2}]`, and a full load–unload–reload cycle
    /// closes the loop with the energy of Mindlin et al. (1951) lost.
    #[test]
    fn unloading_is_the_masing_branch_and_the_loop_closes() {
        let mut row = MdrRow::default();
        row.step(&inp(a(), 0.0));
        let n = 1000;
        let d_star = 0.6 * delta_s();
        let dd = d_star / n as f64;
        let mut t_star = 0.0;
        for _ in 0..n {
            t_star = row.step(&inp(a(), dd)).force[0];
        }
        let e_star = row.step(&inp(a(), 0.0)).energy;
        let mut worst: f64 = 0.0;
        let mut work = 0.0;
        let mut t_old = t_star;
        // Down to −δ*, and back to δ*.
        for k in 1..=4 * n {
            let step = if k <= 2 * n { -dd } else { dd };
            let t = row.step(&inp(a(), step)).force[0];
            work += 0.5 * (t + t_old) * step;
            t_old = t;
            if k <= 2 * n {
                let back = k as f64 * dd;
                let want =
                    t_star - 2.0 * MU * p() * (1.0 - (1.0 - back / (2.0 * delta_s())).powf(1.5));
                worst = worst.max((t - want).abs() / (MU * p()));
            }
        }
        assert!(worst < 6e-3, "{worst}");
        assert!((t_old - t_star).abs() < 1e-3 * MU * p(), "the loop closes");
        let e_end = row.step(&inp(a(), 0.0)).energy;
        assert!((e_end - e_star).abs() < 1e-3 * e_star);
        // Mindlin et al. (1951): the loss per cycle of amplitude T* (Johnson 1985 (7.59)).
        let q = t_star / (MU * p());
        let loss = 9.0 * (MU * p()).powi(2) / (10.0 * G * a())
            * (1.0 - (1.0 - q).powf(5.0 / 3.0) - 5.0 / 6.0 * q * (1.0 + (1.0 - q).powf(2.0 / 3.0)));
        assert!((work / loss - 1.0).abs() < 0.03, "{work} {loss}");
    }

    /// Sliding along x, then along y: the force is `μP` along the motion (Coulomb per
    /// spring, in any direction).
    #[test]
    fn full_sliding_is_coulomb_in_any_direction() {
        let mut row = MdrRow::default();
        row.step(&inp(a(), 0.0));
        let d = 0.01 * delta_s();
        let mut t = [0.0; 2];
        for k in 0..1500 {
            let dd = if k < 200 { [d, 0.0] } else { [0.0, d] };
            t = row
                .step(&MdrInput {
                    dd,
                    ..inp(a(), 0.0)
                })
                .force;
        }
        assert!(
            (t[1] / (MU * p()) - 1.0).abs() < 1e-3,
            "{}",
            t[1] / (MU * p())
        );
        assert!(t[0].abs() < 1e-3 * MU * p(), "{}", t[0] / (MU * p()));
    }

    /// A contact loaded tangentially together with its normal force, `ΔT/ΔP` below `μ`, keeps
    /// the traction proportional to the pressure (no spring slips) and, at the end, `T` equals
    /// that ratio times `P` (Mindlin & Deresiewicz 1953); unloading the normal force at a fixed
    /// displacement then keeps `T/T₀` of tests/it/oblique_impact.rs's table (0.945 at
    /// `α/α₀ = 0.75`), not the Cattaneo field's 0.831.
    #[test]
    fn proportional_loading_keeps_its_field() {
        let mut row = MdrRow::default();
        let n = 400;
        let ratio = 0.5 * MU;
        let mut t = 0.0;
        for k in 1..=n {
            let al = ALPHA * k as f64 / n as f64;
            let al0 = ALPHA * (k - 1) as f64 / n as f64;
            // δ = ratio E* α/(4G*) gives every spring u = ratio/μ × its limit.
            let dd = ratio * E * (al - al0) / (4.0 * G);
            t = row.step(&inp((R * al).sqrt(), dd)).force[0];
        }
        assert!(
            (t / (ratio * p()) - 1.0).abs() < 2e-3,
            "{}",
            t / (ratio * p())
        );
        let t1 = row.step(&inp((R * 0.75 * ALPHA).sqrt(), 0.0)).force[0];
        assert!((t1 / t - 0.945).abs() < 5e-3, "{}", t1 / t);
    }

    /// A contact that shrinks clears the springs it leaves, and they come back into a regrown
    /// contact at zero (the law: a spring enters at `u = 0`): after loading at `a`, shrinking
    /// to `a/4` and growing back with no tangential motion, only the springs of `x < a/4` hold
    /// a displacement, and the force is theirs, `8G* dx Σu` summed spring by spring.
    #[test]
    fn springs_left_by_a_shrinking_contact_are_cleared() {
        let mut row = MdrRow::default();
        row.step(&inp(a(), 0.0));
        for _ in 0..10 {
            row.step(&inp(a(), 0.05 * delta_s()));
        }
        row.step(&inp(0.25 * a(), 0.0));
        let t = row.step(&inp(a(), 0.0)).force[0];
        let h = row.a_ref / NODES as f64;
        let mut sum = 0.0;
        for (i, u) in row.u.iter().enumerate() {
            let x = (i as f64 + 0.5) * h;
            if x < 0.25 * a() {
                assert!(u[0] > 0.0, "spring {i} kept");
                sum += u[0];
            } else {
                assert_eq!(*u, [0.0; 2], "spring {i} cleared");
            }
        }
        assert!((t / (8.0 * G * h * sum) - 1.0).abs() < 1e-14, "{t}");
    }

    /// A row made for a contact already holding a force gives that force back.
    #[test]
    fn a_row_made_mid_contact_holds_the_force() {
        let i = inp(a(), 0.0);
        let (e1, _) = frame([0.0; 3], [0.0, 0.0, 1.0]);
        let mut row = MdrRow::holding([0.3 * MU * p(), -0.2 * MU * p()], e1, &i);
        let t = row.step(&i).force;
        assert!((t[0] / (0.3 * MU * p()) - 1.0).abs() < 1e-12);
        assert!((t[1] / (-0.2 * MU * p()) - 1.0).abs() < 1e-12);
    }

    /// The frame is orthonormal and in the plane; a frame in the plane is kept.
    #[test]
    fn the_frame_turns_with_the_plane() {
        let n = [0.6, 0.0, 0.8];
        let (e1, e2) = frame([0.0; 3], n);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for (x, y) in [(e1, n), (e2, n), (e1, e2)] {
            assert!(dot(x, y).abs() < 1e-15);
        }
        assert!((dot(e1, e1) - 1.0).abs() < 1e-15 && (dot(e2, e2) - 1.0).abs() < 1e-15);
        assert_eq!(frame(e1, n).0, e1);
    }
}
