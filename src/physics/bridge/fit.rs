//! Lian's fitted half-filling angle, Lian 1994 (5.37)–(5.49) with the two
//! sign corrections of doc/spec/physics-lian1994.md §3.5 (slopes of (5.42) and (5.43)),
//! and the sphere–plane force of Rabinovich et al. (2005) as used by Olsson
//! (2017) eqs (33)–(35) (with α² = 2d/R, the corrected (35)).
//!
//! Sphere 1 is always the smaller sphere; `q = R1/R2 ∈ (0, 1]`.

use super::Norm;
use std::f64::consts::PI;

/// Table 5.3 coefficients `[b0, k0, b1, k1, b2, k2, b3, k3]` as linear
/// functions of `q = R1/R2`, Lian 1994 (5.42)–(5.49). The printed slopes of
/// (5.42) and (5.43) have the wrong sign (a least-squares line through
/// Table 5.3 gives +0.00771 and −0.07758); corrected here:
/// `b0 = 0.26958 + 0.00766 q` (5.42, corrected), `k0 = 1.20420 − 0.07753 q`
/// (5.43, corrected), `b1 = −0.93128 + 0.33513 q` (5.44),
/// `k1 = −0.17990 + 0.07435 q` (5.45), `b2 = 0.98431 − 0.40353 q` (5.46),
/// `k2 = 0.13948 − 0.06938 q` (5.47), `b3 = −0.36328 + 0.17703 q` (5.48),
/// `k3 = −0.03245 + 0.02456 q` (5.49).
#[inline]
pub fn table53(q: f64) -> [f64; 8] {
    [
        0.26958 + 0.00766 * q,
        1.20420 - 0.07753 * q,
        -0.93128 + 0.33513 * q,
        -0.17990 + 0.07435 * q,
        0.98431 - 0.40353 * q,
        0.13948 - 0.06938 * q,
        -0.36328 + 0.17703 * q,
        -0.03245 + 0.02456 * q,
    ]
}

/// Polynomial coefficients `[C0, C1, C2, C3]` for `V* = V/R1³`, Lian 1994
/// (5.38)–(5.41): `C0 = k0 V*^{b0}`, `Cj = bj + kj log10 V*` (the "log" of
/// (5.39)–(5.41) is base 10, unlike the natural log of (5.33)).
#[inline]
pub fn poly_coeffs_from(t: [f64; 8], v_star: f64) -> [f64; 4] {
    let lg = v_star.log10();
    [
        t[1] * v_star.powf(t[0]),
        t[2] + t[3] * lg,
        t[4] + t[5] * lg,
        t[6] + t[7] * lg,
    ]
}

/// `[C0..C3]` for the ratio `q = R1/R2` and `V* = V/R1³`: (5.38)–(5.49).
#[inline]
pub fn poly_coeffs(q: f64, v_star: f64) -> [f64; 4] {
    poly_coeffs_from(table53(q), v_star)
}

/// Half-filling angle on the smaller sphere (rad), Lian 1994 (5.37):
/// `φ1 = C0 + C1 x + C2 x² + C3 x³`, `x = S/S_c` clamped to [0, 1].
#[inline]
pub fn phi1_poly(c: [f64; 4], x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    c[0] + x * (c[1] + x * (c[2] + x * c[3]))
}

/// Fitted φ1 for a normalised bridge at `x = S/S_c` (extrapolated linearly in
/// `q` for a plane, used only as a starting guess there).
#[inline]
pub(crate) fn phi1_guess(n: &Norm, x: f64) -> f64 {
    let q = if n.k.is_finite() { 1.0 / n.k } else { 0.0 };
    phi1_poly(poly_coeffs(q, n.v), x)
}

/// Sphere–plane bridge of Rabinovich et al. (2005) as implemented by Olsson
/// (2017) eqs (33)–(35), dimensionless (`R` = sphere radius, `h = H/R`,
/// `v = V/R³`): `d = −h + sqrt(h² + v/π)` (34), `α² = 2d` ((35) corrected:
/// the printed `2V` contradicts (34)),
/// `F/(γR) = 4π cos θ / (1 + h/d) + 2π sin α sin(θ + α)` (33), attractive.
/// Returns `(F*, α)`.
#[inline]
pub fn olsson_wall_star(v: f64, h: f64, theta: f64) -> (f64, f64) {
    let h = h.max(0.0);
    let d = -h + (h * h + v / PI).sqrt();
    if !(d > 0.0) {
        return (0.0, 0.0);
    }
    let alpha = (2.0 * d).sqrt();
    let f = 4.0 * PI * theta.cos() / (1.0 + h / d) + 2.0 * PI * alpha.sin() * (theta + alpha).sin();
    // (meaningless, possibly negative, for absurd volumes where α > π/2)
    (f.max(0.0), alpha)
}

/// [`olsson_wall_star`] force only, with `sin θ`, `cos θ` precomputed.
#[inline]
pub(crate) fn olsson_wall_force_star(v: f64, h: f64, sin_t: f64, cos_t: f64) -> f64 {
    let h = h.max(0.0);
    let d = -h + (h * h + v / PI).sqrt();
    if !(d > 0.0) {
        return 0.0;
    }
    let (sa, ca) = (2.0 * d).sqrt().sin_cos();
    (4.0 * PI * cos_t * d / (d + h) + 2.0 * PI * sa * (sa * cos_t + ca * sin_t)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::super::{Bridge, BridgeModel, half_filling_angle, static_force};
    use super::*;

    /// Table 5.2 verbatim (R2/R1, V/R1³, C0..C3).
    pub(crate) const TABLE_5_2: [(f64, f64, [f64; 4]); 25] = [
        (1.0, 0.00100, [0.16702, -0.28582, 0.37579, -0.16440]),
        (1.0, 0.00500, [0.25947, -0.35601, 0.43167, -0.17593]),
        (1.0, 0.01000, [0.31461, -0.38911, 0.45302, -0.17792]),
        (1.0, 0.02000, [0.38246, -0.42474, 0.47284, -0.17819]),
        (1.0, 0.03000, [0.42938, -0.44723, 0.48390, -0.17763]),
        (1.2, 0.00102, [0.17069, -0.30147, 0.40023, -0.17671]),
        (1.2, 0.00519, [0.26593, -0.37800, 0.46296, -0.19087]),
        (1.2, 0.01049, [0.32299, -0.41431, 0.48704, -0.19368]),
        (1.2, 0.02126, [0.39351, -0.45349, 0.50925, -0.19445]),
        (1.2, 0.03219, [0.44248, -0.47824, 0.52151, -0.19400]),
        (1.5, 0.00105, [0.17477, -0.31925, 0.42825, -0.19090]),
        (1.5, 0.00540, [0.27313, -0.40321, 0.49922, -0.20831]),
        (1.5, 0.01104, [0.33238, -0.44330, 0.52656, -0.21213]),
        (1.5, 0.02268, [0.40597, -0.48667, 0.55157, -0.21348]),
        (1.5, 0.03470, [0.45733, -0.51410, 0.56514, -0.21312]),
        (2.0, 0.00107, [0.17933, -0.33966, 0.46078, -0.20749]),
        (2.0, 0.00563, [0.28125, -0.43246, 0.54180, -0.22896]),
        (2.0, 0.01164, [0.34301, -0.47710, 0.57317, -0.23407]),
        (2.0, 0.02429, [0.42015, -0.52553, 0.60160, -0.23617]),
        (2.0, 0.03758, [0.47431, -0.55620, 0.61670, -0.23588]),
        (5.0, 0.00112, [0.18917, -0.38552, 0.53511, -0.24577]),
        (5.0, 0.00608, [0.29893, -0.49937, 0.64127, -0.27783]),
        (5.0, 0.01288, [0.36628, -0.55504, 0.68297, -0.28650]),
        (5.0, 0.02774, [0.45145, -0.61588, 0.72017, -0.29073]),
        (5.0, 0.04394, [0.51199, -0.65454, 0.73914, -0.29069]),
    ];

    /// Table 5.3 verbatim (R2/R1, b0, k0, b1, k1, b2, k2, b3, k3).
    const TABLE_5_3: [(f64, [f64; 8]); 5] = [
        (
            1.0,
            [
                0.2774, 1.1319, -0.6094, -0.1087, 0.5978, 0.0734, -0.1941, -0.0092,
            ],
        ),
        (
            1.2,
            [
                0.2758, 1.1379, -0.6497, -0.1174, 0.6453, 0.0812, -0.2146, -0.0118,
            ],
        ),
        (
            1.5,
            [
                0.2748, 1.1492, -0.6966, -0.1277, 0.7007, 0.0905, -0.2385, -0.0150,
            ],
        ),
        (
            2.0,
            [
                0.2732, 1.1600, -0.7507, -0.1395, 0.7656, 0.1014, -0.2669, -0.0188,
            ],
        ),
        (
            5.0,
            [
                0.2712, 1.1938, -0.8776, -0.1682, 0.9209, 0.1290, -0.3359, -0.0289,
            ],
        ),
    ];

    /// (5.42)–(5.49) (corrected) reproduce Table 5.3 within 0.02 (the scatter
    /// of Lian's own linear fits; largest residual 0.017 on b2), and the
    /// corrected slopes of (5.42)/(5.43) are needed for that.
    #[test]
    fn linear_fits_reproduce_table_5_3() {
        for (k, row) in TABLE_5_3 {
            let q = 1.0 / k;
            let t = table53(q);
            for j in 0..8 {
                assert!(
                    (t[j] - row[j]).abs() < 0.02,
                    "k={k} j={j} {} {}",
                    t[j],
                    row[j]
                );
            }
            // as printed (wrong slope signs) b0 and k0 are further off
            let b0p = 0.26958 - 0.00766 * q;
            let k0p = 1.20420 + 0.07753 * q;
            assert!((b0p - row[0]).abs() > (t[0] - row[0]).abs());
            assert!((k0p - row[1]).abs() > (t[1] - row[1]).abs());
        }
        // k0(q = 1): printed 1.2817, corrected 1.1267, table 1.1319
        assert!((table53(1.0)[1] - 1.1319).abs() < 0.006);
    }

    /// (5.38)–(5.41) with Table 5.3 reproduce Table 5.2 (C0 within 0.004, Cj
    /// within 0.008); through the linear fits (5.42)–(5.49) the coefficients
    /// drift more (≤ 0.03) but the curves φ1(S/S_c) stay within 0.01 rad.
    #[test]
    fn power_log_fits_reproduce_table_5_2() {
        let mut worst = [0.0f64; 2];
        for (k, v, c_tab) in TABLE_5_2 {
            let row = TABLE_5_3.iter().find(|r| r.0 == k).unwrap().1;
            for (i, (t, tc0, tcj, tcurve)) in [
                (row, 0.004, 0.008, 0.006),
                (table53(1.0 / k), 0.01, 0.03, 0.01),
            ]
            .into_iter()
            .enumerate()
            {
                let c = poly_coeffs_from(t, v);
                assert!((c[0] - c_tab[0]).abs() < tc0, "{i} k={k} v={v} C0 {c:?}");
                for j in 1..4 {
                    assert!((c[j] - c_tab[j]).abs() < tcj, "{i} k={k} v={v} C{j} {c:?}");
                }
                for m in 0..=10 {
                    let x = m as f64 / 10.0;
                    let d = (phi1_poly(c, x) - phi1_poly(c_tab, x)).abs();
                    worst[i] = worst[i].max(d);
                    assert!(d < tcurve, "{i} k={k} v={v} x={x} d={d}");
                }
            }
        }
        assert!(worst[0] < worst[1]);
    }

    /// Reference values of doc/spec/physics-lian1994.md §3.6 (R = 30 µm, V = 0.1 % of the
    /// particle volume, γ = 0.025 N/m, θ = 0), within 0.5 %.
    #[test]
    fn reference_forces_of_physics_report() {
        let r = 30e-6;
        let v = 0.001 * 4.0 / 3.0 * PI * r * r * r;
        let b = Bridge {
            r1: r,
            r2: r,
            volume: v,
            gamma: 0.025,
            theta: 0.0,
        };
        let sc = super::super::rupture_distance(&b);
        let cases = [
            (0.0, 0.24691, 4.19219e-6),
            (0.25, 0.18389, 1.80620e-6),
            (0.5, 0.15692, 8.11145e-7),
            (0.75, 0.15031, 4.59377e-7),
            (1.0, 0.14835, 2.83103e-7),
        ];
        for (x, phi, f) in cases {
            let got_phi = half_filling_angle(BridgeModel::Fit, &b, x * sc);
            let got_f = static_force(BridgeModel::Fit, &b, x * sc);
            assert!((got_phi - phi).abs() < 1e-4, "x={x} {got_phi}");
            assert!((got_f / f - 1.0).abs() < 0.005, "x={x} {got_f} {f}");
        }
        // beyond rupture: zero; overlap counts as contact
        assert_eq!(static_force(BridgeModel::Fit, &b, 1.0001 * sc), 0.0);
        let f0 = static_force(BridgeModel::Fit, &b, 0.0);
        assert_eq!(static_force(BridgeModel::Fit, &b, -1e-7), f0);
        // unequal pair 30/60 µm
        let b = Bridge { r2: 60e-6, ..b };
        let sc = super::super::rupture_distance(&b);
        assert!((sc - 4.83054e-6).abs() < 2e-11, "{sc}");
        for (x, phi, f) in [
            (0.0, 0.26082, 5.71428e-6),
            (0.5, 0.15365, 8.47536e-7),
            (1.0, 0.14305, 2.72587e-7),
        ] {
            let got_phi = half_filling_angle(BridgeModel::Fit, &b, x * sc);
            let got_f = static_force(BridgeModel::Fit, &b, x * sc);
            assert!((got_phi - phi).abs() < 1e-4, "x={x} {got_phi}");
            assert!((got_f / f - 1.0).abs() < 0.005, "x={x} {got_f} {f}");
        }
    }

    /// Olsson (33): at contact the force is 4πγR cos θ plus the wetting term.
    #[test]
    fn olsson_wall_limits() {
        let (f, a) = olsson_wall_star(1e-9, 0.0, 0.3);
        assert!(
            (f / (4.0 * PI * 0.3f64.cos()) - 1.0).abs() < 0.02,
            "{f} {a}"
        );
        let (f1, _) = olsson_wall_star(0.004, 0.05, 0.0);
        let (f2, _) = olsson_wall_star(0.004, 0.10, 0.0);
        assert!(f1 > f2 && f2 > 0.0);
    }
}
