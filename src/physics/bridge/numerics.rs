//! Small numerical helpers shared by the bridge models: Brent root finding,
//! Gauss–Legendre quadrature and Chebyshev interpolation. Plain `std`, no
//! allocation in the evaluation paths.

use std::sync::OnceLock;

/// Brent's method on a bracket `[a, b]` with `f(a)` and `f(b)` of opposite
/// sign (or one of them zero). Returns `None` if the bracket is invalid or
/// an evaluation is not finite. `xtol` is an absolute tolerance on x.
pub(crate) fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    xtol: f64,
    max_iter: usize,
) -> Option<f64> {
    if !(fa.is_finite() && fb.is_finite()) {
        return None;
    }
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa.signum() == fb.signum() {
        return None;
    }
    let mut c = a;
    let mut fc = fa;
    let mut d = b - a;
    let mut e = d;
    for _ in 0..max_iter {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Some(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
        if !fb.is_finite() {
            return None;
        }
    }
    Some(b)
}

/// Gauss–Legendre nodes and weights on [0, 1] (n points), computed by Newton
/// iteration on the Legendre polynomial.
pub(crate) fn gauss_legendre_01(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    let nf = n as f64;
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            dp = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// Cached 32-point Gauss–Legendre rule on [0, 1].
pub(crate) fn gl32() -> &'static [(f64, f64)] {
    static GL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    GL.get_or_init(|| gauss_legendre_01(32))
}

/// Cached 12-point Gauss–Legendre rule on [0, 1] (used per panel).
pub(crate) fn gl12() -> &'static [(f64, f64)] {
    static GL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    GL.get_or_init(|| gauss_legendre_01(12))
}

/// ∫_a^b f by a composite 12-point Gauss–Legendre rule on `panels` equal panels.
pub(crate) fn integrate<F: FnMut(f64) -> f64>(mut f: F, a: f64, b: f64, panels: usize) -> f64 {
    if !(b > a) {
        return 0.0;
    }
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let x0 = a + h * p as f64;
        for &(t, w) in gl12() {
            sum += w * f(x0 + h * t);
        }
    }
    sum * h
}

/// Chebyshev interpolant of a smooth function on [a, b] (first-kind nodes).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cheb {
    a: f64,
    b: f64,
    c: Vec<f64>,
}

impl Cheb {
    /// The `n` first-kind Chebyshev nodes mapped to [a, b].
    pub(crate) fn nodes(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|j| {
                let x = (std::f64::consts::PI * (j as f64 + 0.5) / n as f64).cos();
                0.5 * (a + b) + 0.5 * (b - a) * x
            })
            .collect()
    }

    /// Build from the values at [`Cheb::nodes`]`(a, b, values.len())`.
    pub(crate) fn from_values(a: f64, b: f64, values: &[f64]) -> Cheb {
        let n = values.len();
        let mut c = vec![0.0; n];
        for (k, ck) in c.iter_mut().enumerate() {
            let mut s = 0.0;
            for (j, v) in values.iter().enumerate() {
                s += v * (std::f64::consts::PI * k as f64 * (j as f64 + 0.5) / n as f64).cos();
            }
            *ck = 2.0 * s / n as f64;
        }
        if let Some(c0) = c.first_mut() {
            *c0 *= 0.5;
        }
        Cheb { a, b, c }
    }

    /// Clenshaw evaluation; x is clamped into [a, b].
    #[inline]
    pub(crate) fn eval(&self, x: f64) -> f64 {
        let x = x.clamp(self.a, self.b);
        let t = (2.0 * x - self.a - self.b) / (self.b - self.a);
        let t2 = 2.0 * t;
        let (mut b1, mut b2) = (0.0, 0.0);
        for &ck in self.c.iter().skip(1).rev() {
            let b0 = ck + t2 * b1 - b2;
            b2 = b1;
            b1 = b0;
        }
        self.c.first().copied().unwrap_or(0.0) + t * b1 - b2
    }

    /// Size of the last two coefficients (a convergence indicator).
    pub(crate) fn tail(&self) -> f64 {
        let n = self.c.len();
        if n < 2 {
            return f64::INFINITY;
        }
        self.c[n - 1].abs() + self.c[n - 2].abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let r = gauss_legendre_01(12);
        let s: f64 = r.iter().map(|&(x, w)| w * x.powi(23)).sum();
        assert!((s - 1.0 / 24.0).abs() < 1e-15);
        let s: f64 = r.iter().map(|&(_, w)| w).sum();
        assert!((s - 1.0).abs() < 1e-15);
    }

    #[test]
    fn brent_finds_cubic_root() {
        let f = |x: f64| x * x * x - 2.0;
        let r = brent(f, 0.0, 2.0, f(0.0), f(2.0), 1e-14, 100).unwrap();
        assert!((r - 2f64.cbrt()).abs() < 1e-13);
        assert!(brent(f, 2.0, 3.0, f(2.0), f(3.0), 1e-14, 100).is_none());
    }

    #[test]
    fn chebyshev_interpolates_smooth_function() {
        let xs = Cheb::nodes(0.0, 2.0, 20);
        let ys: Vec<f64> = xs.iter().map(|x| (x * 1.3).exp()).collect();
        let c = Cheb::from_values(0.0, 2.0, &ys);
        for i in 0..=50 {
            let x = 2.0 * i as f64 / 50.0;
            assert!((c.eval(x) - (x * 1.3).exp()).abs() < 1e-12);
        }
    }
}
