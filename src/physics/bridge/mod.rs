//! Pendular liquid bridges between two spheres or a sphere and a plane wall:
//! static (capillary) force, rupture distance, bond energy and viscous forces.
//!
//! Three static models, chosen per scene ([`BridgeModel`]):
//! * [`BridgeModel::Fit`] — Lian 1994 §5.7 as in TRUBAL: the half-filling
//!   angle from the fitted polynomial (5.37)–(5.49) (two slope signs
//!   corrected), the toroidal geometry (4.53), (4.54), (4.61) and the gorge
//!   force (4.46). Sphere–plane: Rabinovich/Olsson (2017) eqs (33)–(35).
//! * [`BridgeModel::Toroidal`] — same toroidal geometry and gorge force, with
//!   φ1 from an exact solve of the toroidal volume equation (4.55).
//! * [`BridgeModel::Laplace`] — the exact Laplace–Young meniscus at constant
//!   volume (Lian 1994 §4.2), whose fold is the rupture distance.
//! * [`BridgeModel::Rabinovich`] — Olsson (2017): Rabinovich (2005) closed-form
//!   force with the harmonic-mean radius, capped in contact, Willett rupture
//!   distance ([`rabinovich`]).
//!
//! Conventions: gap `S = |x_B − x_A| − R_A − R_B` (m), `S < 0` (overlap)
//! counts as contact; the static force is returned as an attractive magnitude
//! ≥ 0 (in the crate's compressive-positive normal-force convention it
//! contributes `−F`); it is 0 beyond the model's rupture distance. Angles in
//! radians. See `doc/bridge.md`.
//!
//! For the hot loop build a [`BridgeCoeffs`] once when the bridge forms; its
//! [`BridgeCoeffs::force`] costs a polynomial (or Chebyshev) evaluation and
//! one `sin_cos`.

// `!(x > 0.0)` style tests are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod fit;
pub mod laplace;
mod numerics;
pub mod rabinovich;
pub mod rupture;
pub mod toroidal;
pub mod viscous;

#[cfg(test)]
mod tests;

pub use rupture::{lian_rupture_distance, rupture_distance, willett_rupture_distance};
pub use viscous::{viscous_normal, viscous_normal_coefficient, viscous_tangential};

use laplace::Branch;
use numerics::integrate;
use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;
use std::sync::{Arc, Mutex, OnceLock};
use toroidal::ToroidalTable;

/// Static liquid-bridge model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BridgeModel {
    /// Lian's fitted half-filling angle (5.37)–(5.49) + toroidal gorge force
    /// (4.46); sphere–plane by Olsson (2017) (33)–(35). Fast (TRUBAL).
    Fit,
    /// Exact solve of the toroidal volume equation (4.55) + gorge force (4.46).
    Toroidal,
    /// Exact Laplace–Young solution at constant volume (reference).
    Laplace,
    /// Olsson (2017): Rabinovich (2005) (33)/(43) with the harmonic-mean radius (45),
    /// capped at (59)/(60) in contact; Willett (2000) rupture distance (52).
    Rabinovich,
}

/// A liquid bridge: two radii (m; `r2 = f64::INFINITY` for a plane wall),
/// liquid volume (m³), surface tension γ_lv (N/m) and contact angle θ (rad).
/// The order of the radii does not matter: Lian's "sphere 1" is always the
/// smaller one internally; results referring to a sphere refer to `r1`/`r2`
/// as given.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bridge {
    pub r1: f64,
    pub r2: f64,
    pub volume: f64,
    pub gamma: f64,
    pub theta: f64,
}

impl Bridge {
    /// A bridge between two spheres.
    pub fn new(r1: f64, r2: f64, volume: f64, gamma: f64, theta: f64) -> Bridge {
        Bridge {
            r1,
            r2,
            volume,
            gamma,
            theta,
        }
    }

    /// A bridge between a sphere of radius `r` and a plane wall.
    pub fn wall(r: f64, volume: f64, gamma: f64, theta: f64) -> Bridge {
        Bridge::new(r, f64::INFINITY, volume, gamma, theta)
    }

    /// True for a sphere–plane bridge.
    pub fn is_wall(&self) -> bool {
        self.r1.is_infinite() || self.r2.is_infinite()
    }

    /// Reduced radius `R* = R1R2/(R1 + R2)` (3.5); the particle radius for a wall.
    pub fn r_star(&self) -> f64 {
        if self.r2.is_infinite() {
            self.r1
        } else if self.r1.is_infinite() {
            self.r2
        } else {
            self.r1 * self.r2 / (self.r1 + self.r2)
        }
    }

    /// Dimensionless volume `V/R_small³` (Lian's `V/R1³`).
    pub fn v_star(&self) -> f64 {
        let a = self.r1.min(self.r2);
        self.volume / (a * a * a)
    }

    /// Normalised description: lengths in units of the smaller radius.
    pub(crate) fn norm(&self) -> Option<Norm> {
        let (a, big, swapped) = if self.r1 <= self.r2 {
            (self.r1, self.r2, false)
        } else {
            (self.r2, self.r1, true)
        };
        let ok = a > 0.0
            && a.is_finite()
            && big >= a
            && self.volume > 0.0
            && self.volume.is_finite()
            && self.theta >= 0.0
            && self.theta < FRAC_PI_2;
        if !ok {
            return None;
        }
        let (sin_t, cos_t) = self.theta.sin_cos();
        let k = big / a;
        let v = self.volume / (a * a * a);
        if !(v > 0.0 && v.is_finite()) {
            return None;
        }
        Some(Norm {
            a,
            k,
            v,
            theta: self.theta,
            sin_t,
            cos_t,
            swapped,
        })
    }
}

/// A bridge in units of its smaller radius `a` (`k = R2/R1 ≥ 1`, ∞ = plane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Norm {
    pub a: f64,
    pub k: f64,
    pub v: f64,
    pub theta: f64,
    pub sin_t: f64,
    pub cos_t: f64,
    pub swapped: bool,
}

impl Norm {
    fn is_wall(&self) -> bool {
        !self.k.is_finite()
    }
}

/// Dimensionless rupture distance of the Fit/Toroidal models
/// ([`rupture_distance`]).
#[inline]
fn rupture_star_default(n: &Norm) -> f64 {
    rupture::rupture_star(n)
}

/// Laplace–Young branches already traced, keyed by (R2/R1, V/R1³, θ).
fn laplace_cache(n: &Norm) -> Option<Arc<Branch>> {
    type Key = (u64, u64, u64);
    static CACHE: OnceLock<Mutex<HashMap<Key, Option<Arc<Branch>>>>> = OnceLock::new();
    let key = (n.k.to_bits(), n.v.to_bits(), n.theta.to_bits());
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Ok(map) = cache.lock()
        && let Some(b) = map.get(&key)
    {
        return b.clone();
    }
    let mut nn = *n;
    nn.a = 1.0;
    let branch = Branch::from_norm(nn).map(Arc::new);
    if let Ok(mut map) = cache.lock() {
        if map.len() >= 4096 {
            map.clear();
        }
        map.insert(key, branch.clone());
    }
    branch
}

/// Nominal bridge volume (m³) for `LIQuid pvol …` (doc/spec/DECISIONS.md): `pvol` % of
/// the mean volume of the two spheres, `V = pvol/100 · (V1 + V2)/2`; for a
/// wall (`r2 = ∞`) `pvol` % of the particle's volume. With `pvol = 0.1` this is
/// Lian's "0.1 % of the particle volume" (doc/spec/physics-lian1994.md §3.8).
pub fn nominal_volume(pvol_percent: f64, r1: f64, r2: f64) -> f64 {
    let vol = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let mean = if r2.is_infinite() {
        vol(r1)
    } else if r1.is_infinite() {
        vol(r2)
    } else {
        0.5 * (vol(r1) + vol(r2))
    };
    pvol_percent / 100.0 * mean
}

/// Rupture distance (m) of a given model: (5.31)–(5.36) (pairs) or Willett /
/// Olsson eq. (52) (walls) for `Fit` and `Toroidal`; the fold of the
/// constant-volume Laplace–Young branch for `Laplace`.
pub fn model_rupture_distance(model: BridgeModel, b: &Bridge) -> f64 {
    let Some(n) = b.norm() else { return 0.0 };
    match model {
        BridgeModel::Laplace => match laplace_cache(&n) {
            Some(br) => br.rupture_star() * n.a,
            None => rupture_star_default(&n) * n.a,
        },
        BridgeModel::Rabinovich => rupture::willett_star(n.v, n.theta, n.k) * n.a,
        _ => rupture_star_default(&n) * n.a,
    }
}

/// `x = S/R1` clamped to `[0, S_c]`, or `None` beyond rupture. `S = S_c` itself
/// (up to rounding of the scaling by `R1`) still has a bridge: Lian's bridge
/// ruptures when `S > S_c`.
#[inline]
fn within_rupture(x: f64, sc: f64) -> Option<f64> {
    if x <= sc * (1.0 + 8.0 * f64::EPSILON) {
        Some(x.max(0.0).min(sc))
    } else {
        None
    }
}

/// Dimensionless state of a Fit/Toroidal bridge at `x = S/R1`:
/// `(F*, φ_small, φ_large)`; `None` when the bridge has no valid state.
fn toroidal_like(model: BridgeModel, n: &Norm, x: f64, sc: f64) -> Option<(f64, f64, f64)> {
    let x = within_rupture(x, sc)?;
    if model == BridgeModel::Fit {
        if n.is_wall() {
            let (f, alpha) = fit::olsson_wall_star(n.v, x, n.theta);
            return Some((f, alpha, 0.0));
        }
        let q = 1.0 / n.k;
        let phi = fit::phi1_poly(fit::poly_coeffs(q, n.v), x / sc);
        let t = toroidal::torus(n, phi, x)?;
        return Some((t.force_star(), t.phi1, t.phi2));
    }
    let phi = toroidal::solve_phi1(n, x, fit::phi1_guess(n, x / sc))?;
    let t = toroidal::torus(n, phi, x)?;
    Some((t.force_star(), t.phi1, t.phi2))
}

/// Static (capillary) bridge force (N), attractive magnitude ≥ 0, at gap `s`
/// (m); `s < 0` counts as `s = 0`; 0 beyond the model's rupture distance
/// ([`model_rupture_distance`]) and for an invalid bridge.
/// * `Fit`: φ1 from (5.37)–(5.49), geometry (4.53), (4.54), (4.61), gorge
///   force (4.46) `F = π γ ρ2 (1 + ρ2/ρ1)`; walls: Olsson (2017) (33)–(35).
/// * `Toroidal`: φ1 from the toroidal volume equation (4.55), gorge force (4.46).
/// * `Laplace`: exact Laplace–Young force (4.17) (branch traced once per
///   distinct `(R2/R1, V/R1³, θ)` and cached; falls back to `Toroidal` if no
///   Laplace–Young solution exists).
///
/// For the per-step loop prefer [`BridgeCoeffs::force`].
pub fn static_force(model: BridgeModel, b: &Bridge, s: f64) -> f64 {
    let Some(n) = b.norm() else { return 0.0 };
    if !(b.gamma > 0.0) || !b.gamma.is_finite() || s.is_nan() {
        return 0.0;
    }
    if model == BridgeModel::Rabinovich {
        return BridgeCoeffs::new(model, b).force(s);
    }
    let x = s * (1.0 / n.a);
    if model == BridgeModel::Laplace
        && let Some(br) = laplace_cache(&n)
    {
        return match within_rupture(x, br.rupture_star()) {
            Some(x) => b.gamma * n.a * br.force_star(x),
            None => 0.0,
        };
    }
    let model = if model == BridgeModel::Laplace {
        BridgeModel::Toroidal
    } else {
        model
    };
    let sc = rupture_star_default(&n);
    toroidal_like(model, &n, x, sc)
        .map(|(f, _, _)| b.gamma * n.a * f)
        .unwrap_or(0.0)
}

/// Half-filling angles `(φ on r1, φ on r2)` (rad) at gap `s` (m); the angle on a
/// plane is 0. Beyond rupture: the values at the rupture distance. (0, 0) for an
/// invalid bridge.
pub fn half_filling_angles(model: BridgeModel, b: &Bridge, s: f64) -> (f64, f64) {
    let Some(n) = b.norm() else { return (0.0, 0.0) };
    if model == BridgeModel::Rabinovich {
        return BridgeCoeffs::new(model, b).half_filling_angles(s);
    }
    let x = (s * (1.0 / n.a)).max(0.0);
    let sorted = || -> Option<(f64, f64)> {
        if model == BridgeModel::Laplace
            && let Some(br) = laplace_cache(&n)
        {
            return Some(br.half_filling_angles_sorted(x.min(br.rupture_star())));
        }
        let m = if model == BridgeModel::Laplace {
            BridgeModel::Toroidal
        } else {
            model
        };
        let sc = rupture_star_default(&n);
        toroidal_like(m, &n, x.min(sc), sc).map(|(_, p1, p2)| (p1, p2))
    };
    let (p_small, p_large) = sorted().unwrap_or((0.0, 0.0));
    if n.swapped {
        (p_large, p_small)
    } else {
        (p_small, p_large)
    }
}

/// Half-filling angle (rad) on sphere `r1` at gap `s` (m), see
/// [`half_filling_angles`]. With `r1 ≤ r2` this is Lian's φ1.
pub fn half_filling_angle(model: BridgeModel, b: &Bridge, s: f64) -> f64 {
    half_filling_angles(model, b, s).0
}

/// Energy (J) needed to pull the bridge from gap `s` to rupture,
/// `∫_s^{S_c} F dS` (`s < 0` counts as 0; 0 beyond rupture). This is the static
/// bond energy released into the energy ledger when the bridge ruptures
/// (doc/spec/physics-lian1994.md §3.8: C(29)). For `Laplace` it is the surface-energy
/// difference `E(S_c) − E(s)` of (4.35).
pub fn bond_energy(model: BridgeModel, b: &Bridge, s: f64) -> f64 {
    BridgeCoeffs::new(model, b).bond_energy(s)
}

/// Check a bridge for a model. `Err` for input the model cannot handle
/// (non-finite or non-positive radius or volume, negative γ, θ outside
/// [0, 90°), no Laplace–Young solution); `Ok(warnings)` otherwise, listing
/// extrapolations outside the ranges the models were built or validated on.
pub fn validate(model: BridgeModel, b: &Bridge) -> Result<Vec<String>, String> {
    if !(b.r1 > 0.0 && b.r2 > 0.0) || b.r1.is_nan() || b.r2.is_nan() {
        return Err(format!(
            "bridge radii must be positive (got {}, {})",
            b.r1, b.r2
        ));
    }
    if b.r1.is_infinite() && b.r2.is_infinite() {
        return Err("a bridge needs at least one sphere (both radii infinite)".into());
    }
    if !(b.volume > 0.0 && b.volume.is_finite()) {
        return Err(format!(
            "bridge volume must be positive and finite (got {})",
            b.volume
        ));
    }
    if !(b.gamma >= 0.0 && b.gamma.is_finite()) {
        return Err(format!("surface tension must be >= 0 (got {})", b.gamma));
    }
    if !(b.theta >= 0.0 && b.theta < FRAC_PI_2) {
        return Err(format!(
            "contact angle must be in [0, 90) degrees (got {:.3} degrees)",
            b.theta.to_degrees()
        ));
    }
    let Some(n) = b.norm() else {
        return Err("invalid bridge".into());
    };
    let mut w = Vec::new();
    if b.gamma == 0.0 {
        w.push("surface tension is 0: no static bridge force".to_string());
    }
    if b.theta > 40f64.to_radians() + 1e-12 && model != BridgeModel::Rabinovich {
        w.push(format!(
            "contact angle {:.1} deg is outside Lian's studied range 0-40 deg",
            b.theta.to_degrees()
        ));
    }
    let v = n.v;
    match model {
        BridgeModel::Fit | BridgeModel::Toroidal => {
            if n.is_wall() {
                if model == BridgeModel::Fit && (v > 0.01 || b.theta > 10f64.to_radians()) {
                    w.push(format!(
                        "V/R^3 = {v:.3e}, theta = {:.1} deg: the sphere-plane formula of \
                         Olsson/Rabinovich (33)-(35) is a small-bridge approximation (errors \
                         of 25-60 % against Laplace-Young here, see doc/bridge.md): use the \
                         Toroidal model",
                        b.theta.to_degrees()
                    ));
                }
            } else {
                let vmax = 0.03 + 0.014 * (n.k.min(5.0) - 1.0) / 4.0;
                if !(0.0009..=vmax * 1.05).contains(&v) {
                    w.push(format!(
                        "V/R1^3 = {v:.3e} is outside the range of Lian's fits \
                         (0.001-{vmax:.3}, Tables 5.1-5.2)"
                    ));
                }
                if n.k > 5.0 + 1e-12 {
                    w.push(format!(
                        "radius ratio {:.2} is outside the range of Lian's fits (1-5)",
                        n.k
                    ));
                }
            }
            if model == BridgeModel::Fit && !n.is_wall() && b.theta > 0.0 {
                w.push(format!(
                    "Lian's polynomials (5.37)-(5.49) were fitted for theta = 0; at theta = \
                     {:.1} deg the Fit force can be far off near rupture (see doc/bridge.md): \
                     use the Toroidal model",
                    b.theta.to_degrees()
                ));
            }
            if model == BridgeModel::Fit && !n.is_wall() {
                let sc = rupture_star_default(&n);
                let bad = (0..=20).any(|i| {
                    let x = sc * i as f64 / 20.0;
                    toroidal_like(model, &n, x, sc).is_none()
                });
                if bad {
                    w.push(
                        "the fitted half-filling angle gives no valid toroid (neck radius <= 0) \
                         for part of 0..S_c: the force drops to 0 there"
                            .into(),
                    );
                }
            }
            if model == BridgeModel::Toroidal {
                let sc = rupture_star_default(&n);
                if toroidal_like(model, &n, sc, sc).is_none() {
                    w.push("the toroid pinches off before the rupture distance".into());
                }
            }
        }
        BridgeModel::Rabinovich => w.extend(rabinovich_warnings(b, &n)),
        BridgeModel::Laplace => {
            if laplace_cache(&n).is_none() {
                return Err(format!(
                    "no pendular Laplace-Young bridge for R2/R1 = {:.3}, V/R1^3 = {v:.3e}, \
                     theta = {:.1} deg",
                    n.k,
                    b.theta.to_degrees()
                ));
            }
            if !(1e-5..=0.2).contains(&v) {
                w.push(format!(
                    "V/R1^3 = {v:.3e} is outside the tested range 1e-5..0.2"
                ));
            }
        }
    }
    if n.k.is_finite() && n.k > 1e4 {
        w.push("radius ratio > 1e4: consider a plane wall (r2 = infinity)".into());
    }
    Ok(w)
}

/// The validity range of Olsson's Rabinovich model (doc/bridge.md): liquid content (the
/// bridge volume as a percentage of the mean volume of its spheres, the particle's at a
/// wall) in the pendular regime, which Olsson bounds at about 10 % (he simulated
/// 0.01–1 %); the harmonic-mean radius (45), which Rabinovich validated for size ratios
/// 1.44–1.84; bridge radii above ~5 nm (Fisher & Israelachvili, Olsson §2.2.2.4).
fn rabinovich_warnings(b: &Bridge, n: &Norm) -> Vec<String> {
    let mut w = Vec::new();
    let vol = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let mean = if n.is_wall() {
        vol(n.a)
    } else {
        0.5 * (vol(n.a) + vol(n.a * n.k))
    };
    let pct = 100.0 * b.volume / mean;
    if pct > 10.0 {
        w.push(format!(
            "liquid content {pct:.3} % of the particle volume is beyond the pendular regime \
             the Rabinovich model is valid in (Olsson 2017: funicular above about 10 %; he \
             simulated 0.01-1 %)"
        ));
    }
    if n.k.is_finite() && n.k > 1.84 + 1e-9 {
        w.push(format!(
            "radius ratio {:.2} is beyond the size ratios Rabinovich (2005) validated the \
             harmonic-mean radius for (1.44-1.84)",
            n.k
        ));
    }
    let r = if n.is_wall() {
        n.a
    } else {
        rabinovich::harmonic_radius(n.a, n.a * n.k)
    };
    let neck = r * rabinovich::Rabinovich::new(n.a, n.a * n.k, b.volume, b.theta).alpha(0.0);
    if neck < 5e-9 {
        w.push(format!(
            "bridge radius {neck:.2e} m at contact is below the ~5 nm continuum limit of the \
             Rabinovich model (Olsson 2017 §2.2.2.4)"
        ));
    }
    w
}

/// Per-bridge precomputed data, built once when a bridge forms, so that the
/// per-step force costs a few flops:
/// * `Fit`: the polynomial coefficients C0..C3 of (5.38)–(5.49) and S_c;
/// * `Toroidal`: a 24-node Chebyshev table of the exact toroidal φ1(S/S_c);
/// * `Laplace`: the traced Laplace–Young branch (shared, cached).
///
/// Serialises as `(model, bridge)` and is rebuilt (deterministically) on load.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(from = "CoeffsSpec", into = "CoeffsSpec")]
pub struct BridgeCoeffs {
    model: BridgeModel,
    bridge: Bridge,
    n: Norm,
    /// Rupture distance, units of the smaller radius, and its inverse.
    sc: f64,
    inv_sc: f64,
    /// 1 / R_small.
    inv_a: f64,
    /// γ R_small (force scale, N).
    scale: f64,
    kind: Kind,
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// Invalid bridge or γ = 0: no force.
    Null,
    FitPair([f64; 4]),
    FitWall,
    Toroidal(ToroidalTable),
    Laplace(Arc<Branch>),
    /// Olsson's Rabinovich bridge in units of the smaller radius.
    Rabinovich(rabinovich::Rabinovich),
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
struct CoeffsSpec {
    model: BridgeModel,
    bridge: Bridge,
}

impl From<CoeffsSpec> for BridgeCoeffs {
    fn from(s: CoeffsSpec) -> Self {
        BridgeCoeffs::new(s.model, &s.bridge)
    }
}

impl From<BridgeCoeffs> for CoeffsSpec {
    fn from(c: BridgeCoeffs) -> Self {
        CoeffsSpec {
            model: c.model,
            bridge: c.bridge,
        }
    }
}

impl BridgeCoeffs {
    /// Precompute for a bridge (cost: Fit ≈ 0.1 µs, Toroidal ≈ 20 µs,
    /// Laplace a few ms for the first bridge with given R2/R1, V/R1³, θ).
    /// An invalid bridge gives zero forces (check with [`validate`]).
    pub fn new(model: BridgeModel, b: &Bridge) -> BridgeCoeffs {
        let null = |n: Norm| BridgeCoeffs {
            model,
            bridge: *b,
            n,
            sc: 0.0,
            inv_sc: 0.0,
            inv_a: 1.0 / n.a,
            scale: 0.0,
            kind: Kind::Null,
        };
        let Some(n) = b.norm() else {
            return null(Norm {
                a: 1.0,
                k: 1.0,
                v: 0.0,
                theta: 0.0,
                sin_t: 0.0,
                cos_t: 1.0,
                swapped: false,
            });
        };
        let scale = if b.gamma > 0.0 && b.gamma.is_finite() {
            b.gamma * n.a
        } else {
            0.0
        };
        let sc = rupture_star_default(&n);
        let mk = |kind: Kind, sc: f64| BridgeCoeffs {
            model,
            bridge: *b,
            n,
            sc,
            inv_sc: 1.0 / sc,
            inv_a: 1.0 / n.a,
            scale,
            kind,
        };
        match model {
            BridgeModel::Fit => {
                if n.is_wall() {
                    mk(Kind::FitWall, sc)
                } else {
                    mk(Kind::FitPair(fit::poly_coeffs(1.0 / n.k, n.v)), sc)
                }
            }
            BridgeModel::Toroidal => match ToroidalTable::new(&n, sc) {
                Some(t) => mk(Kind::Toroidal(t), sc),
                None => null(n),
            },
            BridgeModel::Rabinovich => {
                let r2 = if n.is_wall() { f64::INFINITY } else { n.k };
                let r = rabinovich::Rabinovich::new(1.0, r2, n.v, n.theta);
                mk(
                    Kind::Rabinovich(r),
                    rupture::willett_star(n.v, n.theta, n.k),
                )
            }
            BridgeModel::Laplace => match laplace_cache(&n) {
                Some(br) => {
                    let sc = br.rupture_star();
                    mk(Kind::Laplace(br), sc)
                }
                None => match ToroidalTable::new(&n, sc) {
                    Some(t) => mk(Kind::Toroidal(t), sc),
                    None => null(n),
                },
            },
        }
    }

    /// The model.
    pub fn model(&self) -> BridgeModel {
        self.model
    }

    /// The bridge the coefficients were built for.
    pub fn bridge(&self) -> &Bridge {
        &self.bridge
    }

    /// Rupture distance (m) of this model ([`model_rupture_distance`]).
    pub fn rupture_distance(&self) -> f64 {
        self.sc * self.n.a
    }

    /// Dimensionless state `(F*, φ_small, φ_large)` at `x = S/R_small ∈ [0, S_c]`.
    #[inline]
    fn state(&self, x: f64) -> Option<(f64, f64, f64)> {
        let n = &self.n;
        match &self.kind {
            Kind::Null => None,
            Kind::FitPair(c) => {
                let phi = fit::phi1_poly(*c, x / self.sc);
                toroidal::torus(n, phi, x).map(|t| (t.force_star(), t.phi1, t.phi2))
            }
            Kind::FitWall => {
                let (f, a) = fit::olsson_wall_star(n.v, x, n.theta);
                Some((f, a, 0.0))
            }
            Kind::Toroidal(t) => {
                let r = (x / self.sc).min(t.s_max);
                let phi = t.cheb.eval(r);
                toroidal::torus(n, phi, r * self.sc).map(|t| (t.force_star(), t.phi1, t.phi2))
            }
            Kind::Laplace(br) => {
                let (p1, p2) = br.half_filling_angles_sorted(x);
                Some((br.force_star(x), p1, p2))
            }
            Kind::Rabinovich(r) => {
                let a = r.alpha(x);
                Some((r.force_per_gamma(x), a, if r.wall { 0.0 } else { a }))
            }
        }
    }

    /// Static force (N), attractive magnitude ≥ 0, at gap `s` (m); see
    /// [`static_force`]. `s < 0` counts as 0; 0 beyond the rupture distance.
    /// This is the per-step path: one polynomial (Fit) or Chebyshev (Toroidal,
    /// Laplace) evaluation, one `sin_cos` and a few divisions.
    #[inline]
    pub fn force(&self, s: f64) -> f64 {
        let Some(x) = within_rupture(s * self.inv_a, self.sc) else {
            return 0.0;
        };
        let n = &self.n;
        let f = match &self.kind {
            Kind::Null => None,
            Kind::FitPair(c) => {
                toroidal::gorge_force_star(n, fit::phi1_poly(*c, x * self.inv_sc), x)
            }
            Kind::FitWall => Some(fit::olsson_wall_force_star(n.v, x, n.sin_t, n.cos_t)),
            Kind::Toroidal(t) => {
                let r = (x * self.inv_sc).min(t.s_max);
                toroidal::gorge_force_star(n, t.cheb.eval(r), r * self.sc)
            }
            Kind::Laplace(br) => Some(br.force_star(x)),
            Kind::Rabinovich(r) => Some(r.force_per_gamma(s * self.inv_a)),
        };
        match f {
            Some(f) => self.scale * f,
            None => 0.0,
        }
    }

    /// Half-filling angles `(φ on r1, φ on r2)` at gap `s` (clamped to [0, S_c]).
    pub fn half_filling_angles(&self, s: f64) -> (f64, f64) {
        let x = (s / self.n.a).max(0.0).min(self.sc);
        let (p1, p2) = self.state(x).map(|v| (v.1, v.2)).unwrap_or((0.0, 0.0));
        if self.n.swapped { (p2, p1) } else { (p1, p2) }
    }

    /// Energy (J) to pull the bridge from gap `s` to rupture, `∫_s^{S_c} F dS`.
    pub fn bond_energy(&self, s: f64) -> f64 {
        let x = (s / self.n.a).max(0.0);
        if !(x < self.sc) || self.scale == 0.0 {
            return 0.0;
        }
        let a = self.n.a;
        let e_star = match &self.kind {
            Kind::Laplace(br) => br.bond_energy_star(x),
            _ => integrate(|y| self.state(y).map(|v| v.0).unwrap_or(0.0), x, self.sc, 8),
        };
        self.scale * a * e_star
    }
}
