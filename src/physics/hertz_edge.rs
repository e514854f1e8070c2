//! The edges of an elastic Hertz contact in the leap-frog scheme: where a contact starts and
//! ends within a step, the sampled impulses `P(α_n) Δt` take and give back a little more or
//! less than the strain energy, by an amount set by where in the step the edge falls
//! (doc/limits.md, "Energy drift of an elastic gas"). [`Edge`] works that amount out and
//! [`edge_step`] takes it off, a step after the edge, for contacts without dissipation.

use super::hertz::{force, force_constant, hurwitz_zeta_neg};

/// Where a Hertz contact starts or ends within the leap-frog steps, and the energy the
/// scheme's impulses take there beyond the strain energy (doc/limits.md, "Energy drift of an
/// elastic gas").
///
/// Near the edge the overlap is taken as a quadratic in the step index `s` counted from the
/// instant of touch (away from it for a release, time reversed): `α(s) = h s + ½ c s²`, `c`
/// the second difference of the overlap from the other forces on the pair (a third body
/// pushing, gravity at a wall), not its own. The step of the first (last) overlap `α_e` is
/// at `s = φ ∈ (0, 1]`, the step before (after) at `φ − 1` with `α_e − h_e`; so
/// `h_e = h + c (φ − ½)` and `α_e = (h_e + c/2) φ − c φ²/2`, solved here for `φ` and `h`.
/// The leap-frog work of a step, `P(α_j)(α_{j+1} − α_{j−1})/2`, is `P(α(s)) α'(s)` exactly
/// for a quadratic, i.e. `f(s) = dU(α(s))/ds = K h^{5/2} [s^{3/2} + (7/4)(c/h) s^{5/2} + …]`,
/// and by the generalized Euler–Maclaurin formula the steps' sum `Σ_j f(j + φ)` exceeds the
/// strain energy `∫ f` by `K h^{5/2} [ζ(−3/2, φ) + (7/4)(c/h) ζ(−5/2, φ)]` (`K = 4/3 E* √R*`)
/// besides the midpoint rule's smooth part, which the contact's interior gives back.
/// Returns that excess, `φ` and `h`; `None` when the edge is not a steady approach
/// (separation) within one step (`φ ∉ (0, 1]`, `h ≤ 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The energy the steps take beyond the strain energy (J).
    pub excess: f64,
    /// The phase of the first (last) overlap in steps from the instant of touch (release).
    pub phi: f64,
    /// The overlap's change per step at touch (release).
    pub h: f64,
}

impl Edge {
    /// The edge of a contact from its first (last) overlap `alpha`, the overlap's change
    /// `h_e` from the step before (to the step after) and its second difference `c`.
    pub fn of(e_star: f64, r_star: f64, alpha: f64, h_e: f64, c: f64) -> Option<Edge> {
        let q = h_e + 0.5 * c;
        let disc = q * q - 2.0 * c * alpha;
        if !(alpha > 0.0 && q > 0.0 && disc >= 0.0) {
            return None;
        }
        let phi = 2.0 * alpha / (q + disc.sqrt());
        let h = h_e - c * (phi - 0.5);
        if !(phi > 0.0 && phi <= 1.0 && h > 0.0) {
            return None;
        }
        let z = hurwitz_zeta_neg(1.5, phi) + 1.75 * (c / h) * hurwitz_zeta_neg(2.5, phi);
        let excess = force_constant(e_star, r_star) * h * h * h.sqrt() * z;
        Some(Edge { excess, phi, h })
    }

    /// The force that takes the excess off in a step over which the overlap changes by
    /// `step` (as the leap-frog counts a force's work); none where the step's change is
    /// below `h/2` (a pair pulled apart so that its approach nearly stops within the step),
    /// which a gas meets rarely but which would otherwise divide by a change near zero (a
    /// dense gas ran away at cycle 395,000 before this guard).
    pub fn correction(&self, step: f64) -> f64 {
        if step >= 0.5 * self.h {
            -self.excess / step
        } else {
            0.0
        }
    }
}

/// What [`edge_step`] reads of one contact at a step: its overlap now and at the last step,
/// whether it touched then, the separation rate (positive: opening; `v_{n−½}` of the
/// leap-frog, the velocity the step's positions came from) now and kept from the last step
/// (`+∞`: none kept), the Hertz force of the last step, the reduced mass and the step.
#[derive(Clone, Copy, Debug)]
pub struct EdgeIn {
    pub alpha: f64,
    pub alpha_prev: f64,
    pub was_touching: bool,
    pub v_n: f64,
    pub v_prev: f64,
    pub p_prev: f64,
    pub m_star: f64,
    pub dt: f64,
}

/// The edge correction of an elastic Hertz contact at one step: the force to add to the
/// contact's Hertz force (compressive positive) and the separation rate to keep for the next
/// step (`+∞`: none).
///
/// The phase of an edge needs the second difference `c` of the overlap from the other
/// forces, which is known only a step later, so the correction acts one step after the
/// edge. At the first overlap (step `n`) the rate `v_{n−½}` is kept; at `n + 1` the change
/// of the rate less the contact's own force gives `c = −(v_{n+½} − v_{n−½}) Δt + P_n Δt²/m*`,
/// [`Edge::of`] the excess `E` and the correction `−E/Δα` acts with `Δα = (α_{n+2} −
/// α_n)/2`, the overlap's change over the step as the leap-frog counts a force's work
/// (`α_{n+2}` extrapolated with `c` and the contact's force now). At the first step
/// without overlap (`m + 1`) the rate is kept; at `m + 2`, with no force of its own in
/// between, `c = −(v_{m+3/2} − v_{m+½}) Δt`, and the last overlap `α_m = α_{m+1} +
/// v_{m+½} Δt`: the correction `−E/Δα` with `Δα = (α_{m+1} − α_{m+3})/2 = h + c (φ − 2)`.
/// A contact of a single step, or one that closes again before its release was corrected,
/// is left as it is.
pub fn edge_step(e_star: f64, r_star: f64, x: &EdgeIn) -> (f64, f64) {
    let EdgeIn {
        alpha,
        alpha_prev,
        was_touching,
        v_n,
        v_prev,
        p_prev,
        m_star,
        dt,
    } = *x;
    let pending = v_prev.is_finite();
    let dt2 = dt * dt / m_star;
    match (was_touching, alpha > 0.0) {
        // The first overlap: keep the rate.
        (false, true) => (0.0, v_n),
        // The second step of a contact: its onset.
        (true, true) if pending => {
            let c = -(v_n - v_prev) * dt + p_prev * dt2;
            let h_e = -v_prev * dt;
            let Some(e) = Edge::of(e_star, r_star, alpha_prev, h_e, c) else {
                return (0.0, f64::INFINITY);
            };
            let step = -v_n * dt + 0.5 * (c - force(e_star, r_star, alpha) * dt2);
            (e.correction(step), f64::INFINITY)
        }
        // The first step without overlap: keep the rate (not after a single step).
        (true, false) => (0.0, if pending { f64::INFINITY } else { v_n }),
        // The second step after the release.
        (false, false) if pending => {
            let c = -(v_n - v_prev) * dt;
            let h_e = v_prev * dt;
            let Some(e) = Edge::of(e_star, r_star, alpha_prev + h_e, h_e, c) else {
                return (0.0, f64::INFINITY);
            };
            let step = e.h + c * (e.phi - 2.0);
            (e.correction(step), f64::INFINITY)
        }
        _ => (0.0, f64::INFINITY),
    }
}

#[cfg(test)]
mod tests {
    use super::super::hertz::HERTZ_DURATION_FACTOR;
    use super::*;

    /// A chain of bodies on a line (unit masses, `K = 1`), each neighbouring pair a Hertz
    /// contact when their distance is below 1, on the discrete map of the leap-frog scheme;
    /// with or without the edge corrections. Returns the relative change of the kinetic
    /// energy once every contact has opened.
    fn chain(x: &[f64], v: &[f64], dt: f64, steps: usize, corrected: bool) -> f64 {
        let (e, r) = (0.75, 1.0); // K = 4/3 E* √R* = 1
        let (mut x, mut v) = (x.to_vec(), v.to_vec());
        let n = x.len();
        let e0: f64 = v.iter().map(|v| 0.5 * v * v).sum();
        // Per pair: touching, overlap, Hertz force, kept rate.
        let mut st = vec![(false, 0.0, 0.0, f64::INFINITY); n - 1];
        for _ in 0..steps {
            let mut f = vec![0.0; n];
            for (i, s) in st.iter_mut().enumerate() {
                let alpha = 1.0 - (x[i + 1] - x[i]);
                let v_n = v[i + 1] - v[i];
                let p = force(e, r, alpha);
                let mut fp = p;
                if corrected {
                    let (d, keep) = edge_step(
                        e,
                        r,
                        &EdgeIn {
                            alpha,
                            alpha_prev: s.1,
                            was_touching: s.0,
                            v_n,
                            v_prev: s.3,
                            p_prev: s.2,
                            m_star: 0.5,
                            dt,
                        },
                    );
                    fp += d;
                    s.3 = keep;
                }
                *s = (alpha > 0.0, alpha, p, s.3);
                f[i] -= fp;
                f[i + 1] += fp;
            }
            for i in 0..n {
                v[i] += f[i] * dt;
                x[i] += v[i] * dt;
            }
        }
        assert!(st.iter().all(|s| !s.0), "a contact is still closed");
        v.iter().map(|v| 0.5 * v * v).sum::<f64>() / e0 - 1.0
    }

    /// The step of 13 per contact of a head-on collision at approach speed 1 (FRAction 0.2).
    fn step13() -> f64 {
        let a_max = (1.25f64 * 0.5).powf(0.4);
        HERTZ_DURATION_FACTOR * a_max / 13.0
    }

    /// Mean and largest error over 200 equally spaced phases of first touch.
    fn over_phases(f: impl Fn(f64) -> f64) -> (f64, f64) {
        let n = 200;
        let e: Vec<f64> = (0..n).map(|k| f((k as f64 + 0.5) / n as f64)).collect();
        let mean = e.iter().sum::<f64>() / n as f64;
        (mean, e.iter().fold(0.0f64, |m, x| m.max(x.abs())))
    }

    /// A head-on collision at 13 steps a contact: plain, the error spans ±2.6e-3 with the
    /// phase of first touch and averages +1.6e-5; corrected, within 1.3e-5 and 1.5e-6.
    #[test]
    fn edge_corrections_keep_a_collision_elastic() {
        let dt = step13();
        let run = |corrected: bool| {
            over_phases(|ph| {
                chain(
                    &[0.0, 1.0 + (1.0 + ph) * dt],
                    &[0.5, -0.5],
                    dt,
                    52,
                    corrected,
                )
            })
        };
        let (mean0, max0) = run(false);
        assert!(mean0 > 1.5e-5 && max0 > 2.5e-3, "{mean0} {max0}");
        let (mean, max) = run(true);
        assert!(mean.abs() < 1.5e-6 && max < 1.5e-5, "{mean} {max}");
    }

    /// Newton's cradle: a body hits the first of two at rest in touch, the second contact
    /// starts while the first pushes. Plain: errors up to 1.6e-3, mean +5.2e-6 over the
    /// phases; with the phase in time (the push's `c`): within 4e-6, mean below 1e-6 (the
    /// first attempt, the phase `α/h` at the first step, left −7.7e-6).
    #[test]
    fn edge_corrections_keep_a_cradle_elastic() {
        let dt = step13();
        let run = |corrected: bool| {
            over_phases(|ph| {
                let d = (1.0 + ph) * dt;
                chain(
                    &[0.0, 1.0 + d, 2.0 + d],
                    &[1.0, 0.0, 0.0],
                    dt,
                    104,
                    corrected,
                )
            })
        };
        let (mean0, max0) = run(false);
        assert!(mean0 > 5e-6 && max0 > 1.5e-3, "{mean0} {max0}");
        let (mean, max) = run(true);
        assert!(mean.abs() < 1e-6 && max < 4e-6, "{mean} {max}");
    }
}
