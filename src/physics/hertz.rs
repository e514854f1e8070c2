//! Hertz normal contact of elastic spheres (no adhesion), effective material properties and the
//! Rayleigh critical time step.
//!
//! Conventions (see `doc/spec/DECISIONS.md`): SI units; the overlap (relative approach) `α`
//! is positive in compression and the normal force is compressive-positive. Equation numbers
//! are those of Lian (1994), `seeds/000_6b8655e566374cea.txt`.
//!
//! With `K = 4/3 E* sqrt(R*)` the Hertz law is `P = K α^{3/2}`, the contact radius is
//! `a = sqrt(R* α)` and the stiffness is `dP/dα = 2 E* a`.
//!
//! All functions are pure and never panic. They expect physically meaningful inputs
//! (`E* > 0`, `R* > 0`, `m* > 0`); overlaps `α <= 0` mean "no contact" and give zero.

// `!(x > y)` comparisons are deliberate: they also route NaN to the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// Dimensionless Hertz impact-duration factor: `t_c = HERTZ_DURATION_FACTOR · α_max / v`.
///
/// Derivation (energy conservation of `m* α'' = −K α^{3/2}`, `α'(0) = v`):
/// `t_c = 2 ∫_0^{α_max} dα / sqrt(v² − (4K/5m*) α^{5/2}) = 2 (α_max / v) ∫_0^1 (1 − x^{5/2})^{-1/2} dx`
/// and `∫_0^1 (1 − x^n)^{-1/2} dx = B(1/n, 1/2)/n`, so with `n = 5/2`:
/// `factor = (4/5) Γ(2/5) Γ(1/2) / Γ(9/10) = 2.943275184…`.
/// In the familiar form `t_c = 2.868 (m*² / (R* E*² v))^{1/5}` the constant is
/// `factor · (15/16)^{2/5} = 2.8682657…`.
pub const HERTZ_DURATION_FACTOR: f64 = 2.943_275_184_324_705;

/// Hertz force constant `K = 4/3 E* sqrt(R*)` so that `P = K α^{3/2}`; Lian 1994 (3.14)–(3.15).
pub fn force_constant(e_star: f64, r_star: f64) -> f64 {
    4.0 / 3.0 * e_star * r_star.sqrt()
}

/// Hertz contact radius `a = sqrt(R* α)`; Lian 1994 (3.15). Zero for `overlap <= 0`.
pub fn contact_radius(r_star: f64, overlap: f64) -> f64 {
    if overlap > 0.0 {
        (r_star * overlap).sqrt()
    } else {
        0.0
    }
}

/// Contact radius and normal force of a touching Hertz contact, `a = sqrt(R* α)` and
/// `P = 4/3 E* a α` (= 4/3 E* a³/R*); Lian 1994 (3.14)–(3.15). The form both contact kernels
/// evaluate (`sim::interact` and the vectorised `sim::lanes`), so that they agree bit for bit;
/// `overlap > 0` is the caller's.
#[inline(always)]
pub fn radius_and_force(e_star: f64, r_star: f64, overlap: f64) -> (f64, f64) {
    let a = (r_star * overlap).sqrt();
    (a, 4.0 / 3.0 * e_star * a * overlap)
}

/// Hertz normal force `P = 4/3 E* sqrt(R*) α^{3/2}` (compressive positive); Lian 1994 (3.14),
/// (3.15) combined (`a³ = 3PR*/(4E*)`, `α = a²/R*`). Zero for `overlap <= 0`.
pub fn force(e_star: f64, r_star: f64, overlap: f64) -> f64 {
    if overlap > 0.0 {
        force_constant(e_star, r_star) * overlap * overlap.sqrt()
    } else {
        0.0
    }
}

/// The Hurwitz zeta function at `−σ` (`σ > 0`), `ζ(−σ, a) = Σ_{j≥0} (j + a)^σ` (continued
/// analytically), for `a > 0`: by the Euler–Maclaurin formula after 16 terms of the sum,
/// `Σ_{j<16} (j + a)^σ − [b^{σ+1}/(σ+1) − b^σ/2 + σ/12 b^{σ−1} − σ(σ−1)(σ−2)/720 b^{σ−3} +
/// σ(σ−1)(σ−2)(σ−3)(σ−4)/30240 b^{σ−5}]`, `b = a + 16` (better than 1e-10 absolute for
/// `0 < a ≤ 2`, σ ≤ 5/2; `ζ(−3/2) = −0.0254852019`, `ζ(−5/2) = +0.0085169288`).
pub fn hurwitz_zeta_neg(sigma: f64, a: f64) -> f64 {
    const N: usize = 16;
    let mut sum = 0.0;
    for j in 0..N {
        sum += (j as f64 + a).powf(sigma);
    }
    let b = a + N as f64;
    let s = sigma;
    let tail = b.powf(s + 1.0) / (s + 1.0) - b.powf(s) / 2.0 + s / 12.0 * b.powf(s - 1.0)
        - s * (s - 1.0) * (s - 2.0) / 720.0 * b.powf(s - 3.0)
        + s * (s - 1.0) * (s - 2.0) * (s - 3.0) * (s - 4.0) / 30240.0 * b.powf(s - 5.0);
    sum - tail
}

/// `ζ(−3/2, a)` ([`hurwitz_zeta_neg`]).
pub fn hurwitz_zeta_m32(a: f64) -> f64 {
    hurwitz_zeta_neg(1.5, a)
}

/// Hertz normal stiffness `k_n = dP/dα = 2 E* a = 2 E* sqrt(R* α)`; derivative of Lian 1994
/// (3.14)–(3.15), equal to the `P_c = 0` limit of (3.41). Zero for `overlap <= 0`.
pub fn stiffness(e_star: f64, r_star: f64, overlap: f64) -> f64 {
    2.0 * e_star * contact_radius(r_star, overlap)
}

/// Elastic strain energy stored in a Hertz contact, `U = ∫_0^α P dα' = 8/15 E* sqrt(R*) α^{5/2}`
/// (integral of Lian 1994 (3.14)–(3.15)). Zero for `overlap <= 0`.
pub fn energy(e_star: f64, r_star: f64, overlap: f64) -> f64 {
    if overlap > 0.0 {
        8.0 / 15.0 * e_star * r_star.sqrt() * overlap * overlap * overlap.sqrt()
    } else {
        0.0
    }
}

/// Maximum overlap of a head-on elastic Hertz impact at relative normal speed `v`:
/// `α_max = (15 m* v² / (16 E* sqrt(R*)))^{2/5}` (½ m* v² = 8/15 E* sqrt(R*) α_max^{5/2}, from
/// Lian 1994 (3.14)–(3.15)). `m*` is the reduced mass `m1 m2 / (m1 + m2)`.
pub fn max_overlap(m_star: f64, r_star: f64, e_star: f64, v: f64) -> f64 {
    let k = force_constant(e_star, r_star);
    (1.25 * m_star * v * v / k).powf(0.4)
}

/// Peak force of a head-on elastic Hertz impact, `P_max = 4/3 E* sqrt(R*) α_max^{3/2}` with
/// `α_max` from [`max_overlap`]; Lian 1994 (3.14)–(3.15).
pub fn max_force(m_star: f64, r_star: f64, e_star: f64, v: f64) -> f64 {
    force(e_star, r_star, max_overlap(m_star, r_star, e_star, v))
}

/// Duration of a head-on elastic Hertz impact at relative normal speed `v`,
/// `t_c = 2.9432752 α_max / v = 2.8682657 (m*² / (R* E*² v))^{1/5}` (Hertz theory built on
/// Lian 1994 (3.14)–(3.15); the constant is derived exactly in [`HERTZ_DURATION_FACTOR`]).
/// Returns `+∞` for `v = 0` (the duration grows as `v^{-1/5}`).
pub fn impact_duration(m_star: f64, r_star: f64, e_star: f64, v: f64) -> f64 {
    let k = force_constant(e_star, r_star);
    // α_max / v = (5 m* / (4 K))^{2/5} v^{-1/5}; written this way it stays finite for v → 0⁺.
    HERTZ_DURATION_FACTOR * (1.25 * m_star / k).powf(0.4) * v.abs().powf(-0.2)
}

/// Effective contact modulus `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2`; Lian 1994 (3.16).
/// (The appendix copy (A.4) has a typo, `E2` under `ν1`.) For like spheres `E* = E / (2(1 − ν²))`.
/// A rigid body may be given as `E = +∞`.
pub fn e_star(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Shear modulus of an isotropic solid, `G = E / (2(1 + ν))` (standard elasticity, used with
/// Lian 1994 (3.95)).
pub fn shear_modulus(e: f64, nu: f64) -> f64 {
    e / (2.0 * (1.0 + nu))
}

/// Effective tangential (Mindlin) modulus `1/G* = (2 − ν1)/G1 + (2 − ν2)/G2`; Lian 1994 (3.95)
/// and (A.5). Arguments are the shear moduli `G_i` (see [`shear_modulus`]) and Poisson ratios.
/// For like spheres `G* = G / (2(2 − ν))`, and `k_t = 8 G* a` (3.94).
pub fn g_star(g1: f64, nu1: f64, g2: f64, nu2: f64) -> f64 {
    1.0 / ((2.0 - nu1) / g1 + (2.0 - nu2) / g2)
}

/// Effective radius of two spheres, `1/R* = 1/R1 + 1/R2`; Lian 1994 (3.5).
pub fn r_star(r1: f64, r2: f64) -> f64 {
    r1 * r2 / (r1 + r2)
}

/// Effective radius for a sphere of radius `r` on a plane wall (rigid half-space): `R* = R`
/// (the `R2 → ∞` limit of Lian 1994 (3.5); doc/spec/DECISIONS.md, "Contact laws").
pub fn r_star_plane(r: f64) -> f64 {
    r
}

/// Effective radius for a sphere of radius `r` inside a spherical container of radius `d`
/// (concave wall): `R* = R d / (d − R)`, i.e. Lian 1994 (3.5) with `R2 = −d`
/// (doc/spec/DECISIONS.md, "Contact laws"). Requires `d > r`; returns `+∞` when `d <= r` (conformal or
/// impossible geometry, which the caller must reject).
pub fn r_star_container(r: f64, d: f64) -> f64 {
    if d > r {
        r * d / (d - r)
    } else {
        f64::INFINITY
    }
}

/// Effective radius for a sphere of radius `r` touching a spherical obstacle/indenter of radius
/// `d` from outside: `R* = R d / (d + R)`, i.e. Lian 1994 (3.5) with `R2 = d`
/// (doc/spec/DECISIONS.md, "Contact laws").
pub fn r_star_obstacle(r: f64, d: f64) -> f64 {
    r_star(r, d)
}

/// Rayleigh critical time step `Δt_R = π R_min sqrt(ρ/G) / (0.1631 ν + 0.8766)`
/// (doc/spec/DECISIONS.md, "Time integration and time step"; Lian 1994 §5 only names the Rayleigh-wave criterion, see
/// spec §10 item 1). `0.1631 ν + 0.8766` is the usual linear fit of the Rayleigh-wave speed
/// ratio `c_R / c_S`; `g` is the shear modulus `G`.
pub fn rayleigh_dt(r_min: f64, rho: f64, g: f64, nu: f64) -> f64 {
    std::f64::consts::PI * r_min * (rho / g).sqrt() / (0.1631 * nu + 0.8766)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (3.14)–(3.15): a² = R* α and P = 4/3 E* a³/R*, the same force as `force`.
    #[test]
    fn radius_and_force_is_hertz() {
        let (e, r, alpha) = (3.8e10, 15e-6, 2e-8);
        let (a, p) = radius_and_force(e, r, alpha);
        assert!((a * a - r * alpha).abs() < 1e-15 * r * alpha);
        assert!((p - 4.0 / 3.0 * e * a.powi(3) / r).abs() < 1e-14 * p);
        assert!((p - force(e, r, alpha)).abs() < 1e-14 * p);
    }

    /// ζ(−3/2, a) against its values: ζ(−3/2) (a = 1), (2^{−3/2} − 1) ζ(−3/2) (a = 1/2), and
    /// the recurrence ζ(−3/2, a) = a^{3/2} + ζ(−3/2, a + 1).
    #[test]
    fn hurwitz_zeta_at_minus_three_halves() {
        let z = -0.025_485_201_889_833_03;
        assert!((hurwitz_zeta_m32(1.0) - z).abs() < 1e-10);
        assert!((hurwitz_zeta_m32(0.5) - (0.5f64.powf(1.5) - 1.0) * z).abs() < 1e-10);
        for a in [0.01, 0.3, 0.77, 1.0] {
            let d = hurwitz_zeta_m32(a) - a.powf(1.5) - hurwitz_zeta_m32(a + 1.0);
            assert!(d.abs() < 1e-10, "{a}: {d}");
            let d = hurwitz_zeta_neg(2.5, a) - a.powf(2.5) - hurwitz_zeta_neg(2.5, a + 1.0);
            assert!(d.abs() < 1e-10, "{a}: {d}");
        }
        // ζ(−5/2) and ζ(−5/2, ½) = (2^{−5/2} − 1) ζ(−5/2); the mean over a ∈ (0, 1) is 0.
        let z = 0.008_516_928_777_850_3;
        assert!((hurwitz_zeta_neg(2.5, 1.0) - z).abs() < 1e-10);
        assert!((hurwitz_zeta_neg(2.5, 0.5) - (2f64.powf(-2.5) - 1.0) * z).abs() < 1e-10);
        for sigma in [1.5, 2.5] {
            let n = 20000;
            let mean = (0..n)
                .map(|k| hurwitz_zeta_neg(sigma, (k as f64 + 0.5) / n as f64))
                .sum::<f64>()
                / n as f64;
            assert!(mean.abs() < 1e-8, "{sigma}: {mean}");
        }
    }

    const R: f64 = 30e-6;
    const E: f64 = 70e9;
    const NU: f64 = 0.3;
    const RHO: f64 = 2650.0;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn effective_properties_like_spheres() {
        // Like spheres: E* = E/(2(1−ν²)), G* = G/(2(2−ν)), R* = R/2.
        assert!(rel(e_star(E, NU, E, NU), E / (2.0 * (1.0 - NU * NU))) < 1e-15);
        let g = shear_modulus(E, NU);
        assert!(rel(g, 26.923_076_923_076_923e9) < 1e-15);
        assert!(rel(g_star(g, NU, g, NU), g / (2.0 * (2.0 - NU))) < 1e-15);
        assert!(rel(r_star(R, R), R / 2.0) < 1e-15);
        // Rigid partner: E* = E/(1−ν²).
        assert!(rel(e_star(E, NU, f64::INFINITY, 0.2), E / (1.0 - NU * NU)) < 1e-15);
        // Walls: plane is the d → ∞ limit of both spherical walls.
        assert_eq!(r_star_plane(R), R);
        assert!(rel(r_star_container(R, 1e6), R) < 1e-9);
        assert!(rel(r_star_obstacle(R, 1e6), R) < 1e-9);
        assert!(r_star_container(R, 4.0 * R) > R && r_star_obstacle(R, 4.0 * R) < R);
        assert!(rel(r_star_container(R, 3.0 * R), 1.5 * R) < 1e-15);
        assert_eq!(r_star_container(R, R), f64::INFINITY);
    }

    #[test]
    fn rayleigh_fit_matches_rayleigh_equation() {
        // Independent check: solve the Rayleigh-wave equation for η = c_R/c_S,
        // η⁶ − 8η⁴ + (24 − 16k²)η² − 16(1 − k²) = 0, k² = c_S²/c_P² = (1−2ν)/(2(1−ν)),
        // and compare π R sqrt(ρ/G)/η with the fitted formula (fit error is < 0.5 %).
        for &nu in &[0.0, 0.1, 0.2, 0.3, 0.4, 0.45] {
            let k2 = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
            let f = |e: f64| {
                let e2 = e * e;
                e2 * e2 * e2 - 8.0 * e2 * e2 + (24.0 - 16.0 * k2) * e2 - 16.0 * (1.0 - k2)
            };
            let (mut lo, mut hi) = (0.5_f64, 0.999_999_f64);
            assert!(f(lo) * f(hi) < 0.0);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if f(lo) * f(mid) <= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let eta = 0.5 * (lo + hi);
            let g = shear_modulus(E, nu);
            let exact = std::f64::consts::PI * R * (RHO / g).sqrt() / eta;
            let dt = rayleigh_dt(R, RHO, g, nu);
            assert!(rel(dt, exact) < 5e-3, "nu={nu} dt={dt} exact={exact}");
        }
        // Lian's material: ≈ 3.195e-8 s.
        let dt = rayleigh_dt(R, RHO, shear_modulus(E, NU), NU);
        assert!((dt - 3.195e-8).abs() < 0.001e-8, "{dt}");
    }

    #[test]
    fn zero_for_no_overlap() {
        let es = e_star(E, NU, E, NU);
        for &a in &[0.0, -1e-9, -1.0] {
            assert_eq!(force(es, R, a), 0.0);
            assert_eq!(stiffness(es, R, a), 0.0);
            assert_eq!(energy(es, R, a), 0.0);
            assert_eq!(contact_radius(R, a), 0.0);
        }
    }

    #[test]
    fn force_radius_consistent_with_3_14() {
        // (3.14): a³ = 3PR*/(4E*), with a from (3.15).
        let es = e_star(E, NU, E, NU);
        let rs = r_star(R, R);
        for i in 1..=20 {
            let al = 1e-9 * i as f64;
            let a = contact_radius(rs, al);
            let p = force(es, rs, al);
            assert!(rel(a * a * a, 3.0 * p * rs / (4.0 * es)) < 1e-13);
        }
    }

    #[test]
    fn stiffness_is_numerical_derivative() {
        let es = e_star(E, NU, E, NU);
        let rs = r_star(R, 45e-6);
        for i in 1..=20 {
            let al = 1e-9 * (i as f64).powi(2);
            let h = al * 1e-5;
            let num = (force(es, rs, al + h) - force(es, rs, al - h)) / (2.0 * h);
            assert!(rel(stiffness(es, rs, al), num) < 1e-8);
        }
    }

    #[test]
    fn energy_is_integral_of_force() {
        // ∫_0^α P dα' with α' = s², dα' = 2s ds (smooth integrand), composite Simpson.
        let es = e_star(E, NU, E, NU);
        let rs = r_star(R, R);
        for &al in &[1e-10_f64, 3e-9, 2e-8] {
            let n = 2000;
            let smax = al.sqrt();
            let h = smax / n as f64;
            let f = |s: f64| force(es, rs, s * s) * 2.0 * s;
            let mut sum = f(0.0) + f(smax);
            for k in 1..n {
                sum += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
            }
            let integral = sum * h / 3.0;
            assert!(rel(energy(es, rs, al), integral) < 1e-10);
        }
    }

    #[test]
    fn duration_factor_by_quadrature() {
        // 2 ∫_0^1 (1 − x^{5/2})^{-1/2} dx, with x = 1 − u² to remove the end singularity:
        // dx = −2u du, 1 − x^{5/2} ~ (5/2)u² near u = 0.
        let n = 20000;
        let h = 1.0 / n as f64;
        let f = |u: f64| {
            if u == 0.0 {
                2.0 / (2.5_f64).sqrt()
            } else {
                let x: f64 = 1.0 - u * u;
                2.0 * u / (1.0 - x.powf(2.5)).sqrt()
            }
        };
        let mut sum = f(0.0) + f(1.0);
        for k in 1..n {
            sum += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        let integral = sum * h / 3.0;
        assert!(rel(HERTZ_DURATION_FACTOR, 2.0 * integral) < 1e-10);
        // Familiar textbook constant 2.868.
        assert!((HERTZ_DURATION_FACTOR * (15.0_f64 / 16.0).powf(0.4) - 2.868).abs() < 5e-4);
    }

    #[test]
    fn closed_form_impact_consistent() {
        let es = e_star(E, NU, E, NU);
        let rs = r_star(R, R);
        let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
        let ms = m / 2.0;
        let v = 1.0;
        let amax = max_overlap(ms, rs, es, v);
        // Energy balance at maximum compression.
        assert!(rel(energy(es, rs, amax), 0.5 * ms * v * v) < 1e-13);
        // The (m*²/(R* E*² v))^{1/5} form.
        let tc = impact_duration(ms, rs, es, v);
        let tc2 = 2.868_265_699_195_331_5 * (ms * ms / (rs * es * es * v)).powf(0.2);
        assert!(rel(tc, tc2) < 1e-13);
        assert!(impact_duration(ms, rs, es, 0.0).is_infinite());
        assert_eq!(max_force(ms, rs, es, 0.0), 0.0);
    }

    /// Two unequal spheres, head-on, each integrated with velocity Verlet.
    #[test]
    fn verlet_head_on_impact_matches_closed_forms() {
        let es = e_star(E, NU, E, NU);
        let (r1, r2) = (30e-6, 45e-6);
        let rs = r_star(r1, r2);
        let vol = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let (m1, m2) = (RHO * vol(r1), RHO * vol(r2));
        let ms = m1 * m2 / (m1 + m2);
        let (mut v1, mut v2) = (0.7, -0.5);
        let vrel0 = v1 - v2;
        let tc = impact_duration(ms, rs, es, vrel0);
        let pmax_cf = max_force(ms, rs, es, vrel0);
        let dt = tc / 20000.0;
        // Start exactly touching.
        let (mut x1, mut x2) = (0.0, r1 + r2);
        let overlap = |x1: f64, x2: f64| r1 + r2 - (x2 - x1);
        let fc = |x1: f64, x2: f64| force(es, rs, overlap(x1, x2));
        let mut f = fc(x1, x2);
        let mut t = 0.0;
        let mut pmax: f64 = 0.0;
        let mut prev = overlap(x1, x2);
        let mut t_end = f64::NAN;
        for _ in 0..40000 {
            // Force on sphere 1 is −f (pushed back), on sphere 2 +f.
            v1 += -0.5 * dt * f / m1;
            v2 += 0.5 * dt * f / m2;
            x1 += dt * v1;
            x2 += dt * v2;
            f = fc(x1, x2);
            v1 += -0.5 * dt * f / m1;
            v2 += 0.5 * dt * f / m2;
            t += dt;
            pmax = pmax.max(f);
            let al = overlap(x1, x2);
            if al <= 0.0 && prev > 0.0 {
                t_end = t - dt * al / (al - prev);
            }
            prev = al;
        }
        let e = -(v1 - v2) / vrel0;
        assert!((e - 1.0).abs() < 1e-4, "e = {e}");
        assert!(rel(t_end, tc) < 5e-3, "t = {t_end}, closed form {tc}");
        assert!(
            rel(pmax, pmax_cf) < 5e-3,
            "P = {pmax}, closed form {pmax_cf}"
        );
        // In fact much better than required:
        assert!(rel(t_end, tc) < 1e-5 && rel(pmax, pmax_cf) < 1e-6);
    }
}
