//! Rolling resistance (`SET ROLling μ_r`). Pasha (2013) uses rolling friction coefficients
//! (0.10 in Ch. 5, 0.01 in Ch. 6–7; spec pasha2013.md §1.18) but gives no formula: his runs
//! were in EDEM, whose standard model applies to each sphere a torque of constant magnitude
//! `μ_r F_n R_i` against its rotation (Sakaguchi et al. 1993's "constant directional
//! torque"). A torque of constant magnitude reverses at every step once the relative rotation
//! is near zero and never lets a contact rest; the elastic–plastic spring of Ai et al. (2011,
//! Powder Technol. 206, 269; their model C without its dashpot) has the same torque while
//! the contact rolls and holds a resting contact still:
//!
//! * the rolling moment on sphere A is a spring on the relative rolling rotation
//!   `Δθ = (ω_A − ω_B)_t Δt` (the part normal to the contact normal; twisting is free):
//!   `M ← M − k_r Δθ`, rotated with the contact plane like the tangential force;
//! * capped at `|M| ≤ μ_r R_r F_n` (the sphere rolls: EDEM's torque);
//! * sphere B gets `−M`;
//! * stiffness `k_r = 2.25 k_n μ_r² R_r²` (Ai et al. (17)), `k_n` the normal stiffness;
//! * rolling radius `R_r = 2R_AR_B/(R_A + R_B)` for two spheres (`R` for equal spheres,
//!   EDEM's `R_i`) and `R_r = R` for a sphere on a wall;
//! * while the spring is below its limit a rolling dashpot `M_d = −C_r (ω_A − ω_B)_t`,
//!   `C_r = 2η_r (I_r k_r)^{1/2}` with `η_r = 0.3` and the equivalent inertia
//!   `I_r = [1/(I_A + m_AR_A²) + 1/(I_B + m_BR_B²)]^{-1}` (Ai et al. (19)–(20), their
//!   recommended ratio), damps the rocking of a resting contact (without it a sphere that has
//!   rolled to a stop rocks on the spring for ever).
//!
//! The torque does work `M·Δθ` on the spheres; the spring stores `|M|²/(2k_r)`; the rest is
//! lost to rolling friction (the ledger's friction term).

/// Rolling radius: `2R_AR_B/(R_A + R_B)` for two spheres, `R_A` against a wall (`r_b` = ∞).
pub fn radius(r_a: f64, r_b: f64) -> f64 {
    if r_b.is_finite() {
        2.0 * r_a * r_b / (r_a + r_b)
    } else {
        r_a
    }
}

/// Rolling stiffness `k_r = 2.25 k_n μ_r² R_r²` (Ai et al. 2011 (17)).
pub fn stiffness(k_n: f64, mu_r: f64, r_r: f64) -> f64 {
    2.25 * k_n * mu_r * mu_r * r_r * r_r
}

/// Critical-damping ratio of the rolling dashpot (Ai et al. 2011 recommend 0.3).
pub const ETA_R: f64 = 0.3;

/// Equivalent rotational inertia of a contact, `[1/(I_A + m_AR_A²) + 1/(I_B + m_BR_B²)]^{-1}`
/// with `I = 2/5 m R²` (Ai et al. (20)); `m_b` = ∞ for a wall.
pub fn inertia(m_a: f64, r_a: f64, m_b: f64, r_b: f64) -> f64 {
    let ia = 1.4 * m_a * r_a * r_a;
    if m_b.is_finite() {
        let ib = 1.4 * m_b * r_b * r_b;
        ia * ib / (ia + ib)
    } else {
        ia
    }
}

/// The rolling dashpot's coefficient `C_r = 2η_r (I_r k_r)^{1/2}` (Ai et al. (19)).
pub fn damping(i_r: f64, k_r: f64) -> f64 {
    2.0 * ETA_R * (i_r * k_r).sqrt()
}

/// The largest rolling moment `μ_r R_r F_n` (no resistance under tension).
pub fn limit(mu_r: f64, r_r: f64, f_n: f64) -> f64 {
    mu_r * r_r * f_n.max(0.0)
}

/// What one step of the rolling spring gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollStep {
    /// The moment on sphere A.
    pub moment: [f64; 3],
    /// Work done on the spring over the step, `−½ (M_old + M)·Δθ`.
    pub work: f64,
    /// Energy stored in the spring, `|M|²/(2k_r)`.
    pub energy: f64,
    /// The spring reached its limit (the contact rolls).
    pub rolling: bool,
}

/// One step of the rolling spring: `M = M_old − k_r Δθ`, capped at `cap` along its own
/// direction. `m_old` is the last moment already rotated into the contact plane, `dtheta`
/// the step's relative rolling rotation of A with respect to B.
pub fn step(m_old: [f64; 3], dtheta: [f64; 3], k_r: f64, cap: f64) -> RollStep {
    let mut m = [0.0; 3];
    for c in 0..3 {
        m[c] = m_old[c] - k_r * dtheta[c];
    }
    let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    let rolling = len >= cap;
    if len > cap {
        let s = if len > 0.0 { cap / len } else { 0.0 };
        for x in &mut m {
            *x *= s;
        }
    }
    let work = -0.5 * (0..3).map(|c| (m_old[c] + m[c]) * dtheta[c]).sum::<f64>();
    let energy = if k_r > 0.0 {
        (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) / (2.0 * k_r)
    } else {
        0.0
    };
    RollStep {
        moment: m,
        work,
        energy,
        rolling,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inertia_and_damping() {
        // Two equal spheres: half of 7/5 m R²; a sphere on a wall: 7/5 m R².
        assert!((inertia(2.0, 0.5, 2.0, 0.5) - 0.35).abs() < 1e-15);
        assert!((inertia(2.0, 0.5, f64::INFINITY, 0.0) - 0.7).abs() < 1e-15);
        // ζ = C/(2√(I k)) = η_r.
        let c = damping(0.7, 3.0);
        assert!((c / (2.0 * (0.7f64 * 3.0).sqrt()) - ETA_R).abs() < 1e-15);
    }

    #[test]
    fn radius_and_stiffness() {
        assert_eq!(radius(1e-3, 1e-3), 1e-3);
        assert!((radius(1e-3, 3e-3) - 1.5e-3).abs() < 1e-18);
        assert_eq!(radius(2e-3, f64::INFINITY), 2e-3);
        // k_r = 2.25 k_n μ_r² R_r²: 2.25 × 1e6 × 0.01 × 1e-6.
        assert!((stiffness(1e6, 0.1, 1e-3) - 2.25e-2).abs() < 1e-15);
    }

    /// Elastic below the limit: the moment is −k_r θ and the spring gives back what it took.
    #[test]
    fn elastic_below_the_limit() {
        let (k, cap) = (2.0, 1.0);
        let mut m = [0.0; 3];
        let mut work = 0.0;
        for _ in 0..10 {
            let s = step(m, [0.01, 0.0, 0.0], k, cap);
            m = s.moment;
            work += s.work;
        }
        assert!((m[0] + k * 0.1).abs() < 1e-15);
        assert!((work - k * 0.1 * 0.1 / 2.0).abs() < 1e-15);
        let s = step(m, [0.0; 3], k, cap);
        assert!((s.energy - work).abs() < 1e-15);
        for _ in 0..10 {
            let s = step(m, [-0.01, 0.0, 0.0], k, cap);
            m = s.moment;
            work += s.work;
        }
        assert!(m[0].abs() < 1e-15 && work.abs() < 1e-15);
    }

    /// Rolling: the moment saturates at μ_r R_r F_n against the rotation, whatever the speed
    /// (EDEM's constant torque), and the work beyond the stored energy is lost.
    #[test]
    fn rolling_torque_limit() {
        let (mu_r, r_r, f_n) = (0.1, 5e-4, 2.0);
        let cap = limit(mu_r, r_r, f_n);
        assert!((cap - 1e-4).abs() < 1e-18);
        assert_eq!(limit(mu_r, r_r, -1.0), 0.0);
        let k = stiffness(1e6, mu_r, r_r);
        let mut m = [0.0; 3];
        let mut work = 0.0;
        let d = [0.0, 3e-4, -4e-4];
        for _ in 0..100 {
            let s = step(m, d, k, cap);
            m = s.moment;
            work += s.work;
        }
        let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        assert!((len - cap).abs() < 1e-15 * cap);
        assert!(step(m, d, k, cap).rolling && !step([0.0; 3], [1e-9, 0.0, 0.0], k, cap).rolling);
        // Against the rotation: M ∥ −Δθ.
        assert!((m[1] / len + 0.6).abs() < 1e-12 && (m[2] / len - 0.8).abs() < 1e-12);
        // Past the saturation each step dissipates cap × |Δθ|.
        let s = step(m, d, k, cap);
        assert!((s.work - cap * 5e-4).abs() < 1e-12 * cap * 5e-4);
        assert!(work > s.energy);
    }
}
