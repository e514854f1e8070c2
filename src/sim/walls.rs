//! Wall geometry: gap, contact normal and surface velocity for plane walls, spherical
//! containers and spherical obstacles (Lian (5.7), (5.8); doc/spec/DECISIONS.md, "Contact laws").

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
    }
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
/// obstacle R d/(d + R) (doc/spec/DECISIONS.md).
#[inline]
pub fn wall_r_star(geom: &WallGeom, r: f64) -> f64 {
    match *geom {
        WallGeom::Plane { .. } => r,
        WallGeom::Sphere { radius, .. } => r * radius / (radius - r).max(1e-300),
        WallGeom::Obstacle { radius, .. } => r * radius / (radius + r),
    }
}

/// Velocity of the wall surface at the contact point; `n` is the particle→wall normal.
#[inline]
pub fn surface_velocity(w: &Wall, n: &Vec3) -> Vec3 {
    let v = Vec3::from(w.vel);
    match w.geom {
        WallGeom::Plane { .. } => v,
        // Container: the surface point moves outward (along n) at vr.
        WallGeom::Sphere { .. } => v + n * w.vr,
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
        WallGeom::Sphere { .. } => w.vr = speed,
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
}
