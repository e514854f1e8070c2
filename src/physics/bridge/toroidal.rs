//! Toroidal (Fisher) bridge geometry for unequal spheres and sphere–plane,
//! the gorge-method force, and the exact solve of the toroidal volume
//! equation for the half-filling angle.
//!
//! Lengths are scaled by the smaller radius `R1` (Lian's sphere 1); the larger
//! sphere has radius `k = R2/R1 >= 1` or is a plane (`k = ∞`). Forces are
//! scaled by `γ R1`, volumes by `R1³`.
//!
//! Geometry (Lian 1994 §4.2.5): the meridian is a circular arc of radius
//! `ρ1` centred above the neck at height `ρ1 + ρ2`; at the contact line on
//! sphere i the arc makes the angle `φi + θ` with the axis, so
//! `x_ci = ρ1 cos(φi + θ) = S_i + R_i (1 − cos φi)` (4.53), (4.56) and
//! `ρ2 = R_i sin φi − [1 − sin(φi + θ)] ρ1` (4.54).

use super::Norm;
use super::numerics::{Cheb, brent};
use std::f64::consts::{FRAC_PI_2, PI};

/// A toroidal bridge state (dimensionless, lengths in units of `R1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Torus {
    /// Half-filling angle on the smaller sphere (rad).
    pub phi1: f64,
    /// Half-filling angle on the larger sphere (rad); 0 for a plane.
    pub phi2: f64,
    /// Meridional radius ρ1 (4.53).
    pub rho1: f64,
    /// Neck radius ρ2 (4.54).
    pub rho2: f64,
    /// sin(φ2 + θ) from (4.61) (= sin θ for a plane).
    sin_a2: f64,
    /// cos(φ2 + θ).
    cos_a2: f64,
    /// sin(φ1 + θ), cos(φ1 + θ).
    sin_a1: f64,
    cos_a1: f64,
    /// 1 − cos φ1, R2 (1 − cos φ2) / R1.
    om1: f64,
    ext2: f64,
}

impl Torus {
    /// Gorge-method force `F* = 2π ρ2 {1 + H_min ρ2}` with the neck curvature
    /// `H_min = (ρ2 − ρ1)/(2 ρ1 ρ2)` — Lian 1994 (4.43), (4.46); algebraically
    /// `F* = π ρ2 (1 + ρ2/ρ1)`. Attractive, in units of `γ R1`.
    #[inline]
    pub fn force_star(&self) -> f64 {
        PI * self.rho2 * (1.0 + self.rho2 / self.rho1)
    }

    /// Dimensionless toroidal volume `V/R1³ = V1 + V2`, Lian 1994 (4.55),
    /// (4.42) (with `x_ci/ρ1 = cos(φi + θ)` so that the square root and the
    /// arcsine of (4.55) become `ρ1 sin(φi + θ)` and `π/2 − φi − θ`).
    pub fn volume_star(&self, k: f64) -> f64 {
        let half = |cos_a: f64, sin_a: f64| -> f64 {
            let r1 = self.rho1;
            let a = r1 + self.rho2;
            let x = r1 * cos_a;
            let ang = cos_a.atan2(sin_a); // asin(x/ρ1) = π/2 − (φ + θ)
            PI * (a * a * x + r1 * r1 * x - x * x * x / 3.0 - a * (x * r1 * sin_a + r1 * r1 * ang))
        };
        let cap = |r: f64, om: f64| -> f64 { PI * r * r * r / 3.0 * om * om * (3.0 - om) };
        let v1 = half(self.cos_a1, self.sin_a1) - cap(1.0, self.om1);
        let v2 = half(self.cos_a2, self.sin_a2)
            - if k.is_finite() {
                cap(k, self.ext2 / k)
            } else {
                0.0
            };
        v1 + v2
    }
}

/// Toroidal geometry for a given half-filling angle `phi1` on the smaller
/// sphere and gap `s` (units of `R1`). `φ2` follows from the compatibility
/// condition (4.59) in the explicit form (4.61), rearranged to avoid
/// cancellation for large `R2`:
/// with `A = S + 2R2`, `B = S + 2R1`, `S_R = S + R1 + R2`, `D = R1 − R2`,
/// `sin(φ2+θ) = [A B sin φ1 cos θ + sin θ (A² − (S_R² + D²)(1 − cos φ1))] /
/// [A² + 2 S_R D (1 − cos φ1)]`, which is (4.61) expanded. For a plane
/// (`k = ∞`) `φ2 = 0` and the arc meets the plane at the angle θ.
/// `ρ1 = [S + R1(1 − cos φ1) + R2(1 − cos φ2)] / [cos(φ1+θ) + cos(φ2+θ)]`
/// ((4.53) summed over both sides, i.e. (4.57)–(4.58)).
/// Returns `None` if the state is not a valid pendular bridge (ρ1 ≤ 0, ρ2 ≤ 0,
/// φ + θ ≥ π/2).
#[inline]
pub(crate) fn torus(n: &Norm, phi1: f64, s: f64) -> Option<Torus> {
    let (st, ct) = (n.sin_t, n.cos_t);
    let (s1, c1) = phi1.sin_cos();
    let om1 = s1 * s1 / (1.0 + c1);
    let sin_a1 = s1 * ct + c1 * st;
    let cos_a1 = c1 * ct - s1 * st;
    let (sin_a2, cos_a2, phi2, ext2);
    if n.k.is_finite() {
        let k = n.k;
        let d = 1.0 - k;
        let a = s + 2.0 * k;
        let b = s + 2.0;
        let sr = s + 1.0 + k;
        let num = a * b * s1 * ct + st * (a * a - (sr * sr + d * d) * om1);
        let den = a * a + 2.0 * sr * d * om1;
        let x = num / den;
        if !(x.abs() < 1.0) {
            return None;
        }
        sin_a2 = x;
        cos_a2 = ((1.0 - x) * (1.0 + x)).sqrt();
        let sp2 = x * ct - cos_a2 * st;
        let cp2 = cos_a2 * ct + x * st;
        phi2 = sp2.atan2(cp2);
        ext2 = k * sp2 * sp2 / (1.0 + cp2);
    } else {
        sin_a2 = st;
        cos_a2 = ct;
        phi2 = 0.0;
        ext2 = 0.0;
    }
    let den = cos_a1 + cos_a2;
    let rho1 = (s + om1 + ext2) / den;
    let rho2 = s1 - (1.0 - sin_a1) * rho1;
    if !(cos_a1 > 0.0 && den > 0.0 && rho1 > 0.0 && rho2 > 0.0) {
        return None;
    }
    Some(Torus {
        phi1,
        phi2,
        rho1,
        rho2,
        sin_a2,
        cos_a2,
        sin_a1,
        cos_a1,
        om1,
        ext2,
    })
}

/// The gorge force `F/(γ R1)` of [`torus`] without the bookkeeping (no
/// `atan2`; equal spheres take the symmetric shortcut `φ2 = φ1`, (4.39),
/// (4.40)). Same formulas: (4.53), (4.54), (4.61), (4.46). Used per step.
#[inline]
pub(crate) fn gorge_force_star(n: &Norm, phi1: f64, s: f64) -> Option<f64> {
    let (st, ct) = (n.sin_t, n.cos_t);
    let (s1, c1) = phi1.sin_cos();
    let om1 = s1 * s1 / (1.0 + c1);
    let sin_a1 = s1 * ct + c1 * st;
    let cos_a1 = c1 * ct - s1 * st;
    let (rho1, ok2) = if n.k == 1.0 {
        // (4.39): ρ1 = (S/2 + 1 − cos φ)/cos(φ + θ)
        ((0.5 * s + om1) / cos_a1, true)
    } else if n.k.is_finite() {
        let k = n.k;
        let d = 1.0 - k;
        let a = s + 2.0 * k;
        let b = s + 2.0;
        let sr = s + 1.0 + k;
        let x = (a * b * s1 * ct + st * (a * a - (sr * sr + d * d) * om1))
            / (a * a + 2.0 * sr * d * om1);
        let cos_a2 = ((1.0 - x) * (1.0 + x)).sqrt();
        let sp2 = x * ct - cos_a2 * st;
        let cp2 = cos_a2 * ct + x * st;
        let ext2 = k * sp2 * sp2 / (1.0 + cp2);
        ((s + om1 + ext2) / (cos_a1 + cos_a2), x.abs() < 1.0)
    } else {
        ((s + om1) / (cos_a1 + ct), true)
    };
    let rho2 = s1 - (1.0 - sin_a1) * rho1;
    if !(ok2 && cos_a1 > 0.0 && rho1 > 0.0 && rho2 > 0.0) {
        return None;
    }
    Some(PI * rho2 * (1.0 + rho2 / rho1))
}

/// Largest admissible φ1 (the contact line may not pass the equator of the
/// contact-angle-tilted sphere).
#[inline]
fn phi_max(n: &Norm) -> f64 {
    (FRAC_PI_2 - n.theta - 1e-9).min(FRAC_PI_2)
}

/// Toroidal volume residual; states with no positive neck are counted as
/// "too little liquid" (−v) so that the residual is monotone in φ1.
#[inline]
fn residual(n: &Norm, phi1: f64, s: f64) -> f64 {
    match torus(n, phi1, s) {
        Some(t) => t.volume_star(n.k) - n.v,
        None => {
            // below the pinch-off angle (ρ2 ≤ 0) or above φ_max
            if phi1 >= phi_max(n) {
                f64::INFINITY
            } else {
                -n.v
            }
        }
    }
}

/// Exact solve of the toroidal volume equation (4.55) with (4.61) for the
/// half-filling angle φ1 on the smaller sphere at gap `s` (units of `R1`),
/// starting from `guess`. Returns `None` if no toroidal bridge with a
/// positive neck holds the volume (the toroid has pinched off).
pub(crate) fn solve_phi1(n: &Norm, s: f64, guess: f64) -> Option<f64> {
    let pmax = phi_max(n);
    if !(pmax > 1e-5) || !(n.v > 0.0) || !s.is_finite() {
        return None;
    }
    let g = if guess.is_finite() {
        guess.clamp(1e-6, pmax - 1e-6)
    } else {
        0.3_f64.min(0.5 * pmax)
    };
    let tol = 1e-13;
    let mut step = 2e-3;
    let (mut a, mut fa) = (g - step, residual(n, g - step, s));
    let (mut b, mut fb) = (g + step, residual(n, g + step, s));
    // expand the bracket geometrically
    let mut it = 0;
    while fa.signum() == fb.signum() && it < 60 {
        step *= 2.0;
        if fa > 0.0 {
            b = a;
            fb = fa;
            a = (a - step).max(0.0);
            fa = if a <= 0.0 { -n.v } else { residual(n, a, s) };
            if a <= 0.0 && fa > 0.0 {
                return None;
            }
        } else {
            a = b;
            fa = fb;
            b = (b + step).min(pmax);
            fb = residual(n, b, s);
            if b >= pmax && fb < 0.0 {
                return None;
            }
        }
        it += 1;
    }
    if fa.signum() == fb.signum() {
        return None;
    }
    // a bracket whose lower end is "no neck" is fine: Brent treats it as a
    // negative value and converges to the volume root (or to the pinch-off
    // angle if the volume there already exceeds V: then no solution).
    let fa = if fa.is_finite() { fa } else { -n.v };
    let fb = if fb.is_finite() { fb } else { n.v.max(1.0) };
    let r = brent(
        |p| {
            let f = residual(n, p, s);
            if f.is_finite() { f } else { n.v.max(1.0) }
        },
        a,
        b,
        fa,
        fb,
        tol,
        100,
    )?;
    // reject a "root" that sits on the pinch-off discontinuity
    let t = torus(n, r, s)?;
    if (t.volume_star(n.k) - n.v).abs() > 1e-6 * n.v {
        return None;
    }
    Some(r)
}

/// Chebyshev nodes of a [`ToroidalTable`].
const TABLE_NODES: usize = 24;

/// Per-bridge table of the exact toroidal φ1(S/S_c) on [0, 1] (Chebyshev
/// interpolant of the exact solve), so that the per-step cost equals that
/// of the fitted polynomial.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ToroidalTable {
    pub cheb: Cheb,
    /// Largest S/S_c with a toroidal solution (1 unless the toroid pinches off
    /// before S_c; beyond it the state at `s_max` is used).
    pub s_max: f64,
}

impl ToroidalTable {
    pub(crate) fn new(n: &Norm, s_c: f64) -> Option<ToroidalTable> {
        // find the largest s/s_c in [0,1] with a solution
        let guess0 = solve_phi1(n, 0.0, super::fit::phi1_guess(n, 0.0))?;
        let mut s_max = 1.0;
        if solve_phi1(n, s_c, super::fit::phi1_guess(n, 1.0)).is_none() {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                if solve_phi1(n, mid * s_c, super::fit::phi1_guess(n, mid)).is_some() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            s_max = lo;
        }
        if !(s_max > 1e-9) {
            return None;
        }
        let nodes = Cheb::nodes(0.0, s_max, TABLE_NODES);
        let mut vals = Vec::with_capacity(nodes.len());
        for &x in &nodes {
            let p = solve_phi1(n, x * s_c, super::fit::phi1_guess(n, x))
                .or_else(|| solve_phi1(n, x * s_c, guess0))?;
            vals.push(p);
        }
        Some(ToroidalTable {
            cheb: Cheb::from_values(0.0, s_max, &vals),
            s_max,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::Bridge;
    use super::*;

    /// The per-step force path equals the full toroidal state.
    #[test]
    fn fast_gorge_force_equals_full_state() {
        for k in [1.0, 1.0 + 1e-12, 1.3, 5.0, 1e6, f64::INFINITY] {
            for th in [0.0f64, 0.3, 0.7] {
                let n = Bridge::new(1.0, k, 0.01, 1.0, th).norm().unwrap();
                for phi in [0.05, 0.2, 0.4] {
                    for s in [0.0, 0.05, 0.2] {
                        let full = torus(&n, phi, s).map(|t| t.force_star());
                        let fast = gorge_force_star(&n, phi, s);
                        match (full, fast) {
                            (Some(a), Some(b)) => {
                                assert!((a - b).abs() <= 1e-12 * a, "{k} {th} {phi} {s}")
                            }
                            (None, None) => {}
                            other => panic!("{k} {th} {phi} {s}: {other:?}"),
                        }
                    }
                }
            }
        }
    }

    /// The per-bridge Chebyshev table reproduces the exact solve.
    #[test]
    fn table_matches_exact_solve() {
        let mut worst: f64 = 0.0;
        for (k, v, th) in [
            (1.0, 0.001, 0.0),
            (1.0, 0.05, 0.7),
            (2.0, 0.01, 0.3),
            (5.0, 0.04, 0.0),
            (f64::INFINITY, 0.001, 0.0),
            (f64::INFINITY, 0.05, 0.7),
        ] {
            let n = Bridge::new(1.0, k, v, 1.0, th).norm().unwrap();
            let sc = super::super::rupture::rupture_star(&n);
            let t = ToroidalTable::new(&n, sc).unwrap();
            assert_eq!(t.s_max, 1.0);
            for i in 0..=200 {
                let x = i as f64 / 200.0;
                let exact = solve_phi1(&n, x * sc, 0.3).unwrap();
                worst = worst.max((t.cheb.eval(x) - exact).abs());
            }
        }
        assert!(worst < 1e-8, "{worst}");
    }

    /// Equal spheres: the unequal-sphere geometry reduces to (4.39), (4.40)
    /// and the toroidal volume to (4.42).
    #[test]
    fn equal_spheres_reduce_to_4_39_4_42() {
        let th = 0.25f64;
        let n = Bridge::new(1.0, 1.0, 0.01, 1.0, th).norm().unwrap();
        let (phi, s) = (0.3f64, 0.08);
        let t = torus(&n, phi, s).unwrap();
        let r1 = (s / 2.0 + 1.0 - phi.cos()) / (phi + th).cos();
        let r2 =
            phi.sin() - (1.0 - (phi + th).sin()) * (s / 2.0 + 1.0 - phi.cos()) / (phi + th).cos();
        assert!((t.rho1 - r1).abs() < 1e-14 && (t.rho2 - r2).abs() < 1e-14);
        assert!((t.phi2 - phi).abs() < 1e-12);
        let xc = s / 2.0 + 1.0 - phi.cos();
        let v442 = 2.0
            * PI
            * ((r1 + r2).powi(2) * xc + r1 * r1 * xc
                - xc.powi(3) / 3.0
                - (r1 + r2) * (xc * (r1 * r1 - xc * xc).sqrt() + r1 * r1 * (xc / r1).asin()))
            - 2.0 * PI / 3.0 * (1.0 - phi.cos()).powi(2) * (2.0 + phi.cos());
        assert!(
            (t.volume_star(1.0) - v442).abs() < 1e-13,
            "{} {v442}",
            t.volume_star(1.0)
        );
    }
}
