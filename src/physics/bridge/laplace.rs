//! Exact axisymmetric Laplace–Young liquid bridge at constant volume, zero
//! gravity, between two spheres of radii `R1 ≤ R2` or a sphere and a plane
//! (`R2 = ∞`) — the reference solution of Lian 1994 §4.2.2–4.2.3.
//!
//! Lengths are scaled by the smaller radius `R1`, forces by `γ R1`, energies
//! by `γ R1²`, volumes by `R1³`.
//!
//! **Profile.** With the neck at `x = 0`, radius `y0`, and Lian's mean curvature
//! `H` ((4.5), (4.6): `2H = κ_meridian − cos ψ / y`, `H > 0` for a pressure
//! deficiency), the first integral (4.10) gives the slope everywhere:
//! `y cos ψ + H y² = C = y0 + H y0²` with ψ the tangent angle of the meridian.
//! Integrating in `y` (the substitution `y = y0 + (y_c − y0) t²` removes the
//! `1/√(y − y0)` singularity at the neck) with Gauss–Legendre quadrature gives
//! the axial length `x = ∫ cot ψ dy`, the volume `π ∫ y² dx` and the area
//! `2π ∫ y ds` of each half of the meniscus. The profile is symmetric about the
//! neck, so sphere 1 and sphere 2 are simply placed on the two sides: on each
//! side the contact line is the first point where the meniscus meets the
//! sphere at the contact angle, `y = R sin φ`, `cos ψ = sin(φ + θ)` ((4.11),
//! (4.12); on a plane `cos ψ = sin θ`). Then
//! * gap `S = Σ [x_i − R_i (1 − cos φ_i)]`,
//! * volume `V = Σ [π ∫ y² dx − π R_i³ (1 − cos φ_i)² (2 + cos φ_i)/3]` (4.18),
//! * force `F* = 2π C = 2π y0 (1 + H y0)` (4.17) (the first integral is the
//!   axial force balance, so the force is the same at the neck and at the
//!   contact lines, (4.7)),
//! * free surface energy `E* = A_lv − cos θ A_wet` ((4.34), (4.35)).
//!
//! **Constant volume.** For a fixed neck radius `y0` the volume decreases
//! monotonically with `H`, so `H(y0)` is found by a bracketed root solve. Along
//! the constant-volume branch the neck radius decreases monotonically while the
//! gap first grows and then shrinks: the maximum of `S(y0)` is the fold where
//! the stable (larger neck, lower energy) and unstable branches meet — the
//! rupture distance (Lian 1994 §4.2.3). A [`Branch`] locates the zero-gap
//! state and the fold once, then tabulates the stable branch on Chebyshev
//! nodes in `u = sqrt(1 − S/S_c)` (smooth through the fold, where `S(y0)` is
//! quadratic), so each later evaluation is one square root and a short
//! Clenshaw sum.

use super::numerics::{Cheb, brent, gl32};
use super::{Bridge, Norm};
use std::f64::consts::PI;

/// One side of the meniscus, from the neck to the contact line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Side {
    /// Half-filling angle on this side's sphere (0 on a plane).
    pub phi: f64,
    /// Axial distance from the neck plane to the solid surface on the axis.
    pub gap: f64,
    /// Liquid volume on this side of the neck plane.
    pub vol: f64,
    /// Liquid–vapour area minus cos θ × wetted area on this side.
    pub energy: f64,
}

/// A Laplace–Young state, dimensionless (lengths / `R1`, `R1` the smaller
/// radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LyState {
    /// Neck radius `Y0`.
    pub y0: f64,
    /// Mean curvature `H* = Δp R1/(2γ)` (4.6), positive for a pressure deficiency.
    pub h: f64,
    /// Gap `S* = S/R1`.
    pub s: f64,
    /// Volume `V* = V/R1³` (4.18).
    pub v: f64,
    /// Attractive force `F* = F/(γ R1) = 2π Y0 (1 + H* Y0)` (4.17).
    pub f_star: f64,
    /// Free surface energy `E* = E/(γ R1²) = A_lv − cos θ A_wet` (4.35).
    pub e_star: f64,
    /// Half-filling angle on the smaller sphere.
    pub phi1: f64,
    /// Half-filling angle on the larger sphere (0 for a plane).
    pub phi2: f64,
}

/// One side of the meniscus for a solid of radius `r` (`∞` = plane).
pub(crate) fn side(n: &Norm, r: f64, y0: f64, h: f64) -> Option<Side> {
    let c = y0 + h * y0 * y0;
    if !(c > 0.0) || !(1.0 + 2.0 * h * y0 > 0.0) || !(y0 > 0.0) {
        return None;
    }
    let (st, ct) = (n.sin_t, n.cos_t);
    let cospsi = |y: f64| (c - h * y * y) / y;
    let target = |y: f64| -> f64 {
        if r.is_finite() {
            let u = (y / r).min(1.0);
            u * ct + ((1.0 - u) * (1.0 + u)).sqrt() * st
        } else {
            st
        }
    };
    let hfun = |y: f64| cospsi(y) - target(y);
    // end of the rising part of the profile
    let y_top = if h > 0.0 {
        (c / h).sqrt() // cos ψ = 0
    } else if h < 0.0 {
        -1.0 / h - y0 // bulge (cos ψ = 1 again)
    } else {
        f64::INFINITY
    };
    let mut y_end = y_top;
    if r.is_finite() {
        y_end = y_end.min(r * ct);
    } else if !y_end.is_finite() {
        y_end = 1e3 * (y0 + c);
    }
    if !(y_end > y0) {
        return None;
    }
    let h0 = hfun(y0);
    if h0 < 0.0 {
        return None;
    }
    // first sign change of h on (y0, y_end]; h is monotone up to the inflection
    // point y* = sqrt(c/|h|) for h < 0, so scan only beyond it.
    let y_inf = if h < 0.0 {
        (c / -h).sqrt().min(y_end)
    } else {
        y_end
    };
    let (mut a, mut fa) = (y0, h0);
    let (mut b, mut fb) = (y_inf, hfun(y_inf));
    if fb > 0.0 && fb < 1e-13 {
        // contact exactly at the vertical tangent (θ = 0 on a plane): rounding
        fb = 0.0;
    }
    if fb > 0.0 {
        if y_inf >= y_end {
            return None;
        }
        let mut found = false;
        let m = 16;
        for i in 1..=m {
            let y = y_inf + (y_end - y_inf) * i as f64 / m as f64;
            let fy = hfun(y);
            if fy <= 0.0 {
                b = y;
                fb = fy;
                found = true;
                break;
            }
            a = y;
            fa = fy;
        }
        if !found {
            return None;
        }
    }
    let yc = brent(hfun, a, b, fa, fb, 1e-15 * y_end, 200)?;
    let d = yc - y0;
    if !(d > 0.0) {
        return None;
    }
    let (mut x, mut vol, mut area) = (0.0, 0.0, 0.0);
    for &(t, w) in gl32() {
        let y = y0 + d * t * t;
        let cp = cospsi(y);
        let g2 = d * (1.0 + h * (y + y0)) * (1.0 + cp) / y;
        if !(g2 > 0.0) {
            return None;
        }
        let g = g2.sqrt();
        x += w * 2.0 * d * cp / g;
        vol += w * 2.0 * PI * d * y * y * cp / g;
        area += w * 4.0 * PI * d * y / g;
    }
    let (phi, om, cap, wet) = if r.is_finite() {
        let sp = (yc / r).min(1.0);
        let cp = ((1.0 - sp) * (1.0 + sp)).sqrt();
        let om = sp * sp / (1.0 + cp);
        (
            sp.asin(),
            om,
            PI * r * r * r / 3.0 * om * om * (3.0 - om),
            2.0 * PI * r * r * om,
        )
    } else {
        (0.0, 0.0, 0.0, PI * yc * yc)
    };
    Some(Side {
        phi,
        gap: x - if r.is_finite() { r * om } else { 0.0 },
        vol: vol - cap,
        energy: area - ct * wet,
    })
}

/// The bridge with neck radius `y0` and mean curvature `h` (any volume/gap).
pub(crate) fn forward(n: &Norm, y0: f64, h: f64) -> Option<LyState> {
    let s1 = side(n, 1.0, y0, h)?;
    let s2 = side(n, n.k, y0, h)?;
    Some(LyState {
        y0,
        h,
        s: s1.gap + s2.gap,
        v: s1.vol + s2.vol,
        f_star: 2.0 * PI * (y0 + h * y0 * y0),
        e_star: s1.energy + s2.energy,
        phi1: s1.phi,
        phi2: s2.phi,
    })
}

/// V(y0, H) − v, with "no contact" (too fat) counted as +big.
fn vres(n: &Norm, y0: f64, h: f64) -> (f64, Option<LyState>) {
    match forward(n, y0, h) {
        Some(st) => (st.v - n.v, Some(st)),
        None => (1e3 * n.v.max(1.0), None),
    }
}

/// At fixed neck radius y0, find the mean curvature H giving the volume.
pub(crate) fn solve_h(n: &Norm, y0: f64, h_guess: f64) -> Option<LyState> {
    if !(y0 > 0.0) {
        return None;
    }
    let hmin = -0.5 / y0 * (1.0 - 1e-9);
    let mut h = if h_guess.is_finite() {
        h_guess.max(hmin)
    } else {
        1.0 / y0
    };
    let (f, _) = vres(n, y0, h);
    let mut step = 0.02 * (1.0 / y0 + h.abs());
    let (mut a, mut fa, mut b, mut fb);
    if f > 0.0 {
        a = h;
        fa = f;
        loop {
            h += step;
            step *= 2.0;
            let (g, _) = vres(n, y0, h);
            if g <= 0.0 {
                b = h;
                fb = g;
                break;
            }
            a = h;
            fa = g;
            if step > 1e12 {
                return None;
            }
        }
    } else {
        b = h;
        fb = f;
        loop {
            h = (h - step).max(hmin);
            step *= 2.0;
            let (g, _) = vres(n, y0, h);
            if g > 0.0 {
                a = h;
                fa = g;
                break;
            }
            b = h;
            fb = g;
            if h <= hmin {
                return None;
            }
        }
    }
    let hr = brent(
        |x| vres(n, y0, x).0,
        a,
        b,
        fa,
        fb,
        1e-14 * (1.0 + b.abs()),
        200,
    )?;
    let (r, st) = vres(n, y0, hr);
    if r.abs() > 1e-9 * n.v { None } else { st }
}

/// Warm-started evaluation of the constant-volume family `y0 ↦ state`.
struct Tracer<'a> {
    n: &'a Norm,
    h_last: f64,
    evals: usize,
}

impl Tracer<'_> {
    fn at(&mut self, y0: f64) -> Option<LyState> {
        self.evals += 1;
        let st = solve_h(self.n, y0, self.h_last)?;
        self.h_last = st.h;
        Some(st)
    }
}

/// Number of Chebyshev nodes of a [`Branch`] table.
const NODES: usize = 32;

/// The stable constant-volume branch of one bridge (fixed `R1`, `R2`, `θ`,
/// `V`), from contact (`S = 0`) to the fold (rupture), tabulated once.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    n: Norm,
    /// Fold (rupture) gap `S_c/R1`.
    s_fold: f64,
    /// Neck radius at the fold and at contact.
    y0_fold: f64,
    y0_contact: f64,
    f: Cheb,
    phi1: Cheb,
    phi2: Cheb,
    e: Cheb,
    h: Cheb,
    y0: Cheb,
}

impl Branch {
    /// Trace the branch for a bridge (dimensionless: only `R2/R1`, `V/R1³`
    /// and θ matter). `None` if the bridge is invalid or no pendular
    /// Laplace–Young solution exists (e.g. the contact line would pass
    /// φ + θ = 90°). Costs a few milliseconds.
    pub fn new(b: &Bridge) -> Option<Branch> {
        let mut n = b.norm()?;
        n.a = 1.0;
        Branch::from_norm(n)
    }

    pub(crate) fn from_norm(n: Norm) -> Option<Branch> {
        if !(n.theta >= 0.0 && n.theta < 0.5 * PI) {
            return None;
        }
        let nn = n;
        let n = &nn;
        // toroidal estimate of the contact state
        let phi = super::toroidal::solve_phi1(n, 0.0, super::fit::phi1_guess(n, 0.0))?;
        let t = super::toroidal::torus(n, phi, 0.0)?;
        let mut tr = Tracer {
            n,
            h_last: (t.rho2 - t.rho1) / (2.0 * t.rho1 * t.rho2),
            evals: 0,
        };
        // 1. contact state S(y0) = 0 (S decreases with y0 on the stable branch)
        let mut ya = t.rho2;
        let mut sa = tr.at(ya)?.s;
        let mut yb = ya;
        let mut sb = sa;
        let grow = if sa > 0.0 { 1.05 } else { 1.0 / 1.05 };
        for _ in 0..200 {
            if sa.signum() != sb.signum() {
                break;
            }
            ya = yb;
            sa = sb;
            yb *= grow;
            sb = tr.at(yb)?.s;
        }
        if sa.signum() == sb.signum() {
            return None;
        }
        let h_keep = tr.h_last;
        let y0_contact = brent(
            |y| {
                tr.h_last = h_keep;
                tr.at(y).map(|s| s.s).unwrap_or(f64::NAN)
            },
            ya,
            yb,
            sa,
            sb,
            1e-14,
            100,
        )?;
        let contact = tr.at(y0_contact)?;
        // 2. march towards smaller necks until the gap stops growing
        let mut ys = vec![(y0_contact, contact.s, contact.h)];
        let mut y = y0_contact;
        let fold_bracket;
        loop {
            y *= 0.94;
            let prev = ys[ys.len() - 1];
            tr.h_last = prev.2;
            match tr.at(y) {
                Some(st) if st.s > prev.1 => ys.push((y, st.s, st.h)),
                other => {
                    let lo = y;
                    let hi = if ys.len() >= 2 {
                        ys[ys.len() - 2].0
                    } else {
                        prev.0
                    };
                    let _ = other;
                    fold_bracket = (lo, hi, prev.2);
                    break;
                }
            }
            if ys.len() > 400 || y < 1e-9 {
                return None;
            }
        }
        // 3. golden-section maximisation of S(y0) (failures count as −∞)
        let (mut lo, mut hi, hstart) = fold_bracket;
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let eval = |y: f64, tr: &mut Tracer| -> f64 {
            tr.h_last = hstart;
            tr.at(y).map(|s| s.s).unwrap_or(f64::NEG_INFINITY)
        };
        let mut x1 = hi - g * (hi - lo);
        let mut x2 = lo + g * (hi - lo);
        let mut f1 = eval(x1, &mut tr);
        let mut f2 = eval(x2, &mut tr);
        for _ in 0..60 {
            if (hi - lo) < 1e-10 * hi {
                break;
            }
            // x1 < x2; keep the sub-interval that holds the larger S
            if f1 >= f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = eval(x1, &mut tr);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = eval(x2, &mut tr);
            }
        }
        let (y0_fold, s_fold) = if f1 >= f2 { (x1, f1) } else { (x2, f2) };
        if !(s_fold.is_finite() && s_fold > 0.0) {
            return None;
        }
        let fold = {
            tr.h_last = hstart;
            tr.at(y0_fold)?
        };
        // 4. tabulate on Chebyshev nodes in u = sqrt(1 - S/S_c)
        let us = Cheb::nodes(0.0, 1.0, NODES);
        let mut cols: [Vec<f64>; 6] = Default::default();
        for &u in &us {
            let target = s_fold * (1.0 - u * u);
            let st = if u == 0.0 {
                fold
            } else {
                // warm start H by linear interpolation in y0 between fold and contact
                let mut solve = |y: f64| -> f64 {
                    let w = (y - y0_fold) / (y0_contact - y0_fold);
                    tr.h_last = fold.h + w * (contact.h - fold.h);
                    tr.at(y).map(|s| s.s - target).unwrap_or(f64::NAN)
                };
                let fa = s_fold - target;
                let fb = contact.s - target;
                let yr = brent(&mut solve, y0_fold, y0_contact, fa, fb, 1e-15, 200)?;
                let w = (yr - y0_fold) / (y0_contact - y0_fold);
                tr.h_last = fold.h + w * (contact.h - fold.h);
                tr.at(yr)?
            };
            for (c, v) in cols
                .iter_mut()
                .zip([st.f_star, st.phi1, st.phi2, st.e_star, st.h, st.y0])
            {
                c.push(v);
            }
        }
        let mk = |v: &Vec<f64>| Cheb::from_values(0.0, 1.0, v);
        Some(Branch {
            n: nn,
            s_fold,
            y0_fold,
            y0_contact,
            f: mk(&cols[0]),
            phi1: mk(&cols[1]),
            phi2: mk(&cols[2]),
            e: mk(&cols[3]),
            h: mk(&cols[4]),
            y0: mk(&cols[5]),
        })
    }

    /// `u = sqrt(1 − S/S_c)` for a dimensionless gap (S < 0 counts as 0).
    #[inline]
    fn u_of(&self, s_star: f64) -> f64 {
        let x = s_star.max(0.0) / self.s_fold;
        (1.0 - x).max(0.0).sqrt()
    }

    /// Dimensionless rupture distance `S_c/R1` (R1 the smaller radius): the
    /// fold of the constant-volume branch.
    pub fn rupture_star(&self) -> f64 {
        self.s_fold
    }

    /// Dimensionless attractive force `F/(γ R1)` at `s_star = S/R1` (0 beyond
    /// the fold; S < 0 counts as contact).
    #[inline]
    pub fn force_star(&self, s_star: f64) -> f64 {
        if s_star > self.s_fold {
            return 0.0;
        }
        self.f.eval(self.u_of(s_star))
    }

    /// Half-filling angles `(φ_small, φ_large)` at `s_star` (clamped to the
    /// fold state beyond rupture).
    pub fn half_filling_angles_sorted(&self, s_star: f64) -> (f64, f64) {
        let u = self.u_of(s_star);
        (self.phi1.eval(u), self.phi2.eval(u))
    }

    /// Free surface energy `E/(γ R1²)` ((4.35)) on the branch at `s_star`.
    pub fn energy_star(&self, s_star: f64) -> f64 {
        self.e.eval(self.u_of(s_star))
    }

    /// Work needed to pull the bridge from `s_star` to rupture,
    /// `∫_S^{S_c} F dS = E(S_c) − E(S)`, in units of `γ R1²`.
    pub fn bond_energy_star(&self, s_star: f64) -> f64 {
        if s_star > self.s_fold {
            return 0.0;
        }
        (self.e.eval(0.0) - self.energy_star(s_star)).max(0.0)
    }

    /// Neck radius and mean curvature `(Y0, H*)` on the branch.
    pub fn neck(&self, s_star: f64) -> (f64, f64) {
        let u = self.u_of(s_star);
        (self.y0.eval(u), self.h.eval(u))
    }

    /// Direct (non-interpolated) solve of the stable state at `s_star`,
    /// `0 ≤ s_star ≤ S_c*`. Slow; for tests and reference tables.
    pub fn exact_state(&self, s_star: f64) -> Option<LyState> {
        let target = s_star.max(0.0);
        if target > self.s_fold {
            return None;
        }
        let (_, h_guess) = self.neck(target);
        let mut tr = Tracer {
            n: &self.n,
            h_last: h_guess,
            evals: 0,
        };
        let mut solve = |y: f64| -> f64 {
            tr.h_last = h_guess;
            tr.at(y).map(|st| st.s - target).unwrap_or(f64::NAN)
        };
        let fa = self.s_fold - target;
        let fb = -target;
        let y = brent(
            &mut solve,
            self.y0_fold,
            self.y0_contact,
            fa,
            fb,
            1e-15,
            200,
        )?;
        solve_h(&self.n, y, h_guess)
    }
    /// Any state of the constant-volume family at neck radius `y0`
    /// (dimensionless), stable or unstable; for tests.
    pub fn state_at_neck(&self, y0: f64) -> Option<LyState> {
        let w = (y0 - self.y0_fold) / (self.y0_contact - self.y0_fold);
        let h0 = self.h.eval(0.0);
        let h1 = self.h.eval(1.0);
        solve_h(&self.n, y0, h0 + w * (h1 - h0))
    }

    /// Neck radius at the fold (dimensionless).
    pub fn fold_neck(&self) -> f64 {
        self.y0_fold
    }

    /// Size of the trailing Chebyshev coefficients of the force table
    /// (dimensionless force units); an interpolation-error indicator.
    pub fn table_tail(&self) -> f64 {
        self.f.tail()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn norm(k: f64, v: f64, theta_deg: f64) -> Norm {
        let mut n = Bridge::new(1.0, k, v, 1.0, theta_deg.to_radians())
            .norm()
            .unwrap();
        n.a = 1.0;
        n
    }

    fn cap_and_wet(r: f64, phi: f64) -> (f64, f64) {
        let om = 1.0 - phi.cos();
        (
            PI * r * r * r / 3.0 * om * om * (3.0 - om),
            2.0 * PI * r * r * om,
        )
    }

    /// H = 0 is a catenoid y = y0 cosh(x/y0): the quadrature reproduces its
    /// length, volume and area in closed form.
    #[test]
    fn zero_curvature_profile_is_a_catenoid() {
        for (k, th) in [(1.0, 0.0), (3.0, 25.0)] {
            let n = norm(k, 0.01, th);
            let y0 = 0.08;
            let sd = side(&n, k, y0, 0.0).unwrap();
            let (cap, wet) = cap_and_wet(k, sd.phi);
            let yc = k * sd.phi.sin();
            let x = y0 * (yc / y0).acosh();
            let vol = PI * y0 * y0 / 2.0 * (x + 0.5 * y0 * (2.0 * x / y0).sinh());
            let area = 2.0 * PI / y0 * y0 * y0 / 2.0 * (x + 0.5 * y0 * (2.0 * x / y0).sinh());
            assert!((sd.gap + k * (1.0 - sd.phi.cos()) - x).abs() < 1e-12, "x");
            assert!((sd.vol + cap - vol).abs() < 1e-12 * vol, "vol");
            assert!(
                (sd.energy + n.cos_t * wet - area).abs() < 1e-12 * area,
                "area"
            );
            // contact condition cos ψ = c/y = sin(φ + θ)
            assert!((y0 / yc - (sd.phi + n.theta).sin()).abs() < 1e-12);
        }
    }

    /// Independent check of the first-integral quadrature: integrate the
    /// Laplace–Young equation (4.5) itself, dψ/ds = 2H + cos ψ / y, in arc length
    /// with RK4 from the neck to the contact line.
    #[test]
    fn quadrature_matches_direct_ode_integration() {
        for (k, th, y0, h) in [
            (1.0, 0.0, 0.2, 12.0),
            (1.0, 30.0, 0.1, 3.0),
            (2.0, 10.0, 0.12, -0.3),
            (f64::INFINITY, 0.0, 0.15, 5.0),
            (f64::INFINITY, 40.0, 0.15, 2.0),
        ] {
            let n = norm(k, 0.01, th);
            let sd = side(&n, k, y0, h).unwrap();
            let contact = |y: f64, psi: f64| -> f64 {
                let t = if k.is_finite() {
                    ((y / k).asin() + n.theta).sin()
                } else {
                    n.sin_t
                };
                psi.cos() - t
            };
            let rhs = |st: [f64; 5]| -> [f64; 5] {
                let (x, y, p) = (st[0], st[1], st[2]);
                let _ = x;
                let (sp, cp) = p.sin_cos();
                [cp, sp, 2.0 * h + cp / y, PI * y * y * cp, 2.0 * PI * y]
            };
            let mut st = [0.0, y0, 0.0, 0.0, 0.0];
            let ds = 1e-5;
            let mut prev;
            let mut found = None;
            for _ in 0..10_000_000 {
                let k1 = rhs(st);
                let a = |s: [f64; 5], k: [f64; 5], f: f64| {
                    let mut o = s;
                    for i in 0..5 {
                        o[i] += f * k[i];
                    }
                    o
                };
                let k2 = rhs(a(st, k1, 0.5 * ds));
                let k3 = rhs(a(st, k2, 0.5 * ds));
                let k4 = rhs(a(st, k3, ds));
                prev = st;
                for i in 0..5 {
                    st[i] += ds / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
                let (c0, c1) = (contact(prev[1], prev[2]), contact(st[1], st[2]));
                if c0 > 0.0 && c1 <= 0.0 {
                    let w = c0 / (c0 - c1);
                    let mut o = prev;
                    for i in 0..5 {
                        o[i] += w * (st[i] - prev[i]);
                    }
                    found = Some(o);
                    break;
                }
            }
            let o = found.expect("ODE never reached the contact line");
            let phi = if k.is_finite() {
                (o[1] / k).asin()
            } else {
                0.0
            };
            let (cap, wet) = if k.is_finite() {
                cap_and_wet(k, phi)
            } else {
                (0.0, PI * o[1] * o[1])
            };
            let gap = o[0]
                - if k.is_finite() {
                    k * (1.0 - phi.cos())
                } else {
                    0.0
                };
            assert!((sd.phi - phi).abs() < 1e-6, "phi {} {}", sd.phi, phi);
            assert!((sd.gap - gap).abs() < 1e-7, "gap {} {gap}", sd.gap);
            assert!(
                (sd.vol - (o[3] - cap)).abs() < 1e-7,
                "vol {} {}",
                sd.vol,
                o[3] - cap
            );
            assert!((sd.energy - (o[4] - n.cos_t * wet)).abs() < 1e-7, "energy");
            // the first integral y cos ψ + H y² is conserved along the ODE
            let c = y0 + h * y0 * y0;
            assert!((o[1] * o[2].cos() + h * o[1] * o[1] - c).abs() < 1e-8);
        }
    }

    /// The Chebyshev table reproduces the direct solve.
    #[test]
    fn branch_table_matches_exact_solve() {
        for (k, v, th) in [
            (1.0, 0.001, 0.0),
            (2.0, 0.03, 30.0),
            (f64::INFINITY, 0.01, 10.0),
        ] {
            let br = Branch::from_norm(norm(k, v, th)).unwrap();
            let sc = br.rupture_star();
            for i in 0..=10 {
                let s = sc * (i as f64 / 10.0).min(0.999);
                let ex = br.exact_state(s).unwrap();
                assert!((ex.v / v - 1.0).abs() < 1e-9);
                assert!((ex.s - s).abs() < 1e-12);
                let f = br.force_star(s);
                assert!(
                    (f / ex.f_star - 1.0).abs() < 2e-6,
                    "k={k} v={v} s={s} {f} {}",
                    ex.f_star
                );
                let (p1, p2) = br.half_filling_angles_sorted(s);
                assert!((p1 - ex.phi1).abs() < 1e-6 && (p2 - ex.phi2).abs() < 1e-6);
            }
            assert!(br.table_tail() < 1e-4);
        }
    }

    /// The rupture distance is a fold: two solutions just below S_c (the one
    /// with the larger neck has the lower free energy, Lian 1994 §4.2.3), none
    /// above.
    #[test]
    fn rupture_is_the_fold_of_the_constant_volume_branch() {
        for (k, v, th) in [
            (1.0, 0.005, 0.0),
            (1.0, 0.02, 40.0),
            (f64::INFINITY, 0.005, 20.0),
        ] {
            let br = Branch::from_norm(norm(k, v, th)).unwrap();
            let (sc, yf) = (br.rupture_star(), br.fold_neck());
            let near = br.state_at_neck(yf).unwrap();
            assert!((near.s - sc).abs() < 1e-12);
            for d in [0.02, 0.1] {
                let stable = br.state_at_neck(yf * (1.0 + d)).unwrap();
                assert!(stable.s < sc);
                // the unstable partner with the same gap
                let g = |y: f64| {
                    br.state_at_neck(y)
                        .map(|s| s.s - stable.s)
                        .unwrap_or(f64::NAN)
                };
                let mut a = yf;
                while g(a) > 0.0 && a > 0.05 * yf {
                    a *= 0.98;
                }
                let b = yf;
                let y = brent(g, a, b, g(a), g(b), 1e-14, 200).unwrap();
                let unstable = br.state_at_neck(y).unwrap();
                assert!(unstable.y0 < stable.y0);
                assert!(unstable.e_star > stable.e_star, "{unstable:?} {stable:?}");
                assert!(unstable.f_star < stable.f_star);
            }
            // no solution beyond the fold: the largest gap over all necks is S_c
            for i in 1..40 {
                let y = yf * (0.3 + 1.4 * i as f64 / 40.0);
                if let Some(st) = br.state_at_neck(y) {
                    assert!(st.s <= sc + 1e-12, "y0={y} s={} sc={sc}", st.s);
                }
            }
        }
    }
}
#[cfg(test)]
mod dbg {
    use super::*;
    #[test]
    #[ignore]
    fn dbg_fold() {
        let mut n = Bridge::new(1.0, 1.0, 0.001, 1.0, 0.0).norm().unwrap();
        n.a = 1.0;
        let br = Branch::from_norm(n).unwrap();
        let sc = br.rupture_star();
        println!("sc={sc} yf={} tail={}", br.fold_neck(), br.table_tail());
        for x in [0.0, 0.1, 0.5, 0.9, 0.95, 0.99, 0.995, 0.999, 0.9999, 1.0] {
            let s = sc * x;
            let ex = br.exact_state(s).unwrap();
            println!(
                "x={x} table={:.10} exact={:.10} y0 tab={:.10} ex={:.10} h tab={:.8} ex={:.8}",
                br.force_star(s),
                ex.f_star,
                br.neck(s).0,
                ex.y0,
                br.neck(s).1,
                ex.h
            );
        }
        println!("{:?}", br.f);
        for i in 0..=40 {
            let y = 0.0270 + 0.0001 * i as f64;
            let st = br.state_at_neck(y).unwrap();
            println!("y0={y:.5} s={:.12} h={:.6} f={:.8}", st.s, st.h, st.f_star);
        }
    }
}
