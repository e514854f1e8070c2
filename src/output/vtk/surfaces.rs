//! The walls as surfaces at their current positions: a plane as its polygon inside the
//! work-space box, a sphere (container or obstacle) as a UV sphere of quadrilaterals, a
//! cylinder as a tube of quadrilaterals over the length of its axis that the box spans. Cell
//! arrays: `wall` (its number), `force` (of the particles on it, last step), `normal_force`,
//! `velocity`.

use super::frame::time_fields;
use super::xml::{Array, PolyData, Values};
use crate::sim::Scene;
use crate::sim::model::WallGeom;
use crate::sim::scene::Vec3;

/// Facets around a sphere or a cylinder, and rings from pole to pole of a sphere.
const AROUND: usize = 32;
const RINGS: usize = 16;

pub fn walls(scene: &Scene) -> PolyData {
    let size = scene.size();
    let mut d = PolyData {
        field_data: time_fields(scene),
        ..Default::default()
    };
    let mut owner = Vec::new();
    for (k, w) in scene.walls().iter().enumerate() {
        let before = d.polys.len();
        match w.geom {
            WallGeom::Plane { normal, d: off } => plane(&mut d, normal, off, size),
            WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
                sphere(&mut d, Vec3::from(centre), radius)
            }
            WallGeom::Cylinder {
                point,
                axis,
                radius,
            } => cylinder(&mut d, Vec3::from(point), Vec3::from(axis), radius, size),
        }
        owner.extend(std::iter::repeat_n(k, d.polys.len() - before));
    }
    let walls = scene.walls();
    let cd = &mut d.cell_data;
    cd.push(Array::new(
        "wall",
        1,
        Values::I32(owner.iter().map(|&k| k as i32 + 1).collect()),
    ));
    cd.push(Array::vectors(
        "force",
        owner.iter().map(|&k| walls[k].force),
    ));
    cd.push(Array::scalars(
        "normal_force",
        owner.iter().map(|&k| walls[k].normal_force),
    ));
    cd.push(Array::vectors(
        "velocity",
        owner.iter().map(|&k| walls[k].vel),
    ));
    d
}

/// Two unit vectors normal to `n` and to each other.
fn basis(n: &Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let u = n.cross(&helper).normalize();
    (u, n.cross(&u))
}

fn push(d: &mut PolyData, x: Vec3) -> usize {
    d.points.push([x.x, x.y, x.z]);
    d.points.len() - 1
}

/// The plane n·x = d cut by the box 0 ≤ x_k ≤ size_k: the points where it crosses the box's
/// 12 edges, in order around their centre, as one polygon (none when it misses the box).
fn plane(d: &mut PolyData, normal: [f64; 3], off: f64, size: [f64; 3]) {
    let n = Vec3::from(normal);
    let len = n.norm();
    if !(len > 0.0) {
        return;
    }
    let (nh, off) = (n / len, off / len);
    let corner = |k: usize| {
        Vec3::new(
            if k & 1 != 0 { size[0] } else { 0.0 },
            if k & 2 != 0 { size[1] } else { 0.0 },
            if k & 4 != 0 { size[2] } else { 0.0 },
        )
    };
    let tol = 1e-12 * (size[0] + size[1] + size[2]);
    let mut pts: Vec<Vec3> = Vec::new();
    let mut add = |x: Vec3| {
        if !pts.iter().any(|q| (q - x).norm() <= tol) {
            pts.push(x);
        }
    };
    for a in 0..8usize {
        for bit in [1, 2, 4] {
            if a & bit != 0 {
                continue;
            }
            let (p0, p1) = (corner(a), corner(a | bit));
            let (s0, s1) = (nh.dot(&p0) - off, nh.dot(&p1) - off);
            if s0 == 0.0 {
                add(p0);
            }
            if s1 == 0.0 {
                add(p1);
            }
            if s0 * s1 < 0.0 {
                add(p0 + (p1 - p0) * (s0 / (s0 - s1)));
            }
        }
    }
    if pts.len() < 3 {
        return;
    }
    let c = pts.iter().fold(Vec3::zeros(), |acc, x| acc + x) / pts.len() as f64;
    let (u, v) = basis(&nh);
    pts.sort_by(|a, b| {
        let ang = |x: &Vec3| (x - c).dot(&v).atan2((x - c).dot(&u));
        ang(a).total_cmp(&ang(b))
    });
    let ids: Vec<usize> = pts.into_iter().map(|x| push(d, x)).collect();
    d.polys.push(&ids);
}

/// A sphere of quadrilaterals (triangles at the poles).
fn sphere(d: &mut PolyData, c: Vec3, r: f64) {
    let top = push(d, c + Vec3::new(0.0, 0.0, r));
    let mut rings = Vec::new();
    for i in 1..RINGS {
        let th = std::f64::consts::PI * i as f64 / RINGS as f64;
        let ring: Vec<usize> = (0..AROUND)
            .map(|j| {
                let ph = 2.0 * std::f64::consts::PI * j as f64 / AROUND as f64;
                let x = Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                push(d, c + x * r)
            })
            .collect();
        rings.push(ring);
    }
    let bottom = push(d, c - Vec3::new(0.0, 0.0, r));
    for j in 0..AROUND {
        let j1 = (j + 1) % AROUND;
        d.polys.push(&[top, rings[0][j], rings[0][j1]]);
        for w in rings.windows(2) {
            d.polys.push(&[w[0][j], w[1][j], w[1][j1], w[0][j1]]);
        }
        let last = &rings[rings.len() - 1];
        d.polys.push(&[last[j1], last[j], bottom]);
    }
}

/// A cylinder around the axis through `p` along `a`, from where the box's corners project
/// least on the axis to where they project most.
fn cylinder(d: &mut PolyData, p: Vec3, a: Vec3, r: f64, size: [f64; 3]) {
    let len = a.norm();
    if !(len > 0.0) {
        return;
    }
    let a = a / len;
    let (mut t0, mut t1) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..8 {
        let x = Vec3::new(
            if k & 1 != 0 { size[0] } else { 0.0 },
            if k & 2 != 0 { size[1] } else { 0.0 },
            if k & 4 != 0 { size[2] } else { 0.0 },
        );
        let t = (x - p).dot(&a);
        t0 = t0.min(t);
        t1 = t1.max(t);
    }
    let (u, v) = basis(&a);
    let mut ring = |t: f64| -> Vec<usize> {
        (0..AROUND)
            .map(|j| {
                let ph = 2.0 * std::f64::consts::PI * j as f64 / AROUND as f64;
                push(d, p + a * t + (u * ph.cos() + v * ph.sin()) * r)
            })
            .collect()
    };
    let (lo, hi) = (ring(t0), ring(t1));
    for j in 0..AROUND {
        let j1 = (j + 1) % AROUND;
        d.polys.push(&[lo[j], lo[j1], hi[j1], hi[j]]);
    }
}
