//! Wall geometry: gap, contact normal and surface velocity for plane walls, spherical
//! containers, spherical obstacles (Lian (5.7), (5.8); doc/spec/DECISIONS.md, "Contact laws")
//! and cylindrical dies (doc/indentation.md, "The cylindrical die").

use crate::sim::model::WallGeom;

use super::scene::{Vec3, Wall};

/// Gap between a particle surface and the wall (negative = overlap) and the unit normal
/// pointing from the particle to the wall (the contact normal, A = particle, B = wall).
#[inline]
pub fn wall_gap(geom: &WallGeom, x: &Vec3, r: f64) -> (f64, Vec3) {
    WallShape::of(geom).gap(x, r)
}

/// A wall's geometry with what every gap needs computed once (a plane's unit normal and
/// offset): [`WallShape::gap`] gives the bits of [`wall_gap`] without a square root and four
/// divisions per particle.
#[derive(Clone, Copy, Debug)]
pub enum WallShape {
    Plane { nh: Vec3, offset: f64 },
    Other(WallGeom),
}

impl WallShape {
    pub fn of(geom: &WallGeom) -> WallShape {
        match *geom {
            WallGeom::Plane { normal, d } => {
                let n = Vec3::from(normal);
                let len = n.norm();
                WallShape::Plane {
                    nh: n / len,
                    offset: d / len,
                }
            }
            g => WallShape::Other(g),
        }
    }

    /// Gap between the wall and a sphere (centre `x`, radius `r`) and the unit normal from the
    /// sphere towards the wall.
    #[inline]
    pub fn gap(&self, x: &Vec3, r: f64) -> (f64, Vec3) {
        match self {
            WallShape::Plane { nh, offset } => {
                let s = nh.dot(x) - offset;
                (s - r, -nh)
            }
            WallShape::Other(g) => curved_gap(g, x, r),
        }
    }
}

fn curved_gap(geom: &WallGeom, x: &Vec3, r: f64) -> (f64, Vec3) {
    match *geom {
        WallGeom::Plane { .. } => WallShape::of(geom).gap(x, r),
        WallGeom::Sphere { centre, radius } => {
            let e = x - Vec3::from(centre);
            let rho = e.norm();
            let dir = if rho > 0.0 {
                e / rho
            } else {
                Vec3::new(0.0, 0.0, 1.0)
            };
            (radius - rho - r, dir)
        }
        WallGeom::Obstacle { centre, radius } => {
            let e = x - Vec3::from(centre);
            let rho = e.norm();
            let dir = if rho > 0.0 {
                e / rho
            } else {
                Vec3::new(0.0, 0.0, 1.0)
            };
            (rho - radius - r, -dir)
        }
        WallGeom::Cylinder {
            point,
            axis,
            radius,
        } => {
            let a = Vec3::from(axis);
            let e = x - Vec3::from(point);
            let e = e - a * a.dot(&e);
            let rho = e.norm();
            let dir = if rho > 0.0 {
                e / rho
            } else {
                any_perpendicular(&a)
            };
            (radius - rho - r, dir)
        }
    }
}

/// A unit vector perpendicular to the unit vector `a` (the normal of a particle on a
/// cylinder's axis, where every radial direction is as good).
fn any_perpendicular(a: &Vec3) -> Vec3 {
    let t = if a.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let p = t - a * a.dot(&t);
    p / p.norm()
}

/// The periodic axes that a plane wall crosses (its unit normal has a component along
/// them): such an axis must be open, or a particle leaving through one side would re-enter
/// at the other, behind the wall (doc/limits.md, "Walls and periodic axes").
pub fn crossed_axes(geom: &WallGeom, periodic: &[bool; 3]) -> [bool; 3] {
    let mut out = [false; 3];
    if let WallGeom::Plane { normal, .. } = geom {
        let n = Vec3::from(*normal);
        let len = n.norm();
        for k in 0..3 {
            out[k] = periodic[k] && (n[k] / len).abs() > 1e-12;
        }
    }
    out
}

/// Makes open every periodic axis that a plane wall of `walls` crosses; returns those axes.
pub fn open_crossed(walls: &[Wall], periodic: &mut [bool; 3]) -> [bool; 3] {
    let mut opened = [false; 3];
    for w in walls {
        let c = crossed_axes(&w.geom, periodic);
        for k in 0..3 {
            opened[k] |= c[k];
        }
    }
    for k in 0..3 {
        if opened[k] {
            periodic[k] = false;
        }
    }
    opened
}

/// The axes' names of `axes`, as "x and z".
pub fn axis_names(axes: &[bool; 3]) -> String {
    let names: Vec<&str> = ["x", "y", "z"]
        .iter()
        .zip(axes)
        .filter(|(_, a)| **a)
        .map(|(n, _)| *n)
        .collect();
    names.join(" and ")
}

/// Effective radius R* of a particle against a wall: plane R, container R d/(d − R),
/// obstacle R d/(d + R) (doc/spec/DECISIONS.md); inside a cylinder of radius d, the Hertz
/// equivalent radius of unequal principal curvatures R_e = sqrt(R' R'') (Johnson, *Contact
/// Mechanics*, 1985, §4.2, (4.31)–(4.33)) with the principal relative radii
/// R' = R d/(d − R) (around the axis: the concave wall) and R'' = R (along the axis: the
/// straight wall), i.e. R_e = R sqrt(d/(d − R)). Against the exact elliptical Hertz contact
/// (Johnson (4.39)–(4.40)) the force at a given overlap is low by 0.10 % at d = 5 R, 0.023 %
/// at 10 R and 1.3e-5 at 40 R (test `cylinder_r_star_against_the_elliptical_hertz_contact`;
/// doc/indentation.md, "The cylindrical die").
#[inline]
pub fn wall_r_star(geom: &WallGeom, r: f64) -> f64 {
    match *geom {
        WallGeom::Plane { .. } => r,
        WallGeom::Sphere { radius, .. } => r * radius / (radius - r).max(1e-300),
        WallGeom::Obstacle { radius, .. } => r * radius / (radius + r),
        WallGeom::Cylinder { radius, .. } => r * (radius / (radius - r).max(1e-300)).sqrt(),
    }
}

/// Velocity of the wall surface at the contact point; `n` is the particle→wall normal.
#[inline]
pub fn surface_velocity(w: &Wall, n: &Vec3) -> Vec3 {
    let v = Vec3::from(w.vel);
    match w.geom {
        WallGeom::Plane { .. } => v,
        // Container or die: the surface point moves outward (along n) at vr.
        WallGeom::Sphere { .. } | WallGeom::Cylinder { .. } => v + n * w.vr,
        // Obstacle: outward from its centre is −n.
        WallGeom::Obstacle { .. } => v - n * w.vr,
    }
}

/// A bound of the speed of a wall's surface: its velocity's magnitude plus its radial speed.
pub fn surface_speed(w: &Wall) -> f64 {
    Vec3::from(w.vel).norm() + w.vr.abs()
}

/// Moves a wall by its velocity over dt (and its radius by vr dt).
pub fn advance(w: &mut Wall, dt: f64) {
    for k in 0..3 {
        w.disp[k] += w.vel[k] * dt;
    }
    match &mut w.geom {
        WallGeom::Plane { normal, d } => {
            let n = Vec3::from(*normal);
            let step = n.dot(&Vec3::from(w.vel)) * dt;
            *d += step;
            // The plane moves along its unit normal by step/|n|.
            w.travel += (step / n.norm()).abs();
        }
        WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
            for k in 0..3 {
                centre[k] += w.vel[k] * dt;
            }
            let r = (*radius + w.vr * dt).max(0.0);
            w.travel += Vec3::from(w.vel).norm() * dt + (r - *radius).abs();
            *radius = r;
        }
        WallGeom::Cylinder { point, radius, .. } => {
            for k in 0..3 {
                point[k] += w.vel[k] * dt;
            }
            let r = (*radius + w.vr * dt).max(0.0);
            w.travel += Vec3::from(w.vel).norm() * dt + (r - *radius).abs();
            *radius = r;
        }
    }
}

/// Servo control (Lian §5.4): the wall's normal (radial) velocity is set from the force
/// error, v = clip(g (F_measured − F_target), ±vmax), along the direction that reduces the
/// error (toward the particles when the measured force is too small).
pub fn servo(w: &mut Wall) {
    let Some(s) = w.servo else { return };
    let err = w.normal_force - s.force;
    let speed = (s.gain * err).clamp(-s.vmax, s.vmax);
    match &w.geom {
        WallGeom::Plane { normal, .. } => {
            // Positive speed = move away from the particles (against the normal).
            let n = Vec3::from(*normal).normalize();
            let v = -n * speed;
            w.vel = [v.x, v.y, v.z];
        }
        WallGeom::Sphere { .. } | WallGeom::Cylinder { .. } => w.vr = speed,
        WallGeom::Obstacle { .. } => w.vr = -speed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_gap_and_normal() {
        let g = WallGeom::Plane {
            normal: [0.0, 0.0, 2.0],
            d: 2.0,
        }; // z = 1, particles above
        let (gap, n) = wall_gap(&g, &Vec3::new(0.3, 0.1, 1.5), 0.2);
        assert!((gap - 0.3).abs() < 1e-15);
        assert_eq!(n, Vec3::new(0.0, 0.0, -1.0));
        let g = WallGeom::Plane {
            normal: [1.0, 1.0, 0.0],
            d: 0.0,
        };
        let (gap, _) = wall_gap(&g, &Vec3::new(1.0, 1.0, 0.0), 0.5);
        assert!((gap - (2f64.sqrt() - 0.5)).abs() < 1e-15);
    }

    #[test]
    fn spheres() {
        let c = WallGeom::Sphere {
            centre: [0.0; 3],
            radius: 1.0,
        };
        let (gap, n) = wall_gap(&c, &Vec3::new(0.5, 0.0, 0.0), 0.1);
        assert!((gap - 0.4).abs() < 1e-15);
        assert_eq!(n, Vec3::new(1.0, 0.0, 0.0));
        let o = WallGeom::Obstacle {
            centre: [0.0; 3],
            radius: 1.0,
        };
        let (gap, n) = wall_gap(&o, &Vec3::new(0.0, 2.0, 0.0), 0.1);
        assert!((gap - 0.9).abs() < 1e-15);
        assert_eq!(n, Vec3::new(0.0, -1.0, 0.0));
        assert!((wall_r_star(&c, 0.1) - 0.1 / 0.9).abs() < 1e-15);
        assert!((wall_r_star(&o, 0.1) - 0.1 / 1.1).abs() < 1e-15);
    }

    fn die(radius: f64) -> WallGeom {
        // Axis through (1, 2, 0) along (0, 0.6, 0.8).
        WallGeom::Cylinder {
            point: [1.0, 2.0, 0.0],
            axis: [0.0, 0.6, 0.8],
            radius,
        }
    }

    #[test]
    fn cylinder_gap_normal_velocity_and_motion() {
        let g = die(1.0);
        // A point 0.7 from the axis along x, anywhere along the axis.
        for t in [-3.0, 0.0, 2.5] {
            let x = Vec3::new(1.7, 2.0 + 0.6 * t, 0.8 * t);
            let (gap, n) = wall_gap(&g, &x, 0.1);
            assert!((gap - 0.2).abs() < 1e-14, "{gap}");
            assert!((n - Vec3::new(1.0, 0.0, 0.0)).norm() < 1e-14, "{n}");
        }
        // On the axis: some unit normal perpendicular to the axis, gap r_cyl − r.
        let (gap, n) = wall_gap(&g, &Vec3::new(1.0, 2.0, 0.0), 0.1);
        assert!((gap - 0.9).abs() < 1e-15);
        assert!((n.norm() - 1.0).abs() < 1e-15 && n.dot(&Vec3::new(0.0, 0.6, 0.8)).abs() < 1e-15);
        // The surface moves outward at vr, plus the translation; a servo sets vr.
        let mut w = Wall {
            geom: g,
            vel: [0.0, 0.0, 1.0],
            vr: -0.5,
            material: 1,
            servo: Some(crate::sim::model::Servo {
                force: 10.0,
                vmax: 0.25,
                gain: 1.0,
            }),
            force: [0.0; 3],
            normal_force: 0.0,
            disp: [0.0; 3],
            travel: 0.0,
        };
        let v = surface_velocity(&w, &Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(v, Vec3::new(-0.5, 0.0, 1.0));
        advance(&mut w, 0.1);
        let WallGeom::Cylinder { point, radius, .. } = w.geom else {
            unreachable!()
        };
        assert_eq!(point, [1.0, 2.0, 0.1]);
        assert!((radius - 0.95).abs() < 1e-15);
        assert!((w.travel - 0.15).abs() < 1e-15);
        // Measured 0 < target 10: the die closes in (vr < 0) at vmax.
        servo(&mut w);
        assert_eq!(w.vr, -0.25);
    }

    /// Complete elliptic integrals K(k), E(k) of modulus k by the arithmetic–geometric mean
    /// (Abramowitz & Stegun 17.6).
    fn elliptic_ke(k: f64) -> (f64, f64) {
        let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
        let (mut sum, mut pow) = (0.5 * k * k, 1.0);
        for _ in 0..40 {
            if (a - b).abs() <= 1e-16 * a {
                break;
            }
            let c = 0.5 * (a - b);
            (a, b) = (0.5 * (a + b), (a * b).sqrt());
            pow *= 2.0;
            sum += 0.5 * pow * c * c;
        }
        let kk = std::f64::consts::PI / (2.0 * a);
        (kk, kk * (1.0 - sum))
    }

    /// Hertz's force at overlap δ for bodies of principal relative radii R1 > R2 (gap
    /// x²/(2R1) + y²/(2R2)): the eccentricity e of the contact ellipse from
    /// B/A = (E/(1 − e²) − K)/(K − E), then A = p0 √(1−e²)(K − E)/(E* e² a),
    /// δ = p0 b K/E*, P = 2/3 π a b p0 (Johnson 1985, (4.39)–(4.40)).
    fn elliptical_hertz(r1: f64, r2: f64, e_star: f64, delta: f64) -> f64 {
        let (aa, bb) = (0.5 / r1, 0.5 / r2);
        let ratio = |e: f64| {
            let (k, ee) = elliptic_ke(e);
            (ee / (1.0 - e * e) - k) / (k - ee)
        };
        let (mut lo, mut hi) = (1e-6, 1.0 - 1e-12);
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if ratio(m) > bb / aa {
                hi = m;
            } else {
                lo = m;
            }
        }
        let e = 0.5 * (lo + hi);
        let (k, ee) = elliptic_ke(e);
        let s = (1.0 - e * e).sqrt();
        let p0_over_a = aa * e_star * e * e / (s * (k - ee));
        let a = (delta * e_star / (p0_over_a * s * k)).sqrt();
        2.0 / 3.0 * std::f64::consts::PI * a.powi(3) * s * p0_over_a
    }

    #[test]
    fn cylinder_r_star_against_the_elliptical_hertz_contact() {
        // The elliptic integrals: K(0.5) = 1.685750354812596, E(0.5) = 1.467462209339427.
        let (k, e) = elliptic_ke(0.5);
        assert!((k - 1.685750354812596).abs() < 1e-14 && (e - 1.467462209339427).abs() < 1e-14);
        // Equal radii: the circular Hertz contact, 4/3 E* √R δ^{3/2}.
        let f = elliptical_hertz(0.5, 0.5 * (1.0 + 1e-12), 2.0, 1e-4);
        assert!(
            (f / (4.0 / 3.0 * 2.0 * 0.5f64.sqrt() * 1e-6) - 1.0).abs() < 1e-5,
            "{f}"
        );
        let (r, e_star, delta) = (1e-3, 3e9, 2e-6f64);
        for (d_over_r, within) in [(5.0, 1.1e-3), (10.0, 2.4e-4), (40.0, 1.4e-5)] {
            let g = die(d_over_r * r);
            let r_star = wall_r_star(&g, r);
            let hertz = 4.0 / 3.0 * e_star * r_star.sqrt() * delta.powf(1.5);
            let exact = elliptical_hertz(r * d_over_r / (d_over_r - 1.0), r, e_star, delta);
            let err = (hertz / exact - 1.0).abs();
            assert!(err < within, "d = {d_over_r} R: {err:e}");
            // The mean curvature (the harmonic mean of the two radii) would be 4 × further off.
            let mean = 2.0 / (1.0 / (r * d_over_r / (d_over_r - 1.0)) + 1.0 / r);
            let off = (4.0 / 3.0 * e_star * mean.sqrt() * delta.powf(1.5) / exact - 1.0).abs();
            assert!(off > 3.0 * err, "{off:e} vs {err:e}");
        }
    }
}
